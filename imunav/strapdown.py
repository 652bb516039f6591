"""Strapdown integration: attitude, velocity and position from rates or increments.

The navigation frame is flat, non-rotating NED with constant gravity ``g_n = [0, 0, +g]``:

    q̇_nb = ½ q_nb ⊗ [0, ω_b],   v̇_n = C_nb f_b + g_n,   ṙ_n = v_n.

Every algorithm is a row of :data:`ALGORITHMS` with its signal kind, its order (the measured
global convergence order of the attitude, velocity and position errors on smooth motion — see
``tests/test_strapdown.py``) and its source. The attitude recursion ``q_k = q_{k−1} ⊗ Δq_k``
is associative, so it is evaluated by a blocked prefix product over cache-sized chunks
(:func:`cumulative_product`, :func:`exp_product`); everything else is vectorised over samples.
``imunav.reference`` holds the plain one-sample-at-a-time loops the fast path is tested against,
and ``benchmarks/bench.py`` times both.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from imunav.errors import ImunavError, as_float_array
from imunav.rotations import FloatArray, _exp, _mul, _rotate, quat_normalize, quat_to_euler
from imunav.simulate import ImuSignals

__all__ = ["ALGORITHMS", "Algorithm", "DEFAULT_ALGORITHM", "NavResult", "cumulative_product",
           "exp_product", "navigate"]


@dataclass
class NavResult:
    """Navigation output at ``t_k``, k = 0..N, starting from the initial state."""

    t: FloatArray
    position: FloatArray
    velocity: FloatArray
    quaternion: FloatArray
    algorithm: str

    def euler(self) -> FloatArray:
        """``[yaw, pitch, roll]`` (rad) of the attitude."""
        return quat_to_euler(self.quaternion)


@dataclass(frozen=True)
class Algorithm:
    """One strapdown algorithm.

    ``order`` is the global convergence order ``(attitude, velocity, position)`` on smooth
    motion; ``func(signals, q0, v0, p0, g) → (q, v, p)`` each with N+1 rows. ``causal``: the
    state at ``t_k`` uses no sample after ``t_k`` (real-time capable; multi-sample
    algorithms update once per major interval).
    """

    name: str
    kind: str
    order: tuple[int, int, int]
    summary: str
    source: str
    func: Callable
    causal: bool = True


def prefix_product(x0: np.ndarray, d: np.ndarray, mul, block: int | None = None) -> np.ndarray:
    """``x_k = mul(x_{k−1}, d_k)`` for k = 1..N with ``x_0`` first, for any associative ``mul``
    on arrays whose first axis is the sample (quaternions ``(N, 4)``, matrices ``(N, 3, 3)``).

    Blocked prefix product: the N factors are split into ~√N blocks; prefix products are
    formed inside all blocks at once (vectorised across blocks), the block totals are
    chained, then applied — about 2√N vectorised operations instead of N scalar ones.
    Same arithmetic as the sequential loop up to associativity (tested to 1e-12).
    """
    n = d.shape[0]
    if n == 0:
        return x0[None].copy()
    L = block or max(1, int(np.ceil(np.sqrt(n))))
    B = -(-n // L)
    pad = B * L - n
    if pad:
        ident = np.broadcast_to(_identity_like(x0), (pad,) + x0.shape)
        d = np.concatenate([d, ident])
    d = d.reshape((B, L) + x0.shape)
    P = np.empty_like(d)
    P[:, 0] = d[:, 0]
    for j in range(1, L):
        P[:, j] = mul(P[:, j - 1], d[:, j])
    S = np.empty((B,) + x0.shape)
    S[0] = x0
    for b in range(1, B):
        S[b] = mul(S[b - 1], P[b - 1, L - 1])
    x = mul(S[:, None], P).reshape((B * L,) + x0.shape)[:n]
    return np.concatenate([x0[None], x])


def _identity_like(x0: np.ndarray) -> np.ndarray:
    if x0.shape[-1] == 4:                      # quaternions, possibly batched (R, 4)
        return np.broadcast_to([1.0, 0.0, 0.0, 0.0], x0.shape)
    return np.broadcast_to(np.eye(x0.shape[-1]), x0.shape)


#: Samples per chunk of the quaternion scan (the working set stays in cache) and block length.
_SCAN_CHUNK = 1 << 16
_SCAN_LEAF = 16


# Quaternions inside the scan are pairs of complex numbers (Cayley–Dickson):
# q = (w + x i) + (y + z i) j, and the Hamilton product is
#     (a₁ + a₂ j) ⊗ (b₁ + b₂ j) = (a₁ b₁ − a₂ b̄₂) + (a₁ b₂ + a₂ b̄₁) j.
# An (..., 4) float array viewed as complex is exactly (..., 2) [w + x i, y + z i], so the
# change of representation is free, and a product costs 8 vectorised complex operations
# instead of 28 real ones.


def _cmul(a, b, out, t):
    """``out = a ⊗ b`` for component-first complex pairs (2, ...); ``t`` is scratch.
    ``out`` must not alias ``a`` or ``b``."""
    np.multiply(a[0], b[0], out=out[0])
    np.multiply(a[1], np.conjugate(b[1], out=t), out=t)
    np.subtract(out[0], t, out=out[0])
    np.multiply(a[0], b[1], out=out[1])
    np.multiply(a[1], np.conjugate(b[0], out=t), out=t)
    np.add(out[1], t, out=out[1])
    return out


def _blocked(x: np.ndarray, L: int, pad: np.ndarray) -> np.ndarray:
    """AoS chunk ``x`` (m, R, c) → component-first blocks ``(c, L, R, nb)`` (contiguous), where
    sample ``b·L + j`` lands at ``[:, j, :, b]``; the last block is padded with ``pad`` (c,)."""
    m, R, c = x.shape
    nb = -(-m // L)
    if nb * L > m:
        x = np.concatenate([x, np.broadcast_to(pad, (nb * L - m, R, c))])
    return np.ascontiguousarray(x.reshape(nb, L, R, c).transpose(3, 1, 2, 0))


def _quat_blocked(dq: np.ndarray, L: int) -> np.ndarray:
    """Quaternion factors (m, R, 4) → complex pairs blocked (2, L, R, nb), identity padding."""
    return _blocked(np.ascontiguousarray(dq).view(np.complex128), L, np.array([1.0 + 0j, 0j]))


def _exp_blocked(phi: np.ndarray, L: int) -> np.ndarray:
    """``exp(φ)`` of rotation vectors (m, R, 3) as complex pairs blocked (2, L, R, nb):
    ``[cos(a/2) + i s φx, s φy + i s φz]`` with ``a = |φ|``, ``s = sin(a/2)/a`` (→ ½ at 0)."""
    v = _blocked(phi, L, np.zeros(3))
    a = v[0] * v[0]
    a += v[1] * v[1]
    a += v[2] * v[2]
    np.sqrt(a, out=a)
    half = 0.5 * a
    out = np.empty((2,) + a.shape, np.complex128)
    s = np.sin(half)
    if a.size and a.max() < 1.0:        # cos(a/2) = √(1 − sin²(a/2)), exact to rounding here
        c = np.square(s, out=half)
        np.subtract(1.0, c, out=c)
        np.sqrt(c, out=out[0].real)
    else:
        np.cos(half, out=out[0].real)
    np.divide(s, a, out=s, where=a > 0)
    s[a == 0] = 0.5
    np.multiply(v[0], s, out=out[0].imag)
    np.multiply(v[1], s, out=out[1].real)
    np.multiply(v[2], s, out=out[1].imag)
    return out


def _quat_scan(q0: np.ndarray, n: int, factors, normalize: bool) -> FloatArray:
    """``q_k = q_{k−1} ⊗ d_k`` for k = 1..n, for ``R`` independent runs at once.

    ``q0`` (R, 4); ``factors(lo, hi, L)`` returns ``d_{lo+1..hi}`` as complex pairs blocked
    (2, L, R, nb) (see :func:`_blocked`). Returns (n+1, R, 4).

    Blocked prefix product, one cache-sized chunk after another: (1) prefix products inside
    every block of L factors, vectorised across the chunk's blocks and the runs; (2) the block
    totals are chained from the running attitude (recursively, by this same function) to give
    every block's starting attitude; (3) that is applied to the block's prefix products and
    the results are normalised and written out. The arithmetic is that of the sequential loop
    up to associativity (tested against :mod:`imunav.reference` to ≤ 1e-12).
    """
    R = q0.shape[0]
    out = np.empty((n + 1, R, 4))
    out[0] = q0
    L = _SCAN_LEAF
    if n <= 4 * L:                                      # short: the plain sequential loop
        if n:
            d = factors(0, n, 1)[:, 0]                          # (2, R, n) complex
            z = out.view(np.complex128)                          # (n+1, R, 2)
            for k in range(n):
                a1, a2, b1, b2 = z[k, :, 0], z[k, :, 1], d[0, :, k], d[1, :, k]
                z[k + 1, :, 0] = a1 * b1 - a2 * np.conjugate(b2)
                z[k + 1, :, 1] = a1 * b2 + a2 * np.conjugate(b1)
        if normalize:
            out /= np.linalg.norm(out, axis=-1, keepdims=True)
        return out
    step = max(1, _SCAN_CHUNK // (L * R))               # blocks per chunk
    P = np.empty((2, L, R, step), np.complex128)        # in-block prefix products
    X = np.empty_like(P)
    t = np.empty((L, R, step), np.complex128)
    r = np.empty((L, R, step))
    flat = out[1:].view(np.complex128)                  # (n, R, 2)
    carry = q0
    for lo in range(0, n, step * L):
        hi = min(n, lo + step * L)
        F = factors(lo, hi, L)
        nbc = F.shape[-1]
        Pc, Xc, tc = P[..., :nbc], X[..., :nbc], t[..., :nbc]
        Pc[:, 0] = F[:, 0]
        for j in range(1, L):                           # (1) inside the blocks
            _cmul(Pc[:, j - 1], F[:, j], Pc[:, j], tc[0])
        tot = np.ascontiguousarray(Pc[:, L - 1].transpose(2, 1, 0)).view(np.float64)
        S = _quat_scan(carry, nbc, lambda a, b, L2, tot=tot: _quat_blocked(tot[a:b], L2), False)
        carry = S[-1]
        S = np.ascontiguousarray(S[:-1].view(np.complex128).transpose(2, 1, 0))  # (2, R, nbc)
        _cmul(S[:, None], Pc, Xc, tc)                   # (3)
        if normalize:                                   # scale by 1/|q| on the float view
            rc = r[..., :nbc]
            xf = Xc.view(np.float64)                    # (2, L, R, 2·nbc): re, im, re, im…
            sq = np.square(xf)
            np.add(sq[0, ..., 0::2], sq[0, ..., 1::2], out=rc)
            rc += sq[1, ..., 0::2]
            rc += sq[1, ..., 1::2]
            np.sqrt(rc, out=rc)
            np.divide(1.0, rc, out=rc)
            xf[..., 0::2] *= rc
            xf[..., 1::2] *= rc
        if hi - lo == nbc * L:                          # (2, L, R, nbc) → (nbc, L, R, 2)
            flat[lo:hi].reshape(nbc, L, R, 2)[...] = Xc.transpose(3, 1, 2, 0)
        else:                                           # the last, padded chunk
            flat[lo:hi] = Xc.transpose(3, 1, 2, 0).reshape(-1, R, 2)[: hi - lo]
    return out


def _check_chain(q0, x, name: str, last: int) -> tuple[np.ndarray, np.ndarray, bool]:
    """Validate ``q0`` (4,) or (R, 4) and factors (N, 4|3) or (N, R, 4|3); return batched views."""
    q0 = as_float_array(q0, "q0", last=4)
    x = as_float_array(x, name, last=last)
    single = q0.ndim == 1
    if q0.ndim not in (1, 2) or x.ndim != q0.ndim + 1 or x.shape[1:-1] != q0.shape[:-1]:
        raise ImunavError(
            f"{name} must have shape (N, {last}) for q0 of shape (4,), or (N, R, {last}) for q0 "
            f"of shape (R, 4); got {name} {x.shape} and q0 {q0.shape}"
        )
    if single:
        q0, x = q0[None], x[:, None]
    return q0, x, single


def cumulative_product(q0: npt.ArrayLike, dq: npt.ArrayLike, normalize: bool = True) -> FloatArray:
    """``q_k = q_{k−1} ⊗ dq_k`` for k = 1..N, returned with ``q_0`` first: shape (N+1, 4).

    Batched: ``q0`` (R, 4) and ``dq`` (N, R, 4) give R independent chains, (N+1, R, 4).
    Vectorised blocked prefix product (:func:`_quat_scan`). ``normalize`` rescales the results
    to unit norm (leave it False to keep the norm drift of unnormalised updates, as some papers
    do).
    """
    q0, dq, single = _check_chain(q0, dq, "dq", 4)
    if normalize:
        q0 = quat_normalize(q0)
    out = _quat_scan(q0, dq.shape[0], lambda lo, hi, L: _quat_blocked(dq[lo:hi], L), normalize)
    return out[:, 0] if single else out


def exp_product(q0: npt.ArrayLike, phi: npt.ArrayLike) -> FloatArray:
    """``q_k = q_{k−1} ⊗ exp(φ_k)`` for k = 1..N (rotation vectors φ in the body frame),
    normalised, with ``q_0`` first: shape (N+1, 4), or (N+1, R, 4) for ``q0`` (R, 4) and ``phi``
    (N, R, 3). The same as ``cumulative_product(q0, quat_exp(phi))`` with the exponential
    computed chunk by chunk inside the scan (one pass less over memory)."""
    q0, phi, single = _check_chain(q0, phi, "phi", 3)
    q0 = quat_normalize(q0)
    out = _quat_scan(q0, phi.shape[0], lambda lo, hi, L: _exp_blocked(phi[lo:hi], L), True)
    return out[:, 0] if single else out


# --------------------------------------------------------------------------- helpers


def _pairs(x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Neighbour pairs for two-sample corrections: (x_{k−1}, x_k) for k ≥ 1, (x_0, x_1) at k = 0.

    For a rate linear in time across the two intervals both pairs give the same correction,
    so the first interval uses the next one instead of a missing previous one.
    """
    if x.shape[0] < 2:
        return np.zeros_like(x), np.zeros_like(x)
    prev = np.concatenate([x[:1], x[:-1]])
    cur = np.concatenate([x[1:2], x[1:]])
    return prev, cur


