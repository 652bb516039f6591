"""Integrals of a smooth vector function over consecutive sample intervals: exact increments.

Two methods, one code path (:func:`integrate_consecutive`):

**Chebyshev blocks** (the fast path). The intervals are grouped in blocks of :data:`BLOCK`. On a
block the integrand is sampled at the ``n + 1`` Chebyshev–Lobatto points; its interpolant
converges geometrically for smooth functions, and the size of its last Chebyshev coefficients
measures that convergence (chebfun's test). Every interval's integral is then one row of a
fixed matrix times the sampled values, ``ΔI = (L/2) W @ f(points)``: ``W[k, j]`` is the integral
of the j-th Lagrange cardinal function over interval k, computed once in extended precision
and rounded. So each increment costs about ``(n+1)/BLOCK`` evaluations of the motion and its
rounding is that of a short weighted sum (``Σ|W| ≈ 3h``), not of a difference of antiderivative
values. The degree is raised 16 → 32 → 64 → 128 (the points nest: each level reuses the
previous level's values) until the tail of the coefficients is below :data:`TOL` of their
largest, or has flattened into a rounding plateau (far from t = 0 the integrand itself carries
rounding: ``sin(Ωt)`` loses digits as ``Ωt`` grows) no larger than :data:`FLOOR`.

**Adaptive Gauss–Legendre** (:func:`integrate_intervals`, the fallback for blocks that do not
converge at degree 128, e.g. sampling far slower than the motion): composite 8-node rules per
interval, doubled until converged.

Accuracy: against high-precision mpmath quadrature, each increment is within 1e-13 of the norm of the
increment vector, or within 1e-15·h·max|f| absolute where that norm is small against the
integrand's size over its block (``tests/sensors/test_quadrature.py``).

May import: ``imunav.core``.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import numpy.typing as npt

from imunav.core.rotations import FloatArray
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, as_float_array

#: Intervals per Chebyshev block.
BLOCK = 64
#: Degrees tried in turn (each doubling reuses the previous points).
DEGREES = (16, 32, 64, 128)
#: A block is converged when its last Chebyshev coefficients are below TOL of the largest …
TOL = 2e-14
#: … or, flat (a plateau of the integrand's own rounding), below FLOOR of it.
FLOOR = 1e-10


@cache
def _rule(n: int, r: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(x, W, C)`` for degree ``n`` and ``r`` equal intervals of [−1, 1]: the Chebyshev–Lobatto
    points ``x_j = cos(jπ/n)``; ``W[k, j] = ∫_{u_k}^{u_{k+1}} ℓ_j(u) du`` (``u_k = −1 + 2k/r``,
    ``ℓ_j`` the cardinal polynomials); ``C`` maps point values to Chebyshev coefficients
    (discrete orthogonality). ``W`` is summed in extended precision (numpy's long double, 64-bit
    mantissa on x86-64) and rounded once: within 2e-16 of 34-digit values (tested)."""
    ld = np.longdouble
    j = np.arange(n + 1)
    x = np.cos(np.pi * j / n)
    c = np.where((j == 0) | (j == n), 2.0, 1.0)
    C = 2.0 / n * np.cos(np.pi * np.outer(j, j) / n) / np.outer(c, c)     # C[m, j]
    pi = ld("3.14159265358979323846264338327950288")
    A = ld(2) / n * np.cos(pi * np.outer(j, j).astype(ld) / n) / np.outer(c, c).astype(ld)
    u = ld(-1) + ld(2) * np.arange(r + 1).astype(ld) / r
    th = np.arccos(np.clip(u, -1, 1))
    integral = np.empty((n + 1, r + 1), dtype=ld)              # antiderivatives of T_m at u_k
    integral[0] = u
    integral[1] = u * u / 2
    m = np.arange(2, n + 1)[:, None].astype(ld)
    integral[2:] = np.cos((m + 1) * th) / (2 * (m + 1)) - np.cos((m - 1) * th) / (2 * (m - 1))
    W = (A @ np.diff(integral, axis=1)).T.astype(np.float64)
    return x, W, C


