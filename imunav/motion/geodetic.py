"""A motion on the rotating WGS-84 Earth: any motion read in the local NED tangent frame at an
origin fixed to the Earth.

:class:`EarthMotion` wraps a :class:`~imunav.motion.base.BaseMotion` (analytic laws, poses,
waypoints) whose position, velocity, acceleration and attitude are given in the NED frame
``n₀`` of a fixed origin ``(L₀, λ₀, h₀)``. Its ECEF position is then an exact function of time,

    r_e(t) = r_e(origin) + C_en₀ p(t),   ṙ_e = C_en₀ v(t),   r̈_e = C_en₀ a(t),

and so is everything an ideal IMU measures (Groves 2nd ed. eqs. 5.x, in ECEF):

    ω_ib^b = ω_n₀b^b + C_bn₀ ω_ie^n₀                     (the body rate plus the Earth rate)
    f^b    = C_be (r̈_e + 2 Ω × ṙ_e − g_e(r_e))            (Ω = [0, 0, ω_ie], g_e normal gravity)

with ``g_e`` the normal gravity of :mod:`imunav.earth` at the current position — the same
model the navigation uses. The truth is given as latitude, longitude, height, the velocity
relative to the Earth in the local NED frame at the current position and ``q_nb`` relative to
that frame (:meth:`EarthMotion.states`, ``frame="wgs84"``).

An ``EarthMotion`` is a ``BaseMotion``: :func:`~imunav.sensors.simulate.simulate_imu` and its
chunked forms simulate it unchanged (rates in closed form, exact increments by the same
quadrature), and the gravity argument of the flat frame is ignored (gravity comes from the
model).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion.base``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.kernels import FloatArray, cross, quat_conj, quat_mul, quat_rotate
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array
from imunav.earth import (
    check_origin,
    dcm_ned_to_ecef,
    earth_rate_ned,
    ecef_to_geodetic,
    geodetic_to_ecef,
    gravity_ecef,
    quat_ned_to_ecef,
)
from imunav.motion.base import BaseMotion, times

__all__ = ["EarthMotion"]


class EarthMotion(BaseMotion):
    """``motion``, given in the local NED frame at ``origin``, on the rotating WGS-84 Earth.

    Parameters
    ----------
    motion : BaseMotion
        A motion in the NED tangent frame at the origin (metres north, east, down from it;
        attitude relative to that frame).
    origin : tuple of float
        ``(lat, lon, h)``: latitude and longitude (rad) and height above the ellipsoid (m)
        of the frame's origin, fixed to the Earth.

    Attributes
    ----------
    local : BaseMotion
        The wrapped motion.
    origin : tuple of float
    frame : str
        ``"wgs84"``.

    Raises
    ------
    ImunavError
        If ``motion`` is not a motion in a flat local frame or ``origin`` is not a geodetic
        point (latitude within ±90°, finite values).

    Notes
    -----
    :meth:`position` returns geodetic coordinates ``[lat, lon, h]`` (rad, rad, m),
    :meth:`velocity` the NED velocity relative to the Earth at the current position,
    :meth:`attitude` ``q_nb`` relative to the local NED frame there, :meth:`angular_rate` the
    inertial rate ``ω_ib^b`` and :meth:`specific_force` ``f^b`` — what an ideal IMU measures.

    Examples
    --------
    >>> from imunav import Motion
    >>> m = EarthMotion(Motion(duration=60.0), (np.radians(55.0), np.radians(37.0), 150.0))
    >>> f = m.specific_force([0.0])[0]
    >>> round(float(-f[2]), 6)                  # at rest, level: the normal gravity
    9.814608
    """

    frame = "wgs84"

    def __init__(self, motion: BaseMotion, origin: tuple[float, float, float]):
        if not isinstance(motion, BaseMotion):
            raise ImunavError(f"motion must be a BaseMotion, got {type(motion).__name__}",
                              argument="motion")
        if isinstance(motion, EarthMotion):
            raise ImunavError("motion is already on the Earth (an EarthMotion)", argument="motion")
        try:
            lat, lon, h = origin
        except (TypeError, ValueError):
            raise ImunavError(f"origin must be (lat, lon, h), got {origin!r}",
                              argument="origin") from None
        self.origin = check_origin(lat, lon, h, "origin")
        self.local = motion
        self.duration = motion.duration
        self.name = motion.name
        self.bounded = motion.bounded
        self.breakpoints = motion.breakpoints
        self.time_offset = motion.time_offset
        lat0, lon0, h0 = self.origin
        self._r0 = geodetic_to_ecef(lat0, lon0, h0)
        self._C0 = dcm_ned_to_ecef(lat0, lon0)                 # C_en₀
        self._q0 = quat_ned_to_ecef(lat0, lon0)                # q_en₀
        self._w0 = earth_rate_ned(lat0)                         # ω_ie in n₀

    def ecef(self, t: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """ECEF position, velocity and acceleration relative to the Earth at times ``t``.

        Parameters
        ----------
        t : array_like

        Returns
        -------
        r_e, v_e, a_e : ndarray, shape t.shape + (3,)
            ``r_e(origin) + C_en₀ p``, ``C_en₀ v``, ``C_en₀ a`` (m, m/s, m/s²).
        """
        t = times(t)
        C = self._C0
        return (self._r0 + self.local.position(t) @ C.T, self.local.velocity(t) @ C.T,
                self.local.acceleration(t) @ C.T)

    def ecef_attitude(self, t: npt.ArrayLike) -> FloatArray:
        """``q_eb = q_en₀ ⊗ q_n₀b``: the body attitude relative to ECEF.

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (4,)
        """
        return quat_mul(np.broadcast_to(self._q0, np.shape(times(t)) + (4,)),
                        self.local.attitude(t))

    def geodetic(self, t: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Latitude, longitude (rad) and height (m) at times ``t``.

        Parameters
        ----------
        t : array_like

        Returns
        -------
        lat, lon, h : ndarray, shape t.shape
        """
        return ecef_to_geodetic(self._r0 + self.local.position(times(t)) @ self._C0.T)

    def position(self, t: npt.ArrayLike) -> FloatArray:
        """``[lat, lon, h]`` (rad, rad, m).

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (3,)
        """
        return np.stack(self.geodetic(t), axis=-1)

    def _q_n_n0(self, lat: FloatArray, lon: FloatArray) -> FloatArray:
        """``q_n n₀ = q_ne ⊗ q_en₀``: the origin's NED frame in the local one."""
        return quat_mul(quat_conj(quat_ned_to_ecef(lat, lon)), self._q0)

    def velocity(self, t: npt.ArrayLike) -> FloatArray:
        """Velocity relative to the Earth (m/s) in the local NED frame at the current position.

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (3,)
        """
        t = times(t)
        lat, lon, _ = self.geodetic(t)
        return quat_rotate(self._q_n_n0(lat, lon), self.local.velocity(t))

    def acceleration(self, t: npt.ArrayLike) -> FloatArray:
        """Acceleration relative to the Earth, ``r̈_e``, in the origin's NED frame (m/s²): the
        wrapped motion's own (the local frames turn as the body moves over the Earth; the
        navigation equations take ``f^b`` and ``ω_ib^b`` instead).

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (3,)
        """
        return self.local.acceleration(t)

    def attitude(self, t: npt.ArrayLike) -> FloatArray:
        """``q_nb`` relative to the local NED frame at the current position.

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (4,)
        """
        t = times(t)
        lat, lon, _ = self.geodetic(t)
        return quat_mul(self._q_n_n0(lat, lon), self.local.attitude(t))

    def angular_rate(self, t: npt.ArrayLike) -> FloatArray:
        """``ω_ib^b`` (rad/s): the body rate relative to the Earth plus the Earth rate.

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        ndarray, shape t.shape + (3,)
        """
        t = times(t)
        return self.local.angular_rate(t) + quat_rotate(quat_conj(self.local.attitude(t)),
                                                        self._w0)

    def specific_force(self, t: npt.ArrayLike, g: float | None = None) -> FloatArray:
        """``f^b = C_be (r̈_e + 2 Ω × ṙ_e − g_e(r_e))`` (m/s²), with the normal gravity of
        :mod:`imunav.earth`.

        Parameters
        ----------
        t : array_like
            Times (s).
        g : float, optional
            The flat frame's gravity: not used (gravity comes from the model).

        Returns
        -------
        ndarray, shape t.shape + (3,)
        """
        t = times(t)
        p, v, a = self.local.position(t), self.local.velocity(t), self.local.acceleration(t)
        C = self._C0
        g_n0 = gravity_ecef(self._r0 + p @ C.T) @ C               # g_e in n₀ coordinates
        f_n0 = a + 2.0 * cross(np.broadcast_to(self._w0, v.shape), v) - g_n0
        return quat_rotate(quat_conj(self.local.attitude(t)), f_n0)

    def states(self, t: npt.ArrayLike) -> States:
        """The truth at times ``t``: ``[lat, lon, h]``, NED velocity and ``q_nb`` relative to the
        local NED frame.

        Parameters
        ----------
        t : array_like, shape (N,)
            Times (s).

        Returns
        -------
        States
            With ``frame="wgs84"``.
        """
        t = as_float_array(t, "t", ndim=1)
        lat, lon, h = self.geodetic(t)
        q_nn0 = self._q_n_n0(lat, lon)
        return States(t, np.stack([lat, lon, h], axis=-1),
                      quat_rotate(q_nn0, self.local.velocity(t)),
                      quat_mul(q_nn0, self.local.attitude(t)), frame="wgs84")

    def __repr__(self) -> str:
        lat, lon, h = self.origin
        return (f"EarthMotion({self.local!r}, origin=({np.degrees(lat):.9g}°, "
                f"{np.degrees(lon):.9g}°, {h:g} m))")