# --------------------------------------------------------------------------- rate algorithms

def _rates_trapezoid_nav(sig, q, v0, p0, g):
    # v_k = v_{k−1} + h/2 (a_{k−1} + a_k); p exact for a linear in time.
    h = sig.dt
    a = _rotate(q, sig.accel) + np.array([0.0, 0.0, g])
    dv = h / 2 * (a[:-1] + a[1:])
    dp_extra = h * h / 6 * (2 * a[:-1] + a[1:])
    return _accumulate(v0, p0, dv, dp_extra, h)


def _accumulate(v0, p0, dv, dp_extra, h):
    v = np.concatenate([v0[None], v0 + np.cumsum(dv, axis=0)])
    dp = h * v[:-1] + dp_extra
    p = np.concatenate([p0[None], p0 + np.cumsum(dp, axis=0)])
    return v, p


def _check_rates(sig, algo):
    if sig.kind != "rates":
        raise ImunavError(f"algorithm {algo!r} needs rate signals, got {sig.kind}")
    if len(sig) < 2:
        raise ImunavError("rate signals need at least 2 samples")


def _rates_first_order(sig, q0, v0, p0, g):
    _check_rates(sig, "first_order")
    h = sig.dt
    dq = np.concatenate([np.ones((len(sig) - 1, 1)), 0.5 * h * sig.gyro[:-1]], axis=1)
    dq /= np.linalg.norm(dq, axis=1, keepdims=True)  # q + ½ q⊗ω h, then normalise
    q = cumulative_product(q0, dq)
    v, p = _rates_trapezoid_nav(sig, q, v0, p0, g)
    return q, v, p


