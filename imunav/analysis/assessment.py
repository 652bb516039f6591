"""The applicability verdict: can this IMU track this motion? Percentiles of the Monte Carlo
position error against a tolerance, the error budget per term, the minimum useful rate, and the
text a non-specialist can act on.

With ``aiding``, :func:`assess` answers through the aided verdict
(:mod:`imunav.analysis.aided_assessment`): one entry for every verdict.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``, ``imunav.analysis``.
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.aided_assessment import assess_aided
from imunav.analysis.covariance import (
    ENVELOPE_POINTS,
    LINEAR_LIMIT,
    CovarianceResult,
    CovarianceSummary,
    covariance_summary,
    envelope_index,
)
from imunav.analysis.gaussnorm import norm_quantile
from imunav.analysis.metrics import nav_errors
from imunav.analysis.montecarlo import AUTO_RUNS, CONFIDENCE, MonteCarloResult, monte_carlo, runs_interval
from imunav.core.deprecation import renamed
from imunav.core.validation import ImunavError, check_positive
from imunav.estimation.alignment import WINDOW, check_alignment
from imunav.motion.base import BaseMotion, span
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel, TriadModel
from imunav.sensors.simulate import signal_chunks
from imunav.strapdown.registry import navigate_chunks

RATE_CANDIDATES = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)

#: The verdict's rules, in one place: a run is within tolerance if its *maximum* position error
#: over the whole motion is; the IMU is SUITABLE if at least this fraction of runs are; envelopes
#: and the error budget are this percentile; sampling alone must stay below this fraction of the
#: tolerance for a rate to count as enough.
SUITABLE_FRACTION = 0.95
PERCENTILE = 95
SAMPLING_SHARE = 0.1


@renamed(output="kind")
def run_errors(motion: BaseMotion, rate: float, duration: float | None = None,
               kind: str = "increments", imu: ImuModel | None = None
               ) -> tuple[float, float]:
    """Maximum position (m) and attitude (rad) error of one run navigated with the default
    algorithm: the ideal signals, or ``imu``'s (seed 0) — streamed in chunks, so the memory
    does not grow with the duration.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"increments", "rates"}
    imu : ImuModel, optional

    Returns
    -------
    position, attitude : float
    """
    duration = span(motion, rate, duration)
    q0, v0, p0 = motion.states(np.array([0.0])).initial()
    chunks = signal_chunks(motion, rate, duration, kind=kind, imu=imu)
    pos = att = 0.0
    for st in navigate_chunks(kind, rate, chunks, q0, v0, p0, earth=motion.frame):
        err = nav_errors(st, motion)
        pos, att = max(pos, float(err.position.max())), max(att, float(err.attitude.max()))
    return pos, att


@renamed(output="kind")
def sampling_error(motion: BaseMotion, rate: float, duration: float,
                   kind: str = "increments") -> float:
    """Maximum position error (m) of an ideal sensor at ``rate`` with the default algorithm:
    what sampling alone costs on this motion (streamed: :func:`run_errors`)."""
    return run_errors(motion, rate, duration, kind)[0]


@renamed(output="kind")
def min_sample_rate(motion: BaseMotion, tolerance: float, duration: float | None = None,
                    kind: str = "increments", candidates=RATE_CANDIDATES) -> float | None:
    """Smallest candidate rate at which the sampling error alone (ideal sensor, default
    algorithm) stays within :data:`SAMPLING_SHARE` of ``tolerance`` over the whole motion.

    Parameters
    ----------
    motion : BaseMotion
        The motion.
    tolerance : float
        The position tolerance (m).
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"increments", "rates"}, default "increments"
        The signal kind.
    candidates : sequence of float, default RATE_CANDIDATES
        Rates (Hz) tried in increasing order; a rate giving fewer than 10 samples over the
        duration is skipped.

    Returns
    -------
    float or None
        The rate (Hz), or None if no candidate is enough.

    Raises
    ------
    ImunavError
        For the reasons of the simulation and the navigation (an unknown ``kind``, a
        duration that is not a finite number > 0, …).

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> min_sample_rate(Motion(x="sin(3*t)", yaw="sin(2*t)", duration=10.0), tolerance=1e-3)
    20.0
    """
    for r in candidates:
        d = span(motion, r, duration) if r * (duration or motion.duration or 0) >= 10 else None
        if d is None:
            continue
        if sampling_error(motion, r, d, kind) <= SAMPLING_SHARE * tolerance:
            return float(r)
    return None


#: Fewest runs whose interval can clear :data:`SUITABLE_FRACTION` (all of them within):
#: ``(1 − CONFIDENCE)/2 ≥ SUITABLE_FRACTION ** runs``.
MIN_RUNS = int(np.ceil(np.log((1 - CONFIDENCE) / 2) / np.log(SUITABLE_FRACTION)))


def verdict(mc: MonteCarloResult, tolerance: float, budget: dict[str, MonteCarloResult],
            min_rate: float | None, *, motion: str = "motion", imu: str = "imu",
            seed: int = 0) -> dict:
    """The numbers of the verdict from Monte Carlo results (a pure function of them).

    ``mc``: all error terms together; ``budget``: each term alone. Returns the dictionary that
    :func:`format_verdict` prints and ``imunav assess --json`` writes.
    """
    tolerance = check_positive(tolerance, "tolerance")
    inside = int(np.sum(mc.position.max(axis=1) <= tolerance))
    within = inside / mc.runs
    lo, hi = runs_interval(inside, mc.runs)
    warnings = []
    if lo < SUITABLE_FRACTION <= hi:
        warnings.append(
            f"{mc.runs} run{'' if mc.runs == 1 else 's'} cannot support a "
            f"{100 * SUITABLE_FRACTION:g} % verdict: the fraction of runs within {tolerance:g} m "
            f"is between {100 * lo:.1f} % and {100 * hi:.1f} % "
            f"({100 * CONFIDENCE:g} % confidence, Clopper–Pearson); at least {MIN_RUNS} runs "
            "are needed, more when some exceed")
    env = np.percentile(mc.position, PERCENTILE, axis=0)
    over = np.nonzero(env > tolerance)[0]
    terms = {k: float(np.percentile(b.position[:, -1], PERCENTILE)) for k, b in budget.items()}
    idx = _envelope_index(mc.t.size)
    return {
        "motion": motion, "imu": imu, "rate_hz": float(mc.rate), "tolerance_m": tolerance,
        "runs": mc.runs, "seed": seed,
        "fraction_within_tolerance": within,
        "fraction_ci95": [lo, hi],
        "suitable": within >= SUITABLE_FRACTION,
        # the Clopper–Pearson interval on one side of SUITABLE_FRACTION: the runs decide
        "conclusive": not lo < SUITABLE_FRACTION <= hi,
        "time_p95_exceeds_s": float(mc.t[over[0]]) if over.size else None,
        "final_p95_position_m": float(env[-1]),
        "error_budget": dict(sorted(terms.items(), key=lambda kv: -kv[1])),
        "min_rate_hz": min_rate,
        "saturated_runs": int(np.sum(mc.saturated > 0)),
        "method": "montecarlo",
        "warnings": warnings,
        "envelope": {"t": mc.t[idx].tolist(),
                     "position_p95_m": np.percentile(mc.position[:, idx], PERCENTILE,
                                                     axis=0).tolist(),
                     "attitude_p95_rad": np.percentile(mc.attitude[:, idx], PERCENTILE,
                                                       axis=0).tolist()},
    }


def _envelope_index(n: int) -> np.ndarray:
    return envelope_index(n, ENVELOPE_POINTS)


def verdict_covariance(cov: CovarianceResult | CovarianceSummary, tolerance: float,
                       min_rate: float | None, *,
                       motion: str = "motion", imu: str = "imu") -> dict:
    """The verdict from a covariance analysis: the same keys as :func:`verdict`.

    ``fraction_within_tolerance`` is the probability at the worst time that the position error
    is within the tolerance, ``min_t P(|δp(t)| ≤ tol)``: an upper bound on the fraction of runs
    that stay within over the whole motion (a run can exceed at different times), equal to it
    when each run's error grows steadily, as drift does. The envelope and the budget are exact
    95th percentiles of the error norm of the linear model.
    """
    tolerance = check_positive(tolerance, "tolerance")
    # there P < 95 % ⇔ the 95th percentile exceeds the tolerance
    within, first_over = cov.within_summary(tolerance, SUITABLE_FRACTION)
    idx = _envelope_index(cov.t.size)
    env_p = cov.position_quantile(PERCENTILE / 100, index=idx)
    env_a = cov.attitude_quantile(PERCENTILE / 100, index=idx)
    terms = {k: float(cov.position_quantile(PERCENTILE / 100, term=k, index=-1))
             for k in cov.terms}
    return {
        "motion": motion, "imu": imu, "rate_hz": cov.rate, "tolerance_m": tolerance,
        "method": "covariance", "runs": None, "seed": None,
        "fraction_within_tolerance": within,
        "fraction_ci95": None,
        "suitable": within >= SUITABLE_FRACTION,
        "conclusive": True,                   # exact for the linear model: no sampling
        "time_p95_exceeds_s": None if first_over is None else cov.time_at(first_over),
        "final_p95_position_m": float(env_p[-1]),
        "error_budget": dict(sorted(terms.items(), key=lambda kv: -kv[1])),
        "min_rate_hz": min_rate,
        "saturated_runs": 0,
        "warnings": list(cov.warnings),
        "envelope": {"t": cov.t[idx].tolist(), "position_p95_m": env_p.tolist(),
                     "attitude_p95_rad": env_a.tolist()},
    }


@renamed(model="imu", output="kind")
def deterministic_error(motion: BaseMotion, imu: ImuModel, rate: float,
                        duration: float | None = None, kind: str = "increments",
                        peaks: tuple[float, float] | None = None
                        ) -> tuple[float, float] | None:
    """Maximum position (m) and attitude (rad) error of one noise-free run keeping only the
    sensor's deterministic, non-linear terms — the anti-alias filter (its lag on the signal) and
    the range (clipping) — or None if the model has neither, or (given the motion's ``peaks``
    ``(max |ω_b|, max |f_b|)``) no filter and a range the motion stays far inside (below half
    of it: that run would be the ideal sensor's). The covariance models only their effect on
    noise; this measures what they do to the motion itself (streamed: :func:`run_errors`)."""
    def keep(m):
        return TriadModel(range=m.range, bandwidth=m.bandwidth, internal_rate=m.internal_rate)

    gyro, accel = imu.gyro, imu.accel
    if not any(t.bandwidth or t.range for t in (gyro, accel)):
        return None
    if peaks is not None and not (gyro.bandwidth or accel.bandwidth) and all(
            not m.range or peak <= m.range / 2 for m, peak in ((gyro, peaks[0]),
                                                                (accel, peaks[1]))):
        return None
    det = ImuModel(keep(gyro), keep(accel), f"{imu.name}:deterministic")
    return run_errors(motion, rate, duration, kind, imu=det)


@renamed(model="imu", output="kind")
def assess_covariance(motion: BaseMotion, imu: ImuModel, rate: float, tolerance: float,
                      duration: float | None = None, kind: str = "increments",
                      progress: bool = True, vertical: str = "free", *,
                      alignment: str = "truth", align_window: float = WINDOW) -> dict:
    """The applicability verdict by linear covariance analysis (:mod:`~imunav.analysis.covariance`).

    A fraction of a second where Monte Carlo takes tens of seconds; exact for the linear
    model, and flagged when the motion leaves its validity (clipping, large attitude errors,
    a filter lag that matters on this motion: :func:`deterministic_error`).

    Parameters
    ----------
    motion : BaseMotion
        The motion to track.
    imu : ImuModel
        The sensor's errors.
    rate : float
        Output sample rate (Hz).
    tolerance : float
        The position tolerance (m), > 0.
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"increments", "rates"}, default "increments"
        The signal kind.
    progress : bool, default True
        Show a progress bar on long analyses.
    vertical : {"free", "hold"}, default "free"
        On the WGS-84 Earth: hold the vertical channel at the true height (a perfect height
        aid); free, a verdict dominated by the unstable vertical channel says so.
    alignment : {"truth", "level"}, default "truth"
        The initial attitude: the truth, or levelled from the accelerometer at rest over
        ``align_window`` seconds before the motion (:mod:`imunav.estimation.alignment`; flat
        frame only; the heading is given). With ``"level"`` the verdict says so
        (``r["alignment"]``).
    align_window : float, default WINDOW
        The levelling window (s), > 0.

    Returns
    -------
    dict
        The keys of :func:`verdict_covariance` (``suitable``, ``fraction_within_tolerance``,
        ``final_p95_position_m`` in m, ``error_budget``, ``envelope``, ``warnings`` …), plus
        ``deterministic_position_m`` (m or None) and, on the WGS-84 Earth, ``vertical`` and
        ``final_p95_horizontal_m`` (m).

    Raises
    ------
    ImunavError
        If ``tolerance`` is not a finite number > 0, or for the reasons of the covariance
        analysis (a ``rate`` or duration that is not a finite number > 0, an unknown
        ``kind`` or ``vertical``, ``"hold"`` on the flat frame, …).
        Also if ``alignment`` is not ``"truth"`` or ``"level"``, ``align_window`` is not
        a finite number > 0, or ``"level"`` is asked on the WGS-84 Earth.

    Examples
    --------
    An accelerometer bias of σ = 0.01 m/s² per axis, at rest for 10 s, against 1 m:

    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> r = assess_covariance(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)),
    ...                       rate=10, tolerance=1.0, progress=False)
    >>> r["suitable"], round(r["final_p95_position_m"], 3), r["time_p95_exceeds_s"]
    (False, 1.398, 8.5)
    """
    tolerance = check_positive(tolerance, "tolerance")
    alignment, align_window = check_alignment(alignment, align_window, motion.frame)
    al = {} if alignment == "truth" else {"alignment": alignment, "align_window": align_window}
    cov = covariance_summary(motion, imu, rate, duration, kind=kind, tolerance=tolerance,
                             level=SUITABLE_FRACTION, progress=progress, vertical=vertical,
                             **al)
    r = verdict_covariance(cov, tolerance, min_sample_rate(motion, tolerance, duration, kind),
                           motion=motion.name, imu=imu.name)
    r["warnings"] += imu.missing_term_warnings()      # issue 38: no bias instability, say so
    att = float(cov.attitude_quantile(index=-1)) if cov.terms else 0.0
    r["max_p95_attitude_rad"] = att
    r["linear"] = bool(att <= LINEAR_LIMIT)
    if not r["linear"]:
        # beyond its own linearisation the covariance has no word on the verdict (issue 37)
        r["suitable"] = False
        r["outside_linearisation"] = True
    det = deterministic_error(motion, imu, rate, duration, kind,
                              peaks=(cov.max_rate, cov.max_force))
    r["deterministic_position_m"] = None if det is None else det[0]
    if det is not None and det[0] > tolerance:
        # the error without noise already exceeds the tolerance: no spread of noise around it
        # can keep 95 % within (the covariance, blind to it, said SUITABLE at 24.7 m vs 5 m)
        r["suitable"] = False
        r["deterministic_exceeds"] = True
    if det is not None and det[0] > SAMPLING_SHARE * tolerance:
        r["warnings"].append(
            f"the filter and range alone, without noise, give a {det[0]:.3g} m position error on "
            f"this motion (signal lag or clipping: not in the covariance, which models their "
            f"effect on noise); the error can reach the 95th percentile plus this. Check with "
            "--method montecarlo")
    min_rate = r["min_rate_hz"]
    if det is None and (min_rate is None or rate < min_rate):
        # below the rate where sampling stays within SAMPLING_SHARE of the tolerance: what a
        # perfect sensor at this rate costs (the covariance, blind to it, said SUITABLE at 0 m
        # where the sampling alone gave 518 m)
        try:
            samp = sampling_error(motion, rate, duration, kind)
        except ImunavError:
            samp = None
        r["sampling_position_m"] = samp
        if samp is not None and not samp <= tolerance:
            r["suitable"] = False
            r["sampling_exceeds"] = True
        elif samp is not None and samp > SAMPLING_SHARE * tolerance:
            r["warnings"].append(
                f"at {rate:g} Hz the sampling alone (a perfect sensor, the default algorithm) "
                f"gives a {samp:.3g} m position error on this motion, not in the covariance: "
                "the error can reach the 95th percentile plus this"
                + (f"; {min_rate:g} Hz keeps it below {SAMPLING_SHARE:g} × the tolerance"
                   if min_rate else ""))
    if motion.frame == "wgs84" and cov.terms:
        Ph = cov.total[-1:, 6:9, 6:9].copy()
        Ph[:, 2, :] = Ph[:, :, 2] = 0.0                      # the horizontal part alone
        hor = float(norm_quantile(Ph, PERCENTILE / 100)[0])
        r["vertical"] = vertical
        r["final_p95_horizontal_m"] = hor
        note = vertical_note(r["final_p95_position_m"], hor, vertical)
        if note:
            r["warnings"].append(note)
    _say_alignment(r, alignment, align_window)
    return r


def _say_alignment(r: dict, alignment: str, window: float) -> None:
    """Record a levelled start in the verdict (the truth start, the default, adds nothing)."""
    if alignment == "level":
        r["alignment"] = {"method": "level", "window_s": float(window)}


#: The methods of :func:`assess`.
METHODS = ("covariance", "montecarlo", "auto")



@renamed(model="imu", output="kind")
def assess(motion: BaseMotion, imu: ImuModel, rate: float, runs: int | None = None,
           tolerance: float | None = None, seed: int = 0, duration: float | None = None,
           kind: str = "increments", budget_runs: int | None = None,
           scheduler: str | None = None, progress: bool = True,
           method: str | None = None, vertical: str = "free", *, alignment: str = "truth",
           align_window: float = WINDOW, aiding: AidingConfig | None = None,
           covariance_step: float = 0.1) -> dict:
    """The applicability verdict: the numbers of ``imunav assess`` (see :func:`verdict`,
    :func:`verdict_covariance` and :func:`format_verdict`), by either method, aided or not,
    as the command line chooses it — the one entry for the verdict.

    Unaided, by linear covariance analysis (:func:`assess_covariance`) or Monte Carlo
    (:func:`~imunav.analysis.montecarlo.monte_carlo` and :func:`verdict`); with ``aiding``,
    the aided verdict through every GNSS outage
    (:func:`~imunav.analysis.aided_assessment.assess_aided`: the filter's covariance along the
    truth, and with ``runs`` a Monte Carlo of the filter too).

    Parameters
    ----------
    motion : BaseMotion
        The motion to track.
    imu : ImuModel
        The sensor's errors.
    rate : float
        Output sample rate (Hz).
    runs : int, optional
        Monte Carlo runs with all error terms together, ≥ 1 (the Monte Carlo method only).
    tolerance : float
        The position tolerance (m), > 0: a run is within it if its maximum position error
        over the whole motion is.
    seed : int, default 0
        Random seed, ≥ 0.
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"increments", "rates"}, default "increments"
        The signal kind.
    budget_runs : int, optional
        Runs per error term alone (same seed) for the error budget; default min(runs, 200).
    scheduler : str, optional
        A Dask scheduler's address to run the chunks on (see
        :func:`~imunav.analysis.montecarlo.monte_carlo`).
    progress : bool, default True
        Show a progress bar on long runs.
    method : {"covariance", "montecarlo", "auto"}, optional
        ``"auto"``: the covariance analysis, and the Monte Carlo (``runs``, default
        :data:`AUTO_RUNS`) when its own linearisation check fails (the p95 attitude error
        beyond :data:`~imunav.analysis.covariance.LINEAR_LIMIT`: the covariance then says NOT
        SUITABLE on its own). Default: Monte Carlo when ``runs`` is given, else linear covariance analysis
        (:func:`assess_covariance`).
    vertical : {"free", "hold"}, default "free"
        On the WGS-84 Earth: hold the vertical channel at the true height (a perfect height
        aid); free, a verdict dominated by the unstable vertical channel says so.
    alignment : {"truth", "level"}, default "truth"
        Each run from the true attitude, or from its own levelled one (as
        :func:`assess_covariance`); with ``"level"`` the verdict says so (``r["alignment"]``).
    align_window : float, default WINDOW
        The levelling window (s), > 0.
    aiding : AidingConfig, optional
        The aids (an ``AIDING.toml``, :class:`~imunav.sensors.aids.AidingConfig`): the aided
        verdict. Not with ``budget_runs``, ``vertical="hold"`` or ``alignment="level"`` (the
        aided analysis starts from the true attitude; its budget is per source at the worst
        outage's end).
    covariance_step : float, default 0.1
        With ``aiding``: the longest covariance step of the filter (s).

    Returns
    -------
    dict
        The keys of :func:`verdict`: ``suitable``, ``fraction_within_tolerance``,
        ``time_p95_exceeds_s`` (s or None), ``final_p95_position_m`` (m), ``error_budget``
        (term → final 95th-percentile position error alone, m, largest first),
        ``min_rate_hz``, ``saturated_runs``, ``envelope``, ``warnings`` …; on the WGS-84 Earth
        also ``vertical`` and ``final_p95_horizontal_m`` (m). With ``aiding``, those of
        :func:`~imunav.analysis.aided_assessment.assess_aided` (``suitable``,
        ``max_p95_position_m``, ``outages``, ``error_budget`` …).

    Raises
    ------
    ImunavError
        If ``tolerance`` is not a finite number > 0, or for the reasons of
        :func:`~imunav.analysis.montecarlo.monte_carlo` (``runs``, ``seed``, ``rate``,
        ``vertical``, ``scheduler`` …).
        Also if ``alignment`` is not ``"truth"`` or ``"level"``, ``align_window`` is not
        a finite number > 0, or ``"level"`` is asked on the WGS-84 Earth.
        Also for a bad ``method``, ``runs`` or ``scheduler`` with the covariance method, or
        the Monte Carlo method without ``runs``; with ``aiding``, for an option of the
        unaided verdict only (``budget_runs``, ``vertical``, ``alignment``,
        ``align_window``) and for the reasons of the aided one; without it, for a
        ``covariance_step`` other than its default.

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> r = assess(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)), rate=10,
    ...            runs=200, tolerance=1.0, progress=False)
    >>> r["suitable"], list(r["error_budget"])
    (False, ['accel.bias'])
    """
    method = method or ("montecarlo" if runs is not None else "covariance")
    if method not in METHODS:
        raise ImunavError(f"method must be one of {', '.join(METHODS)}, got {method!r}",
                          argument="method")
    tolerance = check_positive(tolerance, "tolerance")
    if aiding is not None:
        return _assess_aided(motion, imu, rate, runs, tolerance, seed, duration, kind,
                             budget_runs, scheduler, progress, method, vertical, alignment,
                             align_window, aiding, covariance_step)
    if covariance_step != 0.1:
        raise ImunavError("covariance_step applies with aiding only (the aided filter's "
                          "covariance steps)", argument="covariance_step")
    alignment, align_window = check_alignment(alignment, align_window, motion.frame)
    al = {} if alignment == "truth" else {"alignment": alignment, "align_window": align_window}
    if method == "covariance":
        for name, value in (("runs", runs), ("scheduler", scheduler),
                            ("budget_runs", budget_runs)):
            if value is not None:
                raise ImunavError(f"{name} applies to the Monte Carlo method only "
                                  "(method 'montecarlo')", argument=name)
        return assess_covariance(motion, imu, rate, tolerance, duration, kind,
                                 progress=progress, vertical=vertical, alignment=alignment,
                                 align_window=align_window)
    if method == "auto":
        r = assess_covariance(motion, imu, rate, tolerance, duration, kind, progress=progress,
                              vertical=vertical, alignment=alignment, align_window=align_window)
        if r["linear"]:
            r["method_chosen"] = "covariance"
            return r
        why = (f"the covariance analysis's p95 attitude error, {r['max_p95_attitude_rad']:.3g} "
               f"rad, is beyond its linear range ({LINEAR_LIMIT:g} rad)")
        runs = runs or AUTO_RUNS
        r = assess(motion, imu, rate, runs, tolerance, seed, duration, kind, budget_runs,
                   scheduler, progress, "montecarlo", vertical, alignment=alignment,
                   align_window=align_window)
        r["method_chosen"] = "montecarlo"
        r["warnings"].insert(0, f"{why}: the verdict is the Monte Carlo's ({runs} runs)")
        return r
    if runs is None:
        raise ImunavError("runs is required for the Monte Carlo method (method 'montecarlo')",
                          argument="runs")
    mc = monte_carlo(motion, imu, rate, duration, runs, seed, kind, scheduler=scheduler,
                     progress=progress, vertical=vertical, **al)
    br = budget_runs or min(runs, 200)
    budget = {term: monte_carlo(motion, imu.only(term), rate, duration, br, seed, kind,
                                scheduler=scheduler, progress=False, vertical=vertical,
                                **al)
              for term in imu.terms()}
    r = verdict(mc, tolerance, budget, min_sample_rate(motion, tolerance, duration, kind),
                motion=motion.name, imu=imu.name, seed=seed)
    r["warnings"] += imu.missing_term_warnings()      # issue 38: no bias instability, say so
    if mc.horizontal is not None:
        r["vertical"] = vertical
        hor = float(np.percentile(mc.horizontal[:, -1], PERCENTILE))
        r["final_p95_horizontal_m"] = hor
        note = vertical_note(r["final_p95_position_m"], hor, vertical)
        if note:
            r["warnings"].append(note)
    _say_alignment(r, alignment, align_window)
    return r


def _assess_aided(motion, imu, rate, runs, tolerance, seed, duration, kind, budget_runs,
                  scheduler, progress, method, vertical, alignment, align_window, aiding,
                  covariance_step) -> dict:
    """:func:`assess` with ``aiding``: the options of the unaided verdict refused by name, the
    method's rules checked as unaided, then :func:`assess_aided`."""
    if alignment != "truth" or align_window != WINDOW:
        raise ImunavError("alignment and align_window apply without aiding only (the aided "
                          "analysis starts from the true attitude)",
                          argument=("alignment", "align_window"))
    for name, value, default in (("budget_runs", budget_runs, None),
                                 ("vertical", vertical, "free")):
        if value != default:
            raise ImunavError(f"{name} applies without aiding only", argument=name)
    if method == "covariance" and runs is not None:
        raise ImunavError("runs applies to the Monte Carlo method only (method 'montecarlo')",
                          argument="runs")
    if method == "montecarlo" and runs is None:
        raise ImunavError("runs is required for the Monte Carlo method (method 'montecarlo')",
                          argument="runs")
    if runs is None and scheduler is not None:
        raise ImunavError("scheduler applies to a Monte Carlo (runs) only", argument="scheduler")

    return assess_aided(motion, imu, aiding, rate, tolerance, duration, runs=runs, seed=seed,
                        scheduler=scheduler, kind=kind, covariance_step=covariance_step,
                        progress=progress, method=method)


