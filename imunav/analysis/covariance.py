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

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis.gaussnorm``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.special import gammaincinv, ndtri

from imunav.analysis.gaussnorm import (
    eigenvalues,
    norm_cdf,
    norm_cdf_bounds,
    norm_quantile,
    tabulated_quantile_bounds,
)
from imunav.core.constants import G0
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

#: How far (in probability, or relatively for a quantile) a bound must clear a threshold to
#: decide without the exact integral, which is itself good to about 1e-11.
MARGIN = 1e-9

#: The same, relative to the smallest probability found (which can be tiny).
RELATIVE = 1e-9

#: Probabilities whose lower bounds are all this close to 1 are equal to the exact integral's
#: accuracy: beyond :data:`NEAR_ONE_BUDGET` exact evaluations of them (a long record where the
#: error never comes near the tolerance) only the most promising step of each piece is.
NEAR_ONE = 1e-9
NEAR_ONE_BUDGET = 20_000

#: Steps evaluated exactly at once while pruning.
BATCH = 64

#: Candidate steps kept before they are resolved by exact evaluations.
BUFFER = 4096


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


class _Candidates:
    """Steps that may still hold an extremum: their covariances and bounds, kept until the
    bounds of later steps rule them out, resolved by exact evaluations only when the buffer
    fills or the answer is asked for — so a quantity that keeps growing (or shrinking) along
    the record costs about one exact evaluation per buffer, not one per piece.

    ``sign`` +1 tracks a maximum (keep steps whose upper bound reaches the best lower bound),
    −1 a minimum (the mirror). ``exact(P)`` evaluates the covariances (n, 3, 3)."""

    def __init__(self, sign: int, exact, start: float):
        self.sign, self.exact = sign, exact
        self.best = start                 # an exact value reached (the extremum so far)
        self.floor = start                # a bound the extremum is known to reach
        self.P = np.zeros((0, 3, 3))
        self.lo = self.hi = np.zeros(0)   # bounds in the tracked direction (lo ≤ value ≤ hi)
        self.evaluated = 0
        self.near = 0                     # exact evaluations of values within NEAR_ONE of 1

    def _reach(self, hi: FloatArray, floor: float) -> np.ndarray:
        """Whether a step with upper bound ``hi`` may still reach the extremum ``floor``
        (relative margin: the exact values are good to ~1e-11 of themselves)."""
        return hi >= floor - abs(floor) * RELATIVE

    def add(self, P: FloatArray, lo: FloatArray, hi: FloatArray) -> None:
        """Offer steps with bounds ``lo ≤ value ≤ hi`` (in the tracked direction)."""
        if lo.size:
            self.floor = max(self.floor, float(lo.max()))
        keep = self._reach(hi, self.floor)
        self.P = np.concatenate([self.P, P[keep]])
        self.lo, self.hi = np.concatenate([self.lo, lo[keep]]), np.concatenate([self.hi, hi[keep]])
        old = self._reach(self.hi, self.floor)
        self.P, self.lo, self.hi = self.P[old], self.lo[old], self.hi[old]
        if self.hi.size > BUFFER:
            self.resolve()

    def resolve(self, near_budget=None) -> float:
        """Evaluate what remains, most promising first, pruning as exact values come in.

        Returns
        -------
        float
            The extremum (in the tracked direction's sign convention).
        """
        order = np.argsort(-self.hi, kind="stable")
        P, lo, hi = self.P[order], self.lo[order], self.hi[order]
        size = 1
        while hi.size:
            if near_budget is not None and lo.min() >= near_budget[0]:
                if self.near >= near_budget[1]:          # within 1e-9 of 1: to that accuracy
                    P, lo, hi = P[:1], lo[:1], hi[:1]
            n = min(size, hi.size)
            vals = self.sign * self.exact(P[:n])
            self.evaluated += n
            if near_budget is not None and lo[:n].min() >= near_budget[0]:
                self.near += n
            self.best = max(self.best, float(vals.max()))
            self.floor = max(self.floor, self.best)
            P, lo, hi = P[n:], lo[n:], hi[n:]
            keep = self._reach(hi, self.best)
            P, lo, hi = P[keep], lo[keep], hi[keep]
            size = BATCH
        self.P, self.lo, self.hi = P, lo, hi
        return self.best


