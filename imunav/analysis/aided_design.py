"""The worst IMU that still bridges the outages: the aided design — each IMU term's limit with
these aids (the filter retuned to it), every term scaled together, every preset ranked — the
aided counterpart of :mod:`imunav.analysis.design`.

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
    file_outages,
    gnss_times,
    no_fix_warnings,
    outage_budget,
    outage_line,
    outage_p95,
    outage_pass,
)
from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.gaussnorm import norm_quantile
from imunav.analysis.outage import ROW_KEYS, check_start, exceeds, find_outage
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DP
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS
from imunav.sensors.terms import TERMS, printed

__all__ = ["GAIN_VALID", "OUTAGE_KEYS", "TERM_RANGE", "common_scale", "design_aided",
           "format_outage_design", "outage_answer", "rank_presets", "term_limits"]

#: The keys of :func:`~imunav.analysis.outage.find_outage`'s answer that ``design --find
#: outage`` carries at its top level.
OUTAGE_KEYS = ("max_outage_s", "last_fix_s", "next_fix_s", "outage_start_s", "gnss_outage_s",
               "p_within_whole_outage", "p_within_whole_outage_se",
               "p_within_whole_outage_horizontal", "p_within_whole_outage_horizontal_se",
               "level", "position_p95_end_m", "t_end_s", "position_p95_max_m",
               "max_outage_p95_s", "limited_by_motion", "gnss_interval_s", "samples",
               "starts_compared", "searched_from_s")


def common_scale(at: AlongTruth, tolerance: float, outages, *, rtol: float = 0.01,
                 iters: int = 8) -> float:
    """The largest factor on every IMU term for which the p95 position error stays within
    ``tolerance`` over the whole motion with these outages. The filter's gains change with the
    IMU, so each trial is one pass; the largest p95 grows smoothly and nearly as a power of the
    factor, so a secant on its logarithms lands within ``rtol`` of the tolerance in a few
    passes (the answer is the largest factor tried that passes).

    Parameters
    ----------
    at : AlongTruth
    tolerance : float
    outages : list of (float, float)
    rtol : float
        Stop when the p95 is this close to the tolerance (relative).
    iters : int
        At most this many secant steps.

    Returns
    -------
    float
        0 when even the smallest factor tried exceeds the tolerance (the aids' own errors do).
    """
    def worst(k):
        return float(outage_p95(at, outages, imu_scale=k)[1].max())

    tried = [(1.0, worst(1.0))]
    k1 = tolerance / tried[0][1] if tried[0][1] > 0 else 1e3
    tried.append((k1, worst(k1)))
    for _ in range(iters):
        (k0, p0), (k1, p1) = tried[-2], tried[-1]
        if p1 <= 0 or 0 <= 1 - p1 / tolerance < rtol:         # just within: done
            break
        slope = (np.log(p1) - np.log(p0)) / (np.log(k1) - np.log(k0)) if k1 != k0 else 1.0
        slope = float(np.clip(slope, 0.05, 2.0))
        k2 = k1 * (tolerance / p1) ** (1 / slope) * (1 - rtol / 2)
        tried.append((k2, worst(k2)))
    ok = [k for k, p in tried if p <= tolerance]
    return float(max(ok)) if ok else 0.0


#: Per-term limits are searched between this fraction and this multiple of the base value.
TERM_RANGE = (1e-3, 1e4)

#: A gain error (misalignment in rad, scale factor) whose 1σ limit passes this is flagged: the
#: error model is linear in it (small angles), and the filter estimating it may hide that.
GAIN_VALID = 0.05


def _term_weights(at: AlongTruth, j: int, k: float, retune: bool
                  ) -> tuple[FloatArray, FloatArray]:
    """The weights with ingredient ``j`` (an IMU term) times ``k``: in the truth, and with
    ``retune`` in the filter's model too."""
    wf, wt, _ = at.weights()
    wt = wt.copy()
    wt[:, j] *= k * k
    if retune:
        wf = wf.copy()
        wf[j] *= k * k
    return wf, wt


def _fixed_tuning_limit(P_rest: FloatArray, P_term: FloatArray, tolerance: float) -> float:
    """The largest ``k`` with ``max_t p95(P_rest + k² P_term) ≤ tolerance`` (the filter's gains
    fixed, the true covariance linear in each source's weight): bisection on ``log k`` (every
    epoch's p95 grows with ``k``), each trial decided by :func:`exceeds` (bounds first, the
    exact probability where they do not decide). 0 when the rest alone exceeds the tolerance,
    inf when the term cannot reach it within :data:`TERM_RANGE`."""
    def passes(k):
        return not exceeds(P_rest + k * k * P_term, tolerance).any()

    if not passes(0.0):
        return 0.0
    lo, hi = np.log(TERM_RANGE[0]), np.log(TERM_RANGE[1])
    if passes(np.exp(hi)):
        return float("inf")
    if not passes(np.exp(lo)):
        return 0.0
    while hi - lo > 1e-6:                       # 24 bisections of 16 decades
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if passes(np.exp(mid)) else (lo, mid)
    return float(np.exp(lo))


def _term_pass(at: AlongTruth, act: np.ndarray, j: int, k: float
               ) -> tuple[FloatArray, FloatArray]:
    """One pass with the filter tuned to IMU term ``j`` times ``k``: the true position
    covariance of that term (at ``k``) and of every other source, at every epoch."""
    wf, wt = _term_weights(at, j, k, True)
    rows = np.zeros((2, wt.shape[1]))
    rows[0, j] = wt[0, j]
    rows[1] = wt[0]
    rows[1, j] = 0.0
    res = at.propagate(wf, rows, act)
    P = res.truth_post[0][:, :, DP, DP]
    return P[0], P[1]


def _retuned_limit(at: AlongTruth, act: np.ndarray, j: int, k0: float, tolerance: float,
                   rtol: float, iters: int) -> tuple[float, float]:
    """The largest factor ``k`` on IMU term ``j`` with the largest p95 within ``tolerance``,
    the filter tuned to the term at ``k``: a fixed-point iteration from ``k0``. Each pass is
    tuned to the current ``k`` and split into the term and the rest; with those gains the
    true covariance is ``rest + (k'/k)² term`` exactly, so the next ``k'`` is the exact limit
    at those gains (:func:`_fixed_tuning_limit`). The gains of a filter tuned to the truth
    are (nearly: the models may differ) optimal, so the true covariance is stationary in them:
    the iteration converges in a few passes, usually from below. Stops when a tried ``k``
    passes within ``rtol`` below the tolerance; returns the largest passing ``k`` tried and
    its largest p95 (``(0, p)`` when the others
    alone exceed the tolerance even with the term at ``TERM_RANGE[0]``)."""
    lo_k, hi_k = TERM_RANGE
    k = float(np.clip(k0, lo_k, hi_k))
    best = (0.0, float("nan"))
    for _ in range(iters):
        P_term, P_rest = _term_pass(at, act, j, k)
        p = float(norm_quantile(P_rest + P_term, P95).max())
        if p <= tolerance and k > best[0]:
            best = (k, p)
            if 1 - p / tolerance < rtol or k >= hi_k:
                break
        # the exact limit with these gains, aimed a hair inside the tolerance
        r = _fixed_tuning_limit(P_rest, P_term / (k * k), tolerance * (1 - rtol / 4))
        if r == 0.0:
            if k <= lo_k:
                return (0.0, p) if best[0] == 0.0 else best
            r = lo_k
        k_new = float(np.clip(r, lo_k, hi_k))
        if k_new == k:
            break
        k = k_new
    return best


def term_limits(at: AlongTruth, tolerance: float, outages, *, retune: bool = True,
                rtol: float = 0.01, iters: int = 8) -> dict[str, dict]:
    """The largest value of each IMU error term, every other term at the IMU's own value, for
    which the p95 position error stays within ``tolerance`` over the whole motion with these
    GNSS outages (the aided counterpart of :func:`~imunav.analysis.design.design`'s limits).

    **The filter is retuned** to the term's value (``retune=True``, the default): the filter
    of ``imunav filter --imu`` is built from the IMU file, so an engineer who asks "how bad
    may this term be with this filter" fits the IMU they would buy and gives the filter its
    datasheet; the gains then change with the value, and a fixed-point iteration of passes
    tuned to the current value (:func:`_retuned_limit`; two or three per term) lands within
    ``rtol`` below the tolerance. The limit with the filter **kept at the IMU's own tuning** (the
    same gains, the real term worse than the filter believes) is exact from one pass split by
    source — the true covariance is then linear in each source's weight — and is reported
    beside it (``limit_base_tuning_si``); it also starts the retuned search.

    Parameters
    ----------
    at : AlongTruth
        Built with ``terms=True`` (one ingredient per IMU term).
    tolerance : float
    outages : list of (float, float)
    retune : bool
        The filter follows the term (default) or keeps the IMU's tuning.
    rtol : float
        Stop when the p95 at the limit is this close below the tolerance (relative).
    iters : int
        At most this many passes per term.

    Returns
    -------
    dict
        ``{term: {"limit_si", "limit", "base", "max_p95_at_limit_m", "limit_base_tuning_si",
        "limit_base_tuning", "note"}}`` for each IMU term with an effect, ``limit_si`` the
        term's value at the limit (SI; 0 when no value in ``TERM_RANGE`` × the IMU's meets the
        tolerance — the other sources alone exceed it —, None when even ``TERM_RANGE[1]`` ×
        it does); ``note`` says which, or that a gain error's limit passes
        :data:`GAIN_VALID`.
    """
    tolerance = check_positive(tolerance, "tolerance")
    act = active_fixes(at, [outages])
    names = [i.name for i in at.ingredients]
    imu_j = [j for j, i in enumerate(at.ingredients) if i.kind == "imu" and "." in i.name]
    if not imu_j:
        return {}
    wf, wt_split, _ = at.weights(split=True)
    split = at.propagate(wf, wt_split, act).truth_post[0][:, :, DP, DP]     # (M, E + 1, 3, 3)
    total = split.sum(axis=0)
    out: dict[str, dict] = {}
    for j in imu_j:
        term = names[j]
        triad, _, name = term.partition(".")
        value = float(getattr(getattr(at.imu, triad), name))
        if not np.any(split[j]):
            continue
        k_fix = _fixed_tuning_limit(total - split[j], split[j], tolerance)
        note = None
        if not retune or not np.isfinite(k_fix):
            k = k_fix
            p = (float(norm_quantile(total - split[j] + k * k * split[j], P95).max())
                 if np.isfinite(k) else float("nan"))
        else:
            k, p = _retuned_limit(at, act, j, k_fix, tolerance, rtol, iters)
        if k == 0.0:
            note = "the other sources alone exceed the tolerance"
        elif not np.isfinite(k) or k >= TERM_RANGE[1]:
            note = f"within the tolerance up to {TERM_RANGE[1]:g} × this IMU's value"
            k = float("inf")
        elif name in ("misalignment", "scale_factor") and value * k > GAIN_VALID:
            note = (f"beyond the small-error model (1σ above {GAIN_VALID:g}): check with "
                    "Monte Carlo")
        lim = None if not np.isfinite(k) else value * k
        fix = None if not np.isfinite(k_fix) else value * k_fix
        out[term] = {"limit_si": lim,
                     "limit": "unbounded" if lim is None else _show(term, lim),
                     "base": _show(term, value),
                     "max_p95_at_limit_m": p if np.isfinite(p) else None,
                     "limit_base_tuning_si": fix,
                     "limit_base_tuning": "unbounded" if fix is None else _show(term, fix),
                     "note": note}
    return out


def _show(term: str, si: float) -> str:
    triad, _, name = term.partition(".")
    return TERMS[name].show(si, triad)


def rank_presets(motion: BaseMotion, aiding: AidingConfig, rate: float, tolerance: float,
                 duration: float | None = None, *, presets: list[str] | None = None,
                 find: str | None = None, start: float | None = None, **kw) -> list[dict]:
    """Every IMU preset with these aids, best first: the largest p95 position error through
    the file's GNSS outages (the whole motion), within the tolerance or not, and with
    ``find="outage"`` its longest bridgeable outage (:func:`find_outage`; the table of
    :func:`bridgeable_outages`).

    Parameters
    ----------
    motion, aiding, rate, tolerance, duration
    presets : list of str, optional
        Default every preset.
    find : {None, "outage"}
    start : float, optional
        With ``find="outage"``: the outage's start.
    **kw
        ``kind``, ``covariance_step``, ``algorithm``, ``g``.

    Returns
    -------
    list of dict
        ``{"name", "max_p95_position_m", "final_p95_position_m", "suitable", "warnings"}``
        (the keys of :func:`~imunav.analysis.design.design`'s presets, ``max_p95…`` added;
        ``suitable``: the p95 within the tolerance at every epoch and every file outage
        within it at every epoch with a probability of at least 95 %), the file outages'
        ``p_within_whole_outages``, and ``outside_linearisation`` (the attitude error's p95
        beyond :data:`ATTITUDE_VALID`: the real EKF may diverge where the covariance does
        not), with ``find`` the keys of :data:`~imunav.analysis.outage.ROW_KEYS`
        (``max_outage_s``, ``last_fix_s``, ``next_fix_s``, ``p_within_whole_outage``, …);
        sorted by the largest p95, those outside the linearisation last.
    """
    outs = file_outages(aiding)
    rows = []
    for name in presets or list(PRESETS):
        imu = ImuModel.load(name)
        at = aided_covariance(motion, imu, aiding, rate, duration, **kw)
        t, truth, _, per, att = outage_pass(at, outs, tolerance=tolerance)
        warnings = list(at.warnings)
        if att.max() > ATTITUDE_VALID:
            warnings.append(f"the attitude error reaches a p95 of {att.max():.3g} rad: beyond "
                            "the filter's linearisation")
        row = {"name": name, "max_p95_position_m": float(truth.max()),
               "final_p95_position_m": float(truth[-1]),
               # beyond its linearisation the covariance has no word on the verdict
               "suitable": bool(truth.max() <= tolerance and att.max() <= ATTITUDE_VALID
                                and all(o["within_tolerance"] for o in per)),
               "p_within_whole_outages": [o["p_within_whole_outage"] for o in per],
               "warnings": warnings,
               "outside_linearisation": bool(att.max() > ATTITUDE_VALID)}
        if find == "outage":
            f = find_outage(motion, imu, aiding, rate, tolerance, duration, start=start, at=at,
                            budget=False)
            flag = row["outside_linearisation"]
            row.update({k: f[k] for k in ROW_KEYS})
            row["outside_linearisation"] = flag or f["outside_linearisation"]
        rows.append(row)
    # a preset beyond the linearisation last: its small p95 is not to be trusted
    rows.sort(key=lambda r: (r["outside_linearisation"], r["max_p95_position_m"]))
    return rows


def design_aided(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                 tolerance: float, duration: float | None = None, *, find: str | None = None,
                 outage_start: float | None = None, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None,
                 g: float = G0, presets: bool = True, retune: bool = True) -> dict:
    """The numbers of ``imunav design --aiding`` (its JSON), the aided counterpart of
    :func:`~imunav.analysis.design.design`: the limit of each IMU error term with these aids
    (:func:`term_limits`: the others at the IMU's values, **the filter retuned to the term's
    value** — the limit with the filter kept at the IMU's own tuning beside it), the worst IMU
    that still passes (every IMU term scaled together, the filter retuned:
    :func:`common_scale`), every preset ranked (:func:`rank_presets`), all through the file's
    GNSS outages; the error budget at the worst time; and with ``find="outage"`` the longest
    bridgeable outage (:func:`find_outage`; top-level ``max_outage_s``, and each preset's).

    The term limits and the common scale keep the p95 within the tolerance at every epoch; an
    outage (the file's, each preset's, the one found) is within the tolerance when the
    probability of staying within it at every epoch from its last fix to the next is at
    least 95 % (``p_within_whole_outage``, :mod:`~imunav.analysis.crossing`).

    Parameters
    ----------
    motion, imu, aiding, rate, tolerance, duration
    find : {None, "outage"}
    outage_start : float, optional
        With ``find="outage"``: the outage's start (s).
    kind, covariance_step, algorithm, g
    presets : bool
        Rank every preset (one analysis each).
    retune : bool
        The term limits with the filter retuned (default) or kept at ``imu``'s tuning.

    Returns
    -------
    dict
        ``motion``, ``imu``, ``rate_hz``, ``tolerance_m``, ``aiding``, ``max_p95_position_m``,
        ``time_max_p95_s``, ``outages`` (as :func:`~imunav.analysis.aided_assessment.
        assess_aided`'s, with ``p_within_whole_outage`` and ``within_tolerance``); ``terms``
        (as :func:`term_limits`: ``limit_si``, ``limit``, ``base`` — the keys of the unaided
        design's ``terms``); ``common_scale``; ``presets`` (``name``,
        ``max_p95_position_m``, ``final_p95_position_m``, ``suitable``, ``warnings``, with
        ``find`` ``max_outage_s``, ``last_fix_s``, ``next_fix_s``…), best first;
        ``error_budget_at_s``, ``error_budget``; with ``find`` the keys of
        :data:`OUTAGE_KEYS` (``max_outage_s == next_fix_s − last_fix_s``,
        ``p_within_whole_outage``, …) and ``outage_error_budget``; ``warnings``.

    Raises
    ------
    ImunavError
        For a non-positive tolerance, another ``find``, an outage start outside the record, or
        the reasons of :class:`~imunav.analysis.aided_covariance.AlongTruth`.
    """
    tolerance = check_positive(tolerance, "tolerance")
    if find not in (None, "outage"):
        raise ImunavError(f"find must be 'outage', got {find!r}", argument="find")
    duration = aided_span(motion, rate, duration)
    if aiding.gnss is not None:
        aiding.gnss.check_within(0.0, duration)
    at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                          covariance_step=covariance_step, algorithm=algorithm, g=g,
                          terms=True)
    if find == "outage" and outage_start is not None and aiding.gnss is not None:
        # before the term limits' passes
        check_start(gnss_times(at), float(outage_start), float(at.t[-1]),
                     1.0 / aiding.gnss.rate)
    outs = file_outages(aiding)
    t, truth, _, per, att = outage_pass(at, outs, tolerance=tolerance)
    worst = int(np.argmax(truth))
    r: dict = {"motion": motion.name, "earth": motion.frame, "imu": imu.name,
               "rate_hz": float(rate),
               "tolerance_m": tolerance, "tolerance_on": TOLERANCE_ON,
               "aiding": list(aiding.sensors),
               "max_p95_position_m": float(truth[worst]), "time_max_p95_s": float(t[worst]),
               "outages": per,
               "terms": term_limits(at, tolerance, outs, retune=retune),
               "term_limits_filter": "retuned" if retune else "base",
               "common_scale": common_scale(at, tolerance, outs)}
    r["error_budget_at_s"] = float(t[worst])
    r["error_budget"] = outage_budget(at, outs, float(t[worst]))
    warnings = list(at.warnings) + no_fix_warnings(at, outs)
    r["max_p95_attitude_rad"] = float(att.max())
    r["outside_linearisation"] = bool(att.max() > ATTITUDE_VALID)
    if r["outside_linearisation"]:
        warnings.append(f"the attitude error reaches a p95 of {att.max():.3g} rad, beyond the "
                        f"filter's linearisation ({ATTITUDE_VALID:g} rad): the limits below are "
                        "not to be trusted; check with assess --aiding --runs N")
    if find == "outage":
        f = find_outage(motion, imu, aiding, rate, tolerance, duration, start=outage_start,
                        at=at)
        r.update({k: f[k] for k in OUTAGE_KEYS})
        r["outage_p95_attitude_max_rad"] = f["p95_attitude_max_rad"]
        r["outside_linearisation"] = r["outside_linearisation"] or f["outside_linearisation"]
        r["outage_error_budget"] = f["error_budget"]
        r["outage_error_budget_at_s"] = f.get("error_budget_at_s")
        warnings += [w for w in f["warnings"] if w not in warnings]
    if presets:
        r["presets"] = rank_presets(motion, aiding, rate, tolerance, duration, find=find,
                                    start=outage_start, kind=kind,
                                    covariance_step=covariance_step, algorithm=algorithm, g=g)
    r["warnings"] = warnings
    return r


