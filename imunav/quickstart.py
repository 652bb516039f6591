"""Compute and plot functions behind ``notebooks/00_quickstart.ipynb`` and its figures."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.assess import NavErrors, fit_order, nav_errors
from imunav.motion import BaseMotion, Motion
from imunav.simulate import ImuSignals, simulate_imu
from imunav.strapdown import ALGORITHMS, NavResult, navigate


def quickstart_motion() -> Motion:
    """A 20 s motion that moves along all three axes and turns about all three.

    Position (m): a horizontal figure-eight that climbs; attitude (rad): yaw, pitch and
    roll oscillate at different frequencies.
    """
    return Motion(
        x="10*sin(0.3*t)", y="5*sin(0.6*t)", z="-0.05*t**2",
        yaw="0.8*sin(0.25*t) + 0.1*t", pitch="0.3*sin(0.7*t)", roll="0.5*sin(1.1*t)",
        duration=20.0, name="quickstart",
    )


@dataclass
class QuickstartRun:
    motion: BaseMotion
    signals: ImuSignals
    nav: NavResult
    errors: NavErrors


def run(motion: BaseMotion | None = None, rate: float = 100.0, output: str = "increments",
        algorithm: str | None = None, duration: float | None = None) -> QuickstartRun:
    """Simulate ideal signals for ``motion`` and navigate them back from the true initial state."""
    motion = motion or quickstart_motion()
    sig = simulate_imu(motion, rate, duration, output=output)
    t0 = sig.t[0] if output == "rates" else sig.t[0] - sig.dt
    tt = np.array([t0])
    nav = navigate(sig, motion.attitude(tt)[0], motion.velocity(tt)[0], motion.position(tt)[0],
                   algorithm=algorithm)
    return QuickstartRun(motion, sig, nav, nav_errors(nav, motion))


def error_table(motion: BaseMotion | None = None, rates=(50, 100, 200, 400),
                duration: float | None = None) -> list[dict]:
    """Final position / attitude error of every algorithm at several rates, with fitted orders."""
    motion = motion or quickstart_motion()
    rows = []
    for kind, table in ALGORITHMS.items():
        for name in table:
            errs = [run(motion, r, kind, name, duration).errors.summary() for r in rates]
            row = {"kind": kind, "algorithm": name}
            for r, e in zip(rates, errs, strict=True):
                row[f"att_{r}"] = e["max_attitude"]
                row[f"pos_{r}"] = e["max_position"]
            row["order_att"] = _order(rates, [e["max_attitude"] for e in errs], FLOOR_ATT)
            row["order_pos"] = _order(rates, [e["max_position"] for e in errs], FLOOR_POS)
            rows.append(row)
    return rows


#: Errors below these are rounding, not truncation, on the quickstart motion (20 s, |r| ≈ 20 m):
#: they are not used to fit an order. Attitude in rad, position in m.
FLOOR_ATT, FLOOR_POS = 1e-13, 1e-10


def _order(rates, errs, floor) -> float | None:
    """Fitted order over the rates whose error is above ``floor`` (None if < 3 remain)."""
    keep = [(r, e) for r, e in zip(rates, errs, strict=True) if e > floor]
    if len(keep) < 3:
        return None
    return fit_order([1 / r for r, _ in keep], [e for _, e in keep])


def plot_run(res: QuickstartRun, fig=None):
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

    fig = fig or plt.figure(figsize=(11, 4))
    axp = fig.add_subplot(1, 2, 1)
    axa = fig.add_subplot(1, 2, 2)
    for row in rows:
        lab = f"{row['kind']}/{row['algorithm']}"
        ls = "-" if row["kind"] == "increments" else "--"
        op = "—" if row["order_pos"] is None else f"{row['order_pos']:.1f}"
        oa = "—" if row["order_att"] is None else f"{row['order_att']:.1f}"
        axp.loglog(rates, [row[f"pos_{r}"] for r in rates], ls, marker="o",
                   label=f"{lab} (order {op})")
        axa.loglog(rates, [np.degrees(row[f"att_{r}"]) for r in rates], ls, marker="o",
                   label=f"{lab} (order {oa})")
    axp.set(xlabel="sample rate (Hz)", ylabel="max position error (m)")
    axa.set(xlabel="sample rate (Hz)", ylabel="max attitude error (deg)")
    axp.legend(fontsize=7)
    axa.legend(fontsize=7)
    fig.tight_layout()
    return fig
