"""Exact extrema over time of a streamed covariance analysis, at a fraction of the cost of
evaluating every step: ``min_t P(|δp(t)| ≤ tol)`` and its first drop below a level
(:class:`WithinTracker`), ``max_t`` of a quantile of ``|δp(t)|`` (:class:`MaxQuantileTracker`).
Each step's eigenvalue bounds (:mod:`imunav.analysis.gaussnorm`) decide what they can; the
exact integral is evaluated only where they leave the answer open.

May import: ``imunav.core``, ``imunav.analysis.gaussnorm``.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaincinv, ndtri

from imunav.analysis.gaussnorm import (
    eigenvalues,
    norm_cdf,
    norm_cdf_bounds,
    norm_quantile,
    tabulated_quantile_bounds,
)
from imunav.core.kernels import FloatArray

__all__ = ["BATCH", "BUFFER", "MARGIN", "NEAR_ONE", "NEAR_ONE_BUDGET", "RELATIVE",
           "MaxQuantileTracker", "WithinTracker"]

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
