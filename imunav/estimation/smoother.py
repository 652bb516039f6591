"""The Rauch–Tung–Striebel smoother: the backward pass over a Kalman filter's stored history.

For a linear system ``x_{k+1} = Φ_k x_k + u_k + w_k`` the filter gives, at each epoch, the
filtered ``(x⁺_k, P⁺_k)`` and the predicted ``(x⁻_{k+1}, P⁻_{k+1})``; the smoother runs back
from the last epoch (where smoothed = filtered)::

    A_k   = P⁺_k Φ_kᵀ (P⁻_{k+1})⁻¹
    x^s_k = x⁺_k + A_k (x^s_{k+1} − x⁻_{k+1})
    P^s_k = P⁺_k + A_k (P^s_{k+1} − P⁻_{k+1}) A_kᵀ

(Rauch, Tung & Striebel 1965). On a linear-Gaussian problem it equals the batch least-squares
solution over all measurements (``tests/test_filter.py`` checks it to 1e-9). The error-state
filter of :mod:`imunav.estimation.filters` uses :func:`rts_step` on its own history (in the
coordinates where its predicted error is zero, see there).

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.linalg import cho_factor, cho_solve

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError

__all__ = ["rts", "rts_gain", "rts_step"]


def rts_gain(P_f: FloatArray, Phi: FloatArray, P_p: FloatArray) -> FloatArray:
    """``A = P⁺ Φᵀ (P⁻)⁻¹``, by a Cholesky solve (a pseudo-inverse if ``P⁻`` is singular).

    Parameters
    ----------
    P_f : ndarray, shape (n, n)
        Filtered covariance at k.
    Phi : ndarray, shape (n, n)
        Transition k → k + 1.
    P_p : ndarray, shape (n, n)
        Predicted covariance at k + 1.

    Returns
    -------
    ndarray, shape (n, n)
    """
    B = Phi @ P_f                                    # (P_f Φᵀ)ᵀ
    try:
        return cho_solve(cho_factor(P_p), B).T
    except np.linalg.LinAlgError:
        return (np.linalg.pinv(P_p, hermitian=True) @ B).T


def rts_step(x_f, P_f, Phi, x_p, P_p, x_s_next, P_s_next) -> tuple[FloatArray, FloatArray]:
    """One backward step of the smoother.

    Parameters
    ----------
    x_f, P_f : ndarray
        Filtered state and covariance at k.
    Phi : ndarray
        Transition k → k + 1.
    x_p, P_p : ndarray
        Predicted state and covariance at k + 1.
    x_s_next, P_s_next : ndarray
        Smoothed state and covariance at k + 1.

    Returns
    -------
    x_s, P_s : ndarray
        Smoothed at k.
    """
    A = rts_gain(P_f, Phi, P_p)
    x = x_f + A @ (x_s_next - x_p)
    P = P_f + A @ (P_s_next - P_p) @ A.T
    return x, 0.5 * (P + P.T)


def rts(x_f: npt.ArrayLike, P_f: npt.ArrayLike, x_p: npt.ArrayLike, P_p: npt.ArrayLike,
        Phi: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Smooth a whole filtered history.

    Parameters
    ----------
    x_f : array_like, shape (K + 1, n)
        Filtered states at epochs 0 … K.
    P_f : array_like, shape (K + 1, n, n)
    x_p : array_like, shape (K, n)
        Predicted states at epochs 1 … K (from the epoch before).
    P_p : array_like, shape (K, n, n)
    Phi : array_like, shape (K, n, n)
        Transitions from epoch k to k + 1.

    Returns
    -------
    x_s : ndarray, shape (K + 1, n)
    P_s : ndarray, shape (K + 1, n, n)

    Raises
    ------
    ImunavError
        For shapes that do not fit together.
    """
    x_f, P_f, x_p, P_p, Phi = (np.asarray(a, dtype=float) for a in (x_f, P_f, x_p, P_p, Phi))
    K1, n = x_f.shape
    if (P_f.shape != (K1, n, n) or x_p.shape != (K1 - 1, n) or P_p.shape != (K1 - 1, n, n)
            or Phi.shape != (K1 - 1, n, n)):
        raise ImunavError(f"rts needs x_f (K+1, n), P_f (K+1, n, n), x_p (K, n), P_p (K, n, n) "
                          f"and Phi (K, n, n); got {x_f.shape}, {P_f.shape}, {x_p.shape}, "
                          f"{P_p.shape}, {Phi.shape}")
    x_s, P_s = x_f.copy(), P_f.copy()
    for k in range(K1 - 2, -1, -1):
        x_s[k], P_s[k] = rts_step(x_f[k], P_f[k], Phi[k], x_p[k], P_p[k], x_s[k + 1],
                                  P_s[k + 1])
    return x_s, P_s
