"""The plot functions behind the notebooks and ``imunav reproduce`` (general ones; each paper
module draws its own figures), in the one figure style of :mod:`imunav.plotting.style` — re-exported
here, so ``from imunav.plotting import styled, use_book_style, check_figure`` works: one readable
name, one colour and line style per named thing in every figure (:func:`thing_style`), and the
figure check. ``imunav.plotting.style`` is that module (its function ``style``, which hid it, is
now ``thing_style``; the old call still works with a warning).

Each plot function takes computed results and an optional axes/figure, draws, and returns it;
nothing here computes what the analysis layer already does.

May import: anything in imunav but the papers and the faces; matplotlib (imported lazily).
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.montecarlo import MonteCarloResult
from imunav.analysis.roundtrip import RoundTrip, round_trip
from imunav.motion.base import BaseMotion
from imunav.plotting.style import (  # noqa: F401 — the style's API, re-exported
    ALGORITHM_GROUPS,
    BOOK_RC,
    DISTINCT,
    MAX_LEGEND,
    MAX_WIDTH_IN,
    MIN_DPI,
    MIN_FONT_PT,
    THINGS,
    WIDTH_IN,
    FigureCheckError,
    Thing,
    algorithm_id,
    check_figure,
    colour,
    figure,
    install_figure_check,
    internal_ids_in,
    name,
    rate_ticks,
    series_style,
    styled,
    thing_style,
    units_in,
    use_book_style,
)

# ------------------------------------------------------------ round trips

def _floor(x, lo=1e-16):
    return np.maximum(x, lo)


def plot_run(res: RoundTrip, fig=None):
    """Truth vs navigated trajectory (plan and height) and the position, velocity and attitude
    error norms vs time, one quantity per panel."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(WIDTH_IN, 4.8), layout="constrained")
    gs = fig.add_gridspec(2, 3)
    t = res.nav.t
    tp = res.motion.position(t)
    ax1 = fig.add_subplot(gs[0, :2])
    ax1.plot(tp[:, 1], tp[:, 0], **styled("truth", lw=3, alpha=0.35))
    ax1.plot(res.nav.position[:, 1], res.nav.position[:, 0], **styled("estimate", lw=1.2))
    ax1.set(xlabel="east y (m)", ylabel="north x (m)", title="plan view")
    ax1.set_aspect("equal", adjustable="datalim")
    ax1.legend(loc="upper right")
    ax2 = fig.add_subplot(gs[0, 2])
    ax2.plot(t, -tp[:, 2], **styled("truth", lw=3, alpha=0.35))
    ax2.plot(t, -res.nav.position[:, 2], **styled("estimate", lw=1.2))
    ax2.set(xlabel="t (s)", ylabel="height −z (m)", title="height")
    e = res.errors
    for k, (key, unit, scale) in enumerate((("position", "m", 1.0), ("velocity", "m/s", 1.0),
                                            ("attitude", "deg", 180 / np.pi))):
        ax = fig.add_subplot(gs[1, k])
        ax.semilogy(t[1:], _floor(getattr(e, key)[1:] * scale), color=colour("estimate"))
        ax.set(xlabel="t (s)", ylabel=f"{key} error ({unit})")
    kind = "rate samples" if res.signals.kind == "rates" else "increments"
    fig.suptitle(f"{name(algorithm_id(res.signals.kind, res.nav.algorithm))}, {kind} at "
                 f"{res.signals.rate:g} Hz")
    return fig


def _merge_identical(ids, series, rtol=0.05):
    """Group ids whose series agree to ``rtol`` at every point (on a log axis: the same line)."""
    groups: list[list[str]] = []
    for i in ids:
        for g in groups:
            a, b = np.asarray(series[g[0]], float), np.asarray(series[i], float)
            if np.allclose(a, b, rtol=rtol, atol=0):
                g.append(i)
                break
        else:
            groups.append([i])
    return groups


#: Length (pt) of each colour's stripe in a line drawn for several coinciding series.
STRIPE_PT = 5.0


