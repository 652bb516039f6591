"""The error dynamics of strapdown navigation on the rotating WGS-84 Earth
(:class:`EarthErrorModel`; :data:`EARTH`, :data:`EARTH_HOLD`): the flat model's blocks in the
inertial frame the navigation runs in, plus the gravity feedback ``Γ`` from δr into δv, with
its exact first-order term in the transition of a step. The theory:
:mod:`imunav.estimation.error_model`.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.estimation.discretisation``,
``imunav.estimation.nominal``, ``imunav.estimation.error_sources``,
``imunav.estimation.flat_model``.
"""

from __future__ import annotations

import math

import numpy as np

from imunav.core.kernels import FloatArray, skew
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.core.validation import ImunavError
from imunav.estimation.discretisation import (
    StepBlocks,
    blocks_from_full,
    flat_transition,
    process_noise,
)
from imunav.estimation.error_sources import ErrorSource
from imunav.estimation.flat_model import FlatErrorModel
from imunav.estimation.nominal import Trajectory
from imunav.sensors.terms import SensorErrorStates

__all__ = ["EARTH", "EARTH_HOLD", "EarthErrorModel"]


class EarthErrorModel(FlatErrorModel):
    """The error dynamics of strapdown navigation on the rotating WGS-84 Earth, in the inertial
    frame the navigation runs in (see the module's docstring): the flat model's blocks with
    ``C = C_ib`` and ``f = f_i``, plus the gravity feedback ``Γ`` from δr into δv.

    The transition of a step is the flat frame's closed form plus the exact first-order term in
    Γ, ``∫ e^{F(h−s)} G e^{Fs} ds`` — on the navigation block and on the sensor states'
    columns, in closed form with ``A³ = 0`` and the φ-functions of the decay rates: Γh² ≈ 3e-10
    at 100 Hz, so what is left (Γ² h⁴) is ~1e-19 of a step; :meth:`discretise_generic` (Van
    Loan, the whole matrix) is its independent check.

    Parameters
    ----------
    vertical : {"free", "hold"}
        The vertical channel free, or held at the true height and vertical velocity (a perfect
        height aid: see :meth:`hold_projection`).

    Raises
    ------
    ImunavError
        For another ``vertical``.
    """

    name = "wgs84"
    #: Γ couples δr back into δv: the navigation transition is not unipotent, so the
    #: propagation goes step by step (:func:`~imunav.estimation.propagation.step_blocks`).
    unipotent = False

    def __init__(self, vertical: str = "free"):
        if vertical not in ("free", "hold"):
            raise ImunavError(f"vertical must be 'free' or 'hold', got {vertical!r}",
                              argument="vertical")
        #: ``"free"``, or ``"hold"``: the vertical channel held at the true height and vertical
        #: velocity (a perfect height aid): after every step the error state is projected by
        #: ``T = H⁻¹ Z H`` (``Z`` zeroes δv_D and δp_D in local NED), as the navigation's
        #: per-step kicks of :mod:`imunav.strapdown.rotating` do to first order.
        self.vertical = vertical

    def nav_matrix(self, traj: Trajectory) -> FloatArray:
        """The navigation block ``A`` (N, 9, 9): the flat frame's, plus Γ from δr into δv.

        Parameters
        ----------
        traj : Trajectory
            On the Earth (``traj.gradient`` set).

        Returns
        -------
        ndarray, shape (N, 9, 9)
        """
        A = super().nav_matrix(traj)
        A[:, DV, DP] = traj.gradient
        return A

    def transition(self, traj: Trajectory, B: FloatArray, D: FloatArray, h: float
                   ) -> FloatArray:
        """The transition ``Φ`` over a step ``h``: the flat closed form plus the term in Γ.

        Parameters
        ----------
        traj : Trajectory
        B : ndarray, shape (N, 9, k)
        D : ndarray, shape (k,)
        h : float

        Returns
        -------
        ndarray, shape (N, 9 + k, 9 + k)
        """
        F = skew(traj.f_n)
        Phi = flat_transition(F, B, D, h)
        return _with_gravity(Phi, F, traj.gradient, B, D, h)

    def discretise(self, traj: Trajectory, source: ErrorSource, h: float | None = None
                   ) -> tuple[FloatArray, FloatArray]:
        """The discrete system of one (sub-)step of ``source`` along ``traj``.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource
        h : float, optional
            The step (s); default one sub-step, ``traj.h / source.sub``.

        Returns
        -------
        Phi, Qd : ndarray, shape (N, 9 + k, 9 + k)
        """
        h = traj.h / source.sub if h is None else h
        F = skew(traj.f_n)
        k = source.size
        B = self.sensor_input(traj, source.states) if k else np.zeros((traj.steps, NAV, 0))
        D = source.states.D
        Gm = traj.gradient

        def phi(s):
            return _with_gravity(flat_transition(F, B, D, s), F, Gm, B, D, s)

        Phi, Qd = phi(h), process_noise(phi, source.noise_psd(), h)
        if self.vertical == "hold":
            T = self.hold_projection(traj, k)
            Phi = T @ Phi
            Qd = T @ Qd @ np.swapaxes(T, 1, 2)
        return Phi, Qd

    def hold_projection(self, traj: Trajectory, k: int = 0) -> FloatArray:
        """``T = H⁻¹ Z H`` at the end of each step (``Z`` zeroes the down velocity and position
        errors in local NED), extended by the identity on ``k`` sensor states.

        Parameters
        ----------
        traj : Trajectory
        k : int
            Sensor states.

        Returns
        -------
        ndarray, shape (N, 9 + k, 9 + k)
        """
        H = traj.output[1:]
        Z = np.ones(NAV)
        Z[[5, 8]] = 0.0
        T = np.eye(NAV + k)[None].repeat(H.shape[0], axis=0)
        T[:, :NAV, :NAV] = np.linalg.solve(H, Z[:, None] * H)
        return T

    def discretise_blocks(self, traj: Trajectory, source: ErrorSource, h: float | None = None
                          ) -> StepBlocks:
        """:meth:`discretise` in its blocks (split by
        :func:`~imunav.estimation.discretisation.blocks_from_full`); a differenced source (the
        last quantisation residual as 3 states drawn afresh) through this model's response
        ``G`` to a constant input over the step, as :meth:`FlatErrorModel.discretise_blocks`.

        Parameters
        ----------
        traj : Trajectory
        source : ErrorSource
        h : float, optional
            The step (s); default one sub-step, ``traj.h / source.sub``.

        Returns
        -------
        StepBlocks
        """
        h = traj.h / source.sub if h is None else h
        if not source.differenced:
            return blocks_from_full(*self.discretise(traj, source, h), NAV)
        white = ErrorSource(SensorErrorStates(source.name, source.states.triad,
                                              white_psd=source.states.white_psd), source.sub)
        nav, Qnn = self.discretise(traj, white, h)
        var = source.states.differenced_white
        B = self.sensor_input(traj, source.states)
        Gh = self.transition(traj, B, np.zeros(3), h)[:, :NAV, NAV:] / h
        if self.vertical == "hold":                  # the residual's response held too
            Gh = self.hold_projection(traj)[:, :NAV, :NAV] @ Gh
        Qnn = Qnn + var * Gh @ np.swapaxes(Gh, 1, 2)
        return StepBlocks(nav, -Gh, np.zeros(3), Qnn, var * Gh, var * np.eye(3))

    def local(self, traj: Trajectory, P: FloatArray, lo: int = 0) -> FloatArray:
        """``H P Hᵀ``: the covariances of the errors in the local NED frame at the true position
        (attitude, NED velocity, NED position in metres) at ``t_lo, …``.

        Parameters
        ----------
        traj : Trajectory
        P : ndarray, shape (M, 9, 9)
            Covariances of the inertial error state.
        lo : int
            Index in ``traj.t`` of the first.

        Returns
        -------
        ndarray, shape (M, 9, 9)
        """
        H = traj.output[lo: lo + P.shape[0]]
        return H @ P @ np.swapaxes(H, 1, 2)


