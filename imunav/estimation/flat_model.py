"""The error dynamics of strapdown navigation in the flat, non-rotating NED frame
(:class:`FlatErrorModel`, :data:`FLAT`): the navigation block ``A(t)``, how each error source
enters it, and the exact discretisation of a step in closed form (``A³ = 0``), whole or in the
blocks the propagation and the filters use. The theory: :mod:`imunav.estimation.error_model`.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.estimation.discretisation``,
``imunav.estimation.nominal``, ``imunav.estimation.error_sources``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from imunav.core.kernels import FloatArray, skew
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.estimation.discretisation import (
    GAUSS_LEGENDRE,
    StepBlocks,
    flat_transition,
    phi_functions,
    process_noise,
    van_loan,
)
from imunav.estimation.error_sources import ErrorSource
from imunav.estimation.nominal import Trajectory
from imunav.sensors.terms import SensorErrorStates

__all__ = ["FLAT", "FlatErrorModel"]


class FlatErrorModel:
    """The error dynamics of strapdown navigation in the flat, non-rotating NED frame.

    ``A(t)`` has ``[f_n×]`` from φ into δv and the identity from δv into δp: it is nilpotent
    (``A³ = 0``) over a step where ``f_n`` is held at the midpoint value, which makes the
    discretisation exact in closed form (:func:`~imunav.estimation.discretisation.flat_transition`).
    """

    name = "flat"
    #: The navigation transition of a step is ``I + N`` with ``N`` strictly lower block
    #: triangular in the order φ, δv, δp (``A³ = 0``): what lets the propagation run along the
    #: time axis in closed recursions (:func:`~imunav.estimation.propagation.propagate_chunks`).
    unipotent = True

    def nav_matrix(self, traj: Trajectory) -> FloatArray:
        """The navigation block ``A`` (N, 9, 9) at each step of ``traj``.

        Parameters
        ----------
        traj : Trajectory

        Returns
        -------
        ndarray, shape (N, 9, 9)
        """
        A = np.zeros((traj.steps, NAV, NAV))
        A[:, DV, PHI] = skew(traj.f_n)
        A[:, DP, DV] = np.eye(3)
        return A

    def sensor_input(self, traj: Trajectory, states: SensorErrorStates) -> FloatArray:
        """``B``: how the sensor states drive the navigation errors.

        ``−C M`` into φ (gyro) or ``C M`` into δv (accel), ``M`` the term's input matrix over the steps.

        Parameters
        ----------
        traj : Trajectory
        states : SensorErrorStates

        Returns
        -------
        ndarray, shape (N, 9, k)
        """
        M = states.input_matrix(traj.measured(states.triad), traj.f_b)
        B = np.zeros((M.shape[0], NAV, M.shape[2]))
        CM = traj.C @ M
        if states.triad == "gyro":
            B[:, PHI] = -CM
        else:
            B[:, DV] = CM
        return B

    def noise_input(self, traj: Trajectory) -> FloatArray:
        """``G``: the gyro and accelerometer white noises ``[w_g, w_a]`` into the navigation errors.

        ``−C`` into φ, ``C`` into δv.

        Parameters
        ----------
        traj : Trajectory

        Returns
        -------
        ndarray, shape (N, 9, 6)
        """
        G = np.zeros((traj.steps, NAV, 6))
        G[:, PHI, 0:3] = -traj.C
        G[:, DV, 3:6] = traj.C
        return G

    def dynamics(self, traj: Trajectory, source: ErrorSource) -> tuple[FloatArray, FloatArray]:
        """The continuous system of ``[e, x]`` for ``source`` at each step.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource

        Returns
        -------
        F : ndarray, shape (N, 9 + k, 9 + k)
            ``[[A, B], [0, diag(D)]]``.
        Qc : ndarray, shape (9 + k,)
            Diagonal PSD of the white inputs (:meth:`ErrorSource.noise_psd`).
        """
        k = source.size
        F = np.zeros((traj.steps, NAV + k, NAV + k))
        F[:, :NAV, :NAV] = self.nav_matrix(traj)
        if k:
            F[:, :NAV, NAV:] = self.sensor_input(traj, source.states)
            F[:, NAV:, NAV:] = np.diag(source.states.D)
        return F, source.noise_psd()

    def transition(self, traj: Trajectory, B: FloatArray, D: FloatArray, h: float
                   ) -> FloatArray:
        """The exact transition ``Φ`` over a step ``h`` (closed form: ``A³ = 0``).

        Parameters
        ----------
        traj : Trajectory
        B : ndarray, shape (N, 9, k)
            Sensor-state input of the navigation errors.
        D : ndarray, shape (k,)
            Decay rates of the sensor states.
        h : float
            The step (s).

        Returns
        -------
        ndarray, shape (N, 9 + k, 9 + k)
        """
        return flat_transition(skew(traj.f_n), B, D, h)

    def discretise(self, traj: Trajectory, source: ErrorSource, h: float | None = None
                   ) -> tuple[FloatArray, FloatArray]:
        """The exact discrete system of one (sub-)step of ``source`` along ``traj``.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource
        h : float, optional
            The step (s); default one sub-step, ``traj.h / source.sub``.

        Returns
        -------
        Phi : ndarray, shape (N, 9 + k, 9 + k)
            The transition, exact for the motion held at each step's midpoint.
        Qd : ndarray, shape (N, 9 + k, 9 + k)
            The process noise ``∫₀ʰ Φ(s) Qc Φ(s)ᵀ ds`` (6-node Gauss–Legendre on the exact
            transition: exact for its polynomial part).
        """
        h = traj.h / source.sub if h is None else h
        F = skew(traj.f_n)
        k = source.size
        B = self.sensor_input(traj, source.states) if k else np.zeros((traj.steps, NAV, 0))
        D = source.states.D
        return (flat_transition(F, B, D, h),
                process_noise(lambda s: flat_transition(F, B, D, s), source.noise_psd(), h))

    def discretise_blocks(self, traj: Trajectory, source: ErrorSource, h: float | None = None
                          ) -> StepBlocks:
        """The discrete system of :meth:`discretise` in its blocks, computed block by block.

        The same integrals, arranged for what is sparse here: the sensor states enter through
        ``Γ(s) = Σ_{i≤2} Aⁱ B φ_i(D, s)`` (each ``Aⁱ B`` nonzero in a few rows), so
        ``Γ Q_x Γᵀ`` integrates to ``Σ_ij Aⁱ B diag(W_ij) (Aʲ B)ᵀ`` with the weights
        ``W_ij = Σ_s w_s φ_i(s) φ_j(s) q_x`` of the 6-node Gauss–Legendre rule; the white noise
        on the navigation rows likewise with ``Φ_nav(s) = I + A s + A² s²/2``. A differenced
        source (quantised increments with a carried residual, :attr:`ErrorSource.differenced`)
        carries the last residual ``e`` as 3 states drawn afresh every step: ``δu = (e_k −
        e_{k−1})/h`` enters through the response ``G`` to a constant input over the step,
        ``Γ = −G/h``, ``Q_d = var·[G/h; I][G/h; I]ᵀ``.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource
        h : float, optional
            The step (s); default one sub-step, ``traj.h / source.sub``.

        Returns
        -------
        StepBlocks
            ``k`` = :attr:`ErrorSource.block_size`.
        """
        h = traj.h / source.sub if h is None else h
        T = traj.steps
        cache = traj.cache.setdefault(self.name, {})
        if "F" not in cache:
            cache["F"] = skew(traj.f_n)
        F = cache["F"]
        if ("nav", h) not in cache:
            cache["nav", h] = flat_transition(F, np.zeros((T, NAV, 0)), np.zeros(0), h)
        nav = cache["nav", h]
        Qnn = np.zeros((T, NAV, NAV))
        qn = source.noise_psd()[:NAV]
        cols = np.nonzero(qn)[0]
        if cols.size:                                   # white noise on the navigation rows
            if ("white", cols.tobytes()) not in cache:
                E = np.zeros((T, NAV, cols.size))
                E[:, cols, np.arange(cols.size)] = 1.0
                cache["white", cols.tobytes()] = np.concatenate(_powers(F, E), axis=2)
            Qnn += _sandwich(cache["white", cols.tobytes()],
                             _white_weights(h, qn[cols].tobytes()))
        if source.differenced:
            var = source.states.differenced_white
            B = self.sensor_input(traj, source.states)
            Gh = _powers_input(F, B, phi_functions(np.zeros(3), h)) / h
            Qnn += var * Gh @ np.ascontiguousarray(np.swapaxes(Gh, 1, 2))
            return StepBlocks(nav, -Gh, np.zeros(3), Qnn, var * Gh, var * np.eye(3))
        k = source.size
        if not k:
            return StepBlocks(nav, np.zeros((T, NAV, 0)), np.zeros(0), Qnn,
                              np.zeros((T, NAV, 0)), np.zeros((0, 0)))
        D, qx = source.states.D, source.states.Qs
        phis, W, V, qxx = _state_weights(h, D.tobytes(), qx.tobytes())
        states = source.states
        M0 = source.constant_input()
        if M0 is not None:
            # a constant input M: B = B₀ M, B₀ the triad's rows, so Γ = [B₀, A B₀, A² B₀]·R
            # with R = [M φ₀; M φ₁; M φ₂] constant (one matrix product for all steps)
            if ("triad", states.triad) not in cache:
                B0 = self.noise_input(traj)[:, :, _TRIAD_COLUMNS[states.triad]]
                cache["triad", states.triad] = np.concatenate(_powers(F, B0), axis=2)
            Gs = cache["triad", states.triad]                                 # (T, 9, 9)
            Rg, Rq, Om = _constant_factors(h, D.tobytes(), qx.tobytes(), M0.tobytes(), k)
            flat = Gs.reshape(T * NAV, 9)
            gamma = (flat @ Rg).reshape(T, NAV, k)
            if Om is not None:
                Qnx = (flat @ Rq).reshape(T, NAV, k)
                Qnn += _sandwich(Gs, Om)
            else:
                Qnx = np.zeros((T, NAV, k))
            return StepBlocks(nav, gamma, np.exp(D * h), Qnn, Qnx, np.diag(qxx))
        B = self.sensor_input(traj, source.states)
        powers = _powers(F, B)
        gamma = powers[0] * phis[0] + powers[1] * phis[1] + powers[2] * phis[2]
        if np.any(qx):
            _add_quadratic(Qnn, powers, W)
            Qnx = powers[0] * V[0] + powers[1] * V[1] + powers[2] * V[2]
        else:
            Qnx = np.zeros((T, NAV, k))
        return StepBlocks(nav, gamma, np.exp(D * h), Qnn, Qnx, np.diag(qxx))

    def local(self, traj: Trajectory, P: FloatArray, lo: int = 0) -> FloatArray:
        """The covariances ``P`` of the error state at ``t_lo, t_lo+1, …`` as covariances of the
        errors a user reads (here the same: the flat frame's state is those errors).

        Parameters
        ----------
        traj : Trajectory
        P : ndarray, shape (M, 9, 9)
        lo : int
            Index of the first output time.

        Returns
        -------
        ndarray, shape (M, 9, 9)
        """
        return P

    def discretise_generic(self, traj: Trajectory, source: ErrorSource, h: float
                           ) -> tuple[FloatArray, FloatArray]:
        """The discrete system of :meth:`discretise` by Van Loan's matrix exponential.

        What a model whose ``A`` is not nilpotent (the rotating Earth) uses
        (:func:`~imunav.estimation.discretisation.van_loan`); here the independent check of
        :meth:`discretise`.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource
        h : float
            The step (s).

        Returns
        -------
        Phi, Qd : ndarray, shape (N, 9 + k, 9 + k)
        """
        F, Qc = self.dynamics(traj, source)
        return van_loan(F, Qc, h)


def _powers(F: FloatArray, B: FloatArray) -> list[FloatArray]:
    """``[B, A B, A² B]`` of the flat frame's ``A`` (``[f_n×]`` from φ into δv, I from δv into
    δp) and an input ``B`` (N, 9, k)."""
    AB = np.zeros_like(B)
    AB[:, DV] = F @ B[:, PHI]
    AB[:, DP] = B[:, DV]
    A2B = np.zeros_like(B)
    A2B[:, DP] = AB[:, DV]
    return [B, AB, A2B]


def _powers_input(F: FloatArray, B: FloatArray, phis) -> FloatArray:
    """``Σ_i Aⁱ B φ_i``: the response at a step's end to the sensor states through ``B``."""
    return sum(G * p for G, p in zip(_powers(F, B), phis, strict=True))


