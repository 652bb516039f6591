"""Plot functions behind the notebooks and ``imunav reproduce`` (general ones; each paper module
draws its own figures). Each takes computed results and an optional axes/figure, draws, and
returns it; nothing here computes what the analysis layer already does.

May import: anything in imunav but the papers and the faces; matplotlib (imported lazily).
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.montecarlo import MonteCarloResult
from imunav.analysis.roundtrip import RoundTrip, round_trip
from imunav.motion.base import BaseMotion

#: Up to 20 colours no two alike: matplotlib's ten, then ten more of clearly other hues.
DISTINCT = ("C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9", "black", "gold",
            "lime", "navy", "magenta", "teal", "salmon", "olive", "maroon", "slateblue")


def series_style(i: int) -> dict:
    """Colour and marker for the ``i``-th point series of one axes (colours unique up to 20
    series, then the marker shape changes). For dense curves use only ``["color"]``."""
    return {"color": DISTINCT[i % len(DISTINCT)],
            "marker": ("o", "s", "^", "D")[(i // len(DISTINCT)) % 4]}


def rate_ticks(ax, rates) -> None:
    """Label a log x axis at the sample rates themselves (no overlapping minor labels)."""
    ax.set_xticks(list(rates), [f"{r:g}" for r in rates])
    ax.minorticks_off()


# ------------------------------------------------------------ round trips

def plot_run(res: RoundTrip, fig=None):
    """Truth vs restored trajectory (plan and height) and the errors vs time."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(11, 7))
    t = res.nav.t
    tp = res.motion.position(t)
    ax1 = fig.add_subplot(2, 2, 1)
    ax1.plot(tp[:, 1], tp[:, 0], "k-", lw=3, alpha=0.35, label="truth")
    ax1.plot(res.nav.position[:, 1], res.nav.position[:, 0], "C3--", lw=1.2, label="restored")
    ax1.set(xlabel="east y (m)", ylabel="north x (m)", title="plan view")
    ax1.set_aspect("equal", adjustable="datalim")
    ax1.legend()
    ax2 = fig.add_subplot(2, 2, 2)
    ax2.plot(t, -tp[:, 2], "k-", lw=3, alpha=0.35, label="truth")
    ax2.plot(t, -res.nav.position[:, 2], "C3--", lw=1.2, label="restored")
    ax2.set(xlabel="t (s)", ylabel="height −z (m)", title="height")
    ax2.legend()
    e = res.errors
    ax3 = fig.add_subplot(2, 2, 3)
    ax3.semilogy(t[1:], np.maximum(e.position[1:], 1e-16), label="position (m)")
    ax3.semilogy(t[1:], np.maximum(e.velocity[1:], 1e-16), label="velocity (m/s)")
    ax3.set(xlabel="t (s)", title="error norm")
    ax3.legend()
    ax4 = fig.add_subplot(2, 2, 4)
    ax4.semilogy(t[1:], np.maximum(np.degrees(e.attitude[1:]), 1e-16))
    ax4.set(xlabel="t (s)", ylabel="deg", title="attitude error angle")
    fig.suptitle(f"{res.signals.kind} at {res.signals.rate:g} Hz, algorithm {res.nav.algorithm}")
    fig.tight_layout()
    return fig


def plot_error_vs_rate(rows: list[dict], rates=(50, 100, 200, 400), fig=None):
    """Log–log maximum position and attitude error vs rate for every algorithm."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(13, 4.6))
    axp = fig.add_subplot(1, 2, 1)
    axa = fig.add_subplot(1, 2, 2)
    for i, row in enumerate(rows):
        lab = f"{row['kind']}/{row['algorithm']}"
        ls = "-" if row["kind"] == "increments" else "--"
        op = "—" if row["order_pos"] is None else f"{row['order_pos']:.1f}"
        oa = "—" if row["order_att"] is None else f"{row['order_att']:.1f}"
        st = series_style(i)
        axp.loglog(rates, [row[f"pos_{r}"] for r in rates], ls, ms=4, **st)
        axa.loglog(rates, [np.degrees(row[f"att_{r}"]) for r in rates], ls, ms=4, **st,
                   label=f"{lab} (order {op} / {oa})")
    axp.set(xlabel="sample rate (Hz)", ylabel="max position error (m)")
    axa.set(xlabel="sample rate (Hz)", ylabel="max attitude error (deg)")
    for ax in (axp, axa):
        rate_ticks(ax, rates)
    axa.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0),
               title="signals/algorithm (order pos / att)", title_fontsize=7)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------ algorithm family

def plot_error_vs_time(motion: BaseMotion, rate: float, names, duration: float | None = None,
                       ax=None):
    """Attitude error (deg, log scale) vs time for ``names`` = [(kind, algorithm), …]."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(10, 4)).add_subplot()
    for i, (kind, name) in enumerate(names):
        e = round_trip(motion, rate, kind, name, duration).errors
        ax.semilogy(e.t[1:], np.maximum(np.degrees(e.attitude[1:]), 1e-16),
                    color=series_style(i)["color"], label=f"{kind}/{name}")
    ax.set(xlabel="t (s)", ylabel="attitude error (deg)",
           title=f"{getattr(motion, 'name', 'motion')} at {rate:g} Hz")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