def _with_gravity(Phi: FloatArray, F: FloatArray, Gm: FloatArray, B: FloatArray, D: FloatArray,
                  h: float) -> FloatArray:
    """Add the first-order term in the gravity gradient to a flat transition (in place).

    ``G`` takes δr into δv, so ``∫₀ʰ e^{A(h−u)} G X(u) du`` for the flat transition's columns
    ``X(u)`` keeps X's δr rows, fed into δv (weight 1) and δr (weight h − u). On the navigation
    block X's δr rows are ``[F u²/2, u I, I]``; on the sensor columns ``B_v φ₁(u) + F B_φ φ₂(u)``,
    whose integrals are φ₂, φ₃ (into δv) and φ₃, φ₄ (into δr).
    """
    GF = Gm @ F
    Phi[:, DV, PHI] += GF * (h**3 / 6)
    Phi[:, DV, DV] += Gm * (h * h / 2)
    Phi[:, DV, DP] += Gm * h
    Phi[:, DP, PHI] += GF * (h**4 / 24)
    Phi[:, DP, DV] += Gm * (h**3 / 6)
    Phi[:, DP, DP] += Gm * (h * h / 2)
    if D.size:
        p2, p3, p4 = _phi_234(D, h)
        Bphi, Bv = B[:, PHI], B[:, DV]
        GBv, GFB = Gm @ Bv, GF @ Bphi
        Phi[:, DV, NAV:] += GBv * p2 + GFB * p3
        Phi[:, DP, NAV:] += GBv * p3 + GFB * p4
    return Phi


def _phi_234(d: FloatArray, h: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``φ_i(d) = ∫₀ʰ (h−s)^i/i! e^{d s} ds`` for i = 2, 3, 4 (as
    :func:`~imunav.estimation.discretisation.phi_functions`: the series below |d h| = 0.5)."""
    x = d * h
    small = np.abs(x) < 0.5
    xs = np.where(small, 1.0, x)
    out = []
    for i in (2, 3, 4):
        ser = sum(x**k / math.factorial(k + i + 1) for k in range(18))
        tail = np.expm1(xs) - sum(xs**k / math.factorial(k) for k in range(1, i + 1))
        out.append(np.where(small, h ** (i + 1) * ser, h ** (i + 1) * tail / xs ** (i + 1)))
    return out[0], out[1], out[2]


#: The error models of the rotating WGS-84 Earth: the vertical channel free, or held.
EARTH = EarthErrorModel()
EARTH_HOLD = EarthErrorModel("hold")