def outage_answer(r: dict) -> str:
    """The longest outage (:func:`~imunav.analysis.outage.find_outage`'s answer, or the
    design's top level) as one line of text.

    Parameters
    ----------
    r : dict

    Returns
    -------
    str
    """
    L, level = r["max_outage_s"], 100 * r.get("level", 0.95)
    if r["limited_by_motion"]:
        span = (f"from the last fix at {r['last_fix_s']:g} s to the end of the motion at "
                f"{r['next_fix_s']:g} s — the whole rest of the motion: it bridges at least "
                "this")
    else:
        span = f"from the last fix at {r['last_fix_s']:g} s to the next at {r['next_fix_s']:g} s"
    lost = r.get("gnss_outage_s")
    return (f"  Longest GNSS outage within the tolerance: max_outage_s = {L:g} s, {span}"
            + (f" (fixes {lost[0]:g}–{lost[1]:g} s lost)" if lost else "")
            + f"; within the tolerance at every epoch with probability "
            f"{100 * r['p_within_whole_outage']:.1f} % (± "
            f"{100 * r['p_within_whole_outage_se']:.2g} %, sampled; at least {level:g} % "
            f"asked), p95 {r['position_p95_end_m']:.3g} m at its end; by the per-epoch p95 "
            f"alone {r['max_outage_p95_s']:g} s"
            + (f"; the worst of {r['starts_compared']} placements from "
               f"{r['searched_from_s']:g} s (once the filter has settled) to the end."
               if r.get("searched_from_s") is not None else "."))


