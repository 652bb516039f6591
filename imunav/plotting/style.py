"""The one figure style of imunav, and the figure check: the plotting room's style module
(re-exported by :mod:`imunav.plotting`, where the plot functions are). It imports nothing of
imunav, so the papers — one floor below the plotting room — may import it (the one exception to
the floors, ``tests/package/test_layering.py``): every module that draws uses the same names and colours.
``imunav.core.style``, its former home, still imports with a ``DeprecationWarning`` until 0.3;
so does the function ``style`` of this module, now :func:`thing_style` (it shared the module's
name, and hid the module behind ``imunav.plotting.style``): calling the module runs it.

**Style.** Call :func:`use_book_style` once (the first cell of every notebook does): figures are
stored at 150 dpi, their text at 8–10 pt, and they are displayed at their size in inches (96 CSS
pixels per inch), so a figure no wider than the book's text column (:data:`MAX_WIDTH_IN`, 7 in)
keeps its text at its size on the page. Every named thing — an algorithm, an error term, an IMU
preset, truth and estimate, a paper's scheme — has one readable name (:func:`name`) and one colour
and line style (:func:`thing_style`; :func:`styled` adds the label) that hold in every figure::

    ax.plot(t, err, **styled("increments/coning2"))      # colour, line style, "two-sample coning"

Internal identifiers (``poly8_m6``, ``gyro.noise_density``, ``quat_amended``) never reach a title,
a label or a legend: :func:`name` gives the words.

**Figure check.** :func:`check_figure` lists what keeps a reader from trusting a figure at a glance:
a labelled line, or a dotted or dashed one, hidden under another (at least 80 % of its drawn
pixels under later-drawn ones), a dotted or dashed line lying on a solid line of its own colour
(both unless a label or the title says the lines coincide), a legend over the data of its axes
(more than :data:`LEGEND_OVER_LINES` of its box over drawn lines, or any marker under it), a
legend with more than
:data:`MAX_LEGEND` entries, two units on one axis, an internal id in a title, label, legend or
tick label, text below :data:`MIN_FONT_PT`, a figure wider than :data:`MAX_WIDTH_IN` or stored
below :data:`MIN_DPI`, a panel more than 10:1, a fixed axis range the data fill less than a third
of. :func:`install_figure_check` makes ``plt.show()`` raise :class:`FigureCheckError` on any of
them (the notebook tests and ``make notebooks`` install it in every kernel).

May import: nothing in imunav (numpy; matplotlib and IPython lazily, inside the functions).
"""

from __future__ import annotations

import re
import sys
import types
import warnings
from dataclasses import dataclass

import numpy as np

# ------------------------------------------------------------ the style

#: The book's text column (in): a figure no wider is shown at its size, so 8 pt stays 8 pt.
MAX_WIDTH_IN = 7.0
#: Resolution figures are stored at (dots per inch).
MIN_DPI = 150
#: Smallest text on a figure (pt): tick labels, legends, labels, titles.
MIN_FONT_PT = 8.0
#: Most legend entries per legend: more is a table or small multiples.
MAX_LEGEND = 8
#: Default figure width (in), a little under the column.
WIDTH_IN = 6.5

#: rcParams of :func:`use_book_style`.
BOOK_RC = {
    "figure.dpi": MIN_DPI, "savefig.dpi": MIN_DPI, "figure.figsize": (WIDTH_IN, 3.4),
    "figure.facecolor": "white", "savefig.facecolor": "white", "savefig.bbox": "tight",
    "font.size": 9.0, "axes.titlesize": 9.5, "axes.labelsize": 9.0, "figure.titlesize": 10.0,
    "xtick.labelsize": 8.5, "ytick.labelsize": 8.5, "legend.fontsize": 8.0,
    "legend.title_fontsize": 8.0, "legend.framealpha": 0.85, "lines.linewidth": 1.5,
    "axes.grid": True, "grid.linewidth": 0.4, "grid.alpha": 0.5, "axes.axisbelow": True,
}

#: CSS pixels per inch of a stored figure's display size (the browser's inch).
_CSS_PX_PER_IN = 96


@dataclass(frozen=True)
class Thing:
    """A named thing of the book: its words, its colour and its line style in every figure."""

    name: str
    colour: str
    linestyle: str = "-"


