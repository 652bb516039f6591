"""Plain sequential reference implementations of the strapdown recursions.

One sample at a time, scalar arithmetic only, written out from the equations in
:mod:`imunav.strapdown` — slow in Python, but easy to read and to check by eye. They serve two
purposes:

- **oracles** for the vectorised fast path: ``tests/test_performance.py`` runs them (as plain
  Python) on short inputs and requires the vectorised results to agree to ≤ 1e-12;
- the **compiled baseline** of ``benchmarks/bench.py``: the same functions JIT-compiled with
  numba (the ``bench`` extra) are what "the speed of compiled code" means there.

They use only ``math`` and indexing, so numba compiles them unchanged. Each writes into
preallocated output arrays ``q (N+1, 4)``, ``v (N+1, 3)``, ``p (N+1, 3)`` whose first row holds
the initial state.
"""

from __future__ import annotations

import math


def exp_attitude(dth, q):
    """``q_k = q_{k−1} ⊗ exp(Δθ_k)`` (the exact-exponential attitude), normalised outputs.

    ``dth`` (N, 3) rotation-vector increments (rad); ``q`` (N+1, 4) with ``q[0]`` set.
    The running product is kept unnormalised (as the vectorised prefix product does) and each
    output row is scaled to unit norm.
    """
    n = dth.shape[0]
    w, x, y, z = q[0, 0], q[0, 1], q[0, 2], q[0, 3]
    for k in range(n):
        a0, a1, a2 = dth[k, 0], dth[k, 1], dth[k, 2]
        ang = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        c = math.cos(0.5 * ang)
        s = math.sin(0.5 * ang) / ang if ang > 0.0 else 0.5
        bw, bx, by, bz = c, s * a0, s * a1, s * a2
        w, x, y, z = (w * bw - x * bx - y * by - z * bz,
                      w * bx + x * bw + y * bz - z * by,
                      w * by - x * bz + y * bw + z * bx,
                      w * bz + x * by - y * bx + z * bw)
        r = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
        q[k + 1, 0] = w * r
        q[k + 1, 1] = x * r
        q[k + 1, 2] = y * r
        q[k + 1, 3] = z * r


def exp_navigation(dth, dv, h, g, q, v, p):
    """Increment navigation of the ``exact_exponential`` algorithm, one interval at a time.

    Attitude as :func:`exp_attitude`; velocity ``v_k = v_{k−1} + C(q_{k−1}) (Δv + ½ Δθ×Δv)
    + g_n h``; position ``p_k = p_{k−1} + v_{k−1} h + ½ h (v_k − v_{k−1})``.
    """
    exp_attitude(dth, q)
    n = dth.shape[0]
    gh = g * h
    for k in range(n):
        t0, t1, t2 = dth[k, 0], dth[k, 1], dth[k, 2]
        u0, u1, u2 = dv[k, 0], dv[k, 1], dv[k, 2]
        b0 = u0 + 0.5 * (t1 * u2 - t2 * u1)
        b1 = u1 + 0.5 * (t2 * u0 - t0 * u2)
        b2 = u2 + 0.5 * (t0 * u1 - t1 * u0)
        n0, n1, n2 = _rotate(q[k, 0], q[k, 1], q[k, 2], q[k, 3], b0, b1, b2)
        n2 += gh
        v[k + 1, 0] = v[k, 0] + n0
        v[k + 1, 1] = v[k, 1] + n1
        v[k + 1, 2] = v[k, 2] + n2
        p[k + 1, 0] = p[k, 0] + (h * v[k, 0] + 0.5 * h * n0)
        p[k + 1, 1] = p[k, 1] + (h * v[k, 1] + 0.5 * h * n1)
        p[k + 1, 2] = p[k, 2] + (h * v[k, 2] + 0.5 * h * n2)


def _rotate(w, x, y, z, a, b, c):
    """``q ⊗ [0, v] ⊗ q*`` for unit q as ``v + 2w (u×v) + 2 u×(u×v)``."""
    t0 = 2.0 * (y * c - z * b)
    t1 = 2.0 * (z * a - x * c)
    t2 = 2.0 * (x * b - y * a)
    return (a + w * t0 + (y * t2 - z * t1),
            b + w * t1 + (z * t0 - x * t2),
            c + w * t2 + (x * t1 - y * t0))
