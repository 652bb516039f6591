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

from dataclasses import dataclass

import numpy as np
from scipy.special import erf, gammaincinv, ndtri

from imunav.analysis.gaussnorm import chi3_cdf, norm_cdf, norm_quantile
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.estimation.error_model import Trajectory, linearise
from imunav.estimation.propagation import propagate
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel

__all__ = ["LINEAR_LIMIT", "CovarianceResult", "Trajectory", "covariance"]


@dataclass
class CovarianceResult:
    """Nav-error covariances (N + 1, 9, 9) per error term and in total, at the output times."""

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
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp(t)| ≤ tolerance)`` at every output time."""
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """``max_t`` of the ``p``-quantile of the position error: exact quantiles only where
        the bounds from the largest eigenvalue (``|N(0, λ₁)|`` ≤ q ≤ ``√λ₁·χ₃``) leave the
        maximum possible."""
        P = (self.total if term is None else self.terms[term])[:, 6:9, 6:9]
        top = np.sqrt(np.maximum(np.linalg.eigvalsh(P)[:, -1], 0.0))
        lo, hi = top * ndtri((1 + p) / 2), top * np.sqrt(2 * gammaincinv(1.5, p))
        cand = hi >= lo.max()
        return float(norm_quantile(P[cand], p).max())

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """``(min_t P(|δp(t)| ≤ tol), first index where it is below level)`` — exact CDFs
        only where the bounds ``F_χ₃(tol/√λ₁) ≤ P ≤ erf(tol/√(2λ₁))`` (λ₁ the largest
        eigenvalue) leave the answer open."""
        P = self.total[:, 6:9, 6:9]
        lam = np.maximum(np.linalg.eigvalsh(P)[:, -1], 0.0)
        with np.errstate(divide="ignore"):
            s = tolerance / np.sqrt(lam)                     # inf where the error is 0
        lower, upper = chi3_cdf(s), erf(s / np.sqrt(2))
        sure = np.nonzero(upper < level)[0]
        stop = sure[0] if sure.size else lam.size
        cand = (lower <= upper.min()) | ((lower < level) & (np.arange(lam.size) <= stop))
        idx = np.nonzero(cand)[0]
        exact = norm_cdf(P[idx], tolerance)
        below = idx[exact < level]
        first = min(int(below[0]) if below.size else lam.size, int(stop))
        return float(exact.min()), (first if first < lam.size else None)

    def min_position_within(self, tolerance: float) -> float:
        """``min_t P(|δp(t)| ≤ tolerance)`` (see :meth:`within_summary`)."""
        return self.within_summary(tolerance, 0.0)[0]


#: Above this 95th-percentile attitude error (rad) the small-angle model is no longer reliable.
LINEAR_LIMIT = 0.3


def covariance(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
               g: float = G0, output: str = "increments", trajectory: Trajectory | None = None
               ) -> CovarianceResult:
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

    Returns
    -------
    CovarianceResult
        Per term and in total, at the output times; with warnings where the linear model may
        not hold (a range exceeded, large attitude errors).

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
    terms = dict(zip([s.name for s in sources], propagate(sources, traj), strict=True))
    total = sum(terms.values()) if terms else np.zeros((traj.t.size, 9, 9))
    res = CovarianceResult(traj.t, terms, total, float(rate), model.name, traj.max_rate,
                           traj.max_force, warnings)
    att = float(res.attitude_quantile(index=-1)) if terms else 0.0
    if att > LINEAR_LIMIT:
        warnings.append(f"the 95th-percentile attitude error reaches {att:.2g} rad: beyond about "
                        f"{LINEAR_LIMIT} rad the small-angle error model is not reliable; use "
                        "--method montecarlo")
    return res