def _rates_exponential(sig, q0, v0, p0, g):
    _check_rates(sig, "exact_exponential")
    h = sig.dt
    q = exp_product(q0, 0.5 * h * (sig.gyro[:-1] + sig.gyro[1:]))
    v, p = _rates_trapezoid_nav(sig, q, v0, p0, g)
    return q, v, p


def _poly(kind: str, m: int, order: int, nsub: int):
    """A high-order offline algorithm: local m-node fit + Magnus-`order` (see imunav.highorder)."""
    from imunav import highorder

    def run(sig, q0, v0, p0, g):
        if sig.kind != kind:
            raise ImunavError(f"this algorithm needs {kind} signals, got {sig.kind}")
        if len(sig) < 2:
            raise ImunavError(f"{kind} signals need at least 2 samples for a polynomial fit")
        return highorder.navigate_poly(kind, sig.gyro, sig.accel, sig.dt, q0, v0, p0, g, m=m,
                                       order=order, nsub=nsub)

    return run


# ---------------------------------------------------------------------- increment algorithms


def _check_inc(sig, algo):
    if sig.kind != "increments":
        raise ImunavError(f"algorithm {algo!r} needs increment signals, got {sig.kind}")
    if len(sig) < 1:
        raise ImunavError("increment signals need at least 1 interval")