@limit_blas
def integrate_consecutive(f, t0: float, h: float, k0: int, k1: int, *, groups: int = 1,
                          block: int = BLOCK) -> FloatArray:
    """``∫ f dt`` over the intervals ``[t0 + k h, t0 + (k+1) h]``, ``k = k0 .. k1−1``.

    Chebyshev blocks of ``block`` intervals, adaptive Gauss–Legendre for blocks that do not
    converge (see the module's description). Blocks start at multiples of ``block``, so the
    result of an interval does not depend on how a long run is chunked.

    Parameters
    ----------
    f : callable
        ``f(t)`` maps an array of times (s, any shape) to values of shape
        ``t.shape + (3·groups,)`` (e.g. ω_b in rad/s and f_b in m/s² stacked).
    t0 : float
        Time of interval 0's start (s).
    h : float
        Interval length (s), > 0: ``1/rate``.
    k0, k1 : int
        The first interval and one past the last (``k1 > k0``).
    groups : int, default 1
        Groups of three components in ``f``'s values; convergence is judged per group.
    block : int, default BLOCK
        Intervals per Chebyshev block.

    Returns
    -------
    ndarray, shape (k1 − k0, 3·groups)
        One row per interval: the integral (e.g. Δθ in rad, Δv in m/s).

    Raises
    ------
    ImunavError
        If the fallback quadrature does not converge (see :func:`integrate_intervals`).

    Examples
    --------
    >>> import numpy as np
    >>> f = lambda t: np.stack([np.cos(t), np.sin(t), np.ones_like(t)], axis=-1)
    >>> I = integrate_consecutive(f, 0.0, 0.5, 0, 4)
    >>> k = np.arange(5) * 0.5
    >>> bool(np.allclose(I[:, 0], np.diff(np.sin(k)), rtol=0, atol=1e-15))
    True
    """
    nk = k1 - k0
    out = np.empty((nk, 3 * groups))
    starts = list(range(k0 - k0 % block if k0 % block else k0, k1, block))
    # blocks as (first interval, count), clipped to [k0, k1)
    spans = [(max(s, k0), min(s + block, k1)) for s in starts]
    by_len: dict[int, list[tuple[int, int]]] = {}
    for s, e in spans:
        by_len.setdefault(e - s, []).append((s, e))
    for r, group in by_len.items():
        first = np.array([s for s, _ in group])
        _blocks(f, t0, h, first, r, groups, out, k0)
    return out


def _blocks(f, t0, h, first, r, groups, out, k0):
    """All blocks of ``r`` intervals starting at the intervals ``first``: fill ``out``."""
    L = r * h
    mid = t0 + (first + r / 2) * h                          # (nb,)
    todo = np.arange(first.size)                            # blocks not yet converged
    vals = None
    width = 3 * groups
    for n in DEGREES:
        x, W, C = _rule(n, r)
        if vals is None:
            new = np.ascontiguousarray(f(mid[todo][None, :] + (L / 2) * x[:, None]), dtype=float)
        else:                                               # x_{2j} of degree n are the old points
            new = np.empty((n + 1, todo.size, width))
            new[0::2] = vals
            odd = x[1::2]
            new[1::2] = f(mid[todo][None, :] + (L / 2) * odd[:, None])
        coef = np.tensordot(C, new, axes=(1, 0))            # Chebyshev coefficients (m, nb, 3g)
        np.abs(coef, out=coef)
        # the largest |coefficient| of each block and component: over all degrees, over the
        # last quarter (the tail) and the quarter before it; then over each group's 3 components
        q = n // 4
        tail = coef[n - q:].max(axis=0)                     # (nb, 3g)
        before = coef[n - 2 * q: n - q].max(axis=0)
        scale = np.maximum(np.maximum(coef[: n - 2 * q].max(axis=0), before), tail)
        tail, before, scale = (a.reshape(-1, groups, 3).max(axis=-1) for a in (tail, before, scale))
        # converged; or a rounding plateau: a flat envelope (a geometric series this flat could
        # not be below FLOOR at these degrees) — chebfun's standardChop in its simplest form
        ok = (tail <= TOL * scale) | ((tail <= FLOOR * scale) & (tail >= before / 8))
        ok = ok.all(axis=1)
        if ok.any():
            done = todo[ok]
            sel = new if ok.all() else new[:, ok]
            prod = np.tensordot(sel, W, axes=(0, 1)).transpose(0, 2, 1)          # (nb, r, 3g)
            lo = first[done[0]] - k0
            if first[done[-1]] - first[done[0]] == (done.size - 1) * r:         # consecutive
                np.multiply(prod, L / 2, out=out[lo: lo + done.size * r].reshape(-1, r, width))
            else:
                out[(first[done] - k0)[:, None] + np.arange(r)[None, :]] = (L / 2) * prod
        todo, vals = todo[~ok], new[:, ~ok]
        if not todo.size:
            return
    # the fallback: adaptive Gauss–Legendre on the intervals of unconverged blocks
    k = (first[todo][:, None] + np.arange(r)[None, :]).ravel()
    out[k - k0] = integrate_intervals(f, t0 + k * h, t0 + (k + 1) * h, width=3 * groups)


_GL_CACHE: dict[int, tuple[FloatArray, FloatArray]] = {}


def _gauss_legendre(n: int) -> tuple[FloatArray, FloatArray]:
    if n not in _GL_CACHE:
        x, w = np.polynomial.legendre.leggauss(n)
        _GL_CACHE[n] = ((x + 1) / 2, w / 2)  # nodes and weights on [0, 1]
    return _GL_CACHE[n]