def _things() -> dict[str, Thing]:
    t: dict[str, Thing] = {}
    # Algorithms, as "kind/name" (the registry's ids): one colour each, distinct within each
    # group that is drawn together (rate samples; classic increments; offline high order).
    for key, words, c in (
        ("rates/first_order", "first-order update (rates)", "#BE0032"),
        ("rates/exact_exponential", "mean-rate exponential (rates)", "#E68FAC"),
        ("rates/magnus4", "Magnus-4 (rates)", "#8DB600"),
        ("rates/magnus6", "Magnus-6 (rates)", "#604E97"),
        ("increments/first_order", "small-angle update (increments)", "#654522"),
        ("increments/exact_exponential", "exponential of Δθ, no coning term", "#848482"),
        ("increments/coning2", "two-sample coning", "#E25822"),
        ("increments/ignagni2", "Ignagni 2-sample", "#F6A600"),
        ("increments/miller3", "Miller 3-sample", "#875692"),
        ("increments/ignagni3", "Ignagni 3-sample", "#B3446C"),
        ("increments/ignagni4", "Ignagni 4-sample", "#008856"),
        ("increments/poly6_m4", "6-node fit + Magnus-4", "#56B4E9"),
        ("increments/poly8_m6", "8-node fit + Magnus-6", "#0067A5"),
    ):
        t[key] = Thing(words, c)
    # Sensor error terms, "triad.term": the colour is the term's, the line style the triad's
    # (gyro solid, accelerometer dashed).
    terms = {"noise_density": ("white noise", "#0067A5"), "bias": ("turn-on bias", "#BE0032"),
             "bias_instability": ("bias instability", "#008856"),
             "random_walk": ("random walk", "#875692"),
             "scale_factor": ("scale factor", "#F6A600"),
             "misalignment": ("misalignment", "#604E97"),   # violet: not the bias crimson, not black
             "g_sensitivity": ("g-sensitivity", "#E68FAC"),
             "resolution": ("resolution (quantisation)", "#848482"),
             "bandwidth": ("anti-alias filter", "#56B4E9"), "range": ("range (clipping)", "#654522")}
    for triad, words, ls in (("gyro", "gyro", "-"), ("accel", "accelerometer", "--")):
        for term, (w, c) in terms.items():
            if term == "random_walk":
                w = "rate random walk" if triad == "gyro" else "acceleration random walk"
            t[f"{triad}.{term}"] = Thing(f"{words} {w}", c, ls)
    # The Allan-fit terms (either triad): white noise N, bias instability B, random walk K.
    for term, w in (("noise_density", "white noise N"), ("bias_instability", "bias instability B"),
                    ("random_walk", "random walk K")):
        t[term] = Thing(w, terms[term][1])
    # IMU presets (imunav.sensors.presets).
    for key, words, c in (("ideal", "ideal IMU", "#848482"), ("BNO055", "BNO055", "#E25822"),
                          ("MPU-6050", "MPU-6050", "#BE0032"), ("BMI088", "BMI088", "#875692"),
                          ("ADIS16470", "ADIS16470", "#0067A5"),
                          ("tactical", "tactical-grade IMU", "#008856")):
        t[key] = Thing(words, c)
    # Roles.
    t["truth"] = Thing("truth", "black")
    t["estimate"] = Thing("navigated", "#E25822", "--")
    t["measured"] = Thing("measured", "#848482")
    t["tolerance"] = Thing("tolerance", "black", "--")
    t["montecarlo"] = Thing("Monte Carlo", "#56B4E9")
    t["covariance"] = Thing("covariance analysis", "#B3446C", "--")
    # Aided navigation (notebook 10): the filter, the smoother, stance phases and their detector.
    t["filter"] = Thing("filter", "#E25822")
    t["smoother"] = Thing("smoother", "#008856")
    t["true stance"] = Thing("true stance", "#848482")
    t["SHOE"] = Thing("SHOE detector", "#875692")
    for ax, c in zip("xyz", ("#BE0032", "#008856", "#0067A5"), strict=True):
        t[f"axis.{ax}"] = Thing(f"{ax} axis", c)
    t["rates"] = Thing("rate samples", "#848482", "--")
    t["increments"] = Thing("increments Δθ, Δv", "#0067A5")
    # The papers' schemes (imunav.papers): Marusenkova's attitude schemes, Plaksiy's updates.
    for key, words, c in (("dcm", "classic DCM", "#0067A5"), ("quat", "classic quaternion", "#E25822"),
                          ("quat_amended", "amended quaternion (eq. 36)", "#008856"),
                          ("dcm_amended", "exact DCM (not in the paper)", "#875692"),
                          ("series4", "4th-order series update", "#F6A600"),
                          ("exact", "exact update", "#0067A5")):
        t[key] = Thing(words, c)
    for key in ("fig1a", "fig1b"):
        t[key] = Thing(f"Fig. 1{key[-1]} motion", "#0067A5")
    return t


