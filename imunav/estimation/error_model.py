"""The navigation error model: the error state, its continuous dynamics along a trajectory, and
how each sensor error term enters it.

Error state (flat, non-rotating NED, as the navigation), indices :data:`PHI`, :data:`DV`,
:data:`DP`, then the states of the sensor error terms::

    φ   attitude error, C_est = (I − [φ×]) C_nb        φ̇  = −C_nb δω
    δv  velocity error                                δv̇ = [f_n×] φ + C_nb δf
    δp  position error                                δṗ = δv

with ``f_n = a_n − g_n`` the specific force in the navigation frame and ``δω``, ``δf`` the gyro
and accelerometer errors. A sensor error term (:mod:`imunav.sensors.terms`) linearises itself
as ``k`` states ``x`` with ``ẋ = diag(D) x + w`` entering its triad as ``δu = M(t) x``, plus white
noise; here that becomes an :class:`ErrorSource`: the system

    d/dt [e; x] = [[A(t), B(t)], [0, diag(D)]] [e; x] + G(t) w,      B = [−C M; 0; 0] (gyro)
                                                                       or [0; C M; 0] (accel)

The frame enters only through the navigation block ``A(t)`` (:meth:`FlatErrorModel.nav_matrix`),
the exact discretisation of a step (:meth:`FlatErrorModel.discretise`) and the map of the error
state onto the errors a user reads (:meth:`FlatErrorModel.local`: the identity here).

**On the rotating Earth** (:class:`EarthErrorModel`, ``Trajectory.of`` an
:class:`~imunav.motion.geodetic.EarthMotion`) the error state is that of the navigation's own
frame, the inertial frame ``i`` that coincides with ECEF at ``t = 0``
(:mod:`imunav.strapdown.rotating`): φ, δv, δr in ``i``, ``Ĉ_ib = (I − [φ×]) C_ib``, and

    φ̇ = −C_ib δω,    δv̇ = [f_i×] φ + Γ δr + C_ib δf,    δṙ = δv,

with ``f_i = C_ib f^b`` and ``Γ = ∂G/∂r`` the gradient of the gravitation
(:func:`imunav.earth.gravitation_gradient`: +2g/R vertically, −g/R horizontally — the Schuler
loop and the unstable vertical channel). The Earth rate and the transport rate are not lost:
they are in ``C_ib`` and ``f_i``, which turn with the Earth and the vehicle, and in the exact
map onto the errors in the local NED frame at the true position (:meth:`EarthErrorModel.local`),

    φ_n = C_ni φ + K C_ni δr,   δv_n = C_ni δv − C_ni [Ω×] δr + [v_n×] K C_ni δr,   δp_n = C_ni δr,

``K`` the curvature matrix (:func:`imunav.earth.curvature_matrix`; the frame at the estimated
position is turned by ``K δp``) and Ω the Earth rate — so the local-level error equations of
the textbooks (Earth-rate coupling, the Coriolis terms, the Foucault turn of the Schuler
oscillation) follow from these (``tests/test_estimation_earth.py`` checks them against the
closed forms and Monte Carlo of the full nonlinear chain). An aided filter on the Earth uses the
same state: a measurement of ECEF position, say, has ``H = C_ei [0, 0, I]``.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.estimation.discretisation``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from imunav.core.constants import G0
from imunav.core.kernels import FloatArray, quat_to_dcm, skew
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.core.validation import ImunavError, check_gravity, check_positive
from imunav.earth import (
    OMEGA_E,
    curvature_matrix,
    dcm_ecef_to_inertial,
    dcm_ned_to_ecef,
    gravitation_gradient,
)
from imunav.estimation.discretisation import (
    GAUSS_LEGENDRE,
    StepBlocks,
    blocks_from_full,
    flat_transition,
    phi_functions,
    process_noise,
    van_loan,
)
from imunav.motion.base import BaseMotion
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import interval_count
from imunav.sensors.terms import TERMS, LinearisationContext, SensorErrorStates

__all__ = ["DP", "DV", "EARTH", "EARTH_HOLD", "NAV", "PHI", "EarthErrorModel", "ErrorSource",
           "FlatErrorModel", "LazyTrajectory", "Trajectory", "error_model", "linearise",
           "local_error_map"]

#: The navigation error states (written once in :mod:`imunav.core.layout`): attitude error φ
#: (rad), velocity error δv (m/s), position error δp (m), each 3 components in the navigation
#: frame; ``NAV`` = 9 of them.

#: The rows of the navigation error a triad's error drives: the gyro φ, the accelerometer δv.
TRIAD_ROWS = {"gyro": PHI, "accel": DV}

#: Largest step (in correlation times) of a decaying sensor state: longer output steps are cut
#: into this many sub-steps, so the midpoint linearisation of fast Gauss–Markov states holds.
MAX_DECAY_STEP = 0.5


@dataclass
class Trajectory:
    """The motion at the midpoints of the output steps: the points the error model is
    linearised at (the true motion in a covariance analysis; the estimate in a filter).

    Attributes
    ----------
    h : float
        Output step (s).
    t : ndarray, shape (N + 1,)
        Output times ``t_0 … t_N``.
    C : ndarray, shape (N, 3, 3)
        ``C_nb`` at the step midpoints.
    f_n : ndarray, shape (N, 3)
        ``a_n − g_n`` (m/s²) at the midpoints.
    omega : ndarray, shape (N, 3)
        ``ω_b`` (rad/s) at the midpoints.
    f_b : ndarray, shape (N, 3)
        ``f_b`` (m/s²) at the midpoints.
    max_rate, max_force : float
        Largest ``|ω_b|`` and ``|f_b|`` over the midpoints (range warnings).
    frame : {"flat", "wgs84"}
        On the Earth ``C`` is ``C_ib`` and ``f_n`` is ``f_i = C_ib f^b`` (the inertial frame
        of :mod:`imunav.strapdown.rotating`), ``omega`` is ``ω_ib^b``, and:
    gradient : ndarray, shape (N, 3, 3), optional
        ``Γ = ∂G/∂r`` at the midpoints (Earth only).
    output : ndarray, shape (N + 1, 9, 9), optional
        At ``t_0 … t_N``, the map ``H`` of the inertial error state onto the errors in the local
        NED frame at the true position (Earth only; :meth:`EarthErrorModel.local`).
    """

    h: float
    t: FloatArray
    C: FloatArray
    f_n: FloatArray
    omega: FloatArray
    f_b: FloatArray
    max_rate: float = 0.0
    max_force: float = 0.0
    frame: str = "flat"
    gradient: FloatArray | None = None
    output: FloatArray | None = None
    #: What an error model computes once per trajectory and step length (its transitions),
    #: shared by the sources propagated along it: one dictionary per model name.
    cache: dict = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def of(cls, motion: BaseMotion, rate: float, duration: float, g: float = G0) -> Trajectory:
        """Sample ``motion`` at the midpoints of ``round(duration × rate)`` steps.

        Parameters
        ----------
        motion : BaseMotion
        rate : float
            Output rate (Hz), > 0.
        duration : float
            Seconds (> 0).
        g : float
            Gravity magnitude (m/s²).

        Returns
        -------
        Trajectory

        Raises
        ------
        ImunavError
            For a non-positive rate, duration or gravity, or fewer than one step.

        Notes
        -----
        An :class:`~imunav.motion.geodetic.EarthMotion` gives the trajectory on the rotating
        Earth (``g`` is not used): see :class:`EarthErrorModel`.
        """
        n = interval_count(rate, duration)
        h = 1.0 / check_positive(rate, "rate")
        traj = cls.sampled(motion, np.arange(n + 1) * h, h, check_gravity(g))
        traj.max_rate = float(np.linalg.norm(traj.omega, axis=1).max())
        traj.max_force = float(np.linalg.norm(traj.f_b, axis=1).max())
        return traj

    @classmethod
    def sampled(cls, motion: BaseMotion, t: FloatArray, h: float, g: float,
                max_rate: float = 0.0, max_force: float = 0.0) -> Trajectory:
        """The motion at the midpoints of the steps ending at ``t[1:]``.

        Parameters
        ----------
        motion : BaseMotion
        t : ndarray, shape (n + 1,)
            Step ends ``k·h`` (checked by the caller).
        h : float
            The step (s).
        g : float
            Gravity magnitude (m/s²), checked.
        max_rate, max_force : float
            The range peaks to record.

        Returns
        -------
        Trajectory
        """
        tm = t[:-1] + h / 2
        if motion.frame == "wgs84":
            traj = cls._on_earth(motion, h, t, tm)
            traj.max_rate, traj.max_force = max_rate, max_force
            return traj
        q = motion.attitude(tm)
        a = motion.acceleration(tm) - np.array([0.0, 0.0, g])
        w = motion.angular_rate(tm)
        fb = motion.specific_force(tm, g)
        return cls(h, t, quat_to_dcm(q), a, w, fb, max_rate, max_force)

    @classmethod
    def _on_earth(cls, motion, h: float, t: FloatArray, tm: FloatArray) -> Trajectory:
        """The inertial-frame quantities of an EarthMotion at the midpoints ``tm`` and the output
        maps at ``t`` (the inertial frame is ECEF at t = 0)."""
        C = dcm_ecef_to_inertial(tm) @ quat_to_dcm(motion.ecef_attitude(tm))     # C_ib
        w = motion.angular_rate(tm)
        fb = motion.specific_force(tm)
        f_i = np.einsum("nij,nj->ni", C, fb)
        r_i = np.einsum("nij,nj->ni", dcm_ecef_to_inertial(tm), motion.ecef(tm)[0])
        st = motion.states(t)
        H = local_error_map(t, st.position, st.velocity)
        return cls(h, t, C, f_i, w, fb, float(np.linalg.norm(w, axis=1).max()),
                   float(np.linalg.norm(fb, axis=1).max()), "wgs84",
                   gravitation_gradient(r_i), H)

    @property
    def steps(self) -> int:
        """Number of steps N."""
        return int(self.C.shape[0])

    def piece(self, lo: int, hi: int) -> Trajectory:
        """Steps ``lo … hi − 1`` (and their end times ``t_lo … t_hi``) as a trajectory of their
        own: what chunked propagation works on.

        Parameters
        ----------
        lo, hi : int
            The steps, ``0 ≤ lo < hi ≤ N``.

        Returns
        -------
        Trajectory
            Views into this one's arrays; the range peaks are this one's.
        """
        return Trajectory(self.h, self.t[lo:hi + 1], self.C[lo:hi], self.f_n[lo:hi],
                          self.omega[lo:hi], self.f_b[lo:hi], self.max_rate, self.max_force,
                          self.frame, None if self.gradient is None else self.gradient[lo:hi],
                          None if self.output is None else self.output[lo:hi + 1])

    def measured(self, triad: str) -> FloatArray:
        """What ``triad`` measures over the steps.

        Parameters
        ----------
        triad : {"gyro", "accel"}

        Returns
        -------
        ndarray, shape (N, 3)
            ``ω_b`` (gyro) or ``f_b`` (accel).
        """
        return self.omega if triad == "gyro" else self.f_b


class LazyTrajectory:
    """A motion's :class:`Trajectory`, sampled a piece at a time.

    What a covariance analysis of a record of any length walks along: only the range peaks
    (one pass over the midpoints, in pieces) are kept, and :meth:`piece` samples the motion
    when it is asked for, so the memory does not grow with the record. Its pieces are equal,
    to the bit, to the pieces of :meth:`Trajectory.of`.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output rate (Hz), > 0.
    duration : float
        Seconds (> 0).
    g : float
        Gravity magnitude (m/s²).
    chunk : int
        Steps sampled at once for the range peaks.

    Attributes
    ----------
    h : float
        Output step (s).
    steps : int
        Number of steps N.
    frame : {"flat", "wgs84"}
        The motion's frame (its pieces are :meth:`Trajectory.of`'s on the Earth too).
    max_rate, max_force : float
        Largest ``|ω_b|`` and ``|f_b|`` over the midpoints.

    Raises
    ------
    ImunavError
        For a non-positive rate, duration or gravity, or fewer than one step.
    """

    def __init__(self, motion: BaseMotion, rate: float, duration: float, g: float = G0,
                 chunk: int = 1 << 16):
        self.steps = interval_count(rate, duration)
        self.h = 1.0 / check_positive(rate, "rate")
        self.g = check_gravity(g)
        self.motion = motion
        self.frame = motion.frame
        self.max_rate = self.max_force = 0.0
        for lo in range(0, self.steps, chunk):
            tm = (np.arange(lo, min(self.steps, lo + chunk) + 1) * self.h)[:-1] + self.h / 2
            w = np.linalg.norm(motion.angular_rate(tm), axis=1).max()
            f = np.linalg.norm(motion.specific_force(tm, self.g), axis=1).max()
            self.max_rate, self.max_force = max(self.max_rate, float(w)), max(self.max_force,
                                                                              float(f))

    def piece(self, lo: int, hi: int) -> Trajectory:
        """Steps ``lo … hi − 1`` (and their end times ``t_lo … t_hi``), sampled now.

        Parameters
        ----------
        lo, hi : int
            The steps, ``0 ≤ lo < hi ≤ N``.

        Returns
        -------
        Trajectory
            With this trajectory's range peaks.
        """
        return Trajectory.sampled(self.motion, np.arange(lo, hi + 1) * self.h, self.h, self.g,
                                  self.max_rate, self.max_force)


@dataclass
class ErrorSource:
    """One independent sensor error source as a linear system of the navigation errors and
    ``k`` sensor states (its :class:`~imunav.sensors.terms.SensorErrorStates`).

    Attributes
    ----------
    states : SensorErrorStates
    sub : int
        Sub-steps per output step (``h/sub ≤`` :data:`MAX_DECAY_STEP` correlation times).
    """

    states: SensorErrorStates
    sub: int = 1

    @property
    def name(self) -> str:
        """``"gyro.bias"`` etc."""
        return self.states.name

    @property
    def size(self) -> int:
        """Sensor states ``k``."""
        return self.states.size

    @property
    def differenced(self) -> bool:
        """Whether the source is a differenced white error (quantised increments)."""
        return bool(self.states.differenced_white)

    def constant_input(self) -> FloatArray | None:
        """The input matrix ``M`` (3, k) if it does not depend on what the triad measures
        (a bias: the same every step), else None (a scale factor, a misalignment).

        Returns
        -------
        ndarray or None
        """
        u = np.array([[0.3, -1.1, 2.7], [-5.0, 0.7, 0.2]])
        f = np.array([[1.9, 0.4, -9.6], [0.1, -3.3, 4.4]])
        M = self.states.input_matrix(u, f)
        return M[0].copy() if np.array_equal(M[0], M[1]) else None

    @property
    def block_size(self) -> int:
        """States the propagation carries besides the navigation errors: ``size``, or 3 (the
        last quantisation residual) for a differenced source."""
        return 3 if self.differenced else self.size

    def initial_covariance(self) -> FloatArray:
        """``P₀`` of ``[e, x]``: the navigation errors 0, the sensor states ``states.P0``.

        Returns
        -------
        ndarray, shape (9 + k, 9 + k)
            ``k`` = :attr:`block_size`.
        """
        k = self.block_size
        P0 = np.zeros((NAV + k, NAV + k))
        if not self.differenced:
            P0[NAV:, NAV:] = self.states.P0
        return P0

    def noise_psd(self) -> FloatArray:
        """Diagonal PSD ``Qc`` of the white inputs.

        The triad's white noise on its navigation rows (isotropic, so ``C Q Cᵀ = Q``), then the
        driving noise of the sensor states.

        Returns
        -------
        ndarray, shape (9 + k,)
        """
        q = np.zeros(NAV)
        q[TRIAD_ROWS[self.states.triad]] = self.states.white_psd
        return np.concatenate([q, self.states.Qs])


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


#: The error model of the flat, non-rotating frame (the only frame so far).
#: The error model of the flat, non-rotating frame.
FLAT = FlatErrorModel()


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


def local_error_map(t: FloatArray, lla: FloatArray, v_n: FloatArray, t0: float = 0.0
                    ) -> FloatArray:
    """The exact first-order map of the inertial error state onto the errors in the local NED
    frame at a position: ``[φ_n, δv_n, δp_n] = M [φ, δv, δr]`` with (``C_ni`` the local frame
    against the inertial one, which is ECEF at ``t0``; ``K`` the curvature matrix, Ω the Earth
    rate)

        φ_n = C_ni φ + K C_ni δr,   δv_n = C_ni δv − C_ni [Ω×] δr + [v_n×] K C_ni δr,
        δp_n = C_ni δr.

    Parameters
    ----------
    t : ndarray, shape (...)
        Times (s).
    lla : ndarray, shape (..., 3)
        ``[lat, lon, h]`` (rad, rad, m) there.
    v_n : ndarray, shape (..., 3)
        NED velocity relative to the Earth (m/s).
    t0 : float
        When the inertial frame coincides with ECEF (s).

    Returns
    -------
    ndarray, shape (..., 9, 9)
    """
    t = np.asarray(t, dtype=float)
    lat, lon, alt = lla[..., 0], lla[..., 1], lla[..., 2]
    C_in = dcm_ecef_to_inertial(t, t0) @ dcm_ned_to_ecef(lat, lon)
    C_ni = np.swapaxes(C_in, -1, -2)
    K = curvature_matrix(lat, alt) @ C_ni
    M = np.zeros(np.shape(lat) + (NAV, NAV))
    M[..., PHI, PHI] = C_ni
    M[..., PHI, DP] = K
    M[..., DV, DV] = C_ni
    M[..., DV, DP] = -C_ni @ skew(np.array([0.0, 0.0, OMEGA_E])) + skew(v_n) @ K
    M[..., DP, DP] = C_ni
    return M


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


def error_model(traj: Trajectory, vertical: str = "free") -> FlatErrorModel:
    """The error model of ``traj``'s frame: :data:`FLAT`, :data:`EARTH` or :data:`EARTH_HOLD`.

    Parameters
    ----------
    traj : Trajectory
    vertical : {"free", "hold"}
        On the Earth: the vertical channel free or held (a perfect height aid).

    Returns
    -------
    FlatErrorModel

    Raises
    ------
    ImunavError
        For ``vertical="hold"`` in the flat frame, or another value.
    """
    if vertical not in ("free", "hold"):
        raise ImunavError(f"vertical must be 'free' or 'hold', got {vertical!r}",
                          argument="vertical")
    if traj.frame != "wgs84":
        if vertical == "hold":
            raise ImunavError("vertical='hold' applies to the WGS-84 Earth only",
                              argument="vertical")
        return FLAT
    return EARTH_HOLD if vertical == "hold" else EARTH


def linearise(model: ImuModel, traj: Trajectory, output: str = "increments", decimate: int = 1
              ) -> tuple[list[ErrorSource], list[str]]:
    """Every registered sensor error term of ``model`` as error sources along ``traj``.

    Parameters
    ----------
    model : ImuModel
    traj : Trajectory
    output : {"increments", "rates"}
        The signal kind (quantisation and aliasing differ).
    decimate : int
        Internal samples per output sample (``model.decimation(rate)``).

    Returns
    -------
    sources : list of ErrorSource
        Gyro terms, then accelerometer terms; within a triad the white inputs (sources without
        states of their own: white noise, quantisation) first, then the sources with states,
        each group in registry order.
    warnings : list of str
        From the terms without a linear model (the motion exceeding a range).

    Raises
    ------
    NotImplementedError
        If a present term has a realisation but no linearisation.
    """
    sources, warnings = [], []
    for triad in ("gyro", "accel"):
        m = getattr(model, triad)
        peak = traj.max_rate if triad == "gyro" else traj.max_force
        ctx = LinearisationContext(triad, traj.h, output, decimate, peak, warnings)
        own = []
        for term in TERMS.values():
            if triad not in term.triads:
                continue
            for states in term.linearise(m, ctx):
                rate = np.max(np.abs(states.D), initial=0.0)
                sub = max(1, int(np.ceil(rate * traj.h / MAX_DECAY_STEP)))
                own.append(ErrorSource(states, sub))
        sources += sorted(own, key=lambda s: s.size > 0)          # stable: white inputs first
    return sources, warnings
