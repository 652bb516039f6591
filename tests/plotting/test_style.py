"""Figures and animations work offline: nothing in them is loaded from the internet."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.animation import FuncAnimation  # noqa: E402

from imunav.plotting import DISTINCT, offline_jshtml  # noqa: E402


def test_animation_html_links_nothing_online():
    fig, ax = plt.subplots()
    line, = ax.plot([0, 1], [0, 1])
    anim = FuncAnimation(fig, lambda i: line.set_ydata([0, i]), frames=3)
    raw = anim.to_jshtml()
    assert "font-awesome" in raw                   # what matplotlib does by itself
    html = offline_jshtml(anim)
    plt.close(fig)
    assert "http://" not in html and "https://" not in html
    assert 'class="fa ' not in html and "▶" in html and "<img" in html


def test_distinct_colours_are_distinct():
    from matplotlib.colors import to_rgb

    rgb = [to_rgb(c) for c in DISTINCT]
    assert len(set(rgb)) == len(DISTINCT) == 20


def test_book_figures_are_shown_at_their_size_in_inches():
    """use_book_style's PNG: stored at the figure's dpi (150), with a display size of 96 CSS px
    per inch in its metadata, so 8 pt text stays 8 pt in JupyterLab and the book."""
    import struct

    from imunav.plotting.style import BOOK_RC, _png_with_size

    with matplotlib.rc_context(BOOK_RC):
        fig, ax = plt.subplots(figsize=(6.0, 3.0))
        ax.plot([0, 1], [0, 1])
        data, md = _png_with_size(fig)
        plt.close(fig)
    w, h = struct.unpack(">II", data[16:24])
    assert fig.dpi == 150 and 4.0 * 150 < w <= 6.0 * 150      # 150 dpi; the tight bbox of 6 in
    assert md == {"width": round(w * 96 / 150), "height": round(h * 96 / 150)}