def _striped_handle_class():
    """The legend handle of a group of coinciding series (a proxy that draws nothing in the
    axes) and its legend handler, which draws the group's colours as stripes of one line."""
    from matplotlib.legend import Legend
    from matplotlib.legend_handler import HandlerBase
    from matplotlib.lines import Line2D

    if getattr(_striped_handle_class, "done", None):
        return _striped_handle_class.done

    class Striped(Line2D):
        """Proxy: the colours (and line width) of a group of coinciding series."""

        def __init__(self, colours, lw, label):
            super().__init__([], [], lw=lw, label=label)
            self.colours = list(colours)

    class HandlerStriped(HandlerBase):
        def create_artists(self, legend, orig, xdescent, ydescent, width, height, fontsize,
                           trans):
            k, y = len(orig.colours), height / 2 - ydescent
            step = width / (2 * k)                     # each colour twice along the sample
            out = []
            for n in range(2 * k):
                x0 = n * step - xdescent
                seg = Line2D([x0, x0 + step], [y, y], color=orig.colours[n % k],
                             lw=orig.get_linewidth() + 0.8, solid_capstyle="butt")
                seg.set_transform(trans)
                out.append(seg)
            return out

    Legend.update_default_handler_map({Striped: HandlerStriped()})
    _striped_handle_class.done = Striped
    return Striped


def plot_coinciding(ax, x, series: dict, ids, labels: bool = True, marker: str | None = "o",
                    lw: float = 1.5, note: bool = True, note_loc: str = "best",
                    note_width: int = 34, note_kw: dict | None = None, **kw) -> dict:
    """Draw ``series[i]`` for each id in its colour. Where several coincide (to 5 % at every
    point: one line on a log axis) they are drawn as *one* striped line — each colour in turn
    along it, :data:`STRIPE_PT` long, no series wider than another — with each series' markers
    side by side at the shared points (offset by a few points on the page, not in the data).

    Parameters
    ----------
    ax : Axes
    x : array_like
    series : dict of id to array_like
    ids : list of str
        Named things (:func:`name`, :func:`colour`), in drawing order.
    labels : bool
        Give each series its name as a legend label.
    marker : str or None
    lw : float
    note : bool
        For each group that coincides, a legend entry drawn as the striped line and labelled
        "coincide: …" (a legend of these entries alone is drawn on ``ax``; a later
        ``ax.legend()`` includes them with the series).
    note_loc : str
        Where that legend goes (``loc`` of ``ax.legend``).
    note_width : int
        Characters per line of the "coincide: …" label (it is wrapped).
    note_kw : dict, optional
        More keywords of that legend (e.g. ``bbox_to_anchor`` to put it beside the axes).
    **kw
        Passed to ``ax.plot``.

    Returns
    -------
    dict
        ``{"artists": {id: the labelled Line2D}, "groups": [[id, …], …]}`` (groups of two or
        more that coincide).
    """
    import textwrap

    from matplotlib.transforms import offset_copy

    ms = kw.pop("ms", 3.5)
    artists, groups, notes = {}, [], []
    for g in _merge_identical(ids, series):
        k = len(g)
        if k == 1:
            i = g[0]
            artists[i], = ax.plot(x, series[i], "-", marker=marker, lw=lw, ms=ms,
                                  color=colour(i), label=name(i) if labels else "_" + i, **kw)
            continue
        groups.append(g)
        period = STRIPE_PT * k / lw                    # dash lengths are in line widths
        for j, i in enumerate(g):
            ax.plot(x, series[i], color=colour(i), lw=lw, solid_capstyle="butt",
                    dash_capstyle="butt", label="_" + i,
                    linestyle=(((k - j) % k) * STRIPE_PT / lw,
                               (STRIPE_PT / lw, period - STRIPE_PT / lw)), **kw)
            if marker:
                dx = (j - (k - 1) / 2) * (ms + 0.6)    # points: the markers side by side
                ax.plot(x, series[i], ls="none", marker=marker, ms=ms, color=colour(i),
                        label="_" + i + " markers",
                        transform=offset_copy(ax.transData, fig=ax.figure, x=dx, units="points"))
            # the legend entry of the series: its colour and marker, drawn nowhere in the axes
            artists[i], = ax.plot([], [], "-", marker=marker, lw=lw, ms=ms, color=colour(i),
                                  label=name(i) if labels else "_" + i)
        if note:
            Striped = _striped_handle_class()
            proxy = Striped([colour(i) for i in g], lw,     # wrapped: a legend beside the axes
                            textwrap.fill("coincide: " + ", ".join(name(i) for i in g), note_width,
                                          subsequent_indent="  "))
            ax.add_line(proxy)
            notes.append(proxy)
    if notes:
        ax.legend(handles=notes, loc=note_loc, fontsize=8, **(note_kw or {}))
    return {"artists": artists, "groups": groups}