class WithinTracker:
    """``min_t P(|δp(t)| ≤ tol)`` and the first time it drops below ``level``, exactly, from
    the covariances handed to it piece by piece (:meth:`update`).

    Each step's eigenvalue bounds (:func:`~imunav.analysis.gaussnorm.norm_cdf_bounds`, and for
    the crossing the tabulated quantile bounds) decide what they can; the exact integral is
    evaluated only where they leave the answer open: for the crossing, the steps before the
    first certain one that the bounds do not clear, in order, until one is below; for the
    minimum, the steps whose lower bound does not exceed the smallest upper bound seen, kept
    until later steps rule them out and evaluated most promising first. Exact (the
    brute-force scan's value) wherever a probability is below ``1 − 1e-9``; where all are
    within 1e-9 of 1 — the exact integral's own accuracy — beyond :data:`NEAR_ONE_BUDGET`
    evaluations, to that accuracy.

    Parameters
    ----------
    tolerance : float
        The radius (m), > 0.
    level : float
        The probability whose first crossing is tracked (0: none).

    Attributes
    ----------
    first : int or None
        The first output index where the probability is below ``level``.
    """

    def __init__(self, tolerance: float, level: float):
        self.tolerance, self.level = float(tolerance), float(level)
        self.first, self._crossing = None, 0
        self._min = _Candidates(-1, self._cdf, -1.0)     # −P: 1 at the start (no error yet)

    def _cdf(self, P: FloatArray) -> FloatArray:
        return norm_cdf(P, self.tolerance)

    @property
    def minimum(self) -> float:
        """The smallest probability so far (exact)."""
        return -self._min.resolve((1 - NEAR_ONE, NEAR_ONE_BUDGET))

    @property
    def exact(self) -> int:
        """How many steps needed the exact integral."""
        return self._min.evaluated + self._crossing

    def update(self, P: FloatArray, start: int) -> None:
        """Take the position covariances ``P`` (T, 3, 3) of output indices ``start …``.

        Parameters
        ----------
        P : ndarray, shape (T, 3, 3)
        start : int
            The output index of ``P[0]``.
        """
        T = P.shape[0]
        lam = eigenvalues(P)
        lower, upper = norm_cdf_bounds(lam, self.tolerance)
        if self.first is None and self.level > 0:
            sure = upper < self.level - MARGIN
            clear = lower >= self.level + MARGIN
            if np.count_nonzero(~sure & ~clear) > 2 * BATCH:
                # P(|δp| ≤ tol) < level ⇔ the level-quantile exceeds tol: the tabulated bounds
                # of the quantile decide most of what the probability's bounds leave open
                qlo, qhi = tabulated_quantile_bounds(lam, self.level)
                sure |= qlo > self.tolerance * (1 + MARGIN)
                clear |= qhi < self.tolerance * (1 - MARGIN)
            hit = np.nonzero(sure)[0]
            stop = int(hit[0]) if hit.size else T
            amb = np.nonzero(~clear[:stop])[0]
            first = stop
            for b in range(0, amb.size, BATCH):
                sel = amb[b:b + BATCH]
                vals = self._cdf(P[sel])
                self._crossing += sel.size
                below = np.nonzero(vals < self.level)[0]
                if below.size:
                    first = int(sel[below[0]])
                    break
            if first < T:
                self.first = start + first
        self._min.add(P, -upper, -lower)


