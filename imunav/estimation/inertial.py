"""The aided filter's navigation side on the rotating Earth: the inertial state the feedback
corrects, and what a measurement sees of it.

On ``earth="wgs84"`` the navigation runs in the inertial frame ``i`` that coincides with ECEF at
the record's start (:mod:`imunav.strapdown.rotating`), and so does the error state
(:class:`~imunav.estimation.error_model.EarthErrorModel`: φ, δv, δr in ``i``). A reading is
predicted by the measurement models in the local NED frame at the estimated position — its
origin on the ellipsoid below the estimate, so a height is ``−p_z`` and a GNSS fix its NED
offset from there (:meth:`~imunav.sensors.aids.Measurement.localise`), the body rate relative to
the Earth — and its Jacobian with respect to the local errors is carried onto the inertial ones
by the exact first-order map of :func:`~imunav.estimation.error_model.local_error_map`
(``H = H_local M``). Every method takes one run or ``R`` runs (a leading run axis).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.kernels import FloatArray, quat_conj, quat_exp, quat_mul, quat_rotate, quat_to_dcm
from imunav.core.layout import DP, DV, PHI
from imunav.earth import (
    OMEGA_E,
    dcm_ecef_to_inertial,
    earth_rate_ned,
    ecef_to_geodetic,
    geodetic_to_ecef,
    gravitation_gradient,
    quat_ecef_to_inertial,
    quat_ned_to_ecef,
    radii,
)
from imunav.estimation.error_model import local_error_map
from imunav.sensors.aids import NavPoint
from imunav.strapdown.rotating import EarthIntegrator

__all__ = ["EarthSide", "inject_local"]


class EarthSide:
    """The inertial navigation state of one run or ``R`` runs on the rotating Earth.

    Parameters
    ----------
    h : float
        IMU interval (s).
    t0 : float
        Start (s): the inertial frame is ECEF then.
    q0, v0, p0 : ndarray, shapes ([R,] 4), ([R,] 3), ([R,] 3)
        ``q_nb``, NED velocity relative to the Earth, ``[lat, lon, h]`` (rad, rad, m).
    """

    def __init__(self, h: float, t0: float, q0, v0, p0):
        self.t0 = float(t0)
        self.integ = EarthIntegrator(h, t0, q0, v0, p0)

    def advance(self, algo, gw, aw, h, first, count):
        """The body-frame algorithm (g = 0, from zero velocity and position) and the Earth
        integrator over ``count`` intervals.

        Returns
        -------
        qI, vT : ndarray
            The inertial attitudes and thrust velocities (the linearisation).
        local : tuple or None
            The local states at the new nodes; None if the navigation turned non-finite.
        """
        zero = np.zeros(self.integ.r.shape)
        qI, vT, pT = algo.func(gw, aw, h, self.integ.q_ib, zero, zero, 0.0, first, count)
        if not (np.isfinite(qI[-1]).all() and np.isfinite(vT[-1]).all()
                and np.isfinite(pT[-1]).all()):
            return qI, vT, None
        return qI, vT, self.integ.advance(qI, vT, pT)

    def local(self, t, q_ib, v_i, r_i):
        """Inertial states → ``q_nb``, NED velocity relative to the Earth, ``[lat, lon, h]``.

        Parameters
        ----------
        t : float or ndarray
        q_ib, v_i, r_i : ndarray

        Returns
        -------
        tuple of ndarray
        """
        C_ei = np.swapaxes(dcm_ecef_to_inertial(t, self.t0), -1, -2)
        r_e = np.einsum("...ij,...j->...i", C_ei, r_i)
        lat, lon, alt = ecef_to_geodetic(r_e)
        q_in = quat_mul(quat_ecef_to_inertial(t, self.t0), quat_ned_to_ecef(lat, lon))
        w_r = np.zeros(r_i.shape)                 # Ω × r for Ω = [0, 0, ω_ie] (np.cross's products)
        w_r[..., 0] = -OMEGA_E * r_i[..., 1]
        w_r[..., 1] = OMEGA_E * r_i[..., 0]
        v_rel = v_i - w_r
        v_n = quat_rotate(quat_conj(q_in), v_rel)
        q_nb = quat_mul(quat_conj(q_in), q_ib)
        return q_nb, v_n, np.stack([lat, lon, alt], axis=-1)

    def state(self):
        """The integrator's inertial state at the current node.

        Returns
        -------
        tuple of ndarray
            ``q_ib, v_i, r_i``.
        """
        ig = self.integ
        return ig.q_ib, ig.v, ig.r

    def correct(self, t, e):
        """Feed back the inertial error ``e`` ([R,] 9) at the current node.

        Parameters
        ----------
        t : float
        e : ndarray

        Returns
        -------
        tuple of ndarray
            The corrected local state.
        """
        ig = self.integ
        q = quat_mul(quat_exp(e[..., PHI]), ig.q_ib)
        ig.q_ib = q / np.linalg.norm(q, axis=-1, keepdims=True)
        ig.v = ig.v - e[..., DV]
        dr = e[..., DP]
        # the gravitation history of the integrator's multistep rule, moved with the position
        ig.hist = ig.hist - np.einsum("...ij,...j->...i", gravitation_gradient(ig.r), dr)
        ig.r = ig.r - dr
        return self.local(t, ig.q_ib, ig.v, ig.r)

    def reading(self, t, inertial, x, omega, dt, est, gyro_input):
        """What a measurement model predicts a reading from on the Earth: the state
        ``inertial = (q_ib, v_i, r_i)`` corrected by the navigation error ``x`` ([R,] 9), in
        local NED at the estimate (origin on the ellipsoid below it), the body rate relative to
        the Earth.

        Returns
        -------
        nav : NavPoint
        lla : ndarray, shape ([R,] 3)
            The estimate's ``[lat, lon, h]`` (what :meth:`Measurement.localise` needs).
        M : ndarray, shape ([R,] 9, 9)
            Carries the local Jacobian onto the inertial errors.
        """
        q_i, v_i, r_i = inertial
        qc = quat_mul(quat_exp(x[..., PHI]), q_i)
        q, v, lla = self.local(t, qc / np.linalg.norm(qc, axis=-1, keepdims=True),
                               v_i - x[..., DV], r_i - x[..., DP])
        w_e = np.einsum("...ji,...j->...i", quat_to_dcm(q), earth_rate_ned(lla[..., 0]))
        p = np.zeros(lla.shape)
        p[..., 2] = -lla[..., 2]
        nav = NavPoint(q, v, p, omega - w_e, dt, est, gyro_input)
        return nav, lla, local_error_map(t, lla, v, self.t0)

    def r_inertial(self, t, lla):
        """Inertial positions of ``[lat, lon, h]`` at times ``t``.

        Parameters
        ----------
        t : ndarray
        lla : ndarray, shape (..., 3)

        Returns
        -------
        ndarray, shape (..., 3)
        """
        r_e = geodetic_to_ecef(lla[..., 0], lla[..., 1], lla[..., 2])
        C = dcm_ecef_to_inertial(t, self.t0)
        if np.ndim(t) and C.ndim < r_e.ndim + 1:
            C = C.reshape(C.shape[:1] + (1,) * (r_e.ndim - 2) + C.shape[1:])
        return np.einsum("...ij,...j->...i", C, r_e)


def inject_local(q: FloatArray, v: FloatArray, lla: FloatArray, e: FloatArray
                 ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Local states ``q_nb``, NED velocity, ``[lat, lon, h]`` corrected by the local NED error
    ``e`` (…, 9) (``δp`` in metres).

    Parameters
    ----------
    q, v, lla : ndarray
    e : ndarray, shape (..., 9)

    Returns
    -------
    tuple of ndarray
    """
    q = quat_mul(quat_exp(e[..., PHI]), q)
    rn, re = radii(lla[..., 0])
    dp = e[..., DP]
    out = lla.copy()
    out[..., 0] = lla[..., 0] - dp[..., 0] / (rn + lla[..., 2])
    out[..., 1] = lla[..., 1] - dp[..., 1] / ((re + lla[..., 2]) * np.cos(lla[..., 0]))
    out[..., 2] = lla[..., 2] + dp[..., 2]
    return q / np.linalg.norm(q, axis=-1, keepdims=True), v - e[..., DV], out