def _composite(f, a: FloatArray, b: FloatArray, panels: int, nodes: int) -> FloatArray:
    x, w = _gauss_legendre(nodes)
    h = (b - a) / panels
    # nodes of every panel of every interval: shape (M, panels*nodes)
    s = (np.arange(panels)[:, None] + x[None, :]).ravel()
    tt = a[:, None] + h[:, None] * s[None, :]
    vals = f(tt)  # (M, panels*nodes, width)
    ww = np.tile(w, panels)
    return h[:, None] * np.einsum("mkc,k->mc", vals, ww)


def integrate_intervals(f, a: npt.ArrayLike, b: npt.ArrayLike, *, rtol: float = 1e-13,
                        atol: float = 1e-15, nodes: int = 8, max_panels: int = 1024,
                        budget: int = 2_000_000, width: int = 3) -> FloatArray:
    """``∫_a^b f(t) dt`` for many intervals at once.

    Composite Gauss–Legendre with ``nodes`` points per panel; for each interval the number of
    panels is doubled until two successive estimates agree to ``atol + rtol·|I|`` in every
    component (the finer estimate is returned), only unconverged intervals being refined.
    Far from t = 0 the integrand itself carries rounding (``ω t`` loses digits), so an
    interval whose difference has stopped shrinking (less than 4× per doubling — a converging
    8-node rule gains ~2¹⁶) and is below ``1e-10`` of its scale is accepted at that floor.

    Parameters
    ----------
    f : callable
        ``f(t)`` maps an array of times (s), shape (M, p), to values of shape (M, p, width).
    a, b : array_like, shape (M,)
        The intervals' start and end times (s).
    rtol : float, default 1e-13
        Relative tolerance per component.
    atol : float, default 1e-15
        Absolute tolerance per component (the unit of the integral).
    nodes : int, default 8
        Gauss–Legendre nodes per panel.
    max_panels : int, default 1024
        The most panels per interval before giving up.
    budget : int, default 2_000_000
        The most integrand points evaluated per call of ``f`` (bounded memory).
    width : int, default 3
        Components of ``f``'s values.

    Returns
    -------
    ndarray, shape (M, width)
        The integral over each interval.

    Raises
    ------
    ImunavError
        If ``a`` or ``b`` is not a 1-D finite array, or an interval has not converged at
        ``max_panels`` panels (the motion is not smooth enough at this sample rate).

    Examples
    --------
    >>> import numpy as np
    >>> f = lambda t: np.stack([np.cos(t), np.sin(t), np.ones_like(t)], axis=-1)
    >>> integrate_intervals(f, [0.0], [np.pi / 2])
    array([[1.        , 1.        , 1.57079633]])
    """
    a = as_float_array(a, "a", ndim=1)
    b = as_float_array(b, "b", ndim=1)
    out = np.empty((a.shape[0], width))
    chunk = max(1, budget // (2 * nodes))
    for s in range(0, a.shape[0], chunk):
        idx = np.arange(s, min(a.shape[0], s + chunk))
        prev = _composite(f, a[idx], b[idx], 1, nodes)
        last = np.full(idx.shape, np.inf)
        panels = 1
        while idx.size:
            panels *= 2
            if panels > max_panels:
                raise ImunavError(
                    "increment quadrature did not converge: the motion is not smooth enough "
                    "at this sample rate (try a higher rate)"
                )
            step = max(1, budget // (panels * nodes))
            cur = np.concatenate([_composite(f, a[idx[i:i + step]], b[idx[i:i + step]], panels,
                                             nodes) for i in range(0, idx.size, step)])
            diff = np.abs(cur - prev).max(axis=1)
            scale = np.abs(cur).max(axis=1)
            ok = np.all(np.abs(cur - prev) <= atol + rtol * np.abs(cur), axis=1)
            ok |= (diff > last / 4) & (diff <= 1e-10 * scale + atol)
            out[idx[ok]] = cur[ok]
            idx, prev, last = idx[~ok], cur[~ok], diff[~ok]
    return out


def integrate_piecewise(f, t0: float, h: float, k0: int, k1: int, breakpoints: npt.ArrayLike,
                        width: int = 6) -> FloatArray:
    """``∫ f dt`` over ``[t0 + k h, t0 + (k+1) h]``, ``k = k0 .. k1−1``, for an integrand that is
    smooth only between ``breakpoints`` (a spline motion's knots): every interval is split at
    the breakpoints inside it and each piece integrated by :func:`integrate_intervals` (which
    converges fast on a smooth piece), then the pieces are summed. Returns (k1 − k0, width)."""
    bounds = t0 + np.arange(k0, k1 + 1) * h
    bp = np.asarray(breakpoints, float)
    inside = bp[(bp > bounds[0]) & (bp < bounds[-1])]
    edges = np.union1d(bounds, inside)
    a, b = edges[:-1], edges[1:]
    keep = b > a
    a, b = a[keep], b[keep]
    owner = np.clip(np.searchsorted(bounds, a, side="right") - 1, 0, k1 - k0 - 1)
    parts = integrate_intervals(f, a, b, width=width)
    out = np.zeros((k1 - k0, width))
    np.add.at(out, owner, parts)
    return out