def plot_error_vs_rate(rows: list[dict], rates=(50, 100, 200, 400), fig=None,
                       floors=(1e-10, 1e-11)):
    """Maximum position (left) and attitude (right) error vs rate, log–log, one row per group of
    :data:`ALGORITHM_GROUPS`. Algorithms whose errors coincide are drawn as one striped line
    with a legend entry that names them; values below ``floors`` (m, deg: rounding) are drawn
    on the floor (dotted, shown in panels with a value near it)."""
    import matplotlib.pyplot as plt

    by_id = {algorithm_id(r["kind"], r["algorithm"]): r for r in rows}
    groups = [(title, [i for i in ids if i in by_id]) for title, ids in ALGORITHM_GROUPS]
    groups = [(title, ids) for title, ids in groups if ids]
    fig = fig or plt.figure(figsize=(MAX_WIDTH_IN, 0.9 + 2.3 * len(groups)), layout="constrained")
    axs = fig.subplots(len(groups), 2, sharex=True, squeeze=False)
    striped = False
    for row, (title, ids) in enumerate(groups):
        for col, (key, what, unit, scale, floor) in enumerate(
                (("pos", "position", "m", 1.0, floors[0]),
                 ("att", "attitude", "deg", 180 / np.pi, floors[1]))):
            ax = axs[row, col]
            series = {i: [max(by_id[i][f"{key}_{r}"] * scale, floor) for r in rates] for i in ids}
            last = row == len(groups) - 1         # the left column's note under its panel
            striped |= bool(plot_coinciding(
                            ax, rates, series, ids, labels=col == 1,   # (no tick labels there)
                            note_loc="lower left" if col or last else "upper left",
                            note_width=34 if col else 40,
                            note_kw=None if col or last else
                            {"bbox_to_anchor": (-0.35, -0.02), "frameon": False})["groups"])
            ax.set_xscale("log")
            ax.set_yscale("log")
            if min(min(v) for v in series.values()) <= 10 * floor:
                ax.axhline(floor, color="0.5", lw=0.8, ls=":")
            rate_ticks(ax, rates)
            ax.set(ylabel=f"max {what} error ({unit})")
            ax.set_title(title if col == 0 else "", loc="left")
            if row == len(groups) - 1:
                ax.set_xlabel("sample rate (Hz)")
        axs[row, 1].legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize=8)
    fig.suptitle("dotted: the rounding floor (errors below it are drawn on it)" + (
        "; a striped line is several that coincide,\ntheir markers side by side around the "
        "rate they belong to (shifted on the page, not in the data)" if striped else ""),
        fontsize=8.5)
    return fig


# ------------------------------------------------------------ algorithm family

_QUANTITY = {"attitude": ("attitude", "deg", 180 / np.pi), "velocity": ("velocity", "m/s", 1.0),
             "position": ("position", "m", 1.0)}


def plot_error_vs_time(motion: BaseMotion, rate: float, names, duration: float | None = None,
                       ax=None, quantity: str = "attitude"):
    """Error norm (log scale) vs time for ``names`` = [(kind, algorithm), …] (at most 8);
    ``quantity`` is ``"attitude"`` (deg), ``"velocity"`` (m/s) or ``"position"`` (m).
    Algorithms whose errors coincide are drawn as one striped line, named in a legend entry
    (:func:`plot_coinciding`)."""
    import matplotlib.pyplot as plt

    key, unit, scale = _QUANTITY[quantity]
    ax = ax or plt.figure(figsize=(WIDTH_IN, 3.4), layout="constrained").add_subplot()
    ids, series, t = [], {}, None
    for kind, alg in names:
        e = round_trip(motion, rate, kind, alg, duration).errors
        i = algorithm_id(kind, alg)
        ids.append(i)
        series[i], t = _floor(getattr(e, key)[1:] * scale), e.t[1:]
    plot_coinciding(ax, t, series, ids, marker=None, lw=1.3)
    ax.set_yscale("log")
    ax.set(xlabel="t (s)", ylabel=f"{key} error ({unit})",
           title=f"{getattr(motion, 'name', 'motion')}, sampled at {rate:g} Hz")
    return ax


