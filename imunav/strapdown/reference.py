"""Plain sequential reference implementations of the strapdown recursions.

One sample at a time, scalar arithmetic only, written out from the equations in
:mod:`imunav.strapdown.classic` and :mod:`imunav.strapdown.highorder` — slow in Python, but
easy to read and to check by eye. They serve two
purposes:

- **oracles** for the vectorised fast path: ``tests/strapdown/test_scan.py`` runs them (as plain
  Python) on short inputs and requires the vectorised results to agree to ≤ 1e-12;
- the **compiled baseline** of ``benchmarks/bench.py``: the same functions JIT-compiled with
  numba (the ``bench`` extra) are what "the speed of compiled code" means there.

They use only ``math``, indexing and ``np.zeros``, so numba compiles them unchanged. Each writes into
preallocated output arrays ``q (N+1, 4)``, ``v (N+1, 3)``, ``p (N+1, 3)`` whose first row holds
the initial state. The tables the high-order loop needs (each interval's stencil and the tap
weights of the fitted polynomial) are derived here independently of the fast path:
:func:`poly_tables` builds the interpolating polynomial with SymPy and reads the weights off it.

May import: nothing from imunav (numba must compile every function unchanged).
"""

from __future__ import annotations

import math

import numpy as np


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


# ------------------------------------------------------------------ high-order (poly8_m6)

_SQ15 = math.sqrt(15.0)


def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


def _magnus6(w, r, h):
    """Sixth-order Magnus rotation vector from ω at the 3 Gauss nodes ``w[r], w[r+1], w[r+2]``
    (rows of a (S, 3) array), as :func:`imunav.highorder.magnus6`; the body-frame Lie
    bracket is ``[x, y] = y × x``."""
    k2, k3 = _SQ15 * h / 3, 10 * h / 3
    a10, a11, a12 = h * w[r + 1, 0], h * w[r + 1, 1], h * w[r + 1, 2]
    a20, a21, a22 = (k2 * (w[r + 2, 0] - w[r, 0]), k2 * (w[r + 2, 1] - w[r, 1]),
                     k2 * (w[r + 2, 2] - w[r, 2]))
    a30 = k3 * (w[r + 2, 0] - 2 * w[r + 1, 0] + w[r, 0])
    a31 = k3 * (w[r + 2, 1] - 2 * w[r + 1, 1] + w[r, 1])
    a32 = k3 * (w[r + 2, 2] - 2 * w[r + 1, 2] + w[r, 2])
    c10, c11, c12 = _cross(a20, a21, a22, a10, a11, a12)                  # [a1, a2]
    x0, x1, x2 = _cross(2 * a30 + c10, 2 * a31 + c11, 2 * a32 + c12, a10, a11, a12)
    c20, c21, c22 = -x0 / 60, -x1 / 60, -x2 / 60                         # −[a1, 2a3 + c1]/60
    y0, y1, y2 = _cross(a20 + c20, a21 + c21, a22 + c22,
                        -20 * a10 - a30 + c10, -20 * a11 - a31 + c11, -20 * a12 - a32 + c12)
    return a10 + a30 / 12 + y0 / 240, a11 + a31 / 12 + y1 / 240, a12 + a32 / 12 + y2 / 240


def _exp(p0, p1, p2):
    ang = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
    s = math.sin(0.5 * ang) / ang if ang > 0.0 else 0.5
    return math.cos(0.5 * ang), s * p0, s * p1, s * p2