def _inc_velocity(sig, q, v0, p0, g, sculling: bool):
    """Velocity from Δv with rotation compensation (½ Δθ×Δv) and optional two-sample
    sculling (1/12 (Δθ_{k−1}×Δv_k + Δv_{k−1}×Δθ_k)); position by the trapezoid rule."""
    h = sig.dt
    dth, dv = sig.gyro, sig.accel
    body = dv + 0.5 * np.cross(dth, dv)
    if sculling:
        tp, tc = _pairs(dth)
        vp, vc = _pairs(dv)
        body = body + (np.cross(tp, vc) + np.cross(vp, tc)) / 12
    dvn = _rotate(q[:-1], body) + np.array([0.0, 0.0, g * h])
    return _accumulate(v0, p0, dvn, 0.5 * h * dvn, h)


def _inc_first_order(sig, q0, v0, p0, g):
    _check_inc(sig, "first_order")
    dq = np.concatenate([np.ones((len(sig), 1)), 0.5 * sig.gyro], axis=1)
    q = cumulative_product(q0, dq / np.linalg.norm(dq, axis=1, keepdims=True))
    v, p = _inc_velocity(sig, q, v0, p0, g, sculling=False)
    return q, v, p


def _inc_exponential(sig, q0, v0, p0, g):
    _check_inc(sig, "exact_exponential")
    q = exp_product(q0, sig.gyro)
    v, p = _inc_velocity(sig, q, v0, p0, g, sculling=False)
    return q, v, p


