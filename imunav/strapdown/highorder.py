"""High-order offline strapdown: local polynomial fits feeding Magnus steps.

Offline processing may use samples on both sides of an interval. On each interval
``[t_{k−1}, t_k]`` a centred stencil of samples (shifted inward at the ends) defines

- from **rates**: the interpolating polynomial of ``ω_b`` and of ``f_b`` through ``m`` samples;
- from **increments**: the interpolating polynomial ``S(t)`` through ``m`` cumulative sums
  ``S_j = Σ_{i≤j} Δθ_i`` (``S(t) = ∫ω dt`` exactly at every node), and ``ω = S'``. The fit
  reproduces the interval's own increment exactly.

Attitude: ``q_k = q_{k−1} ⊗ exp(φ)`` with φ from one Magnus step of order 4 (2 Gauss nodes)
or 6 (3 Gauss nodes); for body-frame right multiplication the Lie bracket of rotation vectors
is ``[x, y] = y × x``. (:func:`interval_quaternions` composes several sub-steps, for the cost
and accuracy study of notebook 06.) Velocity and position: 3-point Gauss quadrature of
``C_nb(t) f_b(t)`` over the interval, the attitude at each node from a Magnus step over
``[t_{k−1}, node]``:

    Δv_b = h Σ wᵢ R(Eᵢ) f(sᵢ),   Δp_b = h² Σ wᵢ (1 − sᵢ) R(Eᵢ) f(sᵢ),
    v_k = v_{k−1} + C_{k−1} Δv_b + g_n h,   p_k = p_{k−1} + v_{k−1} h + C_{k−1} Δp_b + g_n h²/2.

Sources: Magnus integrators, Iserles & Nørsett (1999); the sixth-order 3-node form of
Blanes, Casas & Ros (2000), BIT 40, eq. for Ω^[6]; rotation-vector attitude, Bortz (1971).

May import: ``imunav.core``, ``imunav.strapdown.scan``.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from imunav.core.kernels import cross, quat_exp, quat_mul, quat_rotate
from imunav.core.rotations import FloatArray
from imunav.core.threads import limit_blas
from imunav.strapdown.scan import exp_product

_G4 = np.array([0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6])
_G6 = np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])
_GQ_X, _GQ_W = _G6, np.array([5 / 18, 8 / 18, 5 / 18])  # 3-point Gauss–Legendre on [0, 1]


def _br(x: FloatArray, y: FloatArray) -> FloatArray:
    """Lie bracket for right-multiplied body-frame rotation vectors: ``[x, y] = y × x``."""
    return cross(y, x)


def magnus4(w: FloatArray, h: FloatArray | float) -> FloatArray:
    """Fourth-order Magnus rotation vector from ω at the 2 Gauss nodes: ``w`` (..., 2, 3)."""
    w1, w2 = w[..., 0, :], w[..., 1, :]
    return h / 2 * (w1 + w2) - np.sqrt(3) / 12 * h * h * _br(w1, w2)


def magnus6(w: FloatArray, h: FloatArray | float) -> FloatArray:
    """Sixth-order Magnus rotation vector from ω at the 3 Gauss nodes: ``w`` (..., 3, 3)."""
    w1, w2, w3 = w[..., 0, :], w[..., 1, :], w[..., 2, :]
    a1 = h * w2
    a2 = np.sqrt(15) * h / 3 * (w3 - w1)
    a3 = 10 * h / 3 * (w3 - 2 * w2 + w1)
    c1 = _br(a1, a2)
    c2 = -_br(a1, 2 * a3 + c1) / 60
    return a1 + a3 / 12 + _br(-20 * a1 - a3 + c1, a2 + c2) / 240


_MAGNUS = {4: (_G4, magnus4), 6: (_G6, magnus6)}


def _stencil(n_nodes: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """For each of the ``n_nodes − 1`` intervals, the first node of a centred ``m``-node
    stencil (shifted inward at the ends) and the interval's offset inside it."""
    m = min(m, n_nodes)
    k = np.arange(n_nodes - 1)
    start = np.clip(k - (m // 2 - 1), 0, n_nodes - m)
    return start, k - start


_BASIS_CACHE: dict[tuple, FloatArray] = {}


def _basis(m: int, x: FloatArray, deriv: int) -> FloatArray:
    """``B[i, j]``: value (deriv=0) or derivative (deriv=1) at ``x[i]`` of the Lagrange basis
    polynomial j for the nodes 0..m−1.

    Computed exactly in rational arithmetic (the polynomial's coefficients are rationals, the
    double ``x[i]`` is a rational) and rounded once, so every weight is correctly rounded
    whatever the machine. (Inverting the Vandermonde matrix in double precision left 5e-15–1e-14
    relative errors, which a long run accumulates as a systematic drift of the same size.)
    Cached: each (m, deriv, points) is computed once per process.
    """
    x = np.asarray(x, float)
    key = (m, deriv, x.tobytes())
    if key not in _BASIS_CACHE:
        out = np.empty((x.size, m))
        for j in range(m):
            c = _lagrange_coefficients(m, j)                 # ascending powers, exact
            if deriv:
                c = [k * c[k] for k in range(1, m)]
            for i, xi in enumerate(x):
                X = Fraction(float(xi))
                acc = Fraction(0)
                for ck in reversed(c):                       # Horner, exact
                    acc = acc * X + ck
                out[i, j] = float(acc)
        out.flags.writeable = False
        _BASIS_CACHE[key] = out
    return _BASIS_CACHE[key]


@cache
def _lagrange_coefficients(m: int, j: int) -> tuple[Fraction, ...]:
    """Exact ascending-power coefficients of ``Π_{k≠j} (x − k)/(j − k)`` for nodes 0..m−1."""
    c = [Fraction(1)]
    for k in range(m):
        if k == j:
            continue
        c = [Fraction(0)] + c                                # multiply by x …
        for i in range(len(c) - 1):
            c[i] -= k * c[i + 1]                             # … minus k
        c = [ci / (j - k) for ci in c]
    return tuple(c)


class LocalFit:
    """Per-interval polynomial of a signal, evaluable at fractional positions ``s ∈ [0, 1]``.

    ``kind="rates"``: interpolate the ``N+1`` samples (value = signal). ``kind="increments"``:
    interpolate cumulative sums of the ``N`` increments and differentiate (value = rate).

    Either way a value is a fixed linear combination of the stencil's raw samples, so the fit
    is evaluated as tap weights ``W[s, i]`` applied to sliding windows of the samples — one
    matrix product (BLAS) per stencil offset. For increments ``ω(s) = Σ_j B′_j(s) S_j / h`` with
    ``S_j = Σ_{i<j} Δθ_i`` becomes ``Σ_i W_i(s) Δθ_i`` with ``W_i = Σ_{j>i} B′_j / h``: no long
    cumulative sums, so the rounding stays at the size of a few increments.
    """

    def __init__(self, samples: FloatArray, kind: str, h: float, m: int):
        # samples: (N, 3) or batched (N, R, 3) — time first, any run axes in between.
        self.x = samples
        n_nodes = samples.shape[0] + (1 if kind == "increments" else 0)
        self.m = min(m, n_nodes)
        self.start, self.offset = _stencil(n_nodes, self.m)
        self.n = n_nodes - 1
        self.h = h
        self.kind = kind
        self.taps = self.m - 1 if kind == "increments" else self.m
        self._weights: dict[tuple, FloatArray] = {}

    def weights(self, offset: int, s: FloatArray) -> FloatArray:
        """Tap weights ``W`` (len(s), taps): value at ``s`` = ``W @ samples[start:start+taps]``
        for an interval at ``offset`` inside its stencil (computed once per offset and s)."""
        s = np.asarray(s, float)
        key = (int(offset), s.tobytes())
        if key not in self._weights:
            if self.kind == "increments":
                B = _basis(self.m, offset + s, 1) / self.h                    # (S, m)
                W = np.cumsum(B[:, ::-1], axis=1)[:, ::-1][:, 1:]             # Σ_{j>i} B_j
            else:
                W = _basis(self.m, offset + s, 0)
            self._weights[key] = W
        return self._weights[key]

    def at(self, s: FloatArray, lo: int = 0, hi: int | None = None) -> FloatArray:
        """Signal at ``t_{k−1} + s·h`` for the intervals ``k = lo+1 .. hi`` (all by default) and
        every s: shape (hi − lo, [R,] len(s), 3)."""
        return np.moveaxis(self.at_nodes(s, lo, hi), 0, -2)

    def at_nodes(self, s: FloatArray, lo: int = 0, hi: int | None = None) -> FloatArray:
        """As :meth:`at`, node axis first: (len(s), hi − lo, [R,] 3), each node contiguous."""
        s = np.atleast_1d(np.asarray(s, float))
        hi = self.n if hi is None else hi
        rest = self.x.shape[1:]                                   # ([R,] 3)
        out = np.empty((s.size, hi - lo) + rest)
        offs = self.offset[lo:hi]
        windows = sliding_window_view(self.x, self.taps, axis=0)  # (N−taps+1, [R,] 3, taps)
        for o in np.unique(offs):
            ks = np.nonzero(offs == o)[0]                         # a contiguous run of intervals
            st = self.start[lo + ks[0]]
            win = np.ascontiguousarray(windows[st: st + ks.size]).reshape(-1, self.taps)
            out[:, ks[0]: ks[-1] + 1] = (self.weights(o, s) @ win.T).reshape(
                (s.size, ks.size) + rest)
        return out


def interval_quaternions(fit: LocalFit, order: int, nsub: int) -> FloatArray:
    """The attitude increment ``Δq_k`` (N, 4) of every interval, composed from ``nsub`` Magnus
    sub-steps of ``order`` on the fitted rate."""
    nodes, step = _MAGNUS[order]
    dq = None
    for j in range(nsub):
        w = fit.at((j + nodes) / nsub)
        e = quat_exp(step(w, fit.h / nsub))
        dq = e if dq is None else quat_mul(dq, e)
    return dq


#: Interval-runs per chunk of the high-order navigation (bounds the temporaries' memory).
_POLY_CHUNK = 1 << 15


@limit_blas
def navigate_poly(kind: str, gyro: FloatArray, accel: FloatArray, h: float, q0: FloatArray,
                  v0: FloatArray, p0: FloatArray, g: float, first: int = 0,
                  count: int | None = None, *, m: int, order: int
                  ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Attitude, velocity and position at the ends of intervals ``first .. first + count − 1``
    of a window of samples, from the state at the start of interval ``first`` (see the module
    docstring; the samples around those intervals feed their stencils).

    ``gyro``/``accel`` (M, 3), or (M, R, 3) for R runs at once with ``q0`` (R, 4). The
    per-interval work is done chunk by chunk so that temporaries stay small; the outputs and
    one rotation vector and two body-frame increments per interval are all that is stored.
    """
    wfit = LocalFit(gyro, kind, h, m)
    ffit = LocalFit(accel, kind, h, m)
    count = wfit.n - first if count is None else count
    n = count
    q0 = np.broadcast_to(q0, gyro.shape[1:-1] + (4,))
    nodes, step = _MAGNUS[order]
    # ω at the Magnus nodes of the whole interval, then of each partial [0, sᵢ] (sᵢ Gauss nodes)
    s_all = np.concatenate([nodes] + [si * nodes for si in _GQ_X])
    nn = nodes.size
    shape = (n,) + gyro.shape[1:]
    phi = np.empty(shape)
    dv_b, dp_b = np.empty(shape), np.empty(shape)
    runs = int(np.prod(gyro.shape[1:-1]))
    per = max(1, _POLY_CHUNK // runs)                            # intervals per chunk
    for lo in range(0, n, per):
        hi = min(n, lo + per)
        w = wfit.at_nodes(s_all, first + lo, first + hi)         # (12, c, [R,] 3)
        phi[lo:hi] = step(np.moveaxis(w[:nn], 0, -2), h)
        f = ffit.at_nodes(_GQ_X, first + lo, first + hi)         # (3, c, [R,] 3)
        dv_b[lo:hi] = 0.0
        dp_b[lo:hi] = 0.0
        for i, si in enumerate(_GQ_X):                           # R(Eᵢ) fᵢ, body at t_{k−1}
            wi = np.moveaxis(w[nn * (i + 1): nn * (i + 2)], 0, -2)
            rf = quat_rotate(quat_exp(step(wi, h * si)), f[i])
            dv_b[lo:hi] += (h * _GQ_W[i]) * rf
            dp_b[lo:hi] += (h * h * _GQ_W[i] * (1 - si)) * rf
    q = exp_product(q0, phi)
    del phi
    # g: a magnitude (flat NED) or a vector as it is (on the Earth: classic._gravity)
    gn = np.array([0.0, 0.0, g]) if np.ndim(g) == 0 else np.asarray(g, dtype=float)
    v = np.empty((n + 1,) + dv_b.shape[1:])
    p = np.empty_like(v)
    v[0], p[0] = v0, p0
    for lo in range(0, n, per):                                  # navigation-frame increments
        hi = min(n, lo + per)
        v[lo + 1: hi + 1] = quat_rotate(q[lo:hi], dv_b[lo:hi]) + gn * h
    del dv_b
    np.cumsum(v[1:], axis=0, out=v[1:])
    v[1:] += v[0]
    for lo in range(0, n, per):
        hi = min(n, lo + per)
        p[lo + 1: hi + 1] = quat_rotate(q[lo:hi], dp_b[lo:hi]) + gn * h * h / 2 + h * v[lo:hi]
    np.cumsum(p[1:], axis=0, out=p[1:])
    p[1:] += p[0]
    return q, v, p
