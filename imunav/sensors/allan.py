"""Allan deviation: the overlapping estimator, and the analytic Allan variance of the processes
the error models use (for self-checks and fits).

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.rotations import FloatArray


def gauss_markov_allan_variance(tau: FloatArray, sigma: float, T: float) -> FloatArray:
    """Allan variance of a first-order Gauss–Markov process (std σ, correlation time T)."""
    q = 2 * sigma**2 / T
    x = tau / T
    return q * T**2 / tau * (1 - (3 - 4 * np.exp(-x) + np.exp(-2 * x)) / (2 * x))


def allan_deviation(x: FloatArray, rate: float, taus=None) -> tuple[FloatArray, FloatArray]:
    """Overlapping Allan deviation of rate samples ``x`` (n,) or (n, k) at ``rate`` Hz.

    Returns ``(taus, adev)`` with ``adev`` of shape (len(taus),) or (len(taus), k).
    """
    x = np.asarray(x, float)
    n = x.shape[0]
    if taus is None:
        ms = np.unique(np.logspace(0, np.log10(n // 3), 40).astype(int))
    else:
        ms = np.unique(np.maximum(1, np.round(np.asarray(taus) * rate).astype(int)))
        ms = ms[ms <= (n - 1) // 2]
    theta = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)]) / rate
    out = []
    for m in ms:
        d = theta[2 * m:] - 2 * theta[m:-m] + theta[: -2 * m]
        tau = m / rate
        out.append(np.sqrt(np.mean(d * d, axis=0) / (2 * tau * tau)))
    return ms / rate, np.array(out)
