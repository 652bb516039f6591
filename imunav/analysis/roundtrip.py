"""Round trips: simulate ideal signals for a motion, navigate them back from the true initial
state, and measure the errors — one run, or every algorithm at several rates.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.analysis.metrics``.
"""

from __future__ import annotations

from dataclasses import dataclass

from imunav.analysis.metrics import NavErrors, fit_order, nav_errors
from imunav.core.deprecation import renamed
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.motion.base import BaseMotion
from imunav.motion.catalog import figure_eight
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown.registry import ALGORITHMS, navigate


def initial_state(motion: BaseMotion, signals: ImuSignals) -> tuple[FloatArray, FloatArray,
                                                                      FloatArray]:
    """The true initial state of ``motion`` at the signals' start time ``signals.t0``.

    Parameters
    ----------
    motion : BaseMotion
        The motion the signals were simulated from.
    signals : ImuSignals
        The signals (their :attr:`~imunav.sensors.signals.ImuSignals.t0`: the first sample
        for rates, the start of the first interval for increments).

    Returns
    -------
    q0 : ndarray, shape (4,)
        ``q_nb`` at ``t0``.
    v0 : ndarray, shape (3,)
        Velocity (m/s, NED).
    p0 : ndarray, shape (3,)
        Position (m, NED).

    Raises
    ------
    ImunavError
        If the motion cannot be evaluated at ``t0``.
    """
    return motion.states([signals.t0]).initial()


@dataclass
class RoundTrip:
    """One round trip: a motion, its ideal signals, their navigation and its errors.

    Attributes
    ----------
    motion : BaseMotion
        The truth.
    signals : ImuSignals
        The ideal signals simulated from it.
    nav : States
        Their navigation from the true initial state.
    errors : NavErrors
        ``nav`` against ``motion``.
    """

    motion: BaseMotion
    signals: ImuSignals
    nav: States
    errors: NavErrors


@renamed(output="kind")
def round_trip(motion: BaseMotion | None = None, rate: float = 100.0, kind: str = "increments",
               algorithm: str | None = None, duration: float | None = None) -> RoundTrip:
    """Simulate ideal signals for a motion and navigate them back from the true initial state.

    What is left is the algorithm's own error (and rounding): with ideal signals and the true
    initial state nothing else differs.

    Parameters
    ----------
    motion : BaseMotion, optional
        The motion; default the figure-eight of :func:`~imunav.motion.catalog.figure_eight`.
    rate : float, default 100.0
        Sample rate (Hz).
    kind : {"rates", "increments"}, default "increments"
        The signal kind.
    algorithm : str, optional
        A name from ``ALGORITHMS[output]``; default the most accurate.
    duration : float, optional
        Seconds; default the motion's own.

    Returns
    -------
    RoundTrip

    Raises
    ------
    ImunavError
        For the reasons of :func:`~imunav.sensors.simulate.simulate_imu` and
        :func:`~imunav.strapdown.registry.navigate` (an unknown ``kind`` or ``algorithm``,
        a ``rate`` or ``duration`` that is not a finite number > 0, …).

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> rt = round_trip(Motion(yaw="0.5*t", x="t**2", duration=2.0), rate=50)
    >>> rt.nav.algorithm, rt.errors.summary()["max_position"] < 1e-12
    ('poly8_m6', True)
    """
    motion = motion or figure_eight()
    sig = simulate_imu(motion, rate, duration, kind=kind)
    nav = navigate(sig, *initial_state(motion, sig), algorithm=algorithm)
    return RoundTrip(motion, sig, nav, nav_errors(nav, motion))


def error_table(motion: BaseMotion | None = None, rates=(50, 100, 200, 400),
                duration: float | None = None) -> list[dict]:
    """Maximum position and attitude error of every algorithm at several rates, with fitted
    orders.

    Every registered algorithm of both signal kinds makes one :func:`round_trip` per rate.

    Parameters
    ----------
    motion : BaseMotion, optional
        The motion; default the figure-eight.
    rates : sequence of float, default (50, 100, 200, 400)
        Sample rates (Hz).
    duration : float, optional
        Seconds; default the motion's own.

    Returns
    -------
    list of dict
        One row per algorithm: ``kind``, ``algorithm``, ``att_<rate>`` (rad) and
        ``pos_<rate>`` (m) for each rate, and ``order_att``, ``order_pos``: the fitted
        convergence orders over the rates whose errors are above rounding
        (:data:`FLOOR_ATT`, :data:`FLOOR_POS`), or None if fewer than three are.

    Raises
    ------
    ImunavError
        For the reasons of :func:`round_trip`.
    """
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