def plot_convergence(rows: list[dict], ax=None, key: str = "max_att_rad"):
    """Log–log maximum error vs rate (at most 8 algorithms), each labelled with its measured
    and (in parentheses) documented order, and the documented slope drawn dotted from its first
    point where the two differ by more than :data:`DOCUMENTED_APART`; coinciding series are
    drawn as one striped line, named in a legend entry (:func:`plot_coinciding`)."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(WIDTH_IN, 3.6), layout="constrained").add_subplot()
    scale = 180 / np.pi if key == "max_att_rad" else 1.0
    ids = [algorithm_id(r["kind"], r["algorithm"]) for r in rows]
    by = dict(zip(ids, rows, strict=True))
    series = {i: list(np.asarray(by[i][key]) * scale) for i in ids}
    x = np.asarray(rows[0]["rates"], float)
    drawn = plot_coinciding(ax, x, series, ids)
    okey, k = {"max_att_rad": ("order_att", 0), "max_vel": ("order_vel", 1),
               "max_pos": ("order_pos", 2)}[key]
    dotted, drawn_slopes = False, set()
    group_of = {i: tuple(g) for g in drawn["groups"] for i in g}
    for i, line in drawn["artists"].items():
        meas, doc = by[i][okey], by[i]["documented"][k]
        line.set_label(f"{name(i)}: {meas:.1f} ({doc})")
        if abs(meas - doc) > DOCUMENTED_APART:       # a dotted line on its own curve is hidden
            if (group_of.get(i, i), doc) in drawn_slopes:
                continue                            # coinciding series: one slope line is enough
            drawn_slopes.add((group_of.get(i, i), doc))
            e = np.asarray(series[i])
            ax.plot(x, e[0] * (x / x[0]) ** (-doc), ":", color=colour(i), lw=1)
            dotted = True
    ax.set(xscale="log", yscale="log", xlabel="sample rate (Hz)",
           ylabel={"max_att_rad": "max attitude error (deg)", "max_vel": "max velocity error (m/s)",
                   "max_pos": "max position error (m)"}[key])
    rate_ticks(ax, x)
    ax.legend(title="measured order (documented)" + (
        "\ndotted: the documented slope, where it differs" if dotted else "")
        + ("\nstriped: series that coincide, markers\nside by side (shifted on the page)"
           if drawn["groups"] else ""))
    return ax


#: A measured order this far from the documented one gets the documented slope drawn dotted
#: beside it; closer, the dotted line would lie on the measured one (the figure check's
#: "hidden" line) and the legend's numbers say it.
DOCUMENTED_APART = 0.2


# ------------------------------------------------------------ Monte Carlo

def plot_envelope(mc: MonteCarloResult, tolerance: float | None = None, ax=None, label=None,
                  thing: str | None = None):
    """The median, 68th and 95th percentiles of the position error vs time (lines; one colour,
    that of ``thing`` — the IMU preset, by default ``mc.model`` when it is one)."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(WIDTH_IN, 3.4), layout="constrained").add_subplot()
    env = mc.envelope()
    lab = label or name(mc.model)
    thing = thing or (mc.model if mc.model in THINGS else "montecarlo")
    c = colour(thing)
    ax.plot(mc.t, env[95], color=c, lw=2, label=f"{lab}: 95th percentile")
    ax.plot(mc.t, env[68], color=c, lw=1.3, ls="--", label=f"{lab}: 68th percentile")
    ax.plot(mc.t, env[50], color=c, lw=1, ls=":", label=f"{lab}: median")
    if tolerance and not any(ln.get_label() == "tolerance" for ln in ax.lines):
        ax.axhline(tolerance, **styled("tolerance", lw=1))
    ax.set(xlabel="t (s)", ylabel="position error (m)", title=f"{mc.runs} runs at {mc.rate:g} Hz")
    return ax