def plot_convergence(rows: list[dict], ax=None, key: str = "max_att_rad"):
    """Log–log maximum error vs rate with a dotted reference line of each documented order."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(7, 5)).add_subplot()
    for i, r in enumerate(rows):
        rates = np.asarray(r["rates"], float)
        e = np.asarray(r[key])
        if key == "max_att_rad":
            e = np.degrees(e)
        line, = ax.loglog(rates, e, "-", ms=4, **series_style(i),
                          label=f"{r['kind']}/{r['algorithm']} ({r['order_att']:.1f})")
        p = r["documented"][0]
        ax.loglog(rates, e[0] * (rates / rates[0]) ** (-p), ":", color=line.get_color(), lw=1)
    ax.set(xlabel="sample rate (Hz)", ylabel="max attitude error (deg)",
           title="convergence (dotted: documented order)")
    rate_ticks(ax, sorted({float(x) for r in rows for x in r["rates"]}))
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


# ------------------------------------------------------------ Monte Carlo

def plot_envelope(mc: MonteCarloResult, tolerance: float | None = None, ax=None, label=None):
    """Median, 68 % and 95 % envelopes of the position error vs time."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(8, 4)).add_subplot()
    env = mc.envelope()
    lab = label or mc.model
    ax.fill_between(mc.t, 0, env[95], alpha=0.2, label=f"{lab}: 95 %")
    ax.fill_between(mc.t, 0, env[68], alpha=0.3, label=f"{lab}: 68 %")
    ax.plot(mc.t, env[50], lw=1.5, label=f"{lab}: median")
    if tolerance:
        ax.axhline(tolerance, color="k", ls="--", lw=1, label="tolerance")
    ax.set(xlabel="t (s)", ylabel="position error (m)", title=f"{mc.runs} runs at {mc.rate:g} Hz")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


def plot_verdict(r: dict, cov=None, ax=None, top: int = 6, log: bool = False):
    """The 95th-percentile position envelope of a verdict (either method) against its
    tolerance; with the :class:`~imunav.analysis.covariance.CovarianceResult` ``cov``, also the
    ``top`` largest terms alone (their 95th percentiles, thin lines: they do not add up — the
    variances do)."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(9, 4)).add_subplot()
    env = r["envelope"]
    t, p95 = np.asarray(env["t"]), np.asarray(env["position_p95_m"])
    ok = r["suitable"]
    ax.fill_between(t, 0, p95, color="C2" if ok else "C3", alpha=0.25,
                    label=f"all terms, 95 % ({r['method']})")
    ax.plot(t, p95, color="C2" if ok else "C3", lw=2)
    ax.axhline(r["tolerance_m"], color="k", ls="--", lw=1, label="tolerance")
    if r["time_p95_exceeds_s"] is not None:
        ax.axvline(r["time_p95_exceeds_s"], color="C3", ls=":", lw=1,
                   label=f"crosses at {r['time_p95_exceeds_s']:.1f} s")
    if cov is not None:
        idx = np.searchsorted(cov.t, t - 1e-9)
        for j, name in enumerate(list(r["error_budget"])[:min(top, 6)]):   # C4…C9: unused above
            ax.plot(t, cov.position_quantile(0.95, term=name, index=idx), lw=1,
                    color=f"C{4 + j}", label=name)
    ax.set(xlabel="t (s)", ylabel="position error, 95th pct (m)",
           title=f"{r['imu']} on {r['motion']} at {r['rate_hz']:g} Hz: "
                 f"{'SUITABLE' if ok else 'NOT SUITABLE'}")
    if log:
        ax.set_yscale("log")
        ax.set_ylim(bottom=1e-3 * min(r["tolerance_m"], max(p95.max(), 1e-300)))
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


# ------------------------------------------------------------ Allan deviation

def plot_allan(fits: dict, fig=None):
    """Allan deviation of each axis (dots) and the fitted model (black), gyro and accelerometer
    side by side; each identified term as its IEEE 952 asymptote (dashed: N/√τ, the floor B,
    K√(τ/3)) over the τ range where it dominates (shaded)."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(11, 4.2))
    colours = {"noise_density": "C0", "bias_instability": "C2", "random_walk": "C3"}
    shapes = {"noise_density": lambda v, t: v / np.sqrt(t),
              "bias_instability": lambda v, t: np.full_like(t, v),
              "random_walk": lambda v, t: v * np.sqrt(t / 3)}
    for n, (triad, fit) in enumerate(fits.items()):
        ax = fig.add_subplot(1, len(fits), n + 1)
        taus = fit["taus"]
        for j, c in enumerate("xyz"):
            ax.loglog(taus, fit["adev_axes"][:, j], ".", ms=3, alpha=0.6,
                      color=("0.45", "C1", "C9")[j], label=f"axis {c}")
        ax.loglog(taus, fit["model"], "k-", lw=1.5, label="fitted model")
        for name, term in fit["terms"].items():
            if term["value"] is None:
                continue
            ax.loglog(taus, shapes[name](term["value"], taus), "--", lw=1,
                      color=colours[name])
            ax.axvspan(*term["tau_range"], color=colours[name], alpha=0.1,
                       label=name.replace("_", " "))
        unit = "rad/s" if triad == "gyro" else "m/s²"
        lo, hi = fit["adev_axes"].min(), fit["adev_axes"].max()
        ax.set(xlabel="τ (s)", ylabel=f"Allan deviation ({unit})", title=triad,
               ylim=(lo / 2, hi * 2))
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    fig.axes[-1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.02, 0.5))
    fig.tight_layout()
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