def poly_navigation(dth, dv, h, g, start, offset, wq, wf, gx, gw, q, v, p):
    """Increment navigation of the ``poly8_m6`` algorithm, one interval at a time.

    For interval k (0-based) with stencil ``start[k]`` and ``offset[k]``: the rates at the 12
    fit nodes ``ω_s = Σ_i wq[offset, s, i] Δθ[start + i]`` (nodes 0–2 the Gauss nodes of the
    whole interval, 3i+3 … 3i+5 those of ``[0, gx[i]]``) and the specific force at the 3 Gauss
    nodes ``f_s = Σ_i wf[offset, s, i] Δv[start + i]``; the tap weights are
    :meth:`imunav.highorder.LocalFit.weights`. Then ``q_k = q_{k−1} ⊗ exp(Magnus6)``,
    ``Δv_b = h Σ gw_i R(E_i) f_i``, ``Δp_b = h² Σ gw_i (1 − gx_i) R(E_i) f_i`` and
    ``v_k = v_{k−1} + C_{k−1} Δv_b + g_n h``, ``p_k = p_{k−1} + (v_{k−1} h + C_{k−1} Δp_b + g_n h²/2)``.
    """
    n = dth.shape[0]
    taps = wq.shape[2]
    w = q[0, 0], q[0, 1], q[0, 2], q[0, 3]
    wsa = np.zeros((wq.shape[1], 3))
    fsa = np.zeros((wf.shape[1], 3))
    for k in range(n):
        st, o = start[k], offset[k]
        for s in range(wq.shape[1]):
            for c in range(3):
                acc = 0.0
                for i in range(taps):
                    acc += wq[o, s, i] * dth[st + i, c]
                wsa[s, c] = acc
        for s in range(wf.shape[1]):
            for c in range(3):
                acc = 0.0
                for i in range(taps):
                    acc += wf[o, s, i] * dv[st + i, c]
                fsa[s, c] = acc
        b = _exp(*_magnus6(wsa, 0, h))
        w = (w[0] * b[0] - w[1] * b[1] - w[2] * b[2] - w[3] * b[3],
             w[0] * b[1] + w[1] * b[0] + w[2] * b[3] - w[3] * b[2],
             w[0] * b[2] - w[1] * b[3] + w[2] * b[0] + w[3] * b[1],
             w[0] * b[3] + w[1] * b[2] - w[2] * b[1] + w[3] * b[0])
        r = 1.0 / math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3])
        for c in range(4):
            q[k + 1, c] = w[c] * r
        dvb = [0.0, 0.0, 0.0]
        dpb = [0.0, 0.0, 0.0]
        for i in range(gx.shape[0]):
            e = _exp(*_magnus6(wsa, 3 * i + 3, h * gx[i]))
            rf = _rotate(e[0], e[1], e[2], e[3], fsa[i, 0], fsa[i, 1], fsa[i, 2])
            for c in range(3):
                dvb[c] += h * gw[i] * rf[c]
                dpb[c] += h * h * gw[i] * (1 - gx[i]) * rf[c]
        a = _rotate(q[k, 0], q[k, 1], q[k, 2], q[k, 3], dvb[0], dvb[1], dvb[2])
        d = _rotate(q[k, 0], q[k, 1], q[k, 2], q[k, 3], dpb[0], dpb[1], dpb[2])
        for c in range(3):
            gz = g if c == 2 else 0.0
            v[k + 1, c] = v[k, c] + (a[c] + gz * h)
            p[k + 1, c] = p[k, c] + ((d[c] + gz * h * h / 2) + h * v[k, c])


# ------------------------------------------------------------- tables, derived independently

def poly_tables(n: int, h: float, m: int = 8):
    """``start, offset, wq, wf, gx, gw`` for :func:`poly_navigation` on ``n`` increments: each
    interval's stencil (the ``m`` cumulative-sum nodes centred on it, shifted inward at the ends)
    and the tap weights of the rate ``ω = S'(x)/h`` of the polynomial ``S`` through the
    cumulative sums, at the sixth-order Magnus nodes of the interval and of its partial
    intervals ``[0, sᵢ]`` (``wq``) and at the 3-point Gauss nodes (``wf``).

    Written from the definitions with SymPy (``interpolate``, ``diff``, exact arithmetic),
    sharing no code with :mod:`imunav.strapdown.highorder`: the oracle's weights are its own.
    """
    import sympy as sp

    n_nodes = n + 1
    m = min(m, n_nodes)
    start = np.zeros(n, dtype=np.int64)
    offset = np.zeros(n, dtype=np.int64)
    for k in range(n):                               # interval k spans nodes k and k + 1
        st = k - (m // 2 - 1)
        st = max(0, min(st, n_nodes - m))
        start[k], offset[k] = st, k - st
    r15 = sp.sqrt(15)
    g = [sp.Rational(1, 2) - r15 / 10, sp.Rational(1, 2), sp.Rational(1, 2) + r15 / 10]
    gx = [float(x) for x in g]
    gw = np.array([5 / 18, 8 / 18, 5 / 18])
    s_q = [x for x in g] + [si * x for si in g for x in g]      # whole interval, then [0, sᵢ]
    x = sp.Symbol("x")
    d = sp.symbols(f"d0:{m - 1}")                                 # the m − 1 increments
    S = [sum(d[:j], sp.Integer(0)) for j in range(m)]             # cumulative sums at the nodes
    rate = sp.diff(sp.interpolate(list(zip(range(m), S, strict=True)), x), x)
    offs = int(offset.max()) + 1
    wq = np.zeros((offs, len(s_q), m - 1))
    wf = np.zeros((offs, 3, m - 1))
    for o in range(offs):
        for table, points in ((wq, s_q), (wf, g)):
            for j, sj in enumerate(points):
                val = sp.expand(rate.subs(x, o + sj))
                for i in range(m - 1):
                    table[o, j, i] = float(sp.N(val.coeff(d[i]), 30)) / h
    return start, offset, wq, wf, np.array(gx), gw