#: The columns of :meth:`FlatErrorModel.noise_input` of each triad's white noise.
_TRIAD_COLUMNS = {"gyro": slice(0, 3), "accel": slice(3, 6)}


def _sandwich(G: FloatArray, Om: FloatArray) -> FloatArray:
    """``G Ω Gᵀ`` at every step: ``G`` (N, n, r), ``Ω`` (r, r) constant (one matrix product
    for ``G Ω``)."""
    N, n, r = G.shape
    GO = (G.reshape(N * n, r) @ Om).reshape(N, n, r)
    return GO @ np.ascontiguousarray(np.swapaxes(G, 1, 2))


def _row_blocks(G: FloatArray) -> list[tuple[slice, FloatArray, FloatArray]]:
    """The navigation row blocks (φ, δv, δp) of ``G`` (N, 9, k) that are not all zero, each
    with its transpose (contiguous: numpy's batched matmul is slow on strided views)."""
    return [(r, np.ascontiguousarray(G[:, r]), np.ascontiguousarray(np.swapaxes(G[:, r], 1, 2)))
            for r in (PHI, DV, DP) if np.any(G[:, r])]


def _add_quadratic(Q: FloatArray, powers: list[FloatArray], W) -> None:
    """``Q += Σ_ij Gᵢ diag(W_ij) Gⱼᵀ`` over the nonzero row blocks of ``Gᵢ = powers[i]``
    (``W`` symmetric in i, j: each unordered pair once, its mirror by transposition)."""
    blocks = [_row_blocks(G) for G in powers]
    terms = [(i, ra, X, XT) for i, bl in enumerate(blocks) for ra, X, XT in bl]
    for m, (i, ra, X, _) in enumerate(terms):
        for j, rb, _, YT in terms[m:]:
            if not np.any(W[i][j]):
                continue
            q = (X * W[i][j]) @ YT
            Q[:, ra, rb] += q
            if (j, rb) != (i, ra):
                Q[:, rb, ra] += np.swapaxes(q, 1, 2)


