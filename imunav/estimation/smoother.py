"""The Rauch–Tung–Striebel smoother: the backward pass over a Kalman filter's stored history.

For a linear system ``x_{k+1} = Φ_k x_k + u_k + w_k`` the filter gives, at each epoch, the
filtered ``(x⁺_k, P⁺_k)`` and the predicted ``(x⁻_{k+1}, P⁻_{k+1})``; the smoother runs back
from the last epoch (where smoothed = filtered)::

    A_k   = P⁺_k Φ_kᵀ (P⁻_{k+1})⁻¹
    x^s_k = x⁺_k + A_k (x^s_{k+1} − x⁻_{k+1})
    P^s_k = P⁺_k + A_k (P^s_{k+1} − P⁻_{k+1}) A_kᵀ

(Rauch, Tung & Striebel 1965). On a linear-Gaussian problem it equals the batch least-squares
solution over all measurements (``tests/estimation/test_filters.py`` checks it to 1e-9).

The error-state filter of :mod:`imunav.estimation.filters` runs :func:`rts_step` over its own
history (:func:`smooth_history`) in the coordinates of the uncorrected state at each epoch: the
filter feeds its estimate back and restarts its error state from zero, so at every epoch the
predicted error is zero (``x⁻ = 0``) and the filtered one is the correction ``x̂`` it applied;
between two epochs the error state evolves by the covariance steps' ``Φ`` with nothing fed back.
The smoothed error of the uncorrected state ``x^s`` gives that of the corrected (reported)
state as ``x^s − x̂``.

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.linalg import cho_factor, cho_solve

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError

__all__ = ["rts", "rts_gain", "rts_step", "smooth_history"]


def rts_gain(P_f: FloatArray, Phi: FloatArray, P_p: FloatArray) -> FloatArray:
    """``A = P⁺ Φᵀ (P⁻)⁻¹`` (a pseudo-inverse if ``P⁻`` is singular); one filter or a batch.

    Parameters
    ----------
    P_f : ndarray, shape (..., n, n)
        Filtered covariance at k.
    Phi : ndarray, shape (..., n, n)
        Transition k → k + 1.
    P_p : ndarray, shape (..., n, n)
        Predicted covariance at k + 1.

    Returns
    -------
    ndarray, shape (..., n, n)
    """
    B = Phi @ P_f                                    # (P_f Φᵀ)ᵀ
    try:
        if B.ndim == 2:
            return cho_solve(cho_factor(P_p), B).T
        np.linalg.cholesky(P_p)
        return np.swapaxes(np.linalg.solve(P_p, B), -1, -2)
    except np.linalg.LinAlgError:
        return np.swapaxes(np.linalg.pinv(P_p, hermitian=True) @ B, -1, -2)


def rts_step(x_f, P_f, Phi, x_p, P_p, x_s_next, P_s_next) -> tuple[FloatArray, FloatArray]:
    """One backward step of the smoother (one filter, or a batch with leading axes).

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
    x = x_f + np.einsum("...ij,...j->...i", A, x_s_next - x_p)
    P = P_f + A @ (P_s_next - P_p) @ np.swapaxes(A, -1, -2)
    return x, 0.5 * (P + np.swapaxes(P, -1, -2))


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


def smooth_history(segments, x_last: FloatArray, P_last: FloatArray, n_epochs: int, nav: int
                   ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The RTS backward pass over an error-state filter's history (see the module docstring).

    Parameters
    ----------
    segments : list of tuple
        Per interval between two epochs with readings, in time order: ``(x_first, P_first,
        steps)`` — the correction applied and the covariance after it at the interval's start
        ((R, n), (R, n, n)), and the interval's covariance steps as a list of
        ``(Phi, P_predicted)`` ((R, n, n) each).
    x_last, P_last : ndarray, shapes (R, n), (R, n, n)
        The correction and covariance at the last epoch (there smoothed = filtered).
    n_epochs : int
        Covariance epochs in all (one per step, and the start).
    nav : int
        The navigation errors: the first ``nav`` states.

    Returns
    -------
    err : ndarray, shape (E, R, nav)
        The smoothed navigation error of the corrected state at each epoch.
    err_prior : ndarray, shape (E, R, nav)
        … of the uncorrected state.
    P_s : ndarray, shape (E, R, nav, nav)
        Its covariance.
    """
    R = x_last.shape[0]
    xs, Ps = x_last.copy(), P_last.copy()
    err = np.zeros((n_epochs, R, nav))
    err_prior = np.zeros((n_epochs, R, nav))
    P_s = np.zeros((n_epochs, R, nav, nav))
    j = n_epochs - 1
    err_prior[j], P_s[j] = x_last[:, :nav], P_last[:, :nav, :nav]
    zero = np.zeros_like(x_last)
    for x_first, P_first, steps in reversed(segments):
        Pf = [P_first] + [P for _, P in steps]
        for i in range(len(steps) - 1, -1, -1):
            x_f = x_first if i == 0 else zero
            xs, Ps = rts_step(x_f, Pf[i], steps[i][0], zero, Pf[i + 1], xs, Ps)
            j -= 1
            err_prior[j] = xs[:, :nav]
            err[j] = xs[:, :nav] - x_f[:, :nav]
            P_s[j] = Ps[:, :nav, :nav]
    return err, err_prior, P_s
