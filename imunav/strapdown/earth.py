"""Strapdown navigation on the rotating WGS-84 Earth: the navigation-frame side of every
algorithm of the family.

**Mechanisation.** The body-frame integration is each algorithm's own, unchanged; the
navigation frame of its velocity and position recursions is the inertial frame ``i`` that
coincides with ECEF at the start time ``t₀`` (:func:`imunav.earth.dcm_ecef_to_inertial`). There

    q̇_ib = ½ q_ib ⊗ [0, ω_ib^b],    v̇_i = C_ib f^b + G(r_i),    ṙ_i = v_i,

with ``G`` the gravitation of the normal gravity model (:func:`imunav.earth.gravitation_ecef`,
symmetric about the Earth's axis, so the same function in ``i``). The attitude recursion is
exactly the flat frame's (the gyros measure ``ω_ib^b``), and the algorithms' velocity and
position recursions are affine in gravity: run with ``g = 0`` and zero initial velocity and
position they return the *thrust* parts ``v^T_k = Σ C_ib Δv_b`` and ``p^T_k``, and

    v_k = v₀ + v^T_k + Σ_{j≤k} I_j,     r_k = r₀ + v₀ (t_k − t₀) + p^T_k + Σ_{j≤k} (h V_{j−1} + II_j)

with ``I_j = ∫ G dt`` and ``II_j = ∫ (t_j − s) G ds`` over interval j (``V`` the running sum of
``I``). The Earth rate, the Coriolis and centripetal terms and the transport rate of a local-level
mechanisation are all in the exact change of frame at the output,

    r_e = C_ei r_i,   v_e = C_ei (v_i − Ω × r_i),   v_n = C_ne v_e,   q_nb = q_ne ⊗ q_ei ⊗ q_ib,

so each algorithm keeps its order (``tests/test_strapdown_earth.py`` measures it).

**Gravity.** ``I_j`` and ``II_j`` are integrated by an 8-node Adams–Moulton-type rule on the
gravitation at the nodes ``t_{j−7} … t_j`` (weights exact in rational arithmetic; fewer nodes
at the very start): causal, and of order 8 in a field that changes by ``|∇G| ≈ 3e-6 s⁻²`` per
metre. Since ``G(r_k)`` depends on the positions it helps to compute, the positions of a block
of steps are found by fixed-point (Picard) iteration, started from the gravity of a point at
rest on the Earth (the last value turned with the Earth) and corrected once with its gradient
along the predicted path; each further iteration shrinks the error by ``ρ ≈ |∇G| T²/2`` for a
block of T seconds (1e-4 for 8 s blocks), and a block is done when the estimated remaining
error ``ρ/(1−ρ)·Δ`` of its last change Δ is below :data:`TOLERANCE`.

**Vertical channel.** Free: unstable on the real Earth (e-folding in about 10 minutes), as in
every unaided inertial navigator.

May import: ``imunav.core``, ``imunav.earth``.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache

import numpy as np

from imunav.core.kernels import FloatArray, cross, quat_conj, quat_mul, quat_rotate
from imunav.core.validation import ImunavError
from imunav.earth import (
    E2,
    OMEGA_E,
    A,
    check_origin,
    dcm_ned_to_ecef,
    ecef_to_geodetic,
    geodetic_kernel,
    geodetic_to_ecef,
    gravitation_ecef,
    gravitation_gradient,
    gravitation_kernel,
    quat_ned_to_ecef,
)

__all__ = ["BLOCK_SECONDS", "NODES", "TOLERANCE", "EarthIntegrator", "gravity_weights"]

#: Nodes of the gravity quadrature (its order).
NODES = 8
#: Nodes of the quadrature of the iteration's corrections to the predicted gravitation: the
#: same rule, so that the sum is the rule applied to the corrected gravitation (a cheaper rule
#: errs at each block's start, where the correction starts from 0: measured 2e-12 m/s in 10 s).
CORRECTION_NODES = NODES
#: Longest block of the fixed-point iteration (s): ρ = |∇G| T²/2 ≈ 1.6e-3 at 32 s.
BLOCK_SECONDS = 32.0
#: A block's positions are accepted when their estimated remaining error is below this (m).
TOLERANCE = 1e-11
#: Most iterations per block (a block that does not converge by then is an error: a signal far
#: outside anything physical).
MAX_ITERATIONS = 12
#: |∇G| bound used for the contraction estimate (s⁻²): 2 GM/r³ at the surface, with margin.
GRADIENT = 3.2e-6
#: Relative error of the differenced gradient, with margin (the change over a block, 3|d|/R
#: for a departure |d| from a point at rest on the Earth, is added): bounds the error of the
#: linearised updates.
LINEARISATION = 1e-6
#: Step (m) of the central differences of the gradient.
GRADIENT_STEP = 20.0


@cache
def gravity_weights(m: int) -> tuple[FloatArray, FloatArray]:
    """Weights of the gravity quadrature on ``m`` nodes ``0 … m−1`` for the last interval
    ``[m−2, m−1]`` (unit step): ``∫ P`` and ``∫ (m−1 − s) P(s) ds`` of the interpolating
    polynomial ``P``, exactly in rational arithmetic and rounded once.

    Parameters
    ----------
    m : int
        Nodes (≥ 2).

    Returns
    -------
    a, b : ndarray, shape (m,)
        ``I ≈ h Σ a_j G_j`` and ``II ≈ h² Σ b_j G_j``.
    """
    a, b = [], []
    lo, hi = Fraction(m - 2), Fraction(m - 1)
    for j in range(m):
        c = [Fraction(1)]                                  # ascending powers of ℓ_j
        for k in range(m):
            if k == j:
                continue
            c = [Fraction(0)] + c
            for i in range(len(c) - 1):
                c[i] -= k * c[i + 1]
            c = [ci / (j - k) for ci in c]
        ia = sum(ck * (hi ** (n + 1) - lo ** (n + 1)) / (n + 1) for n, ck in enumerate(c))
        # ∫ (hi − s) s^n ds = hi (hi^{n+1} − lo^{n+1})/(n+1) − (hi^{n+2} − lo^{n+2})/(n+2)
        ib = sum(ck * (hi * (hi ** (n + 1) - lo ** (n + 1)) / (n + 1)
                       - (hi ** (n + 2) - lo ** (n + 2)) / (n + 2)) for n, ck in enumerate(c))
        a.append(float(ia))
        b.append(float(ib))
    return np.array(a), np.array(b)


def _rot_z(x: FloatArray, c: FloatArray, s: FloatArray) -> FloatArray:
    """``R_z(α) x`` for vectors ``x`` (..., 3) and ``c = cos α``, ``s = sin α`` broadcast to
    ``x.shape[:-1]``."""
    out = np.empty_like(x)
    out[..., 0] = c * x[..., 0] - s * x[..., 1]
    out[..., 1] = s * x[..., 0] + c * x[..., 1]
    out[..., 2] = x[..., 2]
    return out


def _expand(a: FloatArray, like: FloatArray) -> FloatArray:
    """A per-node scalar (n,) shaped to broadcast against the components ``like[..., i]`` of
    vectors ``like`` (n, [R,] 3)."""
    return a.reshape(a.shape + (1,) * (like.ndim - 2))


class EarthIntegrator:
    """The navigation-frame side of strapdown on the rotating Earth, for one run or ``R`` runs.

    Feed it, block after block, what the body-frame algorithm gives with ``g = 0`` from zero
    velocity and position (:meth:`advance`); it carries the inertial position and velocity, the
    gravity history and the frame, and returns the states in the local NED frame.

    Parameters
    ----------
    h : float
        Step (s).
    t0 : float
        Start time (s): the inertial frame coincides with ECEF then.
    q0 : ndarray, shape (4,) or (R, 4)
        Initial ``q_nb`` relative to local NED.
    v0 : ndarray, shape (3,) or (R, 3)
        Initial NED velocity relative to the Earth (m/s).
    p0 : ndarray, shape (3,) or (R, 3)
        Initial ``[lat, lon, h]`` (rad, rad, m).

    Attributes
    ----------
    q_ib : ndarray
        The body attitude in the inertial frame at the last node (what the body-frame
        algorithm continues from).
    iterations : list of int
        Fixed-point iterations of each block (diagnostics).
    """

    def __init__(self, h: float, t0: float, q0, v0, p0):
        self.h = float(h)
        self.t0 = float(t0)
        q0, v0, p0 = (np.asarray(x, dtype=float) for x in (q0, v0, p0))
        lat, lon, alt = p0[..., 0], p0[..., 1], p0[..., 2]
        for la, lo, al in zip(np.atleast_1d(lat), np.atleast_1d(lon), np.atleast_1d(alt),
                              strict=True):
            check_origin(la, lo, al, "p0")
        r = geodetic_to_ecef(lat, lon, alt)                    # i = e at t0
        C = dcm_ned_to_ecef(lat, lon)
        v_e = np.einsum("...ij,...j->...i", C, v0)
        self.r = r
        self.v = v_e + cross(np.broadcast_to([0.0, 0.0, OMEGA_E], r.shape), r)
        self.q_ib = quat_mul(quat_ned_to_ecef(lat, lon), q0 / np.linalg.norm(q0, axis=-1,
                                                                                keepdims=True))
        self.k = 0                                            # nodes done
        self.hist = gravitation_ecef(r)[None]                 # last ≤ NODES−1 gravitations
        self.iterations: list[int] = []
        self.evaluations: list[int] = []

    # ----------------------------------------------------------------------------- gravity
    def _integrals(self, psi: FloatArray, hist: FloatArray, m: int
                   ) -> tuple[FloatArray, FloatArray]:
        """``I_j``, ``II_j`` for the intervals ending at the ``n`` new nodes whose gravitations
        are ``psi`` (n, [R,] 3), by the ``m``-node rule; ``hist`` holds the values at the nodes
        before (fewer than ``m − 1`` only at the start of a run: lower-order rules there)."""
        n = psi.shape[0]
        back = min(hist.shape[0], m - 1)
        full = np.concatenate([hist[hist.shape[0] - back:], psi])   # nodes k−back+1 … k+n
        h = self.h
        start = max(0, m - 1 - back)                          # first interval with m nodes
        I = np.empty_like(psi)
        II = np.empty_like(psi)
        if start < n:
            a, b = gravity_weights(m)
            off, cnt = back + start - (m - 1), n - start
            w = full[off: off + cnt]
            Ia, Ib = I[start:], II[start:]
            np.multiply(w, h * a[0], out=Ia)
            np.multiply(w, h * h * b[0], out=Ib)
            tmp = np.empty_like(Ia)
            for j in range(1, m):
                w = full[off + j: off + j + cnt]
                Ia += np.multiply(w, h * a[j], out=tmp)
                Ib += np.multiply(w, h * h * b[j], out=tmp)
        for i in range(min(start, n)):                       # the first steps of a run
            s = back + i + 1                                  # nodes available: 0 … back + i
            a, b = gravity_weights(s)
            I[i] = h * np.tensordot(a, full[:s], axes=(0, 0))
            II[i] = h * h * np.tensordot(b, full[:s], axes=(0, 0))
        return I, II

    def _displacement(self, I: FloatArray, II: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Velocity ``V_k = Σ_{j≤k} I_j`` and displacement ``D_k = Σ_{j≤k} (h V_{j−1} + II_j)``
        from the block's start."""
        V = np.cumsum(I, axis=0)
        Vp = np.empty_like(V)
        Vp[0] = 0.0
        np.multiply(V[:-1], self.h, out=Vp[1:])
        Vp += II
        return V, np.cumsum(Vp, axis=0)

    # ------------------------------------------------------------------------------ advance
    def advance(self, q_ib: FloatArray, vT: FloatArray, pT: FloatArray
                ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Integrate ``n`` more steps.

        Parameters
        ----------
        q_ib : ndarray, shape (n + 1, [R,] 4)
            The body-frame algorithm's attitudes from :attr:`q_ib` (node 0 is the current one).
        vT, pT : ndarray, shape (n + 1, [R,] 3)
            Its velocities and positions with ``g = 0`` from zero velocity and position.

        Returns
        -------
        q, v, p : ndarray, shapes (n, [R,] 4), (n, [R,] 3), (n, [R,] 3)
            ``q_nb``, NED velocity and ``[lat, lon, h]`` at the ``n`` new nodes.
        """
        n = q_ib.shape[0] - 1
        if n <= 0:
            return (np.empty((0,) + q_ib.shape[1:]), np.empty((0,) + vT.shape[1:]),
                    np.empty((0,) + vT.shape[1:]))
        per = max(1, int(BLOCK_SECONDS / self.h))
        q = np.empty((n,) + q_ib.shape[1:])
        v = np.empty((n,) + vT.shape[1:])
        p = np.empty_like(v)
        for lo in range(0, n, per):
            hi = min(n, lo + per)
            q[lo:hi], v[lo:hi], p[lo:hi] = self._block(q_ib[lo + 1: hi + 1], vT, pT, lo, hi)
        self.q_ib = q_ib[-1].copy()
        return q, v, p

    def _block(self, q_ib, vT, pT, lo, hi):
        """Nodes ``lo+1 … hi`` of this call by the fixed-point iteration; the states there."""
        h = self.h
        n = hi - lo
        tau = np.arange(1, n + 1) * h                         # time since the block's start
        like = vT[lo + 1: hi + 1]
        tt = _expand(tau, like)[..., None]
        # the block's thrust, relative to its start (the chunk's sums are large: difference)
        dv = vT[lo + 1: hi + 1] - vT[lo]
        dp = pT[lo + 1: hi + 1] - pT[lo] - tt * vT[lo]
        rb, vb = self.r, self.v
        rho = GRADIENT * (n * h) ** 2 / 2
        # predictor: the last gravitation turned with the Earth (its path in closed form to
        # third order in ω τ), corrected with the field's gradient along the departure of the
        # predicted path from a point at rest on the Earth
        ang = OMEGA_E * tau
        c, s = _expand(np.cos(ang), like), _expand(np.sin(ang), like)
        last = np.broadcast_to(self.hist[-1], like.shape[1:])
        wl = np.empty_like(last)
        wl[..., 0], wl[..., 1], wl[..., 2] = -OMEGA_E * last[..., 1], OMEGA_E * last[..., 0], 0.0
        wwl = np.empty_like(last)
        wwl[..., 0], wwl[..., 1], wwl[..., 2] = -OMEGA_E * wl[..., 1], OMEGA_E * wl[..., 0], 0.0
        r = rb + tt * vb + dp + (tt * tt) * (0.5 * last + tt * (wl / 6.0 + tt * (wwl / 24.0)))
        Gb = gravitation_gradient(rb, GRADIENT_STEP)
        d = _rot_z(r, c, -s) - rb
        pred = _rot_z(last + np.einsum("...ij,...j->...i", Gb, d), c, s)
        # the gradient changes by ~3|d|/R over the block: the linearisation's relative error
        lin = 3.0 * float(np.abs(d).max()) / A + LINEARISATION
        # the predictor's integrals by the 8-node rule (with the history), once
        I0, II0 = self._integrals(pred, self.hist, NODES)
        V0, D0 = self._displacement(I0, II0)
        base_r = rb + tt * vb + dp + D0
        # one exact evaluation at the predicted path, then linearised updates about it; the
        # corrections to the predictor are tiny and smooth: a rule of CORRECTION_NODES nodes
        zeros = np.zeros((min(NODES - 1, self.hist.shape[0]),) + like.shape[1:])
        r1 = base_r
        geo = geodetic_kernel(r1)
        G1 = gravitation_kernel(r1, geo[0], geo[2], geo[3])
        psi = G1
        D_cur = np.zeros_like(D0)
        it, evals, first = 0, 1, None
        while True:
            V, D = self._displacement(*self._integrals(psi - pred, zeros, CORRECTION_NODES))
            it += 1
            change = float(np.abs(D - D_cur).max())
            first = change if first is None else first
            D_cur = D
            if rho / (1 - rho) * change <= TOLERANCE:
                if lin * rho * first <= TOLERANCE:
                    break
                # the linearisation's own error could exceed the tolerance: evaluate again
                r1 = base_r + D
                geo = geodetic_kernel(r1)
                G1 = gravitation_kernel(r1, geo[0], geo[2], geo[3])
                psi, first, evals = G1, None, evals + 1
                continue
            if it > MAX_ITERATIONS:
                raise ImunavError(
                    f"navigation on the Earth did not converge at t = "
                    f"{self.t0 + (self.k + 1) * h:.9g} s (the positions change by {change:.3g} m "
                    "per iteration): the signals are far outside a motion near the Earth")
            dr = _rot_z(base_r + D - r1, c, -s)                # in the block's axes
            psi = G1 + _rot_z(np.einsum("...ij,...j->...i", Gb, dr), c, s)
        r = base_r + D
        v = vb + dv + V0 + V
        self.iterations.append(it)
        self.evaluations.append(evals)
        self.hist = np.concatenate([self.hist, psi])[-(NODES - 1):]
        self.r, self.v = r[-1].copy(), v[-1].copy()
        self.k += n
        if not np.isfinite(geo[2]).all():
            raise ImunavError(f"navigation on the Earth left the Earth's surroundings by t = "
                              f"{self.t0 + self.k * h:.9g} s (within 43 km of its centre)")
        return self._local(q_ib, v, r, r1, geo, OMEGA_E * ((self.k - n) * h + tau))

    # ------------------------------------------------------------------------------ output
    def _local(self, q_ib, v_i, r_i, r1, geo, ang):
        """Inertial states → ``q_nb``, NED velocity and ``[lat, lon, h]``; the geodetic
        coordinates from those of the nearby ``r1`` (``geo``: :func:`geodetic_kernel`'s) plus
        the NED components of the small difference (second order: below 1e-15 m). ``ang`` is
        the Earth's turn ``ω_ie (t − t₀)`` at the nodes."""
        sl, cl, alt1, c_rho = geo
        x1, y1 = r1[..., 0], r1[..., 1]
        co, so = c_rho * x1, c_rho * y1                      # cos L cos λ_i, cos L sin λ_i
        d = r_i - r1
        rho = np.sqrt(x1 * x1 + y1 * y1)
        dn = -sl * (x1 * d[..., 0] + y1 * d[..., 1]) / rho + cl * d[..., 2]
        de = (-y1 * d[..., 0] + x1 * d[..., 1]) / rho
        dd = -(co * d[..., 0] + so * d[..., 1]) - sl * d[..., 2]
        x = 1.0 - E2 * sl * sl
        re = A / np.sqrt(x)
        rn = re * (1.0 - E2) / x
        lat = np.arctan2(sl, cl) + dn / (rn + alt1)
        lon_i = np.arctan2(y1, x1) + de / ((re + alt1) * cl)
        alt = alt1 - dd
        if np.abs(d).max(initial=0.0) > 1e-3:                # never expected: be exact
            lat, lon_i, alt = ecef_to_geodetic(r_i)
        # the local NED frame in the inertial frame: q_in = q_en at the inertial longitude
        q_ni = quat_conj(quat_ned_to_ecef(lat, lon_i))
        v_rel = v_i.copy()
        v_rel[..., 0] += OMEGA_E * r_i[..., 1]               # v_i − Ω × r_i
        v_rel[..., 1] -= OMEGA_E * r_i[..., 0]
        v_n = quat_rotate(q_ni, v_rel)
        q_nb = quat_mul(q_ni, q_ib)
        lon = lon_i - ang.reshape(ang.shape + (1,) * (lon_i.ndim - 1))
        lon = np.where(lon > np.pi, lon - 2 * np.pi, np.where(lon <= -np.pi, lon + 2 * np.pi, lon))
        return q_nb, v_n, np.stack([lat, lon, alt], axis=-1)


