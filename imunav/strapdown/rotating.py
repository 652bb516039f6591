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
``I``). In practice the algorithm runs on pieces of the signals (``EARTH_CHUNK_SECONDS`` of
:mod:`imunav.strapdown.stream`) with the gravitation ``g₀`` at the piece's start as a constant
gravity, and ``g₀ τ`` and ``g₀ τ²/2`` are taken out again here, exactly: its sums then grow with
the change of gravity over the piece (the Earth turns ~0.05 rad in 10 minutes), not like g·t,
and so does their rounding. The Earth rate, the Coriolis and centripetal terms and the
transport rate of a local-level mechanisation are all in the exact change of frame at the output,

    r_e = C_ei r_i,   v_e = C_ei (v_i − Ω × r_i),   v_n = C_ne v_e,   q_nb = q_ne ⊗ q_ei ⊗ q_ib,

so each algorithm keeps its order (``tests/strapdown/test_rotating.py`` measures it).

**Gravity.** ``I_j`` and ``II_j`` are integrated by an 8-node Adams–Moulton-type rule on the
gravitation at the nodes ``t_{j−7} … t_j`` (weights exact in rational arithmetic; fewer nodes
at the very start): causal, and of order 8 in a field that changes by ``|∇G| ≈ 3e-6 s⁻²`` per
metre. Since ``G(r_k)`` depends on the positions it helps to compute, the positions of a block
of steps are found by fixed-point (Picard) iteration, started from the gravity of a point at
rest on the Earth (the last value turned with the Earth) and corrected once with its gradient
along the predicted path; each further iteration shrinks the error by ``ρ ≈ |∇G| T²/2`` for a
block of T seconds (1e-4 for 8 s blocks), and a block is done when the estimated remaining
error ``ρ/(1−ρ)·Δ`` of its last change Δ is below :data:`TOLERANCE`.

**Vertical channel.** Free (unstable on the real Earth, e-folding in about 10 minutes, as in
every unaided inertial navigator), or held at given heights and vertical velocities (``hold``,
a perfect height aid): at every step the velocity and the position get a kick along the up
normal that makes the vertical velocity and the height the held ones, the kicks acting on
every later step; they are found in the same iteration as gravity.