class MaxQuantileTracker:
    """``max_t`` of the ``p``-quantile of ``|δp(t)|``, exactly, from covariances handed to it
    piece by piece (:meth:`update`): a step is kept only while an upper bound of its quantile
    (from the trace, then the tabulated bounds of its eigenvalues) reaches the largest lower
    bound seen, and evaluated exactly only if it still may when the answer is asked for.

    Parameters
    ----------
    p : float
        In (0, 1).
    """

    def __init__(self, p: float):
        self.p = float(p)
        self._lo, self._hi = ndtri((1 + p) / 2), np.sqrt(2 * gammaincinv(1.5, p))
        self._max = _Candidates(1, lambda P: norm_quantile(P, self.p), 0.0)

    @property
    def maximum(self) -> float:
        """The largest quantile so far (exact; 0 at the start)."""
        return self._max.resolve()

    @property
    def exact(self) -> int:
        """How many steps needed the exact quantile."""
        return self._max.evaluated

    def update(self, P: FloatArray) -> None:
        """Take the position covariances ``P`` (T, 3, 3).

        Parameters
        ----------
        P : ndarray, shape (T, 3, 3)
        """
        tr = np.maximum(np.trace(P, axis1=-2, axis2=-1), 0.0)
        # λ₁ ≤ tr ≤ 3 λ₁: |N(0, tr/3)| ≤ … ≤ √tr·χ₃ brackets every quantile
        lo_tr, hi_tr = np.sqrt(tr / 3) * self._lo, np.sqrt(tr) * self._hi
        floor = max(self._max.floor, float(lo_tr.max()) if tr.size else 0.0)
        cand = np.nonzero(self._max._reach(hi_tr, floor) & (tr > 0))[0]    # 0: exactly 0
        if cand.size == 0:
            return
        lo, hi = tabulated_quantile_bounds(eigenvalues(P[cand]), self.p)
        self._max.add(P[cand], np.maximum(lo, lo_tr[cand]) * (1 - MARGIN),
                      np.minimum(hi, hi_tr[cand]) * (1 + MARGIN))


