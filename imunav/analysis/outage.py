"""How long an outage can it bridge? The longest GNSS outage an IMU bridges with its aids.

:func:`find_outage` answers by the covariance analysis of the filter along the true motion. An
outage is the gap between the **last fix used** and the **next fix used** (``max_outage_s =
next_fix_s − last_fix_s``: "30 s" is a last fix at 29 s and the next at 59 s, 29 fixes
lost); it is bridged when the probability that the position error stays within the tolerance at
**every** epoch from the last fix up to the next (that one's epoch excluded: there the error is
corrected) is at least :data:`~imunav.analysis.crossing.LEVEL` (95 %) —
``p_within_whole_outage``, the probability over the whole outage
(:mod:`imunav.analysis.crossing`: the exact Gaussian law of the filter's error along the
truth, its joint distribution over the epochs evaluated by sampling the error process itself,
with its standard error). A p95 within the tolerance at each epoch, the older criterion, is
necessary but not enough: a path may leave the tolerance in the middle of the outage and come
back, and a 95th percentile within it at every epoch still leaves more than 5 % of the paths
outside at *some* epoch. The end-of-outage p95 stands beside it (``position_p95_end_m``), and
the longest outage by the per-epoch p95 alone (``max_outage_p95_s``).

Until the fix after it, an outage is the scenario "GNSS lost for good at its start" (the
covariance is causal): one walk from each start answers every length at once, and every start
is walked in one loop, the ones under way at an epoch as one batch (the baseline with every
fix walked once, each start's scenario started from it). :func:`bridgeable_outages` tabulates the
answer for every IMU preset.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis``.
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.aided_assessment import (
    ATTITUDE_VALID,
    P95,
    TOLERANCE_ON,
    active_fixes,
    aided_covariance,
    aided_span,
    gnss_times,
    outage_budget,
    outage_pass,
)
from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.crossing import LEVEL, SAMPLES, Window, walk
from imunav.analysis.gaussnorm import eigenvalues, norm_cdf, norm_quantile, tabulated_quantile_bounds
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS

__all__ = ["REFINE", "ROW_KEYS", "SEARCH_SAMPLES", "baseline_states", "bridgeable_outages",
           "check_start", "exceeds", "find_outage", "outage_lengths"]

#: Paths per placement while the placements are compared (a standard error of about 0.006 on
#: a probability near 0.95); the :data:`REFINE` worst are walked again with
#: :data:`~imunav.analysis.crossing.SAMPLES` paths for the answer.
SEARCH_SAMPLES = 500

#: Placements walked again with the answer's paths.
REFINE = 3


def check_start(tg: FloatArray, start: float, end: float, dt: float) -> None:
    """Refuse an outage start outside ``[0, end)``, one with no GNSS fix before it (an outage
    runs from the last fix used), or one that leaves no room for an outage of one GNSS
    interval before the record's ``end`` and a fix after it (the search would report 0 s as
    "the rest of the motion")."""
    if not 0 <= start < end:
        raise ImunavError(f"outage_start must be in [0, {end:g}) s, got {start:g}",
                          argument="outage_start")
    if start > end - dt + 1e-9 or not np.any(tg > start + 1e-9):
        raise ImunavError(f"outage_start = {start:g} s leaves no GNSS fix after it to end an "
                          f"outage of one GNSS interval ({dt:g} s); expected a start at most "
                          f"{end - dt:g} s (the record ends at {end:g} s)",
                          argument="outage_start")
    if not np.any(tg < start - 1e-9):
        raise ImunavError(f"outage_start = {start:g} s has no GNSS fix before it (an outage "
                          "runs from the last fix used to the next); expected a start after "
                          f"the first fix at {tg[0]:g} s", argument="outage_start")


def exceeds(P: FloatArray, tolerance: float) -> np.ndarray:
    """Where the p95 of ``|x|``, ``x ~ N(0, P)``, exceeds ``tolerance``: the tabulated bounds
    decide most, the exact probability the rest."""
    lo, hi = tabulated_quantile_bounds(eigenvalues(P), P95)
    over = lo > tolerance
    open_ = ~over & (hi > tolerance)
    if open_.any():
        over[open_] = norm_cdf(P[open_], tolerance) < P95
    return over


def baseline_states(at: AlongTruth, epochs, *, imu_scale: float = 1.0,
                    active: np.ndarray | None = None) -> FloatArray:
    """The filter's and the true covariance at these epochs (ascending), after their
    readings, with every GNSS fix (or those of ``active``, shape (1, G)): one pass, walked
    from each epoch to the next.

    Parameters
    ----------
    at : AlongTruth
    epochs : sequence of int
        Ascending.
    imu_scale : float
    active : ndarray of bool, optional

    Returns
    -------
    ndarray, shape (len(epochs), 2, n, n)
        What :func:`~imunav.analysis.crossing.walk` starts from.
    """
    wf, wt, _ = at.weights(imu_scale)
    act = active_fixes(at, [[]]) if active is None else active
    out, P, e0 = [], None, 0
    for e in epochs:
        e = int(e)
        if P is None:
            P = at.propagate(wf, wt, act, stop=e, keep=False).final
        elif e > e0:
            P = at.propagate(wf, wt, act, start=e0, stop=e, P_start=P, keep=False).final
        e0 = e
        out.append(P[0])
    return np.stack(out) if out else np.zeros((0, 2, at.n, at.n))


def outage_lengths(w: Window, last_fix: float, start: float, tg: FloatArray, end: float,
                   level: float = LEVEL) -> dict:
    """An outage walked from its last fix (:func:`~imunav.analysis.crossing.walk`): its
    longest bridged lengths, every next fix at or after ``start`` tried in turn.

    Parameters
    ----------
    w : Window
    last_fix : float
        The last fix used (s).
    start : float
        The outage's start (s): the first fix it may lose is the first at or after it.
    tg : ndarray
        Every GNSS fix (s).
    end : float
        The record's end (s).
    level : float

    Returns
    -------
    dict
        ``next_fix_s`` (the longest bridged: every shorter one bridged too; ``last_fix``
        when not even the first next fix is, ``end`` when the rest of the motion is),
        ``limited_by_motion``, ``p``, ``se``, ``p_horizontal``, ``se_horizontal`` (of that
        window; of the shortest one when none is bridged), ``next_fix_p95_s`` (the same by
        the per-epoch p95 alone: the exact probability inside at every epoch ≥ ``level``),
        ``limited_by_motion_p95``. A window is bridged when its probability is at least
        ``level`` and no epoch of it falls below ``level`` alone (``w`` walked with
        ``decide``: it ends at the first such epoch).
    """
    walked = float(w.t[-1]) if w.t.size else last_fix
    nexts = tg[(tg >= start - 1e-9) & (tg > last_fix + 1e-9) & (tg <= walked + 1e-9)]
    rest = w.stopped == "end"
    until = np.concatenate([nexts, [end + 1e-6]]) if rest else nexts
    out = {}
    if until.size == 0:             # failed before the first next fix: nothing is bridged
        p, se = w.p_within([walked + 1e-6])
        ph, seh = w.p_within([walked + 1e-6], horizontal=True)
        for key in ("", "_p95"):
            out["next_fix" + key + "_s"], out["limited_by_motion" + key] = float(last_fix), False
        out.update(p=float(p[0]), se=float(se[0]), p_horizontal=float(ph[0]),
                   se_horizontal=float(seh[0]), bridged=False)
        return out
    p, se = w.p_within(until)
    ph, seh = w.p_within(until, horizontal=True)
    # the walk stops at the first epoch whose exact probability inside is below the level:
    # a window reaching it fails by the per-epoch p95 already
    p95_ok = until <= (w.t[-1] if w.stopped == "failed" else np.inf) + 1e-9
    for key, ok in (("", (p >= level) & p95_ok), ("_p95", p95_ok)):
        n_ok = int(np.argmin(ok)) if not ok.all() else ok.size
        limited = bool(rest and n_ok == until.size)
        nxt = last_fix if n_ok == 0 else (end if limited else float(until[n_ok - 1]))
        out["next_fix" + key + "_s"] = float(nxt)
        out["limited_by_motion" + key] = limited
        if key == "":
            i = max(n_ok - 1, 0)                   # the longest bridged, or the shortest
            out.update(p=float(p[i]), se=float(se[i]), p_horizontal=float(ph[i]),
                       se_horizontal=float(seh[i]), bridged=n_ok > 0)
    return out


def find_outage(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                tolerance: float, duration: float | None = None, *,
                start: float | None = None, at: AlongTruth | None = None,
                starts: int = 24, settle: float = 30.0, budget: bool = True,
                samples: int = SAMPLES, seed: int = 0, kind: str = "increments",
                covariance_step: float = 0.1, algorithm: str | None = None,
                g: float = G0) -> dict:
    """The longest GNSS outage the IMU bridges with these aids: the probability that its
    position error (3-D norm) stays within ``tolerance`` at every epoch from the last fix used
    until the next one is at least 95 % (``p_within_whole_outage``, :mod:`~imunav.analysis.
    crossing`).

    ``max_outage_s`` is the gap between the last fix used and the next one
    (``next_fix_s − last_fix_s``; whole GNSS intervals). The aiding file's own outages are
    replaced by the one searched. Placed at ``start`` (its last fix is the last one before it)
    or, by default, where it hurts most: of ``starts`` placements from ``settle`` s (the
    filter's convergence) to the end, the one that bridges the shortest outage — compared with
    :data:`SEARCH_SAMPLES` paths each, the :data:`REFINE` shortest walked again with
    ``samples`` paths for the answer. An outage that could outlast the motion is cut at its
    end (``limited_by_motion``: the IMU bridges at least the rest of the motion; ``next_fix_s``
    is then the record's end).

    Parameters
    ----------
    motion, imu, aiding, rate, tolerance, duration
    start : float, optional
        The outage's start (s): the fixes from it on are lost.
    at : AlongTruth, optional
        Reuse a built analysis (its IMU and aids).
    starts : int
        Placements compared.
    settle : float
        Earliest start (s; at most a quarter of the motion).
    budget : bool
        Error budget per source at the outage's end.
    samples : int
        Paths of the error sampled for the answer's probability.
    seed : int
        Of those paths.
    kind, covariance_step, algorithm, g

    Returns
    -------
    dict
        ``max_outage_s``, ``last_fix_s``, ``next_fix_s``, ``outage_start_s``,
        ``gnss_outage_s`` (the fixes lost, ``[first, last]`` as ``[gnss] outages`` writes
        them, or None), ``p_within_whole_outage`` with ``…_se`` and the horizontal error's
        (``p_within_whole_outage_horizontal``, ``…_horizontal_se``), ``level``,
        ``position_p95_end_m`` (the p95 at the last epoch before the next fix,
        ``t_end_s``), ``position_p95_max_m``, ``max_outage_p95_s`` (the longest outage by the
        per-epoch p95 alone), ``limited_by_motion``, ``gnss_interval_s``,
        ``starts_compared``, ``searched_from_s`` (the earliest start compared; None with
        ``start``), ``samples``, ``tolerance_on`` (the 3-D position error norm:
        :data:`~imunav.analysis.aided_assessment.TOLERANCE_ON`), ``error_budget``,
        ``warnings``.

    Raises
    ------
    ImunavError
        Without ``[gnss]``, for a non-positive tolerance, a start outside the record or with
        no fix before it, or a motion too short to place an outage.
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
        grid = tg[(tg >= lo_s - 1e-9) & (tg < T - dt) & (tg > tg[0] + 1e-9)]
        if grid.size == 0:
            raise ImunavError("the motion is too short to place an outage after the filter "
                              "settles", argument="duration")
        cand = grid[np.unique(np.linspace(0, grid.size - 1, min(starts, grid.size)).round()
                              .astype(int))]
    last = np.array([tg[tg < s - 1e-9][-1] for s in cand])
    e_last = np.searchsorted(at.t, last - 1e-9)
    P0 = baseline_states(at, e_last)

    def answers(idx, n_paths, sd):
        wins = walk(at, e_last[idx], P0[idx], tolerance, samples=n_paths, seed=sd,
                    decide=True)
        return [(w, outage_lengths(w, last[b], cand[b], tg, T)) for b, w in
                zip(idx, wins, strict=True)]

    def length(a):
        return a[1]["next_fix_s"] - last[a[2]]

    def worst(rows):
        # the shortest bridged outage among the placements the end of the motion does not cut
        # short (those give only lower bounds); if every one is cut, the longest
        free = [r for r in rows if not r[1]["limited_by_motion"]]
        return min(free, key=length) if free else max(rows, key=length)

    idx = list(range(cand.size))
    if cand.size > 1:
        first = [(w, a, b) for b, (w, a) in zip(idx, answers(idx, SEARCH_SAMPLES, seed),
                                                 strict=True)]
        free = [r for r in first if not r[1]["limited_by_motion"]]
        pool = sorted(free, key=length)[:REFINE] if free else [worst(first)]
        idx = sorted(r[2] for r in pool)
    rows = [(w, a, b) for b, (w, a) in zip(idx, answers(idx, samples, seed + 1), strict=True)]
    w, a, b = worst(rows)
    s_best, t_last = float(cand[b]), float(last[b])
    t_next = a["next_fix_s"]
    L = t_next - t_last
    warnings = list(at.warnings)
    searched_from = None if start is not None else float(cand[0])
    if start is None and cand.size > 1 and b == 0:
        warnings.append(f"the worst placement is the earliest searched (last fix at "
                        f"{t_last:g} s; the search starts {lo_s:g} s in, once the filter has "
                        "settled): an outage before that may be shorter still; ask for one "
                        "with --outage-start S")
    if not a["bridged"]:
        warnings.append(f"from the fix at {t_last:g} s even the next GNSS fix comes too late: "
                        f"the probability that the position error stays within the tolerance "
                        f"until it is {100 * a['p']:.1f} % (below {100 * LEVEL:g} %)")
    # the epochs of the outage: from the last fix to the one before the next fix (the whole
    # walk when the outage is not bridged at all)
    j = w.epochs(t_next if a["bridged"] and not a["limited_by_motion"] else T + 1e-6)
    j = max(j, 1)
    p95 = norm_quantile(w.cov[:j], P95)
    lost = tg[(tg > t_last + 1e-9) & (tg < t_next - 1e-9)] if a["bridged"] else tg[:0]
    if a["limited_by_motion"]:
        lost = tg[tg > t_last + 1e-9]
    # the linearisation checked on the way to the outage (with GNSS) and in it: a filter that
    # left its linear range before the outage does not reach it as the covariance says
    t_b, _, _, _, att_b = outage_pass(at, [])
    before = att_b[t_b <= t_last + 1e-9]
    att = max(float(w.attitude_p95[:j].max()), float(before.max()) if before.size else 0.0)
    if att > ATTITUDE_VALID:
        warnings.append(f"the attitude error reaches a p95 of {att:.3g} rad by the end of this "
                        f"outage, beyond the filter's linearisation ({ATTITUDE_VALID:g} rad): "
                        "the covariance's answer is not to be trusted; check the outage with "
                        "assess --aiding --runs N (the Monte Carlo of the filter)")
    r = {"max_outage_s": float(L), "last_fix_s": t_last, "next_fix_s": float(t_next),
         "outage_start_s": s_best,
         "gnss_outage_s": [float(lost[0]), float(lost[-1])] if lost.size else None,
         "p_within_whole_outage": a["p"], "p_within_whole_outage_se": a["se"],
         "p_within_whole_outage_horizontal": a["p_horizontal"],
         "p_within_whole_outage_horizontal_se": a["se_horizontal"], "level": LEVEL,
         "position_p95_end_m": float(p95[-1]), "t_end_s": float(w.t[j - 1]),
         "position_p95_max_m": float(p95.max()),
         "max_outage_p95_s": float(a["next_fix_p95_s"] - t_last),
         "limited_by_motion": bool(a["limited_by_motion"]), "gnss_interval_s": dt,
         "starts_compared": int(cand.size), "searched_from_s": searched_from,
         "samples": int(samples),
         "tolerance_on": TOLERANCE_ON, "p95_attitude_max_rad": att,
         "outside_linearisation": bool(att > ATTITUDE_VALID)}
    if budget and lost.size:
        r["error_budget_at_s"] = r["t_end_s"]
        r["error_budget"] = outage_budget(at, [(float(lost[0]), float(lost[-1]))],
                                          r["t_end_s"])
    else:
        r["error_budget"] = {}
    r["warnings"] = warnings
    return r


#: The keys of an outage answer that a table of them carries.
ROW_KEYS = ("max_outage_s", "last_fix_s", "next_fix_s", "outage_start_s",
            "p_within_whole_outage", "p_within_whole_outage_se", "position_p95_end_m",
            "limited_by_motion", "outside_linearisation", "starts_compared",
            "searched_from_s")


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
        ``{"imu", "max_outage_s", "last_fix_s", "next_fix_s", "outage_start_s",
        "p_within_whole_outage", "p_within_whole_outage_se", "position_p95_end_m",
        "limited_by_motion", "warnings"}``, longest first.
    """
    names = presets or [p for p in PRESETS if p != "ideal"]
    rows = []
    for name in names:
        f = find_outage(motion, ImuModel.load(name), aiding, rate, tolerance, duration,
                        start=start, budget=False, **kw)
        rows.append({"imu": name, **{k: f[k] for k in ROW_KEYS}, "warnings": f["warnings"]})
    rows.sort(key=lambda d: -d["max_outage_s"])
    return rows