#: Every named thing: ``THINGS[id]`` → :class:`Thing`. Algorithms are ``"kind/name"``, sensor
#: errors ``"triad.term"``; bare algorithm names (``"poly8_m6"``) resolve through :func:`name`.
THINGS: dict[str, Thing] = _things()

_BARE = {}
for _k in THINGS:
    if "/" in _k:
        _BARE.setdefault(_k.split("/")[1], []).append(_k)


def _key(thing: str) -> str:
    if thing in THINGS:
        return thing
    if thing in _BARE and len(_BARE[thing]) == 1:
        return _BARE[thing][0]
    if thing in _BARE:     # first_order, exact_exponential: say which kind
        raise KeyError(f"{thing!r} names an algorithm of both kinds: use one of {_BARE[thing]}")
    raise KeyError(f"no style for {thing!r}: add it to imunav.plotting.THINGS (known: "
                   f"{', '.join(sorted(THINGS))})")


def algorithm_id(kind: str, algorithm: str) -> str:
    """The id of an algorithm of the registry: ``"increments/poly8_m6"``."""
    return f"{kind}/{algorithm}"


def name(thing: str) -> str:
    """The readable name of an internal id (an algorithm ``"increments/poly8_m6"`` or
    ``"poly8_m6"``, an error term ``"gyro.noise_density"``, a preset, a paper's scheme); a string
    that is not an id is returned unchanged."""
    try:
        return THINGS[_key(thing)].name
    except KeyError:
        return thing


def colour(thing: str) -> str:
    """The colour of ``thing`` in every figure (KeyError for a thing without one)."""
    return THINGS[_key(thing)].colour


def thing_style(thing: str, **kw) -> dict:
    """``color`` and ``linestyle`` of ``thing`` for ``ax.plot`` (keywords override)."""
    t = THINGS[_key(thing)]
    for short, full in (("ls", "linestyle"), ("c", "color")):
        if short in kw:
            kw[full] = kw.pop(short)
    return {"color": t.colour, "linestyle": t.linestyle, **kw}


def styled(thing: str, **kw) -> dict:
    """:func:`thing_style` plus ``label=name(thing)``: ``ax.plot(x, y, **styled("truth"))``."""
    return {"label": name(thing), **thing_style(thing, **kw)}


def use_book_style() -> None:
    """The book's figure style for this session: :data:`BOOK_RC`, and in IPython figures stored
    as PNG at their dpi with their display size (96 CSS px per inch) in the output's metadata,
    so a reader sees 8 pt as 8 pt in JupyterLab and in the book."""
    import matplotlib
    import matplotlib.pyplot as plt

    plt.close(plt.figure())   # loads the backend now: the inline one registers its formatter
    matplotlib.rcParams.update(BOOK_RC)
    try:
        from IPython import get_ipython
    except ImportError:       # pragma: no cover — IPython ships with the notebooks extra
        return
    ip = get_ipython()
    if ip is None:
        return
    from matplotlib.figure import Figure

    ip.display_formatter.formatters["image/png"].for_type(Figure, _png_with_size)


def _png_with_size(fig):
    import io
    import struct

    if not fig.axes and not fig.lines and not fig.texts and not fig.images:
        return None           # an empty figure is not shown (the inline backend's rule)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=fig.dpi, bbox_inches="tight", facecolor="white")
    data = buf.getvalue()
    w, h = struct.unpack(">II", data[16:24])
    px = _CSS_PX_PER_IN / fig.dpi
    return data, {"width": round(w * px), "height": round(h * px)}


def figure(nrows: int = 1, ncols: int = 1, width: float = WIDTH_IN, height: float | None = None,
           **kw):
    """``plt.subplots`` at the book's size (default width :data:`WIDTH_IN`; height 2.6 in per
    row + 0.6) with constrained layout. Returns ``(fig, axes)``."""
    import matplotlib.pyplot as plt

    height = height if height is not None else 0.6 + 2.6 * nrows
    kw.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, figsize=(width, height), **kw)