@dataclass
class CovarianceResult:
    """Nav-error covariances (N + 1, 9, 9) per error term and in total, at the output times.

    What :func:`covariance` returns. The error state is ``[φ, δv, δp]``: attitude error (rad),
    velocity error (m/s) and position error (m), each in the navigation frame (NED; on the
    WGS-84 Earth the local NED frame).

    Attributes
    ----------
    t : ndarray, shape (N + 1,)
        The output times (s).
    terms : dict of str to ndarray, shape (N + 1, 9, 9)
        Each error term's covariance, keyed ``"gyro.bias"`` etc. (independent sources: they
        add).
    total : ndarray, shape (N + 1, 9, 9)
        Their sum.
    rate : float
        The output rate (Hz).
    model : str
        The IMU model's name.
    max_rate : float
        The motion's largest ``|ω_b|`` (rad/s).
    max_force : float
        The motion's largest ``|f_b|`` (m/s²).
    warnings : list of str
        Where the linear model may not hold (a range exceeded, large attitude errors).

    Examples
    --------
    An accelerometer bias of σ = 0.01 m/s² per axis, at rest for 10 s: δp = ½ b t² is normal
    with σ = 0.5 m per axis, so its norm's 95th percentile is 0.5 m × √χ²₃(0.95):

    >>> import numpy as np
    >>> from scipy.stats import chi2
    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> r = covariance(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)), rate=10)
    >>> list(r.terms), r.t.shape
    (['accel.bias'], (101,))
    >>> bool(np.isclose(r.position_quantile(index=-1), 0.5 * np.sqrt(chi2.ppf(0.95, 3))))
    True
    """

    t: FloatArray
    terms: dict[str, FloatArray]
    total: FloatArray
    rate: float
    model: str
    max_rate: float
    max_force: float
    warnings: list[str]

    def position_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the position error's norm ``|δp|`` (m).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone (a key of :attr:`terms`); default all together.
        index : int, slice or array, default all
            Output times.

        Returns
        -------
        ndarray or float
            The quantile (m) at each selected output time.
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the attitude error's norm ``|φ|`` (rad).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone (a key of :attr:`terms`); default all together.
        index : int, slice or array, default all
            Output times.

        Returns
        -------
        ndarray or float
            The quantile (rad) at each selected output time.
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp(t)| ≤ tolerance)`` at every output time.

        Parameters
        ----------
        tolerance : float
            The radius (m).

        Returns
        -------
        ndarray, shape (N + 1,)
            The probability at each output time.
        """
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """``max_t`` of the ``p``-quantile of the position error's norm.

        Exact quantiles are computed only where eigenvalue bounds leave the maximum possible
        (:class:`MaxQuantileTracker`).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone; default all together.

        Returns
        -------
        float
            The largest quantile over the output times (m).
        """
        P = (self.total if term is None else self.terms[term])[:, 6:9, 6:9]
        track = MaxQuantileTracker(p)
        for lo in range(0, P.shape[0], CHUNK):
            track.update(P[lo:lo + CHUNK])
        return track.maximum

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """The smallest probability of staying within ``tolerance``, and when it first drops
        below ``level``.

        Exact CDFs are computed only where the eigenvalue bounds leave the answer open
        (:class:`WithinTracker`).

        Parameters
        ----------
        tolerance : float
            The radius (m).
        level : float
            The probability whose first crossing is wanted (0: none).

        Returns
        -------
        minimum : float
            ``min_t P(|δp(t)| ≤ tolerance)``.
        first : int or None
            The first output index where that probability is below ``level``, or None.
        """
        track = WithinTracker(tolerance, level)
        P = self.total[:, 6:9, 6:9]
        for lo in range(0, P.shape[0], CHUNK):
            track.update(P[lo:lo + CHUNK], lo)
        return track.minimum, track.first

    def min_position_within(self, tolerance: float) -> float:
        """``min_t P(|δp(t)| ≤ tolerance)`` (see :meth:`within_summary`).

        Parameters
        ----------
        tolerance : float
            The radius (m).

        Returns
        -------
        float
            The smallest probability over the output times.
        """
        return self.within_summary(tolerance, 0.0)[0]

    def time_at(self, index: int) -> float:
        """The output time of ``index`` (s).

        Parameters
        ----------
        index : int

        Returns
        -------
        float
        """
        return float(self.t[index])


@dataclass
class CovarianceSummary:
    """What an assessment reads of a covariance analysis, gathered while it is streamed
    (:func:`covariance_summary`): the covariances on the envelope's grid only, and the exact
    extrema over every output time that the verdict and the design need.

    The same reading methods as :class:`CovarianceResult` (a verdict and a plot take either);
    ``index`` arguments count the grid's points.

    Attributes
    ----------
    t : ndarray, shape (G,)
        The grid's times (s): :func:`envelope_index` of the output times.
    index : ndarray of int, shape (G,)
        The grid's output indices.
    terms : dict of str to ndarray, shape (G, 9, 9)
        Each error term's navigation-error covariance on the grid.
    total : ndarray, shape (G, 9, 9)
        Their sum.
    rate : float
    model : str
    max_rate, max_force : float
        The motion's largest ``|ω_b|``, ``|f_b|``.
    warnings : list of str
    h : float
        The output step (s).
    steps : int
        Output steps N (the output times are ``k·h``, k = 0 … N).
    tolerance : float or None
        The radius whose probability was tracked.
    level : float
        The probability whose first crossing was tracked.
    within : tuple or None
        ``(min_t P(|δp| ≤ tolerance), first index below level or None)``.
    p : float
        The quantile whose maxima were tracked.
    maxima : dict
        ``max_t`` of the ``p``-quantile of the position error, per term name and (key None)
        in total, if asked for.
    exact_evaluations : int
        Steps that needed the exact integrals (the rest were decided by bounds).
    """

    t: FloatArray
    index: np.ndarray
    terms: dict[str, FloatArray]
    total: FloatArray
    rate: float
    model: str
    max_rate: float
    max_force: float
    warnings: list[str]
    h: float
    steps: int
    tolerance: float | None = None
    level: float = 0.0
    within: tuple[float, int | None] | None = None
    p: float = 0.95
    maxima: dict = field(default_factory=dict)
    exact_evaluations: int = 0

    def position_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the position error's norm on the grid.

        Parameters
        ----------
        p : float
        term : str, optional
            One term alone (default all together).
        index : int, slice or array
            Grid points.

        Returns
        -------
        ndarray or float
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the attitude error's norm (rad) on the grid.

        Parameters
        ----------
        p : float
        term : str, optional
        index : int, slice or array

        Returns
        -------
        ndarray or float
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp| ≤ tolerance)`` on the grid.

        Parameters
        ----------
        tolerance : float

        Returns
        -------
        ndarray
        """
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """The tracked ``(min_t P(|δp| ≤ tolerance), first output index below level)``.

        Parameters
        ----------
        tolerance, level : float
            As tracked (:func:`covariance_summary`); the minimum alone for level 0.

        Returns
        -------
        tuple

        Raises
        ------
        ValueError
            For a tolerance or level that was not tracked.
        """
        if self.within is None or tolerance != self.tolerance or (level and level != self.level):
            raise ValueError(f"this summary tracked tolerance {self.tolerance} and level "
                             f"{self.level}, not {tolerance} and {level}")
        return self.within if level else (self.within[0], None)

    def min_position_within(self, tolerance: float) -> float:
        """The tracked ``min_t P(|δp| ≤ tolerance)``.

        Parameters
        ----------
        tolerance : float

        Returns
        -------
        float
        """
        return self.within_summary(tolerance, 0.0)[0]

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """The tracked ``max_t`` of the ``p``-quantile of the position error.

        Parameters
        ----------
        p : float
        term : str, optional

        Returns
        -------
        float

        Raises
        ------
        ValueError
            If that maximum was not tracked.
        """
        if p != self.p or term not in self.maxima:
            raise ValueError(f"this summary tracked the maxima of the {self.p} quantile"
                             + ("" if self.maxima else " of nothing"))
        return self.maxima[term]

    def time_at(self, index: int) -> float:
        """The time of output ``index`` (s): ``index·h``.

        Parameters
        ----------
        index : int

        Returns
        -------
        float
        """
        return float(np.float64(index) * self.h)


