"""Strapdown integration: attitude, velocity and position from rates or increments.

The navigation frame is flat, non-rotating NED with constant gravity ``g_n = [0, 0, +g]``:

    q̇_nb = ½ q_nb ⊗ [0, ω_b],   v̇_n = C_nb f_b + g_n,   ṙ_n = v_n.

Every algorithm is a row of :data:`ALGORITHMS` with its signal kind, its order (the measured
global convergence order of the attitude, velocity and position errors on smooth motion — see
``tests/test_strapdown.py``) and its source. The attitude recursion ``q_k = q_{k−1} ⊗ Δq_k``
is associative, so it is evaluated by a blocked prefix product (:func:`cumulative_product`),
vectorised; everything else is vectorised over samples.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from imunav.errors import ImunavError, as_float_array
from imunav.rotations import FloatArray, _dcm, _exp, _mul, quat_normalize, quat_to_euler
from imunav.simulate import ImuSignals

__all__ = ["ALGORITHMS", "Algorithm", "DEFAULT_ALGORITHM", "NavResult", "cumulative_product",
           "navigate"]


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


def cumulative_product(q0: npt.ArrayLike, dq: npt.ArrayLike, block: int | None = None,
                       normalize: bool = True) -> FloatArray:
    """``q_k = q_{k−1} ⊗ dq_k`` for k = 1..N, returned with ``q_0`` first (shape (N+1, 4)).

    Vectorised by :func:`prefix_product`. ``normalize`` rescales the results to unit norm
    (leave it False to keep the norm drift of unnormalised updates, as some papers do).
    """
    q0 = as_float_array(q0, "q0", ndim=1, last=4)
    if normalize:
        q0 = quat_normalize(q0)
    dq = as_float_array(dq, "dq", ndim=2, last=4)
    out = prefix_product(q0, dq, _mul, block)
    if normalize:
        out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    return out


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
    a = np.einsum("kij,kj->ki", _dcm(q), sig.accel) + np.array([0.0, 0.0, g])
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
    q = cumulative_product(q0, _exp(0.5 * h * (sig.gyro[:-1] + sig.gyro[1:])))
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
                                       order=order, nsub=nsub,
                                       cumulative_product=cumulative_product)

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
    dvn = np.einsum("kij,kj->ki", _dcm(q[:-1]), body) + np.array([0.0, 0.0, g * h])
    return _accumulate(v0, p0, dvn, 0.5 * h * dvn, h)


def _inc_first_order(sig, q0, v0, p0, g):
    _check_inc(sig, "first_order")
    dq = np.concatenate([np.ones((len(sig), 1)), 0.5 * sig.gyro], axis=1)
    q = cumulative_product(q0, dq / np.linalg.norm(dq, axis=1, keepdims=True))
    v, p = _inc_velocity(sig, q, v0, p0, g, sculling=False)
    return q, v, p


def _inc_exponential(sig, q0, v0, p0, g):
    _check_inc(sig, "exact_exponential")
    q = cumulative_product(q0, _exp(sig.gyro))
    v, p = _inc_velocity(sig, q, v0, p0, g, sculling=False)
    return q, v, p


def _inc_coning2(sig, q0, v0, p0, g):
    _check_inc(sig, "coning2")
    prev, cur = _pairs(sig.gyro)
    phi = sig.gyro + np.cross(prev, cur) / 12
    q = cumulative_product(q0, _exp(phi))
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
        dq_major = np.empty((groups, 4))
        if groups:
            t = th[: groups * n].reshape(groups, n, 3)
            phi = t.sum(axis=1)
            for (i, j), c in coef.items():
                phi = phi + c * np.cross(t[:, i], t[:, j])
            dq_major = _exp(phi)
        qm = cumulative_product(q0, dq_major)                 # at every n-th sample
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
