"""Exact discretisation of the error dynamics over one step: ``(Φ, Q_d)`` from ``(F, Q_c)``.

For a step ``h`` with the motion held at the step's midpoint, the continuous system
``ẋ = F x + w``, ``E[w wᵀ] = Q_c δ``, has the transition ``Φ = e^{F h}`` and the process noise
``Q_d = ∫₀ʰ e^{F s} Q_c e^{Fᵀ s} ds``.

- :func:`flat_transition`: the closed form of ``Φ`` for the flat frame's error model, where the
  navigation block ``A`` is nilpotent (``A³ = 0``) and the sensor states decay independently
  (``diag(D)``): ``Φ = [[e^{A h}, Γ], [0, e^{D h}]]`` with ``Γ = Σ_{i≤2} Aⁱ B φ_i(D)`` and
  ``φ_i`` the integrals of ``(h−s)^i/i! e^{D s}`` (:func:`phi_functions`).
- :func:`process_noise`: ``Q_d`` by 6-node Gauss–Legendre on an exact transition (exact for its
  polynomial part).
- :func:`van_loan`: both from the matrix exponential of ``[[−F, Q_c], [0, Fᵀ]] h`` (Van Loan
  1978) for any ``F``: the general method (a frame whose ``A`` is not nilpotent), and the
  independent check of the closed forms.
- :func:`blocks_from_full`: a full ``(Φ, Q_d)`` split into the blocks of
  :class:`~imunav.estimation.kalman.StepBlocks` (the navigation transition, the sensor-state
  input ``Γ``, the sensor states' diagonal decay, the blocks of ``Q_d``), which is what every
  prediction works on.

May import: ``imunav.core``, ``imunav.estimation.kalman``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.linalg import expm

from imunav.core.kernels import FloatArray
from imunav.estimation.kalman import StepBlocks

__all__ = ["GAUSS_LEGENDRE", "StepBlocks", "blocks_from_full", "flat_transition", "phi_functions",
           "process_noise", "van_loan"]

#: Nodes and weights on [−1, 1] of the quadrature of the process noise.
GAUSS_LEGENDRE = np.polynomial.legendre.leggauss(6)


def phi_functions(d: FloatArray, h: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``φ_i(d) = ∫_0^h (h−s)^i/i! e^{d s} ds`` for i = 0, 1, 2.

    With x = d·h, ``φ_i = h^{i+1} Σ_k x^k/(k+i+1)!``: summed (18 terms, truncation < 1e-18) for
    |x| < 0.5, where the closed forms ``(e^x − 1 − …)/x^{i+1}`` cancel catastrophically (φ2 lost
    7 digits at x = 1e-3); the closed forms, with ``expm1``, above.

    Parameters
    ----------
    d : ndarray
        Decay rates (1/s; ≤ 0 for a stable state), any shape.
    h : float
        The step (s).

    Returns
    -------
    phi0, phi1, phi2 : ndarray
        Each of the shape of ``d``.
    """
    x = d * h
    small = np.abs(x) < 0.5
    xs = np.where(small, 1.0, x)
    em1 = np.expm1(xs)
    s = [np.zeros_like(x, dtype=float) for _ in range(3)]
    xk = np.ones_like(x, dtype=float)
    for k in range(18):
        for i in range(3):
            s[i] = s[i] + xk / math.factorial(k + i + 1)
        xk = xk * x
    p0 = np.where(small, h * s[0], h * em1 / xs)
    p1 = np.where(small, h * h * s[1], h * h * (em1 - xs) / xs**2)
    p2 = np.where(small, h**3 * s[2], h**3 * (em1 - xs - xs * xs / 2) / xs**3)
    return p0, p1, p2


#: φ-functions already computed, by (decay rates, step): a filter discretises thousands of steps
#: of the same few lengths (and their Gauss–Legendre nodes) with the same rates.
_PHI_CACHE: dict[tuple[bytes, float], tuple[FloatArray, FloatArray, FloatArray]] = {}