#: Up to 20 colours no two alike: matplotlib's ten, then ten more of clearly other hues.
DISTINCT = ("C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9", "black", "gold",
            "lime", "navy", "magenta", "teal", "salmon", "olive", "maroon", "slateblue")


def series_style(i: int) -> dict:
    """Colour and marker for the ``i``-th point series of one axes (colours unique up to 20
    series, then the marker shape changes), for series that are not named things (a sweep's
    values). For dense curves use only ``["color"]``."""
    return {"color": DISTINCT[i % len(DISTINCT)],
            "marker": ("o", "s", "^", "D")[(i // len(DISTINCT)) % 4]}


def rate_ticks(ax, rates) -> None:
    """Label a log x axis at the sample rates themselves (no overlapping minor labels)."""
    ax.set_xticks(list(rates), [f"{r:g}" for r in rates])
    ax.minorticks_off()


# ------------------------------------------------------------ the figure check

class FigureCheckError(AssertionError):
    """A figure failed :func:`check_figure` (raised by ``plt.show`` once installed)."""


#: The words that excuse a line under another: the text says they coincide.
_SAYS_COINCIDE = re.compile(r"coincid|identical|overlap|≡|same as", re.I)
_HIDDEN_FRACTION = 0.8

_ATOM = r"(?:(?:µ|u|m|k|M|n)?(?:m|s|rad|g|Hz|N)|min|h|deg|°|K|%|ppm|dB)"
_UNIT1 = rf"√?\(?{_ATOM}(?:[²³]|\^-?\d+)?\)?"
_UNIT = re.compile(rf"^{_UNIT1}(?:\s*[/·*×]\s*{_UNIT1})*$")
_PAREN = re.compile(r"\(([^()]*(?:\([^()]*\)[^()]*)*)\)")
_MATH = re.compile(r"\$[^$]*\$")
_SNAKE = re.compile(r"(?<![\w\\])[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)+(?!\w)")
_DOTTED = re.compile(r"(?<![\w.])(?:gyro|accel)\.[a-z_]+")


def _internal_ids() -> set[str]:
    ids = set()
    for k in THINGS:
        for part in re.split(r"[/.]", k):
            if name(part) != part or part in _BARE:
                if re.search(r"[_\d]", part) or part.islower():
                    ids.add(part)
    return ids - {"rates", "increments", "truth", "estimate", "measured", "tolerance", "ideal",
                  "tactical", "exact", "covariance", "montecarlo", "axis", "x", "y", "z"}


_IDS = _internal_ids()
_ID_WORD = re.compile(r"(?<![\w-])(" + "|".join(sorted(map(re.escape, _IDS), key=len,
                                                        reverse=True)) + r")(?![\w-])")


def internal_ids_in(text: str) -> list[str]:
    """The internal identifiers in ``text`` (outside ``$math$``): snake_case words, sensor-term
    ids, and the ids of :data:`THINGS` (``coning2``, ``dcm``, ``series4``)."""
    plain = _MATH.sub(" ", text)
    found = _SNAKE.findall(plain) + _DOTTED.findall(plain) + _ID_WORD.findall(plain)
    return list(dict.fromkeys(found))


def units_in(label: str) -> str | None:
    """The unit a label states in its last parenthesis (``"velocity (m/s)"`` → ``"m/s"``),
    normalised (deg → °, ^2 → ²); None without one."""
    for content in reversed(_PAREN.findall(_MATH.sub(" ", label))):
        u = content.strip()
        if u and _UNIT.match(u):
            u = u.replace("deg", "°").replace("^2", "²").replace("^3", "³").replace("ug", "µg")
            return re.sub(r"\s+", "", u)
    return None


def _artist_mask(artist, renderer_size, dpi, opaque, grow=True):
    """The pixels ``artist`` draws: any (``opaque`` False) or those it covers (alpha > ½; grown
    by a pixel on every side unless ``grow`` is False)."""
    from matplotlib.backends.backend_agg import RendererAgg

    r = RendererAgg(*renderer_size, dpi)
    artist.draw(r)
    alpha = np.asarray(r.buffer_rgba())[:, :, 3]
    if not opaque:
        return alpha > 20
    m = alpha > 127
    if not grow:
        return m
    grown = m.copy()            # one pixel more on every side: the lower line's antialiased edge
    grown[1:] |= m[:-1]
    grown[:-1] |= m[1:]
    grown[:, 1:] |= m[:, :-1]
    grown[:, :-1] |= m[:, 1:]
    return grown


def _drawn_in_order(ax):
    from matplotlib.collections import Collection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    kids = [a for a in ax.get_children()
            if isinstance(a, (Line2D, Collection, Patch)) and a.get_visible()
            and a is not ax.patch and a not in ax.spines.values()]
    return sorted(kids, key=lambda a: a.get_zorder())


def _label(a) -> str | None:
    lab = a.get_label()
    return None if not lab or lab.startswith("_") else lab


def _dashed(a) -> bool:
    """A line drawn dotted or dashed (not solid, not markers only)."""
    from matplotlib.lines import Line2D

    return isinstance(a, Line2D) and a.get_linestyle() in ("--", ":", "-.")


def _solid(a) -> bool:
    from matplotlib.lines import Line2D

    return isinstance(a, Line2D) and a.get_linestyle() == "-"


def _same_colour(a, b) -> bool:
    from matplotlib.colors import to_rgb

    return bool(np.allclose(to_rgb(a.get_color()), to_rgb(b.get_color()), atol=0.05))


def _describe(a) -> str:
    from matplotlib.colors import to_hex

    kind = {":": "dotted", "--": "dashed", "-.": "dash-dotted"}.get(a.get_linestyle(), "")
    return f"the {kind} line".replace("the  line", "the line") + (
        f" '{_label(a)}'" if _label(a) else f" (unlabelled, {to_hex(a.get_color())})")


def _hidden_lines(fig, ax, where) -> list[str]:
    """Lines a reader cannot see: a labelled line, or a dotted or dashed one (labelled or not),
    with at least :data:`_HIDDEN_FRACTION` of its pixels under artists drawn after it; and a
    dotted or dashed line lying on a solid line of its own colour drawn before it (a dotted
    reference exactly on its curve)."""
    from matplotlib.lines import Line2D

    arts = _drawn_in_order(ax)
    lower = [i for i, a in enumerate(arts) if isinstance(a, Line2D)
             and (_label(a) or _dashed(a)) and len(a.get_xdata(orig=False)) > 0]
    if not lower:
        return []
    size = (int(fig.bbox.width), int(fig.bbox.height))
    masks = {}

    def mask(i, opaque=True):
        if (i, opaque) not in masks:
            masks[i, opaque] = _artist_mask(arts[i], size, fig.dpi, opaque)
        return masks[i, opaque]

    out = []
    title = ax.get_title() + " " + (ax.get_legend().get_title().get_text()
                                     if ax.get_legend() else "")
    for i in lower:
        # a dotted or dashed line is seen by its dashes' cores: their antialiased fringe, a
        # third of a thin dotted line's pixels, is no part of it a reader could still see
        m = (_artist_mask(arts[i], size, fig.dpi, True, grow=False) if _dashed(arts[i])
             else mask(i, opaque=False))
        n = int(m.sum())
        if n == 0:
            x = np.asarray(arts[i].get_xdata(orig=False), float)
            if np.isfinite(x).any() and _label(arts[i]):
                out.append(f"{where}: the line '{_label(arts[i])}' draws nothing inside the axes")
            continue
        lab = _label(arts[i]) or ""
        cover = np.zeros_like(m)
        best, best_n = None, 0
        for j in range(i + 1, len(arts)):
            k = int((m & mask(j)).sum())
            if k:
                cover |= mask(j)
                if k > best_n:
                    best, best_n = j, k
        frac = (m & cover).sum() / n
        if frac >= _HIDDEN_FRACTION:
            up = _label(arts[best]) or "an unlabelled artist"
            if not _SAYS_COINCIDE.search(lab + " " + up + " " + title):
                what = f"the line '{lab}'" if lab else _describe(arts[i])
                out.append(f"{where}: {what} is hidden under '{up}' ({100 * frac:.0f} % of "
                           "its pixels covered): draw it apart, merge the two, or say they "
                           "coincide")
            continue
        if not _dashed(arts[i]):
            continue
        for j in range(i):         # a dotted line on a solid one of its colour, drawn before it
            if not (_solid(arts[j]) and _same_colour(arts[i], arts[j])):
                continue
            frac = (m & mask(j)).sum() / n
            if frac < _HIDDEN_FRACTION:
                continue
            under = _label(arts[j]) or "a solid line"
            if not _SAYS_COINCIDE.search(lab + " " + under + " " + title):
                out.append(f"{where}: {_describe(arts[i])} lies on the solid line '{under}' of "
                           f"its own colour ({100 * frac:.0f} % of its pixels): a reader sees "
                           "one line — draw it apart or say they coincide")
            break
    return out


#: A legend may lie over at most this fraction of its box's area of drawn lines, and over no
#: marker. A line of the book's width (1.5 pt, about 4 px at 150 dpi) crossing a legend covers
#: 3–5 % of its box; 0.25 % is such a line running under it for a few % of its width — more
#: than a corner it grazes (0.16 %, notebook 04), as much as the lines under the legend issue 38
#: found in notebook 01 (0.35 %).
LEGEND_OVER_LINES = 0.0025


def _legend_boxes(fig, renderer):
    """(legend, its box in display pixels, the axes it may cover) for every visible legend."""
    out = []
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is not None and leg.get_visible() and ax.get_visible():
            out.append((leg, leg.get_window_extent(renderer), [ax]))
    for leg in fig.legends:
        if leg.get_visible():
            out.append((leg, leg.get_window_extent(renderer), list(fig.axes)))
    return out


def _data_artists(ax):
    """What an axes draws as data: its lines and its line and point collections (not filled
    areas, images or grid lines)."""
    from matplotlib.collections import LineCollection, PathCollection
    from matplotlib.lines import Line2D

    return [a for a in ax.get_children() if a.get_visible()
            and (isinstance(a, Line2D) and len(a.get_xdata(orig=False)) > 0
                 or isinstance(a, (LineCollection, PathCollection)))]


def _points_in(box, xy, pad: float = 0.0) -> int:
    """How many points ``xy`` (display pixels) lie in ``box`` grown by ``pad`` pixels."""
    xy = np.asarray(xy, float).reshape(-1, 2)
    xy = xy[np.isfinite(xy).all(axis=1)]
    return int(((xy[:, 0] >= box.x0 - pad) & (xy[:, 0] <= box.x1 + pad)
                & (xy[:, 1] >= box.y0 - pad) & (xy[:, 1] <= box.y1 + pad)).sum())


def _legends_over_data(fig, renderer, tag) -> list[str]:
    """Legends whose box covers the data of their axes: more than :data:`LEGEND_OVER_LINES` of
    the box over drawn lines, or any marker (point) under it."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.collections import PathCollection
    from matplotlib.lines import Line2D

    out = []
    W, H = int(fig.bbox.width), int(fig.bbox.height)
    for leg, box, axes in _legend_boxes(fig, renderer):
        if box.width <= 0 or box.height <= 0:
            continue
        area = box.width * box.height
        for n, ax in ((fig.axes.index(a), a) for a in axes):
            if getattr(ax, "name", "") == "3d" or not ax.bbox.overlaps(box):
                continue
            arts = _data_artists(ax)
            if not arts:
                continue
            markers = 0
            r = RendererAgg(W, H, fig.dpi)
            for a in arts:
                a.draw(r)
                if isinstance(a, Line2D) and a.get_marker() not in (None, "None", "", " "):
                    xy = a.get_transform().transform(a.get_xydata())
                    inside = [p for p in xy if ax.bbox.contains(*p)] if a.get_clip_on() else xy
                    # half or more of the marker under the box
                    markers += _points_in(box, inside, a.get_markersize() * fig.dpi / 72 / 4)
                elif isinstance(a, PathCollection) and len(a.get_offsets()):
                    xy = a.get_offset_transform().transform(a.get_offsets())
                    markers += _points_in(box, xy)
            alpha = np.asarray(r.buffer_rgba())[:, :, 3]
            x0, x1 = max(int(box.x0), 0), min(int(np.ceil(box.x1)), W)
            y0, y1 = max(int(H - np.ceil(box.y1)), 0), min(int(H - box.y0), H)
            frac = float((alpha[y0:y1, x0:x1] > 20).sum()) / area
            if frac > LEGEND_OVER_LINES or markers:
                where = f"{tag}, axes {n + 1}" + (f" '{ax.get_title()}'" if ax.get_title() else "")
                what = "figure legend" if leg in fig.legends else "legend"
                over = f"{100 * frac:.1f} % of its box over lines"
                if markers:
                    over += f", {markers} marker{'s' * (markers > 1)} under it"
                out.append(f"{where}: the {what} covers data ({over}): move it (another loc, "
                           "or outside the axes: bbox_to_anchor, fig.legend(loc='outside …'))")
    return out


def _texts(fig, ax=None):
    """(what, Text) of everything written on a figure or one of its axes."""
    items = []
    if ax is None:
        if fig._suptitle is not None:
            items.append(("suptitle", fig._suptitle))
        items += [("figure text", t) for t in fig.texts if t is not fig._suptitle]
        for leg in fig.legends:
            items += [("legend", t) for t in leg.get_texts()] + [("legend title", leg.get_title())]
        return items
    items += [("title", ax.title), ("title", ax._left_title), ("title", ax._right_title),
              ("x label", ax.xaxis.label), ("y label", ax.yaxis.label)]
    items += [("text", t) for t in ax.texts]
    for axis, what in ((ax.xaxis, "x tick label"), (ax.yaxis, "y tick label")):
        items += [(what, t) for t in axis.get_ticklabels(which="both")]
    leg = ax.get_legend()
    if leg is not None:
        items += [("legend", t) for t in leg.get_texts()] + [("legend title", leg.get_title())]
    return [(w, t) for w, t in items if t.get_visible() and t.get_text().strip()]


def _words(i: str) -> str:
    return f"write {name(i)!r}" if name(i) != i else "write it in words: imunav.plotting.style.name"


def check_figure(fig) -> list[str]:
    """Every defect of ``fig`` that keeps a reader from trusting it at a glance, one line each
    (empty: the figure passes). See the module docstring for the rules."""
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    out = []
    num = getattr(fig, "number", None)
    tag = f"figure {num}" if num is not None else "figure"
    width = fig.get_tightbbox(renderer).width
    if width > MAX_WIDTH_IN + 0.05:
        out.append(f"{tag}: {width:.1f} in wide (at most {MAX_WIDTH_IN:g} in, the book's "
                   "column: wider figures are shrunk and their text with them)")
    if fig.dpi < MIN_DPI:
        out.append(f"{tag}: stored at {fig.dpi:g} dpi (at least {MIN_DPI}: "
                   "imunav.plotting.use_book_style())")
    small = {}
    for what, t in _texts(fig):
        if t.get_fontsize() < MIN_FONT_PT:
            small.setdefault(what, t.get_fontsize())
        for i in internal_ids_in(t.get_text()):
            out.append(f"{tag}: internal id {i!r} in the {what} {t.get_text()!r} ({_words(i)})")
    for leg in fig.legends:
        if len(leg.get_texts()) > MAX_LEGEND:
            out.append(f"{tag}: figure legend with {len(leg.get_texts())} entries "
                       f"(at most {MAX_LEGEND}: small multiples or a table)")
    fw, fh = fig.get_size_inches()
    for n, ax in enumerate(fig.axes):
        if not ax.get_visible() or not ax.axison and not ax.lines:
            continue
        where = f"{tag}, axes {n + 1}" + (f" '{ax.get_title()}'" if ax.get_title() else "")
        for what, t in _texts(fig, ax):
            if t.get_fontsize() < MIN_FONT_PT:
                small.setdefault(what, t.get_fontsize())
            for i in internal_ids_in(t.get_text()):
                out.append(f"{where}: internal id {i!r} in the {what} {t.get_text()!r} "
                           f"({_words(i)})")
        leg = ax.get_legend()
        if leg is not None and len(leg.get_texts()) > MAX_LEGEND:
            out.append(f"{where}: legend with {len(leg.get_texts())} entries (at most "
                       f"{MAX_LEGEND}: small multiples or a table)")
        units = {}
        u = units_in(ax.get_ylabel())
        if u:
            units[u] = f"y label '{ax.get_ylabel()}'"
        for a in ax.lines + ax.collections:
            lab = _label(a)
            u = lab and units_in(lab)
            if u:
                units.setdefault(u, f"'{lab}'")
        if len(units) > 1:
            out.append(f"{where}: {len(units)} units on one y axis: "
                       + ", ".join(f"{k} ({v})" for k, v in units.items())
                       + " — one quantity per axis (small multiples or a twin axis)")
        if getattr(ax, "name", "") == "3d":       # 2-D geometry does not apply to 3-D axes
            continue
        if not hasattr(ax, "_colorbar"):
            pos = ax.get_position()
            w, h = pos.width * fw, pos.height * fh
            if min(w, h) > 0 and max(w / h, h / w) > 10:
                out.append(f"{where}: a panel {w:.2g} × {h:.2g} in ({max(w / h, h / w):.0f}:1)")
        if not ax.get_autoscaley_on() and ax.lines:
            ys = []
            x0, x1 = sorted(ax.get_xlim())
            for ln in ax.lines:
                xy = np.asarray(ln.get_xydata(), float)
                if ln.get_transform() != ax.transData or not len(xy):
                    continue
                keep = np.isfinite(xy).all(axis=1) & (xy[:, 0] >= x0) & (xy[:, 0] <= x1)
                if keep.any():
                    ys.append(ax.transData.transform(xy[keep])[:, 1])
            if ys:
                y = np.concatenate(ys)
                b = ax.bbox
                lo, hi = np.clip([y.min(), y.max()], b.y0, b.y1)
                frac = (hi - lo) / b.height
                if frac < 1 / 3:
                    out.append(f"{where}: a fixed y range the data fill {100 * frac:.0f} % of "
                               "(let it autoscale, or set it to the data)")
        out += _hidden_lines(fig, ax, where)
    out += _legends_over_data(fig, renderer, tag)
    for what, size in small.items():
        out.append(f"{tag}: {what}s at {size:g} pt (at least {MIN_FONT_PT:g} pt on the page)")
    return out


def install_figure_check(mode: str = "raise") -> None:
    """Make ``matplotlib.pyplot.show`` run :func:`check_figure` on every open figure first:
    ``mode="raise"`` raises :class:`FigureCheckError` listing the defects (the figures are
    closed); ``"warn"`` prints them (``figure check: …`` lines on stderr) and shows the figures."""
    import sys

    import matplotlib.pyplot as plt

    if mode not in ("raise", "warn"):
        raise ValueError(f"mode must be 'raise' or 'warn', got {mode!r}")
    shown = getattr(plt.show, "_imunav_shown", plt.show)

    def show(*args, **kwargs):
        problems = []
        for num in plt.get_fignums():
            problems += check_figure(plt.figure(num))
        if problems and mode == "raise":
            plt.close("all")
            raise FigureCheckError("the figure check failed:\n  " + "\n  ".join(problems))
        for p in problems:
            print(f"figure check: {p}", file=sys.stderr)
        return shown(*args, **kwargs)

    show._imunav_shown = shown
    show.__doc__ = shown.__doc__
    plt.show = show



#: The groups of algorithms drawn together (no more than 8 a panel).
ALGORITHM_GROUPS = (
    ("rate samples", ("rates/first_order", "rates/exact_exponential", "rates/magnus4",
                      "rates/magnus6")),
    ("increments, classic", ("increments/first_order", "increments/exact_exponential",
                             "increments/coning2", "increments/ignagni2", "increments/miller3",
                             "increments/ignagni3", "increments/ignagni4")),
    ("increments, offline", ("increments/poly6_m4", "increments/poly8_m6")),
)


# ------------------------------------------------------------ the former name (issue 35)

#: Old names of this module: ``style``, the function :func:`thing_style` (it hid the module).
#: This module imports nothing of imunav, so it keeps its own deprecation here (the rest of
#: imunav declares its old names through ``imunav.core.deprecation``).
RENAMED = {"style": "imunav.plotting.style.thing_style"}
_WARNING = ("the function imunav.plotting.style.style is now thing_style (it shared the name of "
            "its module); style will stop working in imunav 0.3")


def __getattr__(name: str):
    if name == "style":
        warnings.warn(_WARNING, DeprecationWarning, stacklevel=2)
        return thing_style
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _CallableModule(types.ModuleType):
    """This module, callable as the function ``style`` it held: ``style("truth")``."""

    def __call__(self, thing: str, **kw) -> dict:
        warnings.warn(_WARNING, DeprecationWarning, stacklevel=2)
        return thing_style(thing, **kw)


sys.modules[__name__].__class__ = _CallableModule
