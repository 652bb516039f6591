"""The classic strapdown algorithms: textbook first-order and exponential updates on rates, and
on increments the exponential, the two-sample coning/sculling form and the multi-sample
rotation-vector algorithms (Ignagni, Miller).

Every function has the registry's signature
``f(gyro, accel, h, q0, v0, p0, g, first, count) → (q, v, p)``: ``gyro``/``accel`` are a window
of samples, (M, 3) or (M, R, 3) for R runs at once (with ``q0`` (R, 4), ``v0``/``p0`` (R, 3));
the function integrates the ``count`` intervals that start at interval ``first`` of the window
(the samples around them are context, e.g. the previous increment of a two-sample correction)
from the state ``(q0, v0, p0)`` at the start of interval ``first``, and returns ``count + 1``
states. Interval k of rates lies between samples k and k+1; of increments, it is sample k.
Inputs are already checked by :func:`imunav.strapdown.registry.navigate`.

The navigation frame is flat, non-rotating NED with constant gravity ``g_n = [0, 0, +g]``:
``q̇_nb = ½ q_nb ⊗ [0, ω_b]``, ``v̇_n = C_nb f_b + g_n``, ``ṙ_n = v_n``.

May import: ``imunav.core``, ``imunav.strapdown.scan``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.kernels import cross, quat_exp, quat_mul, quat_rotate
from imunav.core.rotations import FloatArray
from imunav.strapdown.scan import cumulative_product, exp_product


def _gravity(g) -> FloatArray:
    """The navigation-frame gravity: ``[0, 0, g]`` for a magnitude ``g`` (the flat NED frame),
    or a given vector (…, 3) as it is (on the Earth the driver passes a constant inertial one,
    which keeps the thrust sums small: :mod:`imunav.strapdown.rotating`)."""
    return np.array([0.0, 0.0, g]) if np.ndim(g) == 0 else np.asarray(g, dtype=float)


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


def accumulate(v0: FloatArray, p0: FloatArray, dv: FloatArray, dp_extra: FloatArray,
               h: float) -> tuple[FloatArray, FloatArray]:
    """``v_k = v_{k−1} + dv_k``, ``p_k = p_{k−1} + h v_{k−1} + dp_extra_k`` (navigation frame)."""
    v = np.concatenate([v0[None], v0 + np.cumsum(dv, axis=0)])
    dp = h * v[:-1] + dp_extra
    p = np.concatenate([p0[None], p0 + np.cumsum(dp, axis=0)])
    return v, p


# --------------------------------------------------------------------------- rate algorithms

def _rates_trapezoid_nav(accel, h, q, v0, p0, g):
    # v_k = v_{k−1} + h/2 (a_{k−1} + a_k); p exact for a linear in time.
    a = quat_rotate(q, accel) + _gravity(g)
    dv = h / 2 * (a[:-1] + a[1:])
    dp_extra = h * h / 6 * (2 * a[:-1] + a[1:])
    return accumulate(v0, p0, dv, dp_extra, h)


def rates_first_order(gyro, accel, h, q0, v0, p0, g, first, count):
    """``q ← normalise(q + ½ q⊗ω_{k−1} h)``; trapezoidal velocity."""
    w = gyro[first:first + count]
    accel = accel[first:first + count + 1]
    dq = np.concatenate([np.ones(w.shape[:-1] + (1,)), 0.5 * h * w], axis=-1)
    dq /= np.linalg.norm(dq, axis=-1, keepdims=True)
    q = cumulative_product(q0, dq)
    v, p = _rates_trapezoid_nav(accel, h, q, v0, p0, g)
    return q, v, p


def rates_exponential(gyro, accel, h, q0, v0, p0, g, first, count):
    """``q ← q ⊗ exp(h (ω_{k−1} + ω_k)/2)``; trapezoidal velocity."""
    gyro = gyro[first:first + count + 1]
    accel = accel[first:first + count + 1]
    q = exp_product(q0, 0.5 * h * (gyro[:-1] + gyro[1:]))
    v, p = _rates_trapezoid_nav(accel, h, q, v0, p0, g)
    return q, v, p


# ---------------------------------------------------------------------- increment algorithms

def _inc_velocity(dth, dv, h, q, v0, p0, g, sculling: bool, first: int = 0):
    """Velocity from Δv with rotation compensation (½ Δθ×Δv) and optional two-sample
    sculling (1/12 (Δθ_{k−1}×Δv_k + Δv_{k−1}×Δθ_k)); position by the trapezoid rule. The
    window's intervals ``first .. first + len(q) − 2`` are integrated (the pairs look back)."""
    n = q.shape[0] - 1
    body = dv[first:first + n] + 0.5 * cross(dth[first:first + n], dv[first:first + n])
    if sculling:
        tp, tc = _pairs(dth[: first + n])
        vp, vc = _pairs(dv[: first + n])
        body = body + (cross(tp[first:], vc[first:]) + cross(vp[first:], tc[first:])) / 12
    dvn = quat_rotate(q[:-1], body) + _gravity(g * h)
    return accumulate(v0, p0, dvn, 0.5 * h * dvn, h)