def format_outage_design(r: dict) -> str:
    """The ``--find outage`` answer as text.

    Parameters
    ----------
    r : dict
        ``imunav design --aiding … --find outage``'s JSON.

    Returns
    -------
    str
    """
    where = (" on the rotating WGS-84 Earth" if r.get("earth") == "wgs84" else
             " (flat frame)")
    lines = [f"Aided design for motion {r['motion']}{where}, IMU {r['imu']} at "
             f"{r['rate_hz']:g} Hz with {', '.join(r['aiding'])}, tolerance "
             f"{r['tolerance_m']:g} m on the 3-D position error:"]
    if "max_p95_position_m" in r:
        lines.append(f"  With the file's GNSS outages: largest p95 {r['max_p95_position_m']:.3g} "
                     f"m at t = {r['time_max_p95_s']:.4g} s.")
        for o in r.get("outages", []):
            lines.append(outage_line(o))
    if r.get("terms"):
        retuned = r.get("term_limits_filter", "retuned") == "retuned"
        lines.append("  Largest value of each IMU term, the others at this IMU's, with the "
                     "p95 within the tolerance at every epoch through the file's outages ("
                     + ("the filter retuned to each value; 'filter kept': the limit with the "
                        "filter at this IMU's tuning):" if retuned
                        else "the filter kept at this IMU's tuning):"))
        for k, v in sorted(r["terms"].items()):
            lim = printed(k, v["limit"])                  # "0 °/h": none of it is allowed
            extra = (f"; filter kept: {printed(k, v['limit_base_tuning'])}" if retuned and
                     v.get("limit_base_tuning_si") else "")
            note = f" — {v['note']}" if v.get("note") else ""
            lines.append(f"    {k:24s} {lim:>22s}   (this IMU: {printed(k, v['base'])}{extra})"
                         f"{note}")
    if r.get("common_scale") is not None:
        cs = r["common_scale"]
        if cs > 0:
            lines.append("  All IMU terms together: the p95 within the tolerance up to "
                         f"{cs:.3g} × this IMU's values"
                         + (" (it already meets it)." if cs >= 1 else
                            f" (its errors must shrink {1 / cs:.3g}-fold)."))
        else:
            lines.append("  No scale of this IMU's terms tried meets the tolerance with these "
                         "aids.")
    if r.get("error_budget") and "max_p95_position_m" in r:
        lines.append(f"  Error budget at t = {r['error_budget_at_s']:.4g} s (p95 of each "
                     "source alone):")
        for k, v in list(r["error_budget"].items())[:8]:
            lines.append(f"    {k:28s} {v:10.3g} m")
    if "max_outage_s" in r:
        lines.append(outage_answer(r))
        budget = r.get("outage_error_budget", r.get("error_budget") if "outages" not in r
                       else None)
        if budget:
            lines.append("  Error budget at the outage's end (p95 of each source alone):")
            for k, v in budget.items():
                lines.append(f"    {k:28s} {v:10.3g} m")
    if r.get("presets"):
        find = any("max_outage_s" in p for p in r["presets"])
        lines.append("  Presets, best first (largest 95th-percentile position error through the "
                     "file's outages; SUITABLE: within the tolerance at every epoch of each "
                     "outage with a probability of at least 95 %"
                     + ("; the longest outage each bridges, from its last fix to the next"
                        if find else "") + "):")
        for p in r["presets"]:
            flag = "SUITABLE    " if p["suitable"] else "NOT SUITABLE"
            row = f"    {p['name']:10s} {flag} {p['max_p95_position_m']:10.3g} m"
            if find:
                row += (f"   max_outage_s {p['max_outage_s']:5g} s ({p['last_fix_s']:g}–"
                        f"{p['next_fix_s']:g} s, {100 * p['p_within_whole_outage']:.1f} %)"
                        + (" (the rest of the motion)" if p["limited_by_motion"] else "")
                        + (f" (the earliest start searched, {p['searched_from_s']:g} s: one "
                           "before may be shorter)" if p.get("searched_from_s") is not None
                           and p.get("starts_compared", 1) > 1 and not p["limited_by_motion"]
                           and abs(p["outage_start_s"] - p["searched_from_s"]) < 1e-9 else ""))
            if p.get("outside_linearisation"):
                row += " (outside the linear model: check with Monte Carlo)"
            lines.append(row)
    for w in r["warnings"]:
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)


