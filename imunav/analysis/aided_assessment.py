"""Can it bridge the outage? The aided verdict, by the covariance analysis of the filter along
the true motion and by Monte Carlo of the real filter.

:func:`assess_aided` answers "with these aids, does this IMU keep the tolerance through every
GNSS outage of the motion?" by the covariance analysis of the aided filter linearised along the
true motion (:class:`~imunav.analysis.aided_covariance.AlongTruth`: the filter's gains, and the
*true* error covariance those gains leave when the filter's model differs from the simulation's —
a correlated GNSS error treated as white), and with ``runs`` by a Monte Carlo of the real EKF
(:func:`~imunav.analysis.aided_montecarlo.aided_monte_carlo`). :func:`outage_budget` splits the
error at an outage's end by its sources (the true covariance is linear in them). The aided
counterpart of :mod:`imunav.analysis.assessment`; the outage search is
:mod:`imunav.analysis.outage`, the aided design :mod:`imunav.analysis.aided_design`.

The outage of a scenario is ``[start, end]``, fixes at ``start ≤ t ≤ end`` left out (the
convention of ``[gnss] outages``); its ``position_p95_max_m`` is the largest 95th percentile of
the position-error norm at the covariance epochs from ``start`` until the first fix used after
``end`` (excluded: the error grows until that fix), and ``position_p95_end_m`` the value at the
last of them (``t_end_s``, one covariance step before that fix). On the rotating Earth the
position errors are those of local NED at the true position (metres).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.stats import binom

from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.analysis.covariance import ENVELOPE_POINTS, envelope_index
from imunav.analysis.crossing import LEVEL, SAMPLES, walk
from imunav.analysis.gaussnorm import norm_quantile
from imunav.analysis.montecarlo import AUTO_RUNS, CONFIDENCE, runs_interval
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DP, PHI
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import interval_count

__all__ = ["ATTITUDE_VALID", "P95", "TOLERANCE_ON", "active_fixes", "aided_covariance",
           "aided_span", "assess_aided", "file_outages", "format_aided_verdict", "gnss_times",
           "no_fix_warnings", "outage_budget", "outage_line", "outage_p95", "outage_pass",
           "outage_spans", "outage_windows", "per_outage", "quantile_interval",
           "replace_outages", "runs_within"]


P95 = 0.95

#: What the tolerance of every aided answer applies to (a key of their JSON): the 3-D norm of
#: the position error — ``position_p95_*`` and ``p_within_whole_outage`` alike; the
#: horizontal error's probability is kept beside (``p_within_whole_outage_horizontal``).
TOLERANCE_ON = "3-D position error norm (north, east, down)"

#: p95 attitude error (rad) beyond which the linearised filter is flagged. A coarse flag: a
#: yaw not yet observed before the first accelerations reaches 0.4 rad with a BMI088 on the
#: example drive while the covariance still matches the EKF's Monte Carlo; with an MPU-6050's
#: 20 °/s turn-on bias it reaches 2.6 rad and the real filter diverges.
ATTITUDE_VALID = 0.5

def aided_span(motion: BaseMotion, rate: float, duration: float | None) -> float:
    if duration is None:
        duration = getattr(motion, "duration", None)
        if duration is None:
            raise ImunavError("this motion has no duration of its own: give duration",
                              argument="duration")
    duration = check_positive(duration, "duration")
    return interval_count(rate, duration) / rate


def file_outages(aiding: AidingConfig) -> list[tuple[float, float]]:
    return list(aiding.gnss.outages) if aiding.gnss is not None else []


def aided_covariance(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                     duration: float | None = None, *, kind: str = "increments",
                     covariance_step: float = 0.1, algorithm: str | None = None,
                     g: float = G0, terms: bool = False,
                     measurements: list | None = None) -> AlongTruth:
    """The aided filter linearised along the true motion (built once; passes are cheap).

    Parameters
    ----------
    motion, imu, aiding, rate
        The truth, the IMU (simulated and assumed), the aids, the IMU rate (Hz).
    duration : float, optional
        Seconds (default the motion's own).
    kind, covariance_step, algorithm, g, terms, measurements
        As :class:`~imunav.analysis.aided_covariance.AlongTruth` (``measurements``: a user's
        own aids, their models and reading times).

    Returns
    -------
    AlongTruth
    """
    duration = aided_span(motion, rate, duration)
    at = AlongTruth(motion, imu, aiding, rate, duration, kind=kind,
                    covariance_step=covariance_step, algorithm=algorithm, g=g, terms=terms,
                    measurements=measurements)
    at.warnings += imu.missing_term_warnings()        # issue 38: no bias instability, say so
    return at


def gnss_times(at: AlongTruth) -> FloatArray:
    return np.array([r.t for rs in at.readings for r in rs if r.sensor == "gnss"])


def no_fix_warnings(at: AlongTruth, outages: list[tuple[float, float]]) -> list[str]:
    """A warning when the GNSS outages leave no fix in the record (an aided answer that is
    then the other aids' alone, which a reader of "GNSS outage 0–20 s" would not guess).

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)

    Returns
    -------
    list of str
        Empty, or the one warning.
    """
    tg = gnss_times(at)
    if tg.size and not active_fixes(at, [outages])[0].any():
        return ["the GNSS outages cover every fix of the record: GNSS helps nowhere, the "
                "answer is that of the other aids alone"]
    return []


def active_fixes(at: AlongTruth, outages: list[list[tuple[float, float]]]) -> np.ndarray:
    """Per scenario (a list of outages), which GNSS fixes are used."""
    tg = gnss_times(at)
    act = np.ones((len(outages), tg.size), dtype=bool)
    for b, outs in enumerate(outages):
        for t0, t1 in outs:
            act[b] &= ~((tg >= t0 - 1e-9) & (tg <= t1 + 1e-9))
    return act


def outage_p95(at: AlongTruth, outages: list[tuple[float, float]], *, imu_scale: float = 1.0
               ) -> tuple[FloatArray, FloatArray, FloatArray, list[dict]]:
    """One covariance pass with these outages: the p95 position error at every epoch, the
    filter's own p95 beside it, and each outage's largest p95.

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)
        GNSS outages (s), replacing the aiding file's.
    imu_scale : float
        Every IMU term times this.

    Returns
    -------
    t : ndarray, shape (E + 1,)
    truth_p95, filter_p95 : ndarray, shape (E + 1,)
        95th percentile of the position-error norm (m): the true error and the filter's belief
        (after each epoch's readings).
    per_outage : list of dict
        ``{"start", "end", "last_fix_s", "next_fix_s", "position_p95_max_m",
        "position_p95_end_m", "t_end_s"}``.
    """
    return outage_pass(at, outages, imu_scale)[:4]


def outage_pass(at: AlongTruth, outages, imu_scale: float = 1.0, *,
                tolerance: float | None = None, samples: int = SAMPLES, seed: int = 0):
    """:func:`outage_p95` and the true attitude error's p95 at every epoch; with
    ``tolerance``, each outage's probability of staying within it at every epoch
    (:func:`~imunav.analysis.crossing.walk`: ``p_within_whole_outage``, its standard error
    ``p_within_whole_outage_se``, the horizontal error's beside) and its verdict
    ``within_tolerance`` (that probability at least :data:`~imunav.analysis.crossing.LEVEL`).

    The pass is cut at each outage's last fix (the covariances there start its walk): the
    same numbers as one pass.
    """
    wf, wt, _ = at.weights(imu_scale)
    act = active_fixes(at, [outages])
    spans = outage_spans(at, outages, act[0])
    E = at.t.size - 1
    starts = sorted({e0 for e0, _ in spans}) if tolerance is not None else []
    cuts = [e for e in starts if 0 < e < E]
    parts, P, P_at, e0 = [], None, {}, 0
    for e1 in cuts + [E]:
        res = at.propagate(wf, wt, act, start=e0, stop=e1, P_start=P)
        parts.append(res if not parts else _drop_first(res))
        P, e0 = res.final, e1
        P_at[e1] = P[0]
    if 0 in starts:
        P_at[0] = at.propagate(wf, wt, act, stop=0, keep=False).final[0]
    t = np.concatenate([r.t for r in parts])
    tpost = np.concatenate([r.truth_post[0, 0] for r in parts])
    fpost = np.concatenate([r.filter_post[0] for r in parts])
    truth = norm_quantile(tpost[:, DP, DP], P95)
    filt = norm_quantile(fpost[:, DP, DP], P95)
    att = norm_quantile(tpost[:, PHI, PHI], P95)
    windows = outage_windows(at, outages, act[0])
    per = per_outage(t, truth, outages, windows, spans, at)
    if tolerance is not None:
        keep = [i for i, w in enumerate(windows) if w.any()]
        wins = walk(at, [spans[i][0] for i in keep], np.stack([P_at[spans[i][0]] for i in keep])
                    if keep else np.zeros((0, 2, at.n, at.n)), tolerance,
                    stops=[spans[i][1] for i in keep], samples=samples, seed=seed,
                    imu_scale=imu_scale)
        for o, w in zip(per, wins, strict=True):
            until = w.t[-1] + 1e-6
            (p,), (se,) = w.p_within([until])
            (ph,), (seh,) = w.p_within([until], horizontal=True)
            o.update({"p_within_whole_outage": float(p), "p_within_whole_outage_se": float(se),
                      "p_within_whole_outage_horizontal": float(ph),
                      "p_within_whole_outage_horizontal_se": float(seh)})
            o["within_tolerance"] = bool(p >= LEVEL and o["position_p95_max_m"] <= tolerance)
    return t, truth, filt, per, att


def _drop_first(res):
    """A pass started at an epoch another pass ended at, without that epoch's record."""
    return dataclasses.replace(res, t=res.t[1:], filter_prior=res.filter_prior[:, 1:],
                               filter_post=res.filter_post[:, 1:],
                               truth_prior=res.truth_prior[:, :, 1:],
                               truth_post=res.truth_post[:, :, 1:])


def outage_spans(at: AlongTruth, outages, active: np.ndarray) -> list[tuple[int, int]]:
    """Per outage, its first and last epoch: from the last fix used before it (that fix's
    epoch, after its update; the record's start if there is none) until the epoch before the
    next fix used (that fix corrects the error: the error grows until it, not only until the
    outage's end), or the record's end."""
    tg = gnss_times(at)
    used = tg[active]
    t = at.t
    out = []
    for t0, t1 in outages:
        before, after = used[used < t0 - 1e-9], used[used > t1 + 1e-9]
        e0 = int(np.searchsorted(t, before[-1] - 1e-9)) if before.size else 0
        e1 = int(np.searchsorted(t, after[0] - 1e-9)) - 1 if after.size else t.size - 1
        out.append((e0, max(e0, e1)))
    return out


def outage_windows(at: AlongTruth, outages, active: np.ndarray) -> list[np.ndarray]:
    """Per outage, its epochs (:func:`outage_spans`) as a boolean mask over ``at.t``."""
    out = []
    for e0, e1 in outage_spans(at, outages, active):
        mask = np.zeros(at.t.size, bool)
        mask[e0:e1 + 1] = True
        out.append(mask)
    return out


def per_outage(t: FloatArray, p95: FloatArray, outages, windows, spans=None,
               at: AlongTruth | None = None) -> list[dict]:
    """Each outage's numbers from the p95 at every epoch: ``start``, ``end`` (the outage as
    written), ``last_fix_s`` and ``next_fix_s`` (the fixes used around it: None where the
    record starts or ends first), ``position_p95_max_m``, and ``position_p95_end_m`` at
    ``t_end_s``, the last epoch before the next fix."""
    out = []
    for i, ((t0, t1), inside) in enumerate(zip(outages, windows, strict=True)):
        if not inside.any():
            continue
        idx = np.nonzero(inside)[0]
        o = {"start": float(t0), "end": float(t1)}
        if spans is not None and at is not None:
            e0, e1 = spans[i]
            o["last_fix_s"] = float(t[e0]) if _is_fix(at, e0) else None
            o["next_fix_s"] = float(t[e1 + 1]) if e1 + 1 < t.size else None
        o.update({"position_p95_max_m": float(p95[inside].max()),
                  "position_p95_end_m": float(p95[idx[-1]]), "t_end_s": float(t[idx[-1]])})
        out.append(o)
    return out


def _is_fix(at: AlongTruth, e: int) -> bool:
    return any(r.sensor == "gnss" for r in at.readings[e])


def quantile_interval(x: FloatArray, q: float = P95, confidence: float = CONFIDENCE
                      ) -> tuple[float, float]:
    """The distribution-free confidence interval of the ``q``-quantile from a sample: two of
    its order statistics ``[x_(l), x_(u)]``, with ``l`` and ``u − 1`` the ``(1 ∓
    confidence)/2`` quantiles of Binomial(n, q) — covering the quantile with at least
    ``confidence`` whatever the distribution (Conover, *Practical Nonparametric Statistics*,
    1999, §3.2).

    Parameters
    ----------
    x : array_like, shape (n,)
    q : float
    confidence : float

    Returns
    -------
    lo, hi : float
        ``-inf`` or ``inf`` where the sample is too small for that side.
    """
    xs = np.sort(np.asarray(x, float).ravel())
    n = xs.size
    a = (1 - confidence) / 2
    lo = int(binom.ppf(a, n, q))                 # P(B ≤ lo − 1) < a
    hi = int(binom.ppf(1 - a, n, q)) + 1         # P(B ≤ hi − 1) ≥ 1 − a
    return (float(xs[lo - 1]) if lo >= 1 else -np.inf,
            float(xs[hi - 1]) if hi <= n else np.inf)


def runs_within(errors: FloatArray, window: np.ndarray, tolerance: float
                ) -> tuple[int, int]:
    """How many Monte Carlo runs keep the error norm within ``tolerance`` at every epoch of
    ``window``, of how many.

    Parameters
    ----------
    errors : ndarray, shape (runs, K)
        Error norms (m).
    window : ndarray of bool, shape (K,)
    tolerance : float

    Returns
    -------
    inside, runs : int
    """
    return int(np.count_nonzero((errors[:, window] <= tolerance).all(axis=1))), errors.shape[0]


# ----------------------------------------------------------------------------- Monte Carlo

def outage_budget(at: AlongTruth, outages: list[tuple[float, float]], at_time: float,
                  *, imu_scale: float = 1.0) -> dict[str, float]:
    """Which source eats the tolerance: the p95 position error at ``at_time`` of each source of
    the true error alone (an IMU term, an aid's noise or states, the initial uncertainty),
    the filter's gains those of all of them (the true covariance is their sum).

    Parameters
    ----------
    at : AlongTruth
        Built with ``terms=True`` for one row per IMU term (else one ``"imu"`` row).
    outages : list of (float, float)
    at_time : float
        Seconds (the epoch at or before it).
    imu_scale : float

    Returns
    -------
    dict
        ``{source: p95 (m)}``, largest first (sources that contribute nothing left out).
    """
    e = int(np.searchsorted(at.t, at_time + 1e-9)) - 1
    e = max(0, min(e, at.t.size - 1))
    wf, wt, names = at.weights(imu_scale, split=True)
    res = at.propagate(wf, wt, active_fixes(at, [outages]), stop=e, keep=False)
    P = res.final[0, 1:, :, :]
    q = norm_quantile(P[:, DP, DP], P95)
    out = {nm: float(v) for nm, v in zip(names, q, strict=True) if v > 0}
    return dict(sorted(out.items(), key=lambda kv: -kv[1]))


# ----------------------------------------------------------------------------- assess

def assess_aided(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                 tolerance: float, duration: float | None = None, *, runs: int | None = None,
                 seed: int = 0, scheduler: str | None = None, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None,
                 budget: bool = True, progress: bool = True, g: float = G0,
                 measurements: list | None = None, samples: int = SAMPLES,
                 method: str | None = None) -> dict:
    """The aided verdict: does the tolerance hold through every GNSS outage of ``aiding``?

    By the covariance analysis of the filter along the true motion (the true error covariance,
    the model mismatch included); with ``runs`` by a Monte Carlo of the real filter too (its
    numbers then make the verdict, the covariance's stand beside them).

    An outage runs from the last fix used before it to the next fix used after it; it is
    **within the tolerance** when the probability that the position error (3-D norm) stays
    within it at every epoch of the outage is at least 95 % (``p_within_whole_outage``: from
    the covariance, :mod:`~imunav.analysis.crossing`; by Monte Carlo, the fraction of runs
    inside at every epoch, with its Clopper–Pearson interval). **SUITABLE**: every outage
    within the tolerance, and the p95 position error within it at every epoch of the motion.

    Parameters
    ----------
    motion, imu, aiding, rate
    tolerance : float
        Position (m): the 3-D norm of the position error.
    duration : float, optional
    runs : int, optional
        Monte Carlo runs of the EKF.
    seed, scheduler
        Of the Monte Carlo.
    kind, covariance_step, algorithm, g
        As :class:`~imunav.analysis.aided_covariance.AlongTruth`.
    measurements : list of Aid, optional
        A user's own aids (any :class:`~imunav.estimation.measurements.Measurement` with its
        reading times; the Monte Carlo simulates their readings).
    budget : bool
        The error budget per source at the worst outage's end.
    progress : bool
    samples : int
        Paths of the error sampled per outage for its probability.
    method : {"covariance", "montecarlo", "auto"}, optional
        Default: ``"montecarlo"`` with ``runs``, else ``"covariance"``. The covariance's own
        linearisation check (the p95 attitude error within :data:`ATTITUDE_VALID` at every
        epoch, reported per outage) fails → its verdict is NOT SUITABLE on its word
        (``outside_linearisation``); ``"auto"`` then runs the Monte Carlo of the filter
        (``runs``, default :data:`~imunav.analysis.assessment.AUTO_RUNS`) and its verdict is
        the answer (``method_chosen``).

    Returns
    -------
    dict
        The JSON of ``imunav assess --aiding``: ``method``, ``suitable``,
        ``max_p95_position_m``, ``final_p95_position_m``, ``envelope`` (``t``,
        ``position_p95_m``, ``filter_position_p95_m``), ``outages`` (``start``, ``end``,
        ``last_fix_s``, ``next_fix_s``, ``p_within_whole_outage`` (with ``…_se`` or, by Monte
        Carlo, ``…_interval``), ``position_p95_max_m``, ``position_p95_end_m``, with a Monte
        Carlo ``covariance_…`` beside), ``level``, ``tolerance_on`` (:data:`TOLERANCE_ON`),
        ``error_budget``, ``warnings``; ``linear`` and ``outside_linearisation`` (the
        covariance's own check, and its verdict withheld), each outage's
        ``p95_attitude_max_rad`` and ``linear``; ``method_chosen`` with ``method="auto"``.

    Raises
    ------
    ImunavError
        For a non-positive tolerance, an unknown ``method``, ``runs`` with the covariance
        method or none with the Monte Carlo, GNSS outages outside the record.
    """
    tolerance = check_positive(tolerance, "tolerance")
    method = method or ("montecarlo" if runs is not None else "covariance")
    if method not in ("covariance", "montecarlo", "auto"):
        raise ImunavError(f"method must be covariance, montecarlo or auto, got {method!r}",
                          argument="method")
    if method == "covariance" and runs is not None:
        raise ImunavError("runs applies to the Monte Carlo method only", argument="runs")
    if method == "montecarlo" and runs is None:
        raise ImunavError("runs is required for the Monte Carlo method", argument="runs")
    auto_runs = None
    if method == "auto":
        auto_runs, runs = runs, None
    duration = aided_span(motion, rate, duration)
    if aiding.gnss is not None:
        aiding.gnss.check_within(0.0, duration)
    at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                          covariance_step=covariance_step, algorithm=algorithm, g=g,
                          terms=budget, measurements=measurements)
    outs = file_outages(aiding)
    t, truth, filt, per, att = outage_pass(at, outs, tolerance=tolerance, samples=samples,
                                           seed=seed)
    warnings = list(at.warnings) + no_fix_warnings(at, outs)
    linear = bool(att.max() <= ATTITUDE_VALID)
    if method == "auto" and not linear:
        n = auto_runs or AUTO_RUNS
        r = assess_aided(motion, imu, aiding, rate, tolerance, duration, runs=n, seed=seed,
                         scheduler=scheduler, kind=kind, covariance_step=covariance_step,
                         algorithm=algorithm, budget=budget, progress=progress, g=g,
                         measurements=measurements, samples=samples)
        r["method_chosen"] = "montecarlo"
        r["warnings"].insert(0, f"the covariance analysis's p95 attitude error, {att.max():.3g} "
                                f"rad, is beyond its linear range ({ATTITUDE_VALID:g} rad): the "
                                f"verdict is the Monte Carlo's ({n} runs)")
        return r
    if not linear:
        i = int(np.argmax(att))
        warnings.append(f"the attitude error reaches a p95 of {att[i]:.3g} rad at t = "
                        f"{t[i]:.4g} s: beyond the filter's linearisation (the real EKF may "
                        "diverge where the covariance does not)"
                        + ("" if runs is not None else
                           "; check with --runs N or --method auto"))
    r: dict = {"motion": motion.name, "earth": motion.frame, "imu": imu.name,
               "rate_hz": float(rate),
               "tolerance_m": tolerance, "aiding": list(aiding.sensors),
               "method": "covariance", "runs": None, "seed": None, "level": LEVEL,
               "tolerance_on": TOLERANCE_ON,
               "max_p95_attitude_rad": float(att.max()), "linear": linear}
    if method == "auto":
        r["method_chosen"] = "covariance"
    p95 = truth
    if runs is not None:
        mc = aided_monte_carlo(motion, imu, aiding, rate, duration, runs, seed=seed, times=t,
                               algorithm=algorithm, covariance_step=covariance_step,
                               scheduler=scheduler, progress=progress, g=g,
                               measurements=measurements)
        p95 = mc.p95()
        windows = outage_windows(at, outs, active_fixes(at, [outs])[0])
        norms = np.linalg.norm(mc.position_error, axis=-1)
        horiz = np.linalg.norm(mc.position_error[..., :2], axis=-1)
        mper = per_outage(t, p95, outs, windows, outage_spans(at, outs,
                                                             active_fixes(at, [outs])[0]), at)
        used = [w for w in windows if w.any()]
        for o, c, w in zip(mper, per, used, strict=True):
            o["covariance_p95_max_m"] = c["position_p95_max_m"]
            o["covariance_p95_end_m"] = c["position_p95_end_m"]
            for key in ("p_within_whole_outage", "p_within_whole_outage_se",
                        "p_within_whole_outage_horizontal"):
                o["covariance_" + key] = c[key]
            inside, n = runs_within(norms, w, tolerance)
            lo, hi = runs_interval(inside, n)
            ih, _ = runs_within(horiz, w, tolerance)
            o["p_within_whole_outage"] = inside / n
            o["p_within_whole_outage_interval"] = [lo, hi]
            o["p_within_whole_outage_horizontal"] = ih / n
            o["position_p95_end_interval_m"] = [          # None: too few runs for that side
                float(v) if np.isfinite(v) else None
                for v in quantile_interval(norms[:, np.nonzero(w)[0][-1]])]
            o["within_tolerance"] = bool(inside / n >= LEVEL
                                         and o["position_p95_max_m"] <= tolerance)
            o["conclusive"] = not lo < LEVEL <= hi
            if not o["conclusive"]:
                warnings.append(
                    f"{n} runs cannot settle the outage {o['start']:g}–{o['end']:g} s: the "
                    f"fraction of runs within {tolerance:g} m at every epoch is between "
                    f"{100 * lo:.1f} % and {100 * hi:.1f} % ({100 * CONFIDENCE:g} % "
                    f"confidence, Clopper–Pearson), on both sides of {100 * LEVEL:g} %")
        per = mper
        r.update(method="montecarlo", runs=int(runs), seed=int(seed),
                 rejected_readings=mc.rejected)
    else:
        r["samples"] = int(samples)
    _outage_attitude(at, outs, att, per)
    over = np.nonzero(p95 > tolerance)[0]
    worst = int(np.argmax(p95))
    outages_ok = all(o["within_tolerance"] for o in per)
    # beyond its own linearisation the covariance has no word on the verdict (issue 37)
    outside = runs is None and not linear
    r.update({
        "suitable": bool(over.size == 0 and outages_ok and not outside),
        # a Monte Carlo too short to put an outage's fraction on one side of LEVEL
        "conclusive": all(o.get("conclusive", True) for o in per),
        "outside_linearisation": outside,
        "outages_within_tolerance": bool(outages_ok),
        "time_p95_exceeds_s": float(t[over[0]]) if over.size else None,
        "max_p95_position_m": float(p95[worst]), "time_max_p95_s": float(t[worst]),
        "final_p95_position_m": float(p95[-1]),
        "outages": per,
    })
    if budget:
        # at the end of the worst outage (else at the worst time)
        when = max(per, key=lambda o: o["position_p95_max_m"])["t_end_s"] if per else t[worst]
        r["error_budget_at_s"] = float(when)
        r["error_budget"] = outage_budget(at, outs, when)
    idx = envelope_index(t.size, ENVELOPE_POINTS)
    r["envelope"] = {"t": t[idx].tolist(), "position_p95_m": p95[idx].tolist(),
                     "filter_position_p95_m": filt[idx].tolist()}
    if runs is not None:
        r["envelope"]["covariance_position_p95_m"] = truth[idx].tolist()
    if np.any(filt < 0.8 * truth):
        i = int(np.argmax(truth / np.maximum(filt, 1e-300)))
        warnings.append(f"the filter believes its position better than it is (p95 "
                        f"{filt[i]:.3g} m believed, {truth[i]:.3g} m true at t = {t[i]:.4g} s): "
                        "its model differs from the sensors'")
    r["warnings"] = warnings
    return r


def outage_line(o: dict, runs: int | None = None) -> str:
    """One outage of the aided verdict as text: its fixes, its probability of staying within
    the tolerance at every epoch (with its standard error, or its Monte Carlo interval), the
    p95 at its end, and its verdict.

    Parameters
    ----------
    o : dict
        One of ``outages`` of :func:`assess_aided` (or of the design's).
    runs : int, optional
        The Monte Carlo's runs (its numbers in ``o``).

    Returns
    -------
    str
    """
    nxt = "the end" if o.get("next_fix_s") is None else f"{o['next_fix_s']:g} s"
    last = ("from the record's start" if o.get("last_fix_s") is None
            else f"last fix {o['last_fix_s']:g} s")
    head = f"  GNSS outage {o['start']:g}–{o['end']:g} s ({last}, next {nxt}): "
    verdict = "within" if o["within_tolerance"] else "BEYOND"
    if "p_within_whole_outage" not in o:
        return (head + f"p95 up to {o['position_p95_max_m']:.3g} m — {verdict} the "
                "tolerance")
    p = o["p_within_whole_outage"]
    if runs is None:
        return (head + f"within the tolerance at every epoch with probability {100 * p:.1f} % "
                f"(± {100 * o['p_within_whole_outage_se']:.2g} %, sampled), p95 "
                f"{o['position_p95_end_m']:.3g} m at its end — {verdict} the tolerance")
    lo, hi = o["p_within_whole_outage_interval"]
    qlo, qhi = o["position_p95_end_interval_m"]
    q = (f"{'…' if qlo is None else f'{qlo:.3g}'}–{'…' if qhi is None else f'{qhi:.3g}'} m, 95 % "
         "order statistics" + ("; too few runs for a bound on each side"
                               if qlo is None or qhi is None else ""))
    return (head + f"{100 * p:.1f} % of {runs} runs within the tolerance at every epoch "
            f"[{100 * lo:.1f}–{100 * hi:.1f} %, 95 % Clopper–Pearson] (covariance "
            f"{100 * o['covariance_p_within_whole_outage']:.1f} %); p95 at its end "
            f"{o['position_p95_end_m']:.3g} m [{q}] "
            f"(covariance {o['covariance_p95_end_m']:.3g} m) — {verdict} the "
            "tolerance")


def _outage_attitude(at: AlongTruth, outs, att: FloatArray, per: list[dict]) -> None:
    """Each outage's p95 attitude error (its largest, rad) and whether the covariance is
    within its linearisation there (``linear``), written into ``per``."""
    windows = [w for w in outage_windows(at, outs, active_fixes(at, [outs])[0]) if w.any()]
    for o, w in zip(per, windows, strict=True):
        a = float(att[w].max())
        o["p95_attitude_max_rad"] = a
        o["linear"] = bool(a <= ATTITUDE_VALID)


def format_aided_verdict(r: dict) -> str:
    """The aided verdict as text (what ``imunav assess --aiding`` prints).

    Parameters
    ----------
    r : dict
        :func:`assess_aided`'s result.

    Returns
    -------
    str
    """
    how = ("covariance analysis of the filter" if r["method"] == "covariance" else
           f"Monte Carlo of the filter, {r['runs']} runs")
    level = 100 * r.get("level", LEVEL)
    where = (" on the rotating WGS-84 Earth" if r.get("earth") == "wgs84" else
             " (flat frame)")
    verdict = "SUITABLE" if r["suitable"] else "NOT SUITABLE"
    if r["suitable"] and not r.get("conclusive", True):
        verdict = (f"UNDECIDED ({r['runs']} runs cannot put every outage's probability on "
                   f"one side of {level:g} %: run more, --runs)")
    if r.get("outside_linearisation"):
        verdict = (f"NOT SUITABLE on the covariance's word (its p95 attitude error, "
                   f"{r['max_p95_attitude_rad']:.3g} rad, is beyond the linear model, "
                   f"{ATTITUDE_VALID:g} rad: the verdict needs a Monte Carlo, --runs N or "
                   "--method auto)")
    lines = [f"Aided verdict for motion {r['motion']}{where}, IMU {r['imu']} at "
             f"{r['rate_hz']:g} Hz with {', '.join(r['aiding'])} ({how}), tolerance "
             f"{r['tolerance_m']:g} m on the 3-D position error:",
             f"  {verdict}: largest p95 "
             f"{r['max_p95_position_m']:.3g} m at t = {r['time_max_p95_s']:.4g} s, final "
             f"{r['final_p95_position_m']:.3g} m"
             + (f"; through every GNSS outage (from the last fix used to the next) the error "
                f"must stay within the tolerance at every epoch with a probability of at "
                f"least {level:g} %." if r["outages"] else ".")]
    runs = r["runs"] if r["method"] == "montecarlo" else None
    for o in r["outages"]:
        lines.append(outage_line(o, runs))
    if r.get("error_budget"):
        lines.append(f"  Error budget at t = {r['error_budget_at_s']:.4g} s (p95 of each "
                     "source alone):")
        for k, v in r["error_budget"].items():
            lines.append(f"    {k:28s} {v:10.3g} m")
    for w in r["warnings"]:
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- design

def replace_outages(aiding: AidingConfig, outages) -> AidingConfig:
    """``aiding`` with other GNSS outages."""
    return aiding.replace(gnss=dataclasses.replace(aiding.gnss, outages=tuple(outages)))
