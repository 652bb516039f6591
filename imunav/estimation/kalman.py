"""The generic Kalman steps: prediction with a discrete system, and the measurement update in
Joseph form, with an optional χ² innovation gate.

These know nothing of navigation: the error model supplies ``(Φ, Q_d)``
(:mod:`~imunav.estimation.error_model`), a measurement its ``(z, H, R)``. The Joseph form
``P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ`` keeps ``P`` symmetric and positive semi-definite for any
gain (round-off in the optimal gain cannot make it indefinite, as ``(I − K H) P`` can), and equals
the textbook update for the optimal gain ``K = P Hᵀ S⁻¹``, ``S = H P Hᵀ + R``.

May import: ``imunav.core``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import numpy.typing as npt
from scipy.linalg import cho_factor, cho_solve
from scipy.stats import chi2

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, as_float_array

__all__ = ["Update", "predict", "update"]


def predict(x: npt.ArrayLike, P: npt.ArrayLike, Phi: npt.ArrayLike, Qd: npt.ArrayLike
            ) -> tuple[FloatArray, FloatArray]:
    """One prediction step: ``x ← Φ x``, ``P ← Φ P Φᵀ + Q_d``.

    Parameters
    ----------
    x : array_like, shape (n,)
    P : array_like, shape (n, n)
    Phi : array_like, shape (n, n)
    Qd : array_like, shape (n, n)

    Returns
    -------
    x, P : ndarray
        The predicted state and covariance (``P`` symmetrised).

    Examples
    --------
    >>> import numpy as np
    >>> x, P = predict([1.0, 0.5], np.eye(2), [[1.0, 0.1], [0.0, 1.0]], 0.01 * np.eye(2))
    >>> x
    array([1.05, 0.5 ])
    """
    x = np.asarray(x, dtype=float)
    Phi = np.asarray(Phi, dtype=float)
    P = Phi @ np.asarray(P, dtype=float) @ Phi.T + np.asarray(Qd, dtype=float)
    return Phi @ x, 0.5 * (P + P.T)


@dataclass
class Update:
    """The result of one measurement update.

    Attributes
    ----------
    x, P : ndarray
        The updated state and covariance (unchanged when the measurement was rejected).
    innovation : ndarray, shape (m,)
        ``z − H x`` (before the update).
    S : ndarray, shape (m, m)
        Its covariance ``H P Hᵀ + R``.
    nis : float
        The normalised innovation squared ``νᵀ S⁻¹ ν`` (χ² with m degrees of freedom when the
        filter is consistent).
    accepted : bool
        False when the gate rejected the measurement.
    """

    x: FloatArray
    P: FloatArray
    innovation: FloatArray
    S: FloatArray
    nis: float
    accepted: bool = True


@lru_cache(maxsize=256)
def _quantile(p: float, dof: int) -> float:
    """The χ² quantile of the gate (remembered: a filter gates thousands of readings alike)."""
    return float(chi2.ppf(p, dof))


def update(x: npt.ArrayLike, P: npt.ArrayLike, z: npt.ArrayLike, H: npt.ArrayLike,
           R: npt.ArrayLike, *, gate: float | None = None) -> Update:
    """One measurement update in Joseph form.

    Parameters
    ----------
    x : array_like, shape (n,)
        The state (for an error-state filter, the error estimate).
    P : array_like, shape (n, n)
    z : array_like, shape (m,)
        The measurement (an error-state filter: the measured minus the predicted value).
    H : array_like, shape (m, n)
    R : array_like, shape (m, m)
        Measurement noise covariance (symmetric positive definite).
    gate : float, optional
        Probability of the χ² gate (e.g. 0.999): a measurement whose NIS exceeds the gate's
        quantile for m degrees of freedom is rejected (``accepted`` False, state unchanged).

    Returns
    -------
    Update

    Raises
    ------
    ImunavError
        For shapes that do not fit, a ``gate`` outside (0, 1), or an innovation covariance that
        is not positive definite.

    Examples
    --------
    >>> import numpy as np
    >>> u = update([0.0], [[4.0]], [1.0], [[1.0]], [[1.0]])
    >>> round(float(u.x[0]), 3), round(float(u.P[0, 0]), 3)
    (0.8, 0.8)
    """
    x = as_float_array(x, "x", ndim=1)
    n = x.size
    P = as_float_array(P, "P", ndim=2)
    z = np.atleast_1d(as_float_array(z, "z"))
    m = z.size
    H = as_float_array(H, "H", ndim=2)
    R = as_float_array(R, "R", ndim=2)
    if P.shape != (n, n) or H.shape != (m, n) or R.shape != (m, m):
        raise ImunavError(f"update needs P ({n}, {n}), H ({m}, {n}) and R ({m}, {m}) for x of "
                          f"size {n} and z of size {m}; got P {P.shape}, H {H.shape}, "
                          f"R {R.shape}")
    if gate is not None and not 0 < gate < 1:
        raise ImunavError(f"gate must be a probability in (0, 1), got {gate!r}")
    nu = z - H @ x
    PHt = P @ H.T
    S = H @ PHt + R
    S = 0.5 * (S + S.T)
    try:
        cs = cho_factor(S)
    except np.linalg.LinAlgError:
        raise ImunavError("the innovation covariance H P Hᵀ + R is not positive definite "
                          "(check R)") from None
    nis = float(nu @ cho_solve(cs, nu))
    if gate is not None and nis > _quantile(gate, m):
        return Update(x, P, nu, S, nis, accepted=False)
    K = cho_solve(cs, PHt.T).T                             # P Hᵀ S⁻¹
    A = np.eye(n) - K @ H
    Pn = A @ P @ A.T + K @ R @ K.T
    return Update(x + K @ nu, 0.5 * (Pn + Pn.T), nu, S, nis)
