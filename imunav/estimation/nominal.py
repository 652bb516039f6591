"""The nominal trajectory: the motion at the midpoints of the output steps, the points the
navigation error model (:mod:`imunav.estimation.error_model`) is linearised at — the true motion
in a covariance analysis, the estimate in a filter — sampled whole (:class:`Trajectory`) or a
piece at a time (:class:`LazyTrajectory`); and, on the rotating Earth, the exact map of the
inertial error state onto the errors in local NED (:func:`local_error_map`).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from imunav.core.constants import G0
from imunav.core.kernels import FloatArray, quat_to_dcm, skew
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.core.validation import check_gravity, check_positive
from imunav.earth import (
    OMEGA_E,
    curvature_matrix,
    dcm_ecef_to_inertial,
    dcm_ned_to_ecef,
    gravitation_gradient,
)
from imunav.motion.base import BaseMotion
from imunav.sensors.simulate import interval_count

__all__ = ["LazyTrajectory", "Trajectory", "local_error_map"]


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