def _inc_coning2(sig, q0, v0, p0, g):
    _check_inc(sig, "coning2")
    prev, cur = _pairs(sig.gyro)
    phi = sig.gyro + np.cross(prev, cur) / 12
    q = exp_product(q0, phi)
    v, p = _inc_velocity(sig, q, v0, p0, g, sculling=True)
    return q, v, p


#: N-sample coning corrections δφ = Σ c_ij θ_i × θ_j over a major interval of N increments.
#: Ignagni 1990 (J. Guid. Control Dyn. 13(2)); Miller 1983 (6(4)); Savage 1998 table.
CONING_FAMILIES = {
    "ignagni2": (2, {(0, 1): 2 / 3}),
    "miller3": (3, {(0, 2): 33 / 80, (1, 2): 57 / 80, (0, 1): 57 / 80}),
    "ignagni3": (3, {(0, 2): 9 / 20, (1, 2): 27 / 40, (0, 1): 27 / 40}),
    "ignagni4": (4, {(0, 1): 736 / 945, (2, 3): 736 / 945, (0, 2): 334 / 945,
                     (1, 3): 334 / 945, (0, 3): 526 / 945, (1, 2): 654 / 945}),
}


def _multisample(name: str):
    """N-sample rotation-vector algorithm: the attitude is updated once per N increments with
    φ = Σθ_i + Σ c_ij θ_i×θ_j (θ₂×(θ₃−θ₁) of eq. (2) written as θ₁×θ₂ + θ₂×θ₃). Between
    major updates (and for a trailing partial group) q = q_major ⊗ exp(Σθ + ½ Σ_{a<b} θ_a×θ_b),
    the second-order product of the exponentials."""
    n, coef = CONING_FAMILIES[name]

    def run(sig, q0, v0, p0, g):
        _check_inc(sig, name)
        th = sig.gyro
        N = th.shape[0]
        groups = N // n
        phi = np.empty((groups, 3))
        if groups:
            t = th[: groups * n].reshape(groups, n, 3)
            phi = t.sum(axis=1)
            for (i, j), c in coef.items():
                phi = phi + c * np.cross(t[:, i], t[:, j])
        qm = exp_product(q0, phi)                             # at every n-th sample
        # intermediate samples from the last major attitude
        k = np.arange(1, N + 1)
        base = (k - 1) // n                                   # index of the major attitude
        first = base * n                                      # first increment of the group
        cs = np.cumsum(th, axis=0)
        csum0 = np.concatenate([np.zeros((1, 3)), cs])
        part = cs - csum0[first]                              # Σθ within the group so far
        # ½ Σ_{a<b} θ_a × θ_b = ½ Σ_b (Σ_{a<b} θ_a) × θ_b
        prev_in_group = csum0[:-1] - csum0[first]
        cr = np.cross(prev_in_group, th) / 2
        crs = np.cumsum(cr, axis=0)
        crs0 = np.concatenate([np.zeros((1, 3)), crs])
        part2 = crs - crs0[first]
        q = _mul(qm[base], _exp(part + part2))
        full = (k % n == 0)
        q[full] = qm[k[full] // n]
        q = np.concatenate([q0[None], q])
        v, p = _inc_velocity(sig, q, v0, p0, g, sculling=True)
        return q, v, p

    return run


def _register(*algos: Algorithm) -> dict[str, dict[str, Algorithm]]:
    reg: dict[str, dict[str, Algorithm]] = {"rates": {}, "increments": {}}
    for a in algos:
        reg[a.kind][a.name] = a
    return reg


#: ``ALGORITHMS[kind][name]`` → :class:`Algorithm`.
ALGORITHMS = _register(
    Algorithm("first_order", "rates", (1, 1, 1),
              "q ← normalise(q + ½ q⊗ω_{k−1} h); trapezoidal velocity, position exact for "
              "linear a_n", "textbook Poisson/quaternion update, e.g. Marusenkova 2020 eq. (15); "
              "Madgwick's tutorial", _rates_first_order),
    Algorithm("exact_exponential", "rates", (2, 2, 2),
              "q ← q ⊗ exp(h (ω_{k−1}+ω_k)/2): exact for constant rate; trapezoidal velocity",
              "Dickson & Rae 2021 (rotation quaternion from rates); Savage 1998",
              _rates_exponential),
    Algorithm("magnus4", "rates", (4, 4, 4),
              "local cubic through 4 rate samples, one 2-node fourth-order Magnus step; "
              "velocity/position by 3-point Gauss quadrature of C_nb f_b",
              "Iserles & Nørsett 1999 (Magnus integrators); offline (uses the next sample)",
              _poly("rates", 4, 4, 1), causal=False),
    Algorithm("magnus6", "rates", (6, 6, 6),
              "local quintic through 6 rate samples, one 3-node sixth-order Magnus step; "
              "velocity/position by 3-point Gauss quadrature of C_nb f_b",
              "Blanes, Casas & Ros 2000 (sixth-order Magnus); offline (uses 3 later samples)",
              _poly("rates", 6, 6, 1), causal=False),
    Algorithm("first_order", "increments", (2, 2, 2),
              "q ← normalise(q ⊗ [1, Δθ/2]); Δv with rotation compensation, no sculling",
              "textbook small-angle quaternion, Marusenkova 2020 eq. (25)", _inc_first_order),
    Algorithm("exact_exponential", "increments", (2, 2, 2),
              "q ← q ⊗ exp(Δθ): exact for constant rate; no coning/sculling correction",
              "Marusenkova 2020 eq. (36); Savage 1998", _inc_exponential),
    Algorithm("coning2", "increments", (3, 2, 2),
              "rotation vector φ = Δθ_k + Δθ_{k−1}×Δθ_k/12 (1+1 'previous interval' coning), "
              "two-sample sculling and rotation compensation; trapezoidal position",
              "Savage 1998 (J. Guid. Control Dyn. 21(1)), Titterton & Weston ch. 11",
              _inc_coning2),
    Algorithm("ignagni2", "increments", (3, 2, 2),
              "2-sample rotation vector: θ₁+θ₂ + ⅔ θ₁×θ₂ per major interval of 2 increments",
              "Ignagni 1990 (J. Guid. Control Dyn. 13(2)); causal", _multisample("ignagni2")),
    Algorithm("miller3", "increments", (3, 2, 2),
              "3-sample rotation vector, eq. (2) of Plaksiy & Homozkova with α=33/80, β=57/80",
              "Miller 1983 (J. Guid. Control Dyn. 6(4)); causal", _multisample("miller3")),
    Algorithm("ignagni3", "increments", (3, 2, 2),
              "3-sample rotation vector optimised for coning: α=9/20, β=27/40",
              "Ignagni 1990; causal", _multisample("ignagni3")),
    Algorithm("ignagni4", "increments", (3, 2, 2),
              "4-sample rotation vector optimised for coning (coefficients /945)",
              "Ignagni 1990; Savage 1998 table 1; causal", _multisample("ignagni4")),
    Algorithm("poly6_m4", "increments", (4, 4, 4),
              "6-node fit of cumulative increments, one fourth-order Magnus step per interval; "
              "Gauss quadrature of C_nb f_b for velocity/position",
              "this work (local polynomial + Magnus, Iserles & Nørsett 1999); offline",
              _poly("increments", 6, 4, 1), causal=False),
    Algorithm("poly8_m6", "increments", (6, 6, 6),
              "8-node fit of cumulative increments, one sixth-order Magnus step per interval; "
              "Gauss quadrature of C_nb f_b for velocity/position",
              "this work (local polynomial + Blanes–Casas–Ros sixth-order Magnus); offline",
              _poly("increments", 8, 6, 1), causal=False),
)

#: The most accurate algorithm for each signal kind (used when none is named).
DEFAULT_ALGORITHM = {"rates": "magnus6", "increments": "poly8_m6"}


def navigate(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike = (0.0, 0.0, 0.0),
             p0: npt.ArrayLike = (0.0, 0.0, 0.0), *, algorithm: str | None = None,
             g: float | None = None) -> NavResult:
    """Integrate IMU signals from an initial state.

    Parameters
    ----------
    signals : ImuSignals
        Rates (``t_k``, k = 0..N) or increments (interval ends ``t_k``, k = 1..N).
    q0 : array_like, shape (4,)
        Initial attitude ``q_nb`` at the start time.
    v0, p0 : array_like, shape (3,)
        Initial velocity (m/s) and position (m), NED.
    algorithm : str, optional
        A name from ``ALGORITHMS[signals.kind]``; default the most accurate for the kind.
    g : float, optional
        Gravity magnitude (m/s²); default ``signals.g``.

    Returns
    -------
    NavResult
        States at ``t_k``, k = 0..N (the first row is the initial state).
    """
    if not isinstance(signals, ImuSignals):
        raise ImunavError(f"signals must be ImuSignals, got {type(signals).__name__}")
    q0 = quat_normalize(as_float_array(q0, "q0", ndim=1, last=4))
    v0 = as_float_array(v0, "v0", ndim=1, last=3)
    p0 = as_float_array(p0, "p0", ndim=1, last=3)
    g = signals.g if g is None else float(as_float_array(g, "g", ndim=0))
    name = algorithm or DEFAULT_ALGORITHM[signals.kind]
    table = ALGORITHMS[signals.kind]
    if name not in table:
        raise ImunavError(
            f"unknown algorithm {name!r} for {signals.kind}; choose one of {sorted(table)}"
        )
    q, v, p = table[name].func(signals, q0, v0, p0, g)
    if signals.kind == "rates":
        t = signals.t.copy()
    else:
        t = np.concatenate([[signals.t[0] - signals.dt], signals.t])
    return NavResult(t, p, v, q, name)
