"""Round trips: simulate ideal signals for a motion, navigate them back from the true initial
state, and measure the errors — one run, or every algorithm at several rates.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.analysis.metrics``.
"""

from __future__ import annotations

from dataclasses import dataclass

from imunav.analysis.metrics import NavErrors, fit_order, nav_errors
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.motion.base import BaseMotion
from imunav.motion.catalog import figure_eight
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown.registry import ALGORITHMS, navigate


def initial_state(motion: BaseMotion, signals: ImuSignals) -> tuple[FloatArray, FloatArray,
                                                                      FloatArray]:
    """The true ``(q0, v0, p0)`` of ``motion`` at the signals' start time ``signals.t0``."""
    return motion.states([signals.t0]).initial()


@dataclass
class RoundTrip:
    motion: BaseMotion
    signals: ImuSignals
    nav: States
    errors: NavErrors


def round_trip(motion: BaseMotion | None = None, rate: float = 100.0, output: str = "increments",
               algorithm: str | None = None, duration: float | None = None) -> RoundTrip:
    """Simulate ideal signals for ``motion`` (default: the figure-eight) and navigate them back
    from the true initial state."""
    motion = motion or figure_eight()
    sig = simulate_imu(motion, rate, duration, output=output)
    nav = navigate(sig, *initial_state(motion, sig), algorithm=algorithm)
    return RoundTrip(motion, sig, nav, nav_errors(nav, motion))


def error_table(motion: BaseMotion | None = None, rates=(50, 100, 200, 400),
                duration: float | None = None) -> list[dict]:
    """Maximum position / attitude error of every algorithm at several rates, with fitted
    orders."""
    motion = motion or figure_eight()
    rows = []
    for kind, table in ALGORITHMS.items():
        for name in table:
            errs = [round_trip(motion, r, kind, name, duration).errors.summary() for r in rates]
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
