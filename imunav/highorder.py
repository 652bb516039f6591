"""High-order offline strapdown: local polynomial fits feeding Magnus steps.

Offline processing may use samples on both sides of an interval. On each interval
``[t_{k−1}, t_k]`` a centred stencil of samples (shifted inward at the ends) defines

- from **rates**: the interpolating polynomial of ``ω_b`` and of ``f_b`` through ``m`` samples;
- from **increments**: the interpolating polynomial ``S(t)`` through ``m`` cumulative sums
  ``S_j = Σ_{i≤j} Δθ_i`` (``S(t) = ∫ω dt`` exactly at every node), and ``ω = S'``. The fit
  reproduces the interval's own increment exactly.

Attitude: ``q_k = q_{k−1} ⊗ exp(φ)`` with φ from ``nsub`` Magnus sub-steps of order 4
(2 Gauss nodes) or 6 (3 Gauss nodes); for body-frame right multiplication the Lie bracket
of rotation vectors is ``[x, y] = y × x``. Velocity and position: 3-point Gauss quadrature of
``C_nb(t) f_b(t)`` over the interval, the attitude at each node from a Magnus step over
``[t_{k−1}, node]``:

    Δv_b = h Σ wᵢ R(Eᵢ) f(sᵢ),   Δp_b = h² Σ wᵢ (1 − sᵢ) R(Eᵢ) f(sᵢ),
    v_k = v_{k−1} + C_{k−1} Δv_b + g_n h,   p_k = p_{k−1} + v_{k−1} h + C_{k−1} Δp_b + g_n h²/2.

Sources: Magnus integrators, Iserles & Nørsett (1999); the sixth-order 3-node form of
Blanes, Casas & Ros (2000), BIT 40, eq. for Ω^[6]; rotation-vector attitude, Bortz (1971).
"""

from __future__ import annotations

import numpy as np

from imunav.rotations import FloatArray, _exp, _mul, _rotate

_G4 = np.array([0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6])
_G6 = np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])
_GQ_X, _GQ_W = _G6, np.array([5 / 18, 8 / 18, 5 / 18])  # 3-point Gauss–Legendre on [0, 1]


def _br(x: FloatArray, y: FloatArray) -> FloatArray:
    """Lie bracket for right-multiplied body-frame rotation vectors: ``[x, y] = y × x``."""
    return np.cross(y, x)


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


def _basis(m: int, x: FloatArray, deriv: int) -> FloatArray:
    """``B[i, j]``: value (deriv=0) or derivative (deriv=1) at ``x[i]`` of the Lagrange basis
    polynomial j for the nodes 0..m−1 (centred monomials for conditioning)."""
    c = (m - 1) / 2
    nodes = np.arange(m) - c
    V = np.vander(nodes, m, increasing=True)          # V[j, p] = node_j^p
    C = np.linalg.inv(V)                               # basis_j(x) = Σ_p C[p, j] x^p
    xs = np.asarray(x, float) - c
    p = np.arange(m)
    if deriv == 0:
        X = xs[:, None] ** p[None, :]
    else:
        X = p[None, :] * xs[:, None] ** np.maximum(p - 1, 0)[None, :]
    return X @ C