def _phi_cached(d: FloatArray, h: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`phi_functions`, remembered (at most 4096 entries; a pure function)."""
    key = (np.ascontiguousarray(d, dtype=float).tobytes(), float(h))
    hit = _PHI_CACHE.get(key)
    if hit is None:
        if len(_PHI_CACHE) >= 4096:
            _PHI_CACHE.clear()
        hit = _PHI_CACHE[key] = phi_functions(d, h)
    return hit


def flat_transition(F: FloatArray, B: FloatArray, D: FloatArray, h: float) -> FloatArray:
    """Exact transition over ``h`` of ``[[A, B], [0, diag(D)]]``, ``A`` the flat frame's
    navigation block built from ``F = [f_n×]``.

    Parameters
    ----------
    F : ndarray, shape (N, 3, 3)
        ``[f_n×]`` at each step.
    B : ndarray, shape (N, 9, k)
        Sensor-state input of the navigation errors.
    D : ndarray, shape (k,)
        Decay rates of the sensor states.
    h : float
        The step (s).

    Returns
    -------
    ndarray, shape (N, 9 + k, 9 + k)
    """
    N, k = F.shape[0], D.size
    n = 9 + k
    Phi = np.zeros((N, n, n))
    I3 = np.eye(3)
    Phi[:, 0:3, 0:3] = I3
    Phi[:, 3:6, 0:3] = F * h
    Phi[:, 3:6, 3:6] = I3
    Phi[:, 6:9, 0:3] = F * (h * h / 2)
    Phi[:, 6:9, 3:6] = I3 * h
    Phi[:, 6:9, 6:9] = I3
    if k:
        p0, p1, p2 = _phi_cached(D, h)
        Bphi, Bv = B[:, 0:3], B[:, 3:6]
        G = np.zeros((N, 9, k))
        G += B * p0                                  # B φ0
        G[:, 3:6] += (F @ Bphi) * p1                 # A B φ1: rows δv ← F Bφ, rows δp ← Bv
        G[:, 6:9] += Bv * p1
        G[:, 6:9] += (F @ Bphi) * p2                 # A² B φ2: rows δp ← F Bφ
        Phi[:, :9, 9:] = G
        Phi[:, 9:, 9:] = np.diag(np.exp(D * h))
    return Phi


def process_noise(transition: Callable[[float], FloatArray], Qc: FloatArray, h: float
                  ) -> FloatArray:
    """``Q_d = ∫₀ʰ Φ(s) diag(Qc) Φ(s)ᵀ ds`` by 6-node Gauss–Legendre.

    Parameters
    ----------
    transition : callable
        ``s → Φ(s)`` (N, n, n), the exact transition over ``s``.
    Qc : ndarray, shape (n,)
        Diagonal PSD of the white inputs.
    h : float
        The step (s).

    Returns
    -------
    ndarray, shape (N, n, n)
        Zero where ``Qc`` is all zero.
    """
    Qd = None
    if np.any(Qc):
        x, w = GAUSS_LEGENDRE
        for xi, wi in zip((x + 1) / 2 * h, w / 2 * h, strict=True):
            Ps = transition(xi)
            term = wi * (Ps * Qc[None, None, :]) @ np.swapaxes(Ps, 1, 2)
            Qd = term if Qd is None else Qd + term
    return np.zeros_like(transition(h)) if Qd is None else Qd


def van_loan(F: FloatArray, Qc: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """``(Φ, Q_d)`` of ``ẋ = F x + w`` over ``h`` for any ``F``, by Van Loan's method.

    ``expm([[−F, Q], [0, Fᵀ]] h) = [[·, Φ⁻¹ Q_d], [0, Φᵀ]]``, so ``Φ`` and ``Q_d = Φ (Φ⁻¹ Q_d)``
    follow from one matrix exponential per step (scipy's ``expm``: Padé with scaling and
    squaring).

    Parameters
    ----------
    F : ndarray, shape (N, n, n)
    Qc : ndarray, shape (n,) or (n, n)
        White-noise PSD (a diagonal as a vector).
    h : float

    Returns
    -------
    Phi, Qd : ndarray, shape (N, n, n)
    """
    N, n = F.shape[0], F.shape[-1]
    Q = np.diag(Qc) if np.ndim(Qc) == 1 else np.asarray(Qc)
    M = np.zeros((N, 2 * n, 2 * n))
    M[:, :n, :n] = -F
    M[:, :n, n:] = Q
    M[:, n:, n:] = np.swapaxes(F, 1, 2)
    E = expm(M * h)
    Phi = np.swapaxes(E[:, n:, n:], 1, 2)
    Qd = Phi @ E[:, :n, n:]
    return Phi, 0.5 * (Qd + np.swapaxes(Qd, 1, 2))


def blocks_from_full(Phi: FloatArray, Qd: FloatArray, n: int) -> StepBlocks:
    """Split a full discrete system whose last ``k`` states decay on their own.

    Parameters
    ----------
    Phi, Qd : ndarray, shape (T, n + k, n + k)
        The transition and process noise of each step (``Φ`` with a zero lower-left block, a
        diagonal lower-right block the same at every step, and ``Q_d``'s lower-right block the
        same at every step).
    n : int
        The navigation errors: the first ``n`` states.

    Returns
    -------
    StepBlocks

    Raises
    ------
    ValueError
        If the sensor states are driven by the navigation errors, or do not decay each on
        their own, or change from step to step.
    """
    E = Phi[:, n:, n:]
    decay = np.diagonal(E[0]).copy() if E.shape[0] else np.zeros(E.shape[-1])
    if (np.any(Phi[:, n:, :n]) or np.any(E != np.diag(decay))
            or np.any(Qd[:, n:, n:] != Qd[:1, n:, n:])):
        raise ValueError("blocks_from_full needs sensor states that decay on their own "
                         "(zero lower-left block of Phi, one diagonal lower-right block, "
                         "constant Qd of the states)")
    return StepBlocks(Phi[:, :n, :n], Phi[:, :n, n:], decay, Qd[:, :n, :n], Qd[:, :n, n:],
                      Qd[0, n:, n:] if Qd.shape[0] else np.zeros((decay.size,) * 2))