def plot_verdict(r: dict, cov=None, ax=None, top: int = 5, log: bool = False,
                 legend: bool = True):
    """The 95th-percentile position envelope of a verdict (either method) against its
    tolerance; with the :class:`~imunav.analysis.covariance.CovarianceResult` ``cov``, also the
    ``top`` largest terms alone (at most 5: their 95th percentiles, thin lines in each term's
    colour — they do not add up, the variances do)."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(WIDTH_IN, 3.6), layout="constrained").add_subplot()
    env = r["envelope"]
    t, p95 = np.asarray(env["t"]), np.asarray(env["position_p95_m"])
    ok = r["suitable"]
    ax.plot(t, p95, color="black", lw=4, alpha=0.4, label="all terms together")
    ax.axhline(r["tolerance_m"], **styled("tolerance", lw=1))
    if r["time_p95_exceeds_s"] is not None:
        ax.axvline(r["time_p95_exceeds_s"], color="black", ls=":", lw=1,
                   label="crosses the tolerance")
    if cov is not None:
        idx = np.searchsorted(cov.t, t - 1e-9)
        for term in list(r["error_budget"])[:min(top, 5)]:
            ax.plot(t, cov.position_quantile(0.95, term=term, index=idx), lw=1.2,
                    **styled(term))
    ax.set(xlabel="t (s)", ylabel="position error, 95th percentile (m)",
           title=f"{name(r['imu'])} on {r['motion']} at {r['rate_hz']:g} Hz: "
                 f"{'suitable' if ok else 'not suitable'}")
    if log:
        ax.set_yscale("log")
        ax.set_ylim(bottom=1e-3 * min(r["tolerance_m"], max(p95.max(), 1e-300)))
    if legend:                       # beside the axes: the curves fill the upper left
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    return ax


# ------------------------------------------------------------ Allan deviation

def plot_allan(fits: dict, fig=None):
    """Allan deviation of the three axes (the band they span) and the fitted model (black), gyro
    and accelerometer side by side; each identified term as its IEEE 952 asymptote (dashed: N/√τ, the floor B,
    K√(τ/3)) over the τ range where it dominates (shaded)."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(WIDTH_IN, 3.2), layout="constrained")
    shapes = {"noise_density": lambda v, t: v / np.sqrt(t),
              "bias_instability": lambda v, t: np.full_like(t, v),
              "random_walk": lambda v, t: v * np.sqrt(t / 3)}
    for n, (triad, fit) in enumerate(fits.items()):
        ax = fig.add_subplot(1, len(fits), n + 1)
        taus = fit["taus"]
        a = fit["adev_axes"]
        ax.loglog(taus, fit["model"], "k-", lw=1.2, label="fitted model")
        ax.fill_between(taus, a.min(axis=1), a.max(axis=1), color="0.55", alpha=0.45, lw=0,
                        label="x, y, z axes (their spread)")
        k = np.unique(np.geomspace(1, len(taus), 24).astype(int) - 1)   # dots, not a line
        ax.loglog(taus[k], a.mean(axis=1)[k], "o", ms=3, color="0.35", zorder=3,
                  label="mean of the axes")
        for term, val in fit["terms"].items():
            if val["value"] is None:
                continue
            ax.loglog(taus, shapes[term](val["value"], taus), "--", lw=1, color=colour(term))
            ax.axvspan(*val["tau_range"], color=colour(term), alpha=0.1, label=name(term))
        unit = "rad/s" if triad == "gyro" else "m/s²"
        lo, hi = fit["adev_axes"].min(), fit["adev_axes"].max()
        ax.set(xlabel="τ (s)", ylabel=f"Allan deviation ({unit})",
               title="gyro" if triad == "gyro" else "accelerometer", ylim=(lo / 2, hi * 2))
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    handles = {}                  # one key for both panels, under them: inside, it covered dots
    for ax in fig.axes:
        handles.update(zip(*reversed(ax.get_legend_handles_labels()), strict=True))
    fig.legend(list(handles.values()), list(handles), fontsize=8, loc="outside lower center",
               ncols=3)
    return fig


# ------------------------------------------------------------ animations

#: matplotlib's player buttons use Font Awesome from a CDN; these characters need no font
#: beyond the common ones (media symbols such as ⏸ are missing from many).
_PLAYER_ICONS = {"fa fa-minus": "−", "fa fa-fast-backward": "◀◀", "fa fa-step-backward": "◀|",
                 "fa fa-play fa-flip-horizontal": "◀", "fa fa-pause": "||", "fa fa-play": "▶",
                 "fa fa-step-forward": "|▶", "fa fa-fast-forward": "▶▶", "fa fa-plus": "+"}


def offline_jshtml(anim) -> str:
    """``anim.to_jshtml()`` without the Font Awesome stylesheet matplotlib links from a CDN
    (which an offline reader, or the book, cannot load): the player's icons become plain
    characters. Show it with ``IPython.display.HTML``."""
    import re

    html = anim.to_jshtml()
    html = re.sub(r'<link rel="stylesheet"\s+href="https?://[^"]*font-awesome[^"]*">', "", html)
    for cls, char in _PLAYER_ICONS.items():
        html = html.replace(f'<i class="{cls}"></i>', char)
    if "http://" in html or "https://" in html:
        raise RuntimeError("the animation HTML still links an online resource")
    return html