class LocalFit:
    """Per-interval polynomial of a signal, evaluable at fractional positions ``s ∈ [0, 1]``.

    ``kind="rates"``: interpolate the ``N+1`` samples (value = signal). ``kind="increments"``:
    interpolate cumulative sums of the ``N`` increments and differentiate (value = rate).
    """

    def __init__(self, samples: FloatArray, kind: str, h: float, m: int):
        # samples: (N, 3) or batched (N, R, 3) — time first, any run axes in between.
        n_nodes = samples.shape[0] + (1 if kind == "increments" else 0)
        self.m = min(m, n_nodes)
        self.start, self.offset = _stencil(n_nodes, self.m)
        self.n = n_nodes - 1
        self.h = h
        if kind == "increments":
            # Cumulative sums relative to each stencil's first node, summed from the increments
            # themselves: the constant drops out of S' and the rounding stays at the size of
            # a few increments instead of the whole run's integral.
            win = samples[self.start[:, None] + np.arange(self.m - 1)]
            self.local = np.concatenate([np.zeros((self.n, 1) + samples.shape[1:]),
                                         np.cumsum(win, axis=1)], axis=1)
            self.deriv = 1
        else:
            self.local = samples[self.start[:, None] + np.arange(self.m)]
            self.deriv = 0

    def at(self, s: FloatArray) -> FloatArray:
        """Signal at ``t_{k−1} + s·h`` for every interval k and every s:
        shape (N, [R,] len(s), 3)."""
        s = np.atleast_1d(np.asarray(s, float))
        out = np.empty((self.n,) + self.local.shape[2:-1] + (s.size, 3))
        for o in np.unique(self.offset):
            sel = self.offset == o
            B = _basis(self.m, o + s, self.deriv)  # (len(s), m)
            if self.deriv:
                B = B / self.h
            out[sel] = np.einsum("rm,km...c->k...rc", B, self.local[sel])
        return out


def rotation_vectors(fit: LocalFit, order: int, nsub: int) -> FloatArray:
    """φ_k over each whole interval, composed from ``nsub`` Magnus sub-steps: returns Δq (N, 4)."""
    nodes, step = _MAGNUS[order]
    dq = None
    for j in range(nsub):
        w = fit.at((j + nodes) / nsub)
        e = _exp(step(w, fit.h / nsub))
        dq = e if dq is None else _mul(dq, e)
    return dq


def partial_attitudes(fit: LocalFit, order: int, s: FloatArray) -> FloatArray:
    """``E(s)`` = rotation from ``t_{k−1}`` to ``t_{k−1} + s·h`` (one Magnus step): (N, len(s), 4)."""
    nodes, step = _MAGNUS[order]
    return np.stack([_exp(step(fit.at(si * nodes), fit.h * si)) for si in s], axis=-2)


def navigate_poly(kind: str, gyro: FloatArray, accel: FloatArray, h: float, q0: FloatArray,
                  v0: FloatArray, p0: FloatArray, g: float, *, m: int, order: int,
                  nsub: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Attitude, velocity and position at every ``t_k`` (see the module docstring).

    ``gyro``/``accel`` (N, 3), or (N, R, 3) for R runs at once with ``q0`` (R, 4).
    """
    from imunav.strapdown import cumulative_product, exp_product

    wfit = LocalFit(gyro, kind, h, m)
    ffit = LocalFit(accel, kind, h, m)
    q0 = np.broadcast_to(q0, gyro.shape[1:-1] + (4,))
    if nsub == 1:
        nodes, step = _MAGNUS[order]
        q = exp_product(q0, step(wfit.at(nodes), h))
    else:
        q = cumulative_product(q0, rotation_vectors(wfit, order, nsub))
    E = partial_attitudes(wfit, order, _GQ_X)                    # (N, [R,] 3, 4)
    f = ffit.at(_GQ_X)                                            # (N, [R,] 3, 3)
    rf = _rotate(E, f)                                            # R(E_i) f_i, body at t_{k−1}
    dv_b = h * np.einsum("i,k...ic->k...c", _GQ_W, rf)
    dp_b = h * h * np.einsum("i,k...ic->k...c", _GQ_W * (1 - _GQ_X), rf)
    gn = np.array([0.0, 0.0, g])
    dv = _rotate(q[:-1], dv_b) + gn * h
    dp_extra = _rotate(q[:-1], dp_b) + gn * h * h / 2
    v0 = np.broadcast_to(v0, dv.shape[1:])
    p0 = np.broadcast_to(p0, dv.shape[1:])
    v = np.concatenate([v0[None], v0 + np.cumsum(dv, axis=0)])
    p = np.concatenate([p0[None], p0 + np.cumsum(h * v[:-1] + dp_extra, axis=0)])
    return q, v, p