#: Above this ratio of the whole error to its horizontal part the vertical channel dominates.
VERTICAL_DOMINANCE = 2.0


def vertical_note(total: float, horizontal: float, vertical: str) -> str | None:
    """The warning of a verdict on the Earth whose error is mostly vertical: the free vertical
    channel is unstable (the error e-folds in about 10 minutes); a height aid removes it.

    Parameters
    ----------
    total, horizontal : float
        Final 95th percentiles of the whole and the horizontal position error (m).
    vertical : {"free", "hold"}

    Returns
    -------
    str or None
    """
    if vertical != "free" or total <= VERTICAL_DOMINANCE * horizontal:
        return None
    return (f"the vertical channel dominates: {total:.3g} m in all, {horizontal:.3g} m "
            "horizontally (free, the vertical error of an inertial navigator grows "
            "exponentially, e-folding in about 10 minutes); with a perfect height aid "
            "(--vertical hold) only the horizontal part remains")


def format_verdict(r: dict) -> str:
    """A verdict a non-specialist can act on (either method): what ``imunav assess`` prints.

    Parameters
    ----------
    r : dict
        A result of :func:`assess` or :func:`assess_covariance` (or :func:`verdict`,
        :func:`verdict_covariance`).

    Returns
    -------
    str
        Lines: SUITABLE or NOT SUITABLE with the fraction within tolerance, when the 95th
        percentile crosses it, the dominant term and the error budget, the minimum rate, and
        the warnings.

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> r = assess_covariance(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)),
    ...                       rate=10, tolerance=1.0, progress=False)
    >>> print(format_verdict(r).splitlines()[1])
      NOT SUITABLE: P(position error ≤ 1 m) drops to 73.9 % (needed: 95 % at every time).
    """
    pct = 100 * r["fraction_within_tolerance"]
    cov = r.get("method") == "covariance"
    plural = "" if r.get("runs") == 1 else "s"
    how = "covariance analysis" if cov else f"{r['runs']} run{plural} (seed {r['seed']})"
    lines = [f"IMU {r['imu']} on motion {r['motion']} at {r['rate_hz']:g} Hz, {how}, "
             f"tolerance {r['tolerance_m']:g} m:"]
    if r.get("alignment"):
        lines.append(f"  Initial attitude levelled from the accelerometer at rest over "
                     f"{r['alignment']['window_s']:g} s before the motion (heading given).")
    ok = r.get("suitable", r["fraction_within_tolerance"] >= SUITABLE_FRACTION)
    need = f"(needed: {100 * SUITABLE_FRACTION:g} %)"
    if cov and r.get("outside_linearisation"):
        lines.append(f"  NOT SUITABLE on the covariance's word: its p95 attitude error, "
                     f"{r['max_p95_attitude_rad']:.3g} rad, is beyond the linear model "
                     f"({LINEAR_LIMIT:g} rad), where its P(position error ≤ "
                     f"{r['tolerance_m']:g} m) ≥ {pct:.1f} % is not to be trusted: the verdict "
                     "needs a Monte Carlo (--method montecarlo or auto).")
    elif cov and r.get("sampling_exceeds"):
        samp = r["sampling_position_m"]
        lines.append(f"  NOT SUITABLE: at {r['rate_hz']:g} Hz the sampling alone, with a perfect "
                     f"sensor, gives {samp:.3g} m of position error, beyond the "
                     f"{r['tolerance_m']:g} m tolerance (the sensor noise alone: P(error ≤ "
                     f"{r['tolerance_m']:g} m) ≥ {pct:.1f} %).")
    elif cov and r.get("deterministic_exceeds"):
        lines.append(f"  NOT SUITABLE: the filter and range alone, without noise, give "
                     f"{r['deterministic_position_m']:.3g} m of position error, beyond the "
                     f"{r['tolerance_m']:g} m tolerance (the noise alone: P(error ≤ "
                     f"{r['tolerance_m']:g} m) ≥ {pct:.1f} %).")
    elif cov and ok:
        floor = np.floor(10 * pct) / 10      # "at least": rounded down, never up to 100.0
        lines.append(f"  SUITABLE: P(position error ≤ {r['tolerance_m']:g} m) is at least "
                     f"{floor:.1f} % at every time {need}.")
    elif cov:
        lines.append(f"  NOT SUITABLE: P(position error ≤ {r['tolerance_m']:g} m) drops to "
                     f"{pct:.1f} % (needed: {100 * SUITABLE_FRACTION:g} % at every time).")
    elif ok and not r.get("conclusive", True):
        lo, hi = (100 * x for x in r["fraction_ci95"])
        lines.append(f"  UNDECIDED: {pct:.1f} % of runs stay within {r['tolerance_m']:g} m over "
                     f"the whole motion {need}, but with {r['runs']} run{plural} the fraction "
                     f"could be {lo:.1f}–{hi:.1f} %: run more (--runs).")
    else:
        lines.append(f"  {'SUITABLE' if ok else 'NOT SUITABLE'}: {pct:.1f} % of runs stay within "
                     f"{r['tolerance_m']:g} m over the whole motion {need}.")
    which = "noise-driven " if r.get("deterministic_exceeds") or r.get("sampling_exceeds") else ""
    if r["time_p95_exceeds_s"] is None:
        lines.append(f"  The 95th percentile of the {which}position error never exceeds the "
                     f"tolerance (final {r['final_p95_position_m']:.3g} m).")
    else:
        lines.append(f"  The 95th percentile crosses {r['tolerance_m']:g} m at "
                     f"t = {r['time_p95_exceeds_s']:.2f} s (final {r['final_p95_position_m']:.3g} m).")
    if r["error_budget"]:
        top = next(iter(r["error_budget"]))
        lines.append(f"  Dominant error: {top} ({r['error_budget'][top]:.3g} m alone, 95th pct).")
        lines.append("  Error budget (each term alone, final 95th-percentile position error):")
        for k, v in r["error_budget"].items():
            val = f"{v:10.3g}" if v >= 1e-9 else f"{'< 1e-9':>10s}"   # below: rounding
            lines.append(f"    {k:28s} {val} m")
    mr = r["min_rate_hz"]
    lines.append(f"  Sampling alone stays below {SAMPLING_SHARE:g} × the tolerance from "
                 + (f"{mr:g} Hz." if mr else "no tested rate (≤ 5 kHz)."))
    if r["saturated_runs"]:
        lines.append(f"  warning: {r['saturated_runs']} runs hit the sensor range (clipped).")
    for w in r.get("warnings", []):
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)
