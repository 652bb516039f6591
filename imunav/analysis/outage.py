"""How long an outage can it bridge? The longest GNSS outage an IMU bridges with its aids.

:func:`find_outage` answers by the covariance analysis of the filter along the true motion: the
longest GNSS outage (placed where it hurts most, or at a given start) whose 95th-percentile
position error stays within the tolerance — one covariance pass evaluates many outage
placements side by side (an outage is, until the fix after it, the scenario "GNSS lost for good
at its start"). :func:`bridgeable_outages` tabulates the answer for every IMU preset.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis``.
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.aided_assessment import (
    P95,
    active_fixes,
    aided_covariance,
    aided_span,
    gnss_times,
    outage_budget,
)
from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.gaussnorm import eigenvalues, norm_cdf, norm_quantile, tabulated_quantile_bounds
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DP
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS

__all__ = ["bridgeable_outages", "check_start", "exceeds", "find_outage", "lost_from"]


def check_start(tg: FloatArray, start: float, end: float, dt: float) -> None:
    """Refuse an outage start outside ``[0, end)``, or one that leaves no room for an outage of
    one GNSS interval before the record's ``end`` and a fix after it (the search would report
    0 s as "the rest of the motion")."""
    if not 0 <= start < end:
        raise ImunavError(f"outage_start must be in [0, {end:g}) s, got {start:g}",
                          argument="outage_start")
    if start > end - dt + 1e-9 or not np.any(tg > start + 1e-9):
        raise ImunavError(f"outage_start = {start:g} s leaves no GNSS fix after it to end an "
                          f"outage of one GNSS interval ({dt:g} s); expected a start at most "
                          f"{end - dt:g} s (the record ends at {end:g} s)",
                          argument="outage_start")


def lost_from(at: AlongTruth, starts: FloatArray, tolerance: float, *,
               imu_scale: float = 1.0, chunk: float = 10.0) -> list[tuple[FloatArray, FloatArray]]:
    """Per start (ascending): the epochs' times and true position covariances of the scenario
    "GNSS lost for good at that start", until the p95 passes ``tolerance`` (or the end). Up to
    the fix after it, an outage ``[s, s + L]`` is exactly this scenario (the covariance is
    causal), so it answers every length at once. Before its start a scenario is the baseline
    (every fix), so the baseline is walked once and each scenario started from it, and stopped
    ``chunk`` seconds after it passes the tolerance at the latest."""
    wf, wt, _ = at.weights(imu_scale)
    E = at.t.size - 1
    base_act = active_fixes(at, [[]])
    out = []
    e0, P = 0, None
    step = max(1, int(round(chunk / max(np.diff(at.t).mean(), 1e-9))))
    for s0 in starts:
        e_b = max(0, int(np.searchsorted(at.t, s0 - 1e-9)) - 1)   # the last epoch before s0
        if P is None:                                            # from the initial covariance
            P = at.propagate(wf, wt, base_act, stop=e_b, keep=False).final
        elif e_b > e0:
            P = at.propagate(wf, wt, base_act, start=e0, stop=e_b, P_start=P, keep=False).final
        e0 = e_b
        act = active_fixes(at, [[(float(s0), float(at.t[-1]) + 1.0)]])
        ts, Ps, Pc, e = [], [], P, e_b
        while e < E:
            stop = min(E, e + step)
            res = at.propagate(wf, wt, act, start=e, stop=stop, P_start=Pc)
            Pp = res.truth_post[0, 0][1:][:, DP, DP]
            ts.append(res.t[1:])
            Ps.append(Pp)
            Pc, e = res.final, stop
            if exceeds(Pp, tolerance).any():
                break
        out.append((np.concatenate(ts) if ts else np.zeros(0),
                    np.concatenate(Ps) if Ps else np.zeros((0, 3, 3))))
    return out


def exceeds(P: FloatArray, tolerance: float) -> np.ndarray:
    """Where the p95 of ``|x|``, ``x ~ N(0, P)``, exceeds ``tolerance``: the tabulated bounds
    decide most, the exact probability the rest."""
    lo, hi = tabulated_quantile_bounds(eigenvalues(P), P95)
    over = lo > tolerance
    open_ = ~over & (hi > tolerance)
    if open_.any():
        over[open_] = norm_cdf(P[open_], tolerance) < P95
    return over


def find_outage(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                tolerance: float, duration: float | None = None, *,
                start: float | None = None, at: AlongTruth | None = None,
                starts: int = 24, settle: float = 30.0, budget: bool = True,
                kind: str = "increments", covariance_step: float = 0.1,
                algorithm: str | None = None, g: float = G0) -> dict:
    """The longest GNSS outage the IMU bridges with these aids: its p95 position error stays
    within ``tolerance`` from the outage's start until the first fix after it.

    The aiding file's own outages are replaced by the one searched. Placed at ``start`` or, by
    default, where it hurts most: of ``starts`` placements from ``settle`` s (the filter's
    convergence) to the end, the one that bridges the shortest outage. One covariance pass
    answers every length and placement: until the fix after it, an outage is the scenario
    "GNSS lost for good at its start". Lengths are whole GNSS intervals. An outage that could
    outlast the motion is cut at its end (``limited_by_motion``: the IMU bridges at least the
    rest of the motion).

    Parameters
    ----------
    motion, imu, aiding, rate, tolerance, duration
    start : float, optional
        The outage's start (s).
    at : AlongTruth, optional
        Reuse a built analysis (its IMU and aids).
    starts : int
        Placements compared.
    settle : float
        Earliest start (s; at most a quarter of the motion).
    budget : bool
        Error budget per source at the outage's end.
    kind, covariance_step, algorithm, g

    Returns
    -------
    dict
        ``max_outage_s``, ``outage_start_s``, ``position_p95_end_m`` (the p95 just before the
        fix after it), ``limited_by_motion``, ``gnss_interval_s``, ``error_budget``,
        ``warnings``.

    Raises
    ------
    ImunavError
        Without ``[gnss]``, for a non-positive tolerance, a start outside the record, or a
        motion too short to place an outage.
    """
    tolerance = check_positive(tolerance, "tolerance")
    if aiding.gnss is None:
        raise ImunavError("finding the longest outage needs [gnss] in the aiding file",
                          argument="aiding")
    duration = aided_span(motion, rate, duration)
    if at is None:
        at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                              covariance_step=covariance_step, algorithm=algorithm, g=g,
                              terms=budget)
    T = float(at.t[-1])
    dt = 1.0 / aiding.gnss.rate
    tg = gnss_times(at)
    if start is not None:
        check_start(tg, start, T, dt)
        cand = np.array([float(start)])
    else:
        lo_s = min(settle, T / 4)
        grid = tg[(tg >= lo_s - 1e-9) & (tg < T - dt)]
        if grid.size == 0:
            raise ImunavError("the motion is too short to place an outage after the filter "
                              "settles", argument="duration")
        cand = grid[np.unique(np.linspace(0, grid.size - 1, min(starts, grid.size)).round()
                              .astype(int))]
    scen = lost_from(at, cand, tolerance)
    warnings = list(at.warnings)
    # per start: the longest L (whole GNSS intervals) with p95 ≤ tol on [s, s + L + dt)
    best_L = np.zeros(cand.size)
    limited = np.zeros(cand.size, dtype=bool)
    for b, s0 in enumerate(cand):
        t, Pb = scen[b]
        after = np.nonzero(t >= s0 - 1e-9)[0]
        over = after[exceeds(Pb[after], tolerance)]
        if over.size == 0:
            # the whole rest of the motion (the last fix at or before the end)
            best_L[b] = (np.floor((T - s0) / dt + 1e-9)) * dt
            limited[b] = True
            continue
        t_over = t[over[0]]
        # the fix after the outage must come at or before the first epoch over the tolerance
        n = int(np.floor((t_over - s0) / dt + 1e-9)) - 1
        best_L[b] = max(n, -1) * dt
    # where it hurts most: the shortest bridgeable outage among the placements that the end of
    # the motion does not cut short (those only give lower bounds)
    b = (int(np.argmin(np.where(limited, np.inf, best_L))) if not limited.all()
         else int(np.argmax(best_L)))
    L, s_best = float(best_L[b]), float(cand[b])
    if L < 0:
        warnings.append(f"at {s_best:g} s the p95 position error exceeds the tolerance within "
                        "one GNSS interval even with every fix")
        L = 0.0
    t, Pb = scen[b]
    win = np.nonzero((t >= s_best - 1e-9) & (t < s_best + L + dt - 1e-9))[0]
    e_end = win[-1] if win.size else 0
    end_p95 = float(norm_quantile(Pb[e_end], P95))
    r = {"max_outage_s": L, "outage_start_s": s_best, "position_p95_end_m": end_p95,
         "limited_by_motion": bool(limited[b]), "gnss_interval_s": dt,
         "starts_compared": int(cand.size)}
    if budget and L > 0:
        when = float(t[e_end])
        r["error_budget_at_s"] = when
        r["error_budget"] = outage_budget(at, [(s_best, s_best + L)], when)
    else:
        r["error_budget"] = {}
    r["warnings"] = warnings
    return r


def bridgeable_outages(motion: BaseMotion, aiding: AidingConfig, rate: float, tolerance: float,
                       duration: float | None = None, *, presets: list[str] | None = None,
                       start: float | None = None, **kw) -> list[dict]:
    """:func:`find_outage` for every IMU preset (the table of notebook 10).

    Parameters
    ----------
    motion, aiding, rate, tolerance, duration, start
        As :func:`find_outage`.
    presets : list of str, optional
        Default every preset but ``ideal``.
    **kw
        Passed to :func:`find_outage`.

    Returns
    -------
    list of dict
        ``{"imu", "max_outage_s", "outage_start_s", "position_p95_end_m",
        "limited_by_motion", "warnings"}``, longest first.
    """
    names = presets or [p for p in PRESETS if p != "ideal"]
    rows = []
    for name in names:
        f = find_outage(motion, ImuModel.load(name), aiding, rate, tolerance, duration,
                        start=start, budget=False, **kw)
        rows.append({"imu": name, **{k: f[k] for k in ("max_outage_s", "outage_start_s",
                                                      "position_p95_end_m",
                                                      "limited_by_motion", "warnings")}})
    rows.sort(key=lambda d: -d["max_outage_s"])
    return rows