def increments_first_order(dth, dv, h, q0, v0, p0, g, first, count):
    """``q ← normalise(q ⊗ [1, Δθ/2])``; Δv with rotation compensation, no sculling."""
    dth, dv = dth[first:first + count], dv[first:first + count]
    dq = np.concatenate([np.ones(dth.shape[:-1] + (1,)), 0.5 * dth], axis=-1)
    q = cumulative_product(q0, dq / np.linalg.norm(dq, axis=-1, keepdims=True))
    v, p = _inc_velocity(dth, dv, h, q, v0, p0, g, sculling=False)
    return q, v, p


def increments_exponential(dth, dv, h, q0, v0, p0, g, first, count):
    """``q ← q ⊗ exp(Δθ)``; no coning or sculling correction."""
    dth, dv = dth[first:first + count], dv[first:first + count]
    q = exp_product(q0, dth)
    v, p = _inc_velocity(dth, dv, h, q, v0, p0, g, sculling=False)
    return q, v, p


def increments_coning2(dth, dv, h, q0, v0, p0, g, first, count):
    """``φ = Δθ_k + Δθ_{k−1}×Δθ_k/12``, two-sample sculling and rotation compensation."""
    dth, dv = dth[: first + count], dv[: first + count]
    prev, cur = _pairs(dth)
    q = exp_product(q0, (dth + cross(prev, cur) / 12)[first:])
    v, p = _inc_velocity(dth, dv, h, q, v0, p0, g, sculling=True, first=first)
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


def multisample(name: str):
    """N-sample rotation-vector algorithm ``name`` of :data:`CONING_FAMILIES`: the attitude is
    updated once per N increments with φ = Σθ_i + Σ c_ij θ_i×θ_j (Plaksiy & Homozkova's eq. (2)
    θ₂×(θ₃−θ₁) written as θ₁×θ₂ + θ₂×θ₃). Between major updates (and for a trailing partial
    group) q = q_major ⊗ exp(Σθ + ½ Σ_{a<b} θ_a×θ_b), the second-order product of the
    exponentials."""
    n, coef = CONING_FAMILIES[name]

    def run(window_th, window_dv, h, q0, v0, p0, g, first, count):
        # interval `first` of the window starts a major interval (the registry aligns chunks);
        # the samples before it serve only the sculling term's look-back
        th = window_th[first:first + count]
        N = th.shape[0]
        rest = th.shape[1:]
        groups = N // n
        phi = np.zeros((groups,) + rest)
        if groups:
            t = th[: groups * n].reshape((groups, n) + rest)
            phi = t.sum(axis=1)
            for (i, j), c in coef.items():
                phi = phi + c * cross(t[:, i], t[:, j])
        qm = exp_product(q0, phi)                             # at every n-th sample
        k = np.arange(1, N + 1)
        base = (k - 1) // n                                   # index of the major attitude
        start = base * n                                      # first increment of the group
        cs = np.cumsum(th, axis=0)
        csum0 = np.concatenate([np.zeros((1,) + rest), cs])
        part = cs - csum0[start]                              # Σθ within the group so far
        # ½ Σ_{a<b} θ_a × θ_b = ½ Σ_b (Σ_{a<b} θ_a) × θ_b
        prev_in_group = csum0[:-1] - csum0[start]
        crs = np.cumsum(cross(prev_in_group, th) / 2, axis=0)
        crs0 = np.concatenate([np.zeros((1,) + rest), crs])
        part2 = crs - crs0[start]
        q = quat_mul(qm[base], quat_exp(part + part2))
        full = k % n == 0
        q[full] = qm[k[full] // n]
        q = np.concatenate([qm[:1], q])
        v, p = _inc_velocity(window_th[:first + count], window_dv[:first + count], h, q, v0, p0,
                             g, sculling=True, first=first)
        return q, v, p

    run.__name__ = name
    return run