#: Above this 95th-percentile attitude error (rad) the small-angle model is no longer reliable.
LINEAR_LIMIT = 0.3


def covariance(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
               g: float = G0, output: str = "increments", trajectory: Trajectory | None = None,
               vertical: str = "free", *, alignment: str = "truth",
               align_window: float = WINDOW) -> CovarianceResult:
    """Propagate every sensor error term of ``model`` along ``motion`` at ``rate`` Hz.

    Parameters
    ----------
    motion : BaseMotion
    model : ImuModel
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own (:func:`~imunav.motion.base.span`).
    g : float
        Gravity magnitude (m/s²).
    output : {"increments", "rates"}
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
        If a term of ``model`` has no linearisation.
    """
    duration = span(motion, rate, duration)
    traj = trajectory or Trajectory.of(motion, rate, duration, g)
    sources, warnings = linearise(model, traj, output, model.decimation(rate))
    sources = _aligned(sources, motion, traj, rate, g, alignment, align_window)
    em = frame_model(traj, vertical)
    terms = {s.name: em.local(traj, P) for s, P in zip(sources, propagate(sources, traj, em),
                                                        strict=True)}
    total = _sum(list(terms.values())) if terms else np.zeros((traj.t.size, 9, 9))
    res = CovarianceResult(traj.t, terms, total, float(rate), model.name, traj.max_rate,
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


def covariance_summary(motion: BaseMotion, model: ImuModel, rate: float,
                       duration: float | None = None, g: float = G0,
                       output: str = "increments", *, tolerance: float | None = None,
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
    model : ImuModel
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    g : float
        Gravity magnitude (m/s²).
    output : {"increments", "rates"}
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
        If a term of ``model`` has no linearisation.
    """
    duration = span(motion, rate, duration)
    if trajectory is None:
        check_steps(rate, duration)
    traj = trajectory or LazyTrajectory(motion, rate, duration, g)
    sources, warnings = linearise(model, traj, output, model.decimation(rate))
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
    res = CovarianceSummary(grid * traj.h, grid, terms, total, float(rate), model.name,
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
                            "reliable; use --method montecarlo")
