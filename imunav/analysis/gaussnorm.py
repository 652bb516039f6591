"""The norm of a zero-mean Gaussian 3-vector: its distribution and percentiles, from the covariance.

For ``x ~ N(0, P)`` with eigenvalues ``λ₁ ≥ λ₂ ≥ λ₃ ≥ 0`` of ``P``, ``|x|² = λ₁z₁² + Y`` with
``Y = λ₂z₂² + λ₃z₃²`` independent of ``z₁``. ``Y`` has the closed-form density (Simon,
*Probability Distributions Involving Gaussian Random Variables*, 2002, §4)

    f_Y(y) = e^{−y/2λ₂} I₀e(y(λ₂−λ₃)/4λ₂λ₃) / (2√(λ₂λ₃))       (→ e^{−y/2λ₂}/√(2πλ₂y) as λ₃ → 0)

with ``I₀e`` the exponentially scaled Bessel function, so that

    P(|x| ≤ r) = ∫₀^{r²} f_Y(y) erf(√((r² − y)/2λ₁)) dy
               = ∫₀^{π/2} 2r² sin θ cos θ f_Y(r² sin²θ) erf(r cos θ/√(2λ₁)) dθ    (y = r² sin²θ),

a smooth integrand up to the boundary layers that strong anisotropy puts at the ends (width
``√λ₃/r`` at 0, ``√λ₁/r`` at π/2). Gauss–Legendre on panels graded geometrically towards both
ends resolves them whatever the anisotropy: measured against the same integral on 4× finer
panels over covariances with λ₂/λ₁, λ₃/λ₂ from 1 to 10⁻⁸ (and 0), and r from 0.01 to 8·√λ₁,
the probability is right to 3e-12, and the scheme agrees with an independent nested adaptive
quadrature to 1e-15 where that one converges. Quantiles invert it by Newton steps on the
density (the same integral's derivative), kept inside a bracket.

May import: ``imunav.core``.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from scipy.special import erf, gammaincinv, i0e, ndtri

from imunav.core.rotations import FloatArray


@cache
def _nodes(k0: int = 16, k1: int = 8, m: int = 16, ratio: float = 0.25
           ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(sin θ, cos θ, weights)`` of the graded Gauss–Legendre rule on [0, π/2]: panels from π/4
    shrinking by ``ratio`` towards 0 (``k0`` of them) and towards π/2 (``k1``)."""
    x, w = np.polynomial.legendre.leggauss(m)
    q = np.pi / 4
    edges = np.unique(np.concatenate([[0.0, np.pi / 2], q * ratio ** np.arange(k0 + 1),
                                      np.pi / 2 - q * ratio ** np.arange(k1 + 1)]))
    a, b = edges[:-1, None], edges[1:, None]
    th = ((a + b) / 2 + (b - a) / 2 * x).ravel()
    return np.sin(th), np.cos(th), ((b - a) / 2 * w).ravel()


def chi3_cdf(s: FloatArray) -> FloatArray:
    """CDF of the χ distribution with three degrees of freedom (``s = ∞`` → 1)."""
    s = np.asarray(s, float)
    fin = np.isfinite(s)
    sf = np.where(fin, s, 0.0)
    return np.where(fin, erf(sf / np.sqrt(2)) - np.sqrt(2 / np.pi) * sf * np.exp(-sf * sf / 2),
                    1.0)