@lru_cache(maxsize=256)
def _white_weights(h: float, q: bytes) -> FloatArray:
    """``Ω = [diag(W_ij)]``, ``W_ij = Σ_s w_s (sⁱ/i!)(sʲ/j!) q``, of white noise ``q`` on
    navigation rows over a step ``h`` (``Φ_nav(s) = Σ_i Aⁱ sⁱ/i!``), 6-node Gauss–Legendre."""
    q = np.frombuffer(q)
    nodes, weights = (GAUSS_LEGENDRE[0] + 1) / 2 * h, GAUSS_LEGENDRE[1] / 2 * h
    a = [nodes ** i / math.factorial(i) for i in range(3)]
    return np.block([[np.diag(float(np.sum(weights * a[i] * a[j])) * q) for j in range(3)]
                     for i in range(3)])


@lru_cache(maxsize=256)
def _constant_factors(h: float, D: bytes, qx: bytes, M: bytes, k: int):
    """For a constant input ``M`` (3, k): ``R_Γ = [M φ₀; M φ₁; M φ₂]`` (Γ = G·R_Γ),
    ``R_Q = [M V₀; M V₁; M V₂]`` (Q_nx = G·R_Q) and ``Ω = [M diag(W_ij) Mᵀ]`` (the states'
    part of Q_nn = G Ω Gᵀ; None without driving noise), ``G = [B₀, A B₀, A² B₀]``."""
    phis, W, V, _ = _state_weights(h, D, qx)
    M0 = np.frombuffer(M).reshape(3, k)
    Rg = np.concatenate([M0 * ph for ph in phis])
    if not np.any(np.frombuffer(qx)):
        return Rg, None, None
    Rq = np.concatenate([M0 * v for v in V])
    return Rg, Rq, np.block([[(M0 * W[i][j]) @ M0.T for j in range(3)] for i in range(3)])