The block's fixed pieces (quadrature weights, tables, closed-form paths, the exact evaluation
along a path) are :mod:`~imunav.strapdown.rotating_blocks`.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.strapdown.rotating_blocks``.
"""

from __future__ import annotations

import math

import numpy as np

from imunav.core.kernels import FloatArray, cross, quat_mul
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError
from imunav.earth import (
    OMEGA_E,
    A,
    check_origin,
    dcm_ned_to_ecef,
    geodetic_kernel,
    geodetic_to_ecef,
    gravitation_ecef,
    gravitation_kernel,
    quat_ned_to_ecef,
)
from imunav.strapdown.rotating_blocks import (
    CRUDE,
    Z,
    absmax,
    block_tables,
    evaluate_path,
    expand,
    gradient_t,
    gravity_weights,
    matvec,
    poly_sum,
    quadrature_weights,
    rot_z,
    to_local,
    trapezoid,
)

__all__ = ["BLOCK_SECONDS", "NODES", "TOLERANCE", "EarthIntegrator", "gravity_weights"]

DEBUG = None  # (diagnostics: a list collects (node, evaluations, iteration, change, |d|))
#: Nodes of the gravity quadrature (its order).
NODES = 8
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
#: The held heights are met to this (m; velocity × block length): 10 bits of a position of
#: 6.4e6 m.
HOLD_TOLERANCE = 1e-8
#: A held path this far (m) from the exact evaluation is evaluated again (the linear height
#: there errs by its square over 2R: 1e-15 m at 1e-4 m).
HOLD_RELINEARISE = 1e-4


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
    hold : callable, optional
        ``hold(t) → (h, v_d)``: the heights (m) and down velocities (m/s) at the node times
        ``t`` (n,) — shapes (n,) or (n, R) — at which to hold the vertical channel (a perfect
        height aid); None: free.

    Attributes
    ----------
    q_ib : ndarray
        The body attitude in the inertial frame at the last node (what the body-frame
        algorithm continues from).
    iterations : list of int
        Fixed-point iterations of each block (diagnostics).
    """

    def __init__(self, h: float, t0: float, q0, v0, p0, hold=None):
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
        self.hold = hold
        self.k = 0                                            # nodes done
        self.hist = gravitation_ecef(r)[None]                 # last ≤ NODES−1 gravitations
        self.iterations: list[int] = []
        self.evaluations: list[int] = []
        self._gbt = None                  # the next block's gradient (transposed), if known

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
            # the m shifted node sequences as the rows of one matrix, times the (2, m) weights:
            # one BLAS product (3× faster than m multiply-adds per output)
            off, cnt = back + start - (m - 1), n - start
            X = np.empty((m, cnt * math.prod(psi.shape[1:])))
            for j in range(m):
                X[j] = full[off + j: off + j + cnt].reshape(-1)
            both = quadrature_weights(m, h) @ X
            I[start:] = both[0].reshape(I[start:].shape)
            II[start:] = both[1].reshape(II[start:].shape)
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
    @limit_blas
    def advance(self, q_ib: FloatArray, vT: FloatArray, pT: FloatArray,
                g0: FloatArray | None = None) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Integrate ``n`` more steps.

        Parameters
        ----------
        q_ib : ndarray, shape (n + 1, [R,] 4)
            The body-frame algorithm's attitudes from :attr:`q_ib` (node 0 is the current one).
        vT, pT : ndarray, shape (n + 1, [R,] 3)
            Its velocities and positions from zero velocity and position, with the constant
            inertial gravity ``g0`` (the thrust parts plus ``g0 t`` and ``g0 t²/2``: taken out
            here exactly, block by block).
        g0 : ndarray, shape ([R,] 3), optional
            That gravity (m/s²); default zero. The driver passes the gravitation at the
            current position (the last of :attr:`hist`): the sums then stay near the change
            of gravity over the piece, ~0.3 m/s² over 10 minutes, and their rounding with them.

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
        # the blocks' inertial states and evaluation points, converted to the local frame
        # at once at the end (one pass over the call instead of one per block)
        v = np.empty((n,) + vT.shape[1:])
        r = np.empty_like(v)
        r1 = np.empty_like(v)
        geo = tuple(np.empty((n,) + vT.shape[1:-1]) for _ in range(4))
        ang = np.empty(n)
        g0 = np.zeros(vT.shape[1:]) if g0 is None else np.broadcast_to(g0, vT.shape[1:])
        for lo in range(0, n, per):
            hi = min(n, lo + per)
            self._block(vT, pT, g0, lo, hi, (v, r, r1, geo, ang))
        self.q_ib = q_ib[-1].copy()
        return to_local(q_ib[1:], v, r, r1, geo, ang)

    def _block(self, vT, pT, g0, lo, hi, out):
        """Nodes ``lo+1 … hi`` of this call by the fixed-point iteration; their inertial
        velocities and positions, the evaluation points and their geodetic coordinates, and
        the Earth's turn into ``out[i][lo:hi]`` (the arrays of :meth:`advance`)."""
        h = self.h
        n = hi - lo
        tab = block_tables(n, h)
        tau = tab["tau"]                                       # time since the block's start
        like = vT[lo + 1: hi + 1]
        rb, vb = self.r, self.v
        # the block's thrust, relative to its start, and the path without gravity from the
        # block's start, r_b + τ (v_b − v^T_lo) + Δp^T; with g0 in the sums (v^T + g0 t,
        # p^T + g0 t²/2), Δv^T = Δv − g0 τ and the path is r_b + τ (v_b − v_lo) − g0 τ²/2 + Δp
        # (the terms in the block's start time cancel). The sums added the same rounded
        # g0·h at every step: g0 τ is taken out as that times the step count, or its rounding
        # (1e-17 m/s a step) would stay in the velocity as a drift
        dvb = vb - vT[lo]
        v_base = poly_sum(tab["steps"], np.stack([dvb, -(g0 * h)]), like)   # v_b + Δv^T − g0 τ
        v_base += like
        free_r = poly_sum(tab["p012"], np.stack([rb - pT[lo], dvb, -0.5 * g0]), like)
        free_r += pT[lo + 1: hi + 1]
        rho = GRADIENT * (n * h) ** 2 / 2
        # predictor: the last gravitation turned with the Earth (its path in closed form to
        # third order in ω τ), corrected to first order in the departure d of that path from
        # a point at rest on the Earth (the field's gradient, by differences of the field)
        c, s = expand(tab["cos"], like), expand(tab["sin"], like)
        last = self.hist[-1]
        crude = poly_sum(tab["p234"], np.moveaxis((last @ CRUDE).reshape(last.shape[:-1] + (3, 3)),
                                               -2, 0), like)
        crude += free_r
        GbT = gradient_t(rb) if self._gbt is None else self._gbt
        d = rot_z(crude, c, s, inverse=True)
        d -= rb
        lin = 3.0 * absmax(d) / A + LINEARISATION
        pred = matvec(GbT, d)
        pred += last
        pred = rot_z(pred, c, s)
        # the predictor's integrals by the 8-node rule (with the history), once; one exact
        # evaluation at the path they give (with the six points of the next block's gradient
        # about its last node, within ~1e-5 m of where the next block starts: the gradient
        # changes by 5e-12 of itself there); then the corrections, tiny and smooth, by the
        # trapezoid rule, linearised about that evaluation
        V0, D0 = self._displacement(*self._integrals(pred, self.hist, NODES))
        base_r = free_r
        base_r += D0
        geo, G1, self._gbt = evaluate_path(base_r)
        r1 = base_r
        v_base += V0
        # the gradient turned with the Earth, R_z(α) ∇G R_z(−α) = ∇G + α [Z, ∇G] + O(α²) (the
        # O(α²) term of the linearised update, α² |∇G| |r − r₁| ≈ 2e-16 m/s², is left out)
        KT = Z @ GbT - GbT @ Z
        alpha = expand(tab["ang"], like)[..., None]
        held = None
        if self.hold is not None:
            held = self._targets(tau, like.shape[:-1])
        psi, r_prev = G1, None
        it, evals, first = 0, 1, None
        v = None
        while True:
            V, D = trapezoid(psi - pred, h)
            r = base_r + D
            residual = 0.0
            if held is not None:
                v = v_base + V
                r, v, residual = self._held(r, v, r1, geo, tau, held)
            # r − r₁: at the first evaluation point r₁ = base_r, D itself (before its rounding)
            dr = D if held is None and r1 is base_r else r - r1
            it += 1
            change = absmax(dr if r_prev is None else r - r_prev)
            if DEBUG is not None:
                DEBUG.append((self.k, evals, it, change, float(np.abs(d).max()), residual))
            first = change if first is None else first
            r_prev = r
            if rho / (1 - rho) * change <= TOLERANCE and residual <= HOLD_TOLERANCE:
                far = held is not None and float(np.abs(dr).max()) > HOLD_RELINEARISE
                if lin * rho * first <= TOLERANCE and not far:
                    break
                # the linearisation's own error could exceed the tolerance (or the held path is
                # far from the evaluation): evaluate again there
                r1 = r
                geo = geodetic_kernel(r1)
                G1 = gravitation_kernel(r1, geo[0], geo[2], geo[3])
                psi, first, evals = G1, None, evals + 1
                continue
            if it > MAX_ITERATIONS:
                raise ImunavError(
                    f"navigation on the Earth did not converge at t = "
                    f"{self.t0 + (self.k + 1) * h:.9g} s (the positions change by {change:.3g} m "
                    "per iteration): the signals are far outside a motion near the Earth")
            psi = matvec(KT, dr)
            psi *= alpha
            psi += matvec(GbT, dr)
            psi += G1
        if held is None:
            v = v_base + V
        self.iterations.append(it)
        self.evaluations.append(evals)
        self.hist = np.concatenate([self.hist, psi])[-(NODES - 1):]
        self.r, self.v = r[-1].copy(), v[-1].copy()
        self.k += n
        if not np.isfinite(geo[2]).all():
            raise ImunavError(f"navigation on the Earth left the Earth's surroundings by t = "
                              f"{self.t0 + self.k * h:.9g} s (within 43 km of its centre)")
        v_out, r_out, r1_out, geo_out, ang_out = out
        v_out[lo:hi], r_out[lo:hi], r1_out[lo:hi] = v, r, r1
        for a, b in zip(geo_out, geo, strict=True):
            a[lo:hi] = b
        ang_out[lo:hi] = OMEGA_E * ((self.k - n) * h + tau)

    # ------------------------------------------------------------------------------ hold
    def _targets(self, tau, shape):
        """The held heights and up velocities at the block's nodes, ``(n, [R])`` each."""
        t = self.t0 + self.k * self.h + tau
        hh, vd = self.hold(t)

        def shaped(x, name):
            x = np.asarray(x, dtype=float)
            if x.ndim <= 1:                                   # one value per node, all runs
                x = x.reshape((t.size,) + (1,) * (len(shape) - 1))
            try:
                return np.broadcast_to(x, shape)
            except ValueError:
                raise ImunavError(f"hold(t) must give {name} of shape (n,) or {shape} for the "
                                  f"n = {t.size} times t, got {x.shape}",
                                  argument="hold") from None

        hh, vd = shaped(hh, "heights"), shaped(vd, "down velocities")
        return {"h": hh, "u": -vd, "S": np.zeros(shape), "P": np.zeros(shape)}

    def _held(self, r, v, r1, geo, tau, held):
        """The perfect height aid: at every node a kick along the up normal ``n`` of the velocity
        (so that its vertical part relative to the Earth is the held one) and of the position
        (so that the height is the held one), the kicks acting on every later node (a velocity
        kick at ``t_j`` moves the node at ``t_k`` by ``(t_k − t_j) n_j``). The cumulative kicks
        ``S`` (velocity) and ``P`` (position) are found by the same iteration as gravity:
        moving along ``n`` changes the height by as much, and nearby normals are parallel to
        ~(ω T)², so each pass adds the residuals to them."""
        sl, _, alt1, c_rho = geo
        nup = np.empty_like(r1)
        nup[..., 0] = c_rho * r1[..., 0]
        nup[..., 1] = c_rho * r1[..., 1]
        nup[..., 2] = sl
        S, P = held["S"], held["P"]
        kv = np.diff(S, axis=0, prepend=0.0)[..., None]
        kp = np.diff(P, axis=0, prepend=0.0)[..., None]
        tt = expand(tau, r)[..., None]
        KV = np.cumsum(kv * nup, axis=0)
        dr = np.cumsum(kp * nup, axis=0)
        dr += tt * KV
        dr -= np.cumsum((kv * tt) * nup, axis=0)
        r = r + dr
        v = v + KV
        height = alt1 + np.sum(nup * (r - r1), axis=-1)
        up = np.sum(nup * v, axis=-1) + OMEGA_E * (nup[..., 0] * r[..., 1] - nup[..., 1] * r[..., 0])
        eh, eu = held["h"] - height, held["u"] - up
        # the velocity update moves the later nodes too: by Σ_{j<k} eu_j h (Newton on both)
        moved = np.cumsum(eu, axis=0)
        moved -= eu
        moved *= self.h
        held["S"], held["P"] = S + eu, P + eh - moved
        return r, v, max(float(np.abs(eh).max()), float(np.abs(eu).max()) * tau[-1])

    # ------------------------------------------------------------------------------ output
