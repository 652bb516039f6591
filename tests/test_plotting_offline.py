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