@lru_cache(maxsize=256)
def _state_weights(h: float, D: bytes, qx: bytes):
    """What a step ``h`` of sensor states with decay rates ``D`` and driving PSD ``qx`` needs,
    the same for every step: ``φ_i(D, h)``; ``W_ij = Σ_s w_s φ_i(s) φ_j(s) q_x``;
    ``V_i = Σ_s w_s φ_i(s) q_x e^{D s}`` (the cross block); ``Σ_s w_s q_x e^{2Ds}``."""
    D, qx = np.frombuffer(D), np.frombuffer(qx)
    nodes, weights = (GAUSS_LEGENDRE[0] + 1) / 2 * h, GAUSS_LEGENDRE[1] / 2 * h
    ph = [phi_functions(D, s) for s in nodes]
    decay = [np.exp(D * s) for s in nodes]
    W = [[sum(w * ph[n][i] * ph[n][j] * qx for n, w in enumerate(weights)) for j in range(3)]
         for i in range(3)]
    V = [sum(w * ph[n][i] * qx * decay[n] for n, w in enumerate(weights)) for i in range(3)]
    qxx = sum(w * qx * d * d for w, d in zip(weights, decay, strict=True))
    return phi_functions(D, h), W, V, qxx



#: The error model of the flat, non-rotating frame.
FLAT = FlatErrorModel()