def _eig(cov: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Eigenvalues, largest first, clipped at 0, each with a trailing axis for the nodes."""
    lam = np.maximum(np.linalg.eigvalsh(np.asarray(cov, float))[..., ::-1], 0.0)
    return lam[..., 0, None], lam[..., 1, None], lam[..., 2, None]


def _f_y(y: FloatArray, l2: FloatArray, l3: FloatArray) -> FloatArray:
    """Density of ``λ₂z₂² + λ₃z₃²`` at ``y > 0`` (λ₂ ≥ λ₃ ≥ 0, λ₂ > 0)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        e = np.exp(-y / (2 * l2))
        general = e * i0e(y * (l2 - l3) / (4 * l2 * l3)) / (2 * np.sqrt(l2 * l3))
        limit = e / np.sqrt(2 * np.pi * y * (l2 - l3))
    return np.where(l3 > 0, general, limit)


def _cdf_pdf(l1, l2, l3, r: FloatArray, density: bool = False):
    """``P(|x| ≤ r)`` and, if asked, its derivative in ``r``; shapes ``r.shape``."""
    s, c, w = _nodes()
    rr = r[..., None]
    safe1 = np.where(l1 > 0, l1, 1.0)
    safe2 = np.where(l2 > 0, l2, 1.0)
    y = (rr * s) ** 2
    fy = _f_y(np.where(y > 0, y, 1e-300), safe2, np.where(l2 > 0, l3, 0.0))
    arg = rr * c / np.sqrt(2 * safe1)
    P = (2 * rr * rr * s * c * fy * erf(arg) * w).sum(-1)
    line = erf(r / np.sqrt(2 * safe1[..., 0]))                  # rank 1: Y ≡ 0
    rank1 = l2[..., 0] <= 0
    P = np.where(rank1, line, P)
    P = np.where(l1[..., 0] <= 0, 1.0, P)                        # x ≡ 0
    if not density:
        return P
    # d/dr P(Q ≤ r²) = 2r f_Q(r²),  f_Q(q) = √(2q/πλ₁) ∫ sin θ f_Y(q sin²θ) e^{−q cos²θ/2λ₁} dθ
    D = 2 * rr[..., 0] * np.sqrt(2 * r * r / (np.pi * safe1[..., 0])) * \
        (s * fy * np.exp(-(arg ** 2)) * w).sum(-1)
    D = np.where(rank1, np.sqrt(2 / (np.pi * safe1[..., 0])) * np.exp(-r * r / (2 * safe1[..., 0])),
                 D)
    return P, np.where(l1[..., 0] <= 0, 0.0, D)


def norm_cdf(cov: FloatArray, r) -> FloatArray:
    """``P(|x| ≤ r)`` for ``x ~ N(0, cov)``; ``cov`` (..., 3, 3), ``r`` broadcast to (...)."""
    l1, l2, l3 = _eig(cov)
    r = np.broadcast_to(np.asarray(r, float), l1.shape[:-1])
    return _cdf_pdf(l1, l2, l3, np.maximum(r, 0.0)) * (r > 0)


def norm_quantile(cov: FloatArray, p: float) -> FloatArray:
    """The ``p``-quantile of ``|x|`` for ``x ~ N(0, cov)``: shape ``cov.shape[:-2]``.

    Bracketed between the quantile along the largest axis alone (``|N(0, λ₁)|``: the other axes
    only add) and that of an isotropic vector of variance λ₁ per axis (``√λ₁·χ₃``); Newton on
    the CDF with its exact derivative from the moment-matched scaled χ² quantile.
    """
    l1, l2, l3 = _eig(cov)
    shape = l1.shape[:-1]
    l1, l2, l3 = (a.reshape(-1, 1) for a in (l1, l2, l3))
    top = np.sqrt(l1[:, 0])
    lo = top * ndtri((1 + p) / 2)
    hi = top * np.sqrt(2 * gammaincinv(1.5, p))
    # start from the moment-matched scaled χ² (Patnaik 1949): |x|² ≈ a·χ²_ν, same mean and variance
    tr, tr2 = (l1 + l2 + l3)[:, 0], (l1 * l1 + l2 * l2 + l3 * l3)[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        guess = np.sqrt(2 * tr2 / tr * gammaincinv(tr * tr / tr2 / 2, p))
    r = np.clip(np.nan_to_num(guess), lo, hi)
    act = np.nonzero(top > 0)[0]                     # the ones still iterating
    for _ in range(60):
        if act.size == 0:
            break
        ra = r[act]
        F, dF = _cdf_pdf(l1[act], l2[act], l3[act], ra, density=True)
        lo[act] = np.where(F < p, ra, lo[act])
        hi[act] = np.where(F > p, ra, hi[act])
        with np.errstate(divide="ignore", invalid="ignore"):
            new = np.where(dF > 0, ra - (F - p) / dF, (lo[act] + hi[act]) / 2)
        bad = (new < lo[act]) | (new > hi[act])
        new = np.where(bad, (lo[act] + hi[act]) / 2, new)          # stay bracketed
        done = (np.abs(F - p) <= 1e-13) | (np.abs(new - ra) <= 1e-14 * ra)
        r[act] = np.where(done, ra, new)
        act = act[~done]
    return np.where(top > 0, r, 0.0).reshape(shape)
