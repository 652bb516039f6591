"""Linear covariance analysis of strapdown errors along the true motion: the assessment built
on the error model of :mod:`imunav.estimation`.

To first order the navigation errors are linear in the sensor errors, so their distribution
follows from propagating a covariance along the exact trajectory — in one pass, and exactly per
error term (independent sources add). The error state, its dynamics and its exact
discretisation are :mod:`imunav.estimation.error_model` and
:mod:`~imunav.estimation.discretisation`; how each sensor error term enters it (and which terms
have no linear model: the range, which gives a warning here, the anti-alias filter and the
internal rate, which act through the white noise's aliasing gain) is each term's own
:meth:`~imunav.sensors.terms.Term.linearise`. This module turns the propagated covariances into
what an assessment reads: percentiles of the position and attitude error norms, the probability
of staying within a tolerance, and the warnings where the linear model stops being reliable.

The results are :mod:`~imunav.analysis.covariance_results` (:class:`CovarianceResult`,
:class:`CovarianceSummary`, re-exported here), the exact extrema over time of a streamed
analysis :mod:`~imunav.analysis.trackers`.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis.trackers``, ``imunav.analysis.covariance_results``.
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.covariance_results import CovarianceResult, CovarianceSummary
from imunav.analysis.trackers import MaxQuantileTracker, WithinTracker
from imunav.core.constants import G0
from imunav.core.deprecation import renamed
from imunav.core.kernels import FloatArray
from imunav.core.resources import check_memory
from imunav.core.validation import ImunavError
from imunav.estimation.alignment import WINDOW, check_alignment, levelled_sources
from imunav.estimation.error_model import LazyTrajectory, Trajectory, frame_model, linearise
from imunav.estimation.propagation import CHUNK, propagate, propagate_chunks
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import interval_count

__all__ = ["ENVELOPE_POINTS", "LINEAR_LIMIT", "CovarianceResult", "CovarianceSummary",
           "Trajectory", "covariance", "covariance_summary", "envelope_index"]

#: Points of the envelope an assessment reports (``--json``) and plots: the output times,
#: thinned; all a streamed analysis keeps of the covariance's history.
ENVELOPE_POINTS = 201


def envelope_index(n: int, points: int = ENVELOPE_POINTS) -> np.ndarray:
    """The indices of ``n`` output times an envelope keeps: ``points`` evenly spread, first and
    last included (all of them if there are fewer).

    Parameters
    ----------
    n : int
        Output times.
    points : int

    Returns
    -------
    ndarray of int
    """
    return np.unique(np.linspace(0, n - 1, min(n, points)).round().astype(int))


#: Above this 95th-percentile attitude error (rad) the small-angle model is no longer reliable.
LINEAR_LIMIT = 0.3


@renamed(model="imu", output="kind")
def covariance(motion: BaseMotion, imu: ImuModel, rate: float, duration: float | None = None,
               g: float = G0, kind: str = "increments", trajectory: Trajectory | None = None,
               vertical: str = "free", *, alignment: str = "truth",
               align_window: float = WINDOW) -> CovarianceResult:
    """Propagate every sensor error term of ``imu`` along ``motion`` at ``rate`` Hz.

    Parameters
    ----------
    motion : BaseMotion
    imu : ImuModel
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own (:func:`~imunav.motion.base.span`).
    g : float
        Gravity magnitude (m/s²).
    kind : {"increments", "rates"}
        The signal kind (``increments``: quantisation with a carried residual).
    trajectory : Trajectory, optional
        The motion already sampled by :meth:`Trajectory.of` (to reuse it).
    vertical : {"free", "hold"}
        On the WGS-84 Earth (an :class:`~imunav.motion.geodetic.EarthMotion`): the vertical
        channel free or held at the true height (a perfect height aid).
    alignment : {"truth", "level"}
        The initial attitude: the truth, or levelled from the accelerometer at rest over
        ``align_window`` seconds before the motion (:mod:`imunav.estimation.alignment`: the
        tilt then absorbs the horizontal accelerometer errors of the window; flat frame only).
    align_window : float
        Seconds of the levelling window.

    Returns
    -------
    CovarianceResult
        Per term and in total, at the output times (on the Earth: the errors in the local NED
        frame); with warnings where the linear model may not hold (a range exceeded, large
        attitude errors).

    Raises
    ------
    ImunavError
        For a bad rate, duration or gravity.
    NotImplementedError
        If a term of ``imu`` has no linearisation.
    """
    duration = span(motion, rate, duration)
    traj = trajectory or Trajectory.of(motion, rate, duration, g)
    sources, warnings = linearise(imu, traj, kind, imu.decimation(rate))
    sources = _aligned(sources, motion, traj, rate, g, alignment, align_window)
    em = frame_model(traj, vertical)
    terms = {s.name: em.local(traj, P) for s, P in zip(sources, propagate(sources, traj, em),
                                                        strict=True)}
    total = _sum(list(terms.values())) if terms else np.zeros((traj.t.size, 9, 9))
    res = CovarianceResult(traj.t, terms, total, float(rate), imu.name, traj.max_rate,
                           traj.max_force, warnings)
    _attitude_warning(res, bool(terms))
    return res


def _aligned(sources, motion, traj, rate, g, alignment, align_window):
    """The sources as :func:`~imunav.estimation.alignment.levelled_sources` for
    ``alignment="level"`` (levelling at rest at the motion's initial attitude), else as given."""
    alignment, align_window = check_alignment(alignment, align_window, traj.frame)
    if alignment == "truth":
        return sources
    q0 = motion.attitude(np.zeros(1))[0]
    return levelled_sources(sources, q0, align_window, rate, g)


def _sum(parts: list[FloatArray]) -> FloatArray:
    """The terms added in order (as ``sum``): the same bits in the full and streamed totals."""
    total = parts[0].copy()
    for x in parts[1:]:
        total += x
    return total


@renamed(model="imu", output="kind")
def covariance_summary(motion: BaseMotion, imu: ImuModel, rate: float,
                       duration: float | None = None, g: float = G0,
                       kind: str = "increments", *, tolerance: float | None = None,
                       level: float = 0.0, p: float = 0.95, maxima: bool = False,
                       trajectory: LazyTrajectory | None = None, progress: bool = False,
                       chunk: int = CHUNK, vertical: str = "free", alignment: str = "truth",
                       align_window: float = WINDOW) -> CovarianceSummary:
    """:func:`covariance` streamed: the same propagation, a piece of the trajectory at a time,
    keeping only the grid of the envelope and the exact extrema an assessment needs — in memory
    that does not grow with the record.

    Parameters
    ----------
    motion : BaseMotion
    imu : ImuModel
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    g : float
        Gravity magnitude (m/s²).
    kind : {"increments", "rates"}
    tolerance : float, optional
        Track ``min_t P(|δp(t)| ≤ tolerance)`` (m) and its first drop below ``level``.
    level : float
        The probability of the tracked crossing (0: the minimum alone).
    p : float
        The quantile whose maxima over time ``maxima`` tracks.
    maxima : bool
        Track ``max_t`` of the ``p``-quantile of the position error of each term and in total
        (what the inverse design needs).
    trajectory : LazyTrajectory, optional
        The motion already sampled lazily (to share its range peaks).
    progress : bool
        A progress bar (tqdm, on stderr) when the propagation is long (more than a few
        seconds).
    chunk : int
        Steps per piece.
    vertical : {"free", "hold"}
        On the WGS-84 Earth: the vertical channel free or held (a perfect height aid).
    alignment : {"truth", "level"}
        The initial attitude, as :func:`covariance`.
    align_window : float
        Seconds of the levelling window.

    Returns
    -------
    CovarianceSummary
        Its grid values are those of :func:`covariance` at the same output indices, to the bit,
        and its extrema are the exact ones over every output time.

    Raises
    ------
    ImunavError
        For a bad rate, duration or gravity, or a propagation that would not fit in memory
        (with the estimate).
    NotImplementedError
        If a term of ``imu`` has no linearisation.
    """
    duration = span(motion, rate, duration)
    if trajectory is None:
        check_steps(rate, duration)
    traj = trajectory or LazyTrajectory(motion, rate, duration, g)
    sources, warnings = linearise(imu, traj, kind, imu.decimation(rate))
    sources = _aligned(sources, motion, traj, rate, g, alignment, align_window)
    names = [s.name for s in sources]
    n = traj.steps
    grid = envelope_index(n + 1)
    need = summary_memory(sources, grid.size, chunk)
    check_memory(need, f"the covariance analysis of {n:,} steps ({len(sources)} error terms)",
                 "a lower --rate or a shorter duration")
    terms = {k: np.zeros((grid.size, 9, 9)) for k in names}
    total = np.zeros((grid.size, 9, 9))
    if alignment == "level":                                 # the levelled attitude's error
        for k, src in zip(names, sources, strict=True):
            terms[k][0] = src.initial_covariance()[:9, :9]
        total[0] = _sum([terms[k][0] for k in names]) if names else 0.0
    within = WithinTracker(tolerance, level) if tolerance is not None else None
    tracks = {k: MaxQuantileTracker(p) for k in [*names, None]} if maxima and names else {}
    bar = _progress(n, sources, progress)
    gi = 1                                                   # grid[0]: the initial errors
    for lo, hi, covs in propagate_chunks(sources, traj, frame_model(traj, vertical), chunk=chunk,
                                         local=True):
        tot = _sum(covs) if covs else np.zeros((hi - lo, 9, 9))
        at = grid[gi:gi + np.searchsorted(grid[gi:], hi, side="right")] - lo - 1
        if at.size:
            for k, c in zip(names, covs, strict=True):
                terms[k][gi:gi + at.size] = c[at]
            total[gi:gi + at.size] = tot[at]
            gi += at.size
        if within is not None:
            within.update(tot[:, 6:9, 6:9], lo + 1)
        for k, c in zip([*names, None], [*covs, tot], strict=True):
            if k in tracks:
                tracks[k].update(c[:, 6:9, 6:9])
        if bar is not None:
            bar.update(hi - lo)
    if bar is not None:
        bar.close()
    res = CovarianceSummary(grid * traj.h, grid, terms, total, float(rate), imu.name,
                            traj.max_rate, traj.max_force, warnings, traj.h, n,
                            tolerance=tolerance, level=level, p=p,
                            within=None if within is None else (within.minimum, within.first),
                            maxima={k: t.maximum for k, t in tracks.items()},
                            exact_evaluations=(within.exact if within else 0)
                            + sum(t.exact for t in tracks.values()))
    _attitude_warning(res, bool(terms))
    return res


#: The most steps a streamed covariance analysis takes on: it runs some 1e3–1e4 steps a
#: second on one core (measured 2.5e3 flat and 7e2 on the Earth on a loaded 2-core machine),
#: so 1e8 steps would take hours to days, and it would scan the motion for minutes before its
#: progress bar appeared: a duration or rate typed wrong more likely than an analysis to start.
MAX_STEPS = 10**8


def check_steps(rate: float, duration: float) -> int:
    """The step count ``round(duration × rate)``, or an ImunavError above :data:`MAX_STEPS`.

    Parameters
    ----------
    rate : float
        Hz.
    duration : float
        Seconds.

    Returns
    -------
    int

    Raises
    ------
    ImunavError
        Above :data:`MAX_STEPS`, with the time it would take at 1e4 steps/s.
    """
    n = interval_count(rate, duration)
    if n > MAX_STEPS:
        days = n / 1e4 / 86400
        raise ImunavError(f"the covariance analysis of {n:.3g} steps ({duration:g} s at "
                          f"{rate:g} Hz) would take about {days:.3g} days or more (at best some "
                          f"1e4 steps/s); choose a lower rate or a shorter duration "
                          f"(at most {MAX_STEPS:.0e} steps)", argument="duration")
    return n


def summary_memory(sources, points: int, chunk: int = CHUNK) -> float:
    """Bytes a streamed analysis needs about: each piece's systems and their covariances
    (some twenty arrays of ``chunk × (9 + k)²`` per source), the grid, the trajectory piece.

    Parameters
    ----------
    sources : list of ErrorSource
    points : int
        Grid points kept.
    chunk : int

    Returns
    -------
    float
    """
    states = sum((9 + s.block_size) ** 2 for s in sources)
    return 8.0 * (20 * chunk * states + points * 81 * (len(sources) + 1) + 40 * chunk) + 50e6


#: Steps × states above which a streamed analysis shows progress (about three seconds).
PROGRESS_WORK = 6e6


def _progress(steps: int, sources, enabled: bool):
    """A tqdm bar (terminal or notebook) for propagations of more than a few seconds only."""
    work = steps * sum(9 + s.block_size for s in sources)
    if not enabled or work < PROGRESS_WORK:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=steps, desc="covariance", unit="step", unit_scale=True, mininterval=1.0)


def _attitude_warning(res, any_terms: bool) -> None:
    att = float(res.attitude_quantile(index=-1)) if any_terms else 0.0
    if att > LINEAR_LIMIT:
        res.warnings.append(f"the 95th-percentile attitude error reaches {att:.2g} rad: beyond "
                            f"about {LINEAR_LIMIT} rad the small-angle error model is not "
                            "reliable, and the covariance's verdict is not SUITABLE on its own "
                            "word: use --method montecarlo (or auto)")
