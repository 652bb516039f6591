"""Exact simulation on the rotating WGS-84 Earth (imunav.motion.geodetic.EarthMotion) against
independent truths: the same motion derived in the inertial frame with SymPy (no Coriolis term,
no ECEF), scipy's quadrature of the rates, closed forms at rest, and pyins' generate_imu side by
side."""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

from imunav import ImunavError, Motion, simulate_imu
from imunav import earth as E
from imunav.core.rotations import quat_conj, quat_rotate, quat_to_euler
from imunav.motion import EarthMotion
from tests.earth.test_earth import tr8350_gravity

DEG = np.pi / 180
ORIGIN = (55 * DEG, 37 * DEG, 150.0)
LAWS = dict(x="3*sin(0.4*t)", y="2*t + 0.1*t**2", z="-0.5*cos(0.6*t)",
            yaw="0.6*sin(0.5*t) + 0.1*t", pitch="0.25*sin(0.8*t)", roll="0.4*sin(1.2*t)")
MOTION = Motion(**LAWS, duration=20.0)


def _inertial_truth(laws, origin):
    """ω_ib^b(t) and the inertial acceleration r̈_i(t), r_i(t), C_ib(t) by SymPy in the inertial
    frame (= ECEF at t = 0): r_i = R_z(ω t)(r₀ + C_en₀ p(t)), q_ib = q_z(ω t) ⊗ q_en₀ ⊗ q_n₀b(t)."""
    t = sp.Symbol("t")                                  # the symbol the laws are parsed with
    w = sp.Float(E.OMEGA_E, 30)
    p = sp.Matrix([sp.sympify(laws[k]) for k in "xyz"])
    r0 = sp.Matrix([sp.Float(float(v), 30) for v in E.geodetic_to_ecef(*origin)])
    C0 = sp.Matrix(E.dcm_ned_to_ecef(origin[0], origin[1]).tolist())
    Rz = sp.Matrix([[sp.cos(w * t), -sp.sin(w * t), 0], [sp.sin(w * t), sp.cos(w * t), 0],
                    [0, 0, 1]])
    r_i = Rz * (r0 + C0 * p)
    Q = sp.algebras.Quaternion
    yaw, pitch, roll = (sp.sympify(laws[k]) for k in ("yaw", "pitch", "roll"))
    q_nb = (Q(sp.cos(yaw / 2), 0, 0, sp.sin(yaw / 2)) * Q(sp.cos(pitch / 2), 0, sp.sin(pitch / 2), 0)
            * Q(sp.cos(roll / 2), sp.sin(roll / 2), 0, 0))
    qe = E.quat_ned_to_ecef(origin[0], origin[1])
    q_ib = Q(sp.cos(w * t / 2), 0, 0, sp.sin(w * t / 2)) * Q(*[sp.Float(float(c), 30) for c in qe]) * q_nb
    dq = Q(*[sp.diff(c, t) for c in (q_ib.a, q_ib.b, q_ib.c, q_ib.d)])
    om = 2 * Q(q_ib.a, -q_ib.b, -q_ib.c, -q_ib.d) * dq
    f = sp.lambdify(t, [sp.Matrix([om.b, om.c, om.d]), sp.diff(r_i, t, 2), r_i,
                        sp.Matrix([q_ib.a, q_ib.b, q_ib.c, q_ib.d])], "mpmath")
    return f


@pytest.fixture(scope="module")
def inertial():
    return _inertial_truth(LAWS, ORIGIN)


def test_rates_against_the_inertial_frame_derivation(inertial):
    m = EarthMotion(MOTION, ORIGIN)
    t = np.array([0.0, 0.7, 3.1, 9.9, 17.3])
    w, f = m.angular_rate(t), m.specific_force(t)
    for i, ti in enumerate(t):
        om, a_i, r_i, q = (np.array(x.tolist(), dtype=float).ravel() for x in inertial(ti))
        G = E.gravitation_ecef(r_i)
        f_ref = quat_rotate(quat_conj(q / np.linalg.norm(q)), a_i - G)
        np.testing.assert_allclose(w[i], om, rtol=0, atol=1e-15)      # measured ≤ 3e-17 rad/s
        np.testing.assert_allclose(f[i], f_ref, rtol=0, atol=2e-12)   # 10 m/s²: 2e-13 relative


def test_exact_increments_against_scipy_quad():
    m = EarthMotion(MOTION, ORIGIN)
    sig = simulate_imu(m, 50.0, 2.0, kind="increments")
    for k in (0, 17, 63, 99):
        a, b = sig.t[k] - sig.dt, sig.t[k]
        for j in range(3):
            ref_w = quad(lambda s, j=j: m.angular_rate(np.array([s]))[0, j], a, b, epsabs=0,
                         epsrel=1e-13)[0]
            ref_f = quad(lambda s, j=j: m.specific_force(np.array([s]))[0, j], a, b, epsabs=0,
                         epsrel=1e-13)[0]
            assert sig.gyro[k, j] == pytest.approx(ref_w, rel=1e-12, abs=1e-12 * np.abs(sig.gyro[k]).max())
            assert sig.accel[k, j] == pytest.approx(ref_f, rel=1e-12, abs=1e-12 * np.abs(sig.accel[k]).max())


def test_at_rest_the_imu_measures_the_earth_rate_and_normal_gravity():
    q_nb = np.array([0.9, 0.1, -0.3, 0.3])
    q_nb /= np.linalg.norm(q_nb)
    yaw, pitch, roll = quat_to_euler(q_nb)
    m = EarthMotion(Motion(yaw=float(yaw), pitch=float(pitch), roll=float(roll), duration=5.0),
                    ORIGIN)
    t = np.linspace(0, 5, 7)
    w_n = E.earth_rate_ned(ORIGIN[0])
    g_n = [0, 0, float(E.normal_gravity(ORIGIN[0], ORIGIN[2]))]
    np.testing.assert_allclose(m.angular_rate(t), np.tile(quat_rotate(quat_conj(q_nb), w_n), (7, 1)),
                               atol=1e-19)
    np.testing.assert_allclose(m.specific_force(t), np.tile(-quat_rotate(quat_conj(q_nb), g_n),
                                                            (7, 1)), atol=2e-15)
    st = m.states(t)
    assert st.frame == "wgs84"
    np.testing.assert_allclose(st.position, np.tile(ORIGIN, (7, 1)), rtol=0, atol=1e-9)
    np.testing.assert_allclose(st.velocity, 0.0, atol=1e-15)
    np.testing.assert_allclose(st.quaternion, np.tile(q_nb, (7, 1)), atol=1e-15)


def test_at_rest_high_up_the_accelerometer_measures_tr8350_normal_gravity():
    """The simulator and the navigator share imunav.earth's gravity, so their round trip cannot
    see it wrong: here the ideal accelerometer at rest is held to an independent copy of
    TR8350.2's second-order expansion (typed in test_earth.py). At 80° and 30 km the expansion
    without its −2f sin²L term is 6.1e-5 of γ (6e-4 m/s²) off."""
    q_nb = np.array([0.9, 0.1, -0.3, 0.3])
    q_nb /= np.linalg.norm(q_nb)
    yaw, pitch, roll = quat_to_euler(q_nb)
    for origin in ((80 * DEG, -20 * DEG, 3e4), (-35 * DEG, 140 * DEG, 1e5), (0.0, 0.0, 8e3)):
        m = EarthMotion(Motion(yaw=float(yaw), pitch=float(pitch), roll=float(roll),
                               duration=5.0), origin)
        f = m.specific_force(np.linspace(0, 5, 4))
        g_n = [0, 0, float(tr8350_gravity(origin[0], origin[2]))]
        # measured 4.5e-11 m/s² (the table's k against imunav's); 4.8e-4 without the −2f sin²L
        np.testing.assert_allclose(f, np.tile(-quat_rotate(quat_conj(q_nb), g_n), (4, 1)),
                                   rtol=0, atol=1e-10)


def test_truth_is_the_local_ned_state_at_the_current_position():
    m = EarthMotion(MOTION, ORIGIN)
    t = np.array([0.0, 5.0, 20.0])
    st = m.states(t)
    r_e, v_e, _ = m.ecef(t)
    np.testing.assert_allclose(E.geodetic_to_ecef(*st.position.T), r_e, atol=1e-8)
    C = E.dcm_ned_to_ecef(st.position[:, 0], st.position[:, 1])
    np.testing.assert_allclose(np.einsum("nij,nj->ni", C, st.velocity), v_e, atol=1e-13)
    # at the origin the local frame is the origin's: the wrapped motion's own state
    np.testing.assert_allclose(st.velocity[0], MOTION.velocity([0.0])[0], atol=1e-15)
    np.testing.assert_allclose(st.quaternion[0], MOTION.attitude([0.0])[0], atol=1e-15)
    # 20 s later the motion is 45 m east: the local frame has turned by 45 m / R about north
    _, re = E.radii(ORIGIN[0])
    tilt = np.degrees(np.arccos(np.clip(C[-1][:, 2] @ C[0][:, 2], -1, 1)))
    assert tilt == pytest.approx(np.degrees(np.hypot(*(E.ecef_to_ned(r_e[-1], ORIGIN)[:2]))
                                            / re), rel=2e-3)


def test_increments_agree_with_pyins_generate_imu():
    """pyins' generate_imu on our truth (latitude, longitude, altitude, NED velocity, roll,
    pitch, heading at 100 Hz): its RotationSpline and Hermite position splines reproduce the exact
    increments away from the spline ends; the accelerometers differ by pyins' gravity model (the
    linear height term, γ₀(1 − 2h/a)), which is removed here in closed form."""
    from pyins import sim

    m = EarthMotion(MOTION, ORIGIN)
    rate = 100.0
    sig = simulate_imu(m, rate, kind="increments")
    t = np.arange(len(sig) + 1) / rate
    st = m.states(t)
    lla = np.column_stack([np.degrees(st.position[:, :2]), st.position[:, 2]])
    ypr = np.degrees(quat_to_euler(st.quaternion))
    _, imu = sim.generate_imu(t, lla, ypr[:, ::-1], st.velocity, sensor_type="increment")
    g = imu[["gyro_x", "gyro_y", "gyro_z"]].values[1:]
    a = imu[["accel_x", "accel_y", "accel_z"]].values[1:]
    inner = (t[1:] > 1.0) & (t[1:] < t[-1] - 1.0)
    assert np.abs(g - sig.gyro)[inner].max() < 1e-9            # measured 3.2e-14 rad
    tm = t[1:] - 0.5 / rate
    sm = m.states(tm)
    lat, h = sm.position[:, 0], sm.position[:, 2]
    # the difference of the two gravity models from the independent TR8350.2 copy (test_earth)
    dgam = tr8350_gravity(lat, h) - tr8350_gravity(lat, 0.0) * (1 - 2 * h / E.A)
    model = -quat_rotate(quat_conj(sm.quaternion), np.column_stack([0 * dgam, 0 * dgam, dgam]))
    raw = np.abs(a - sig.accel)[inner].max()
    corrected = np.abs(sig.accel - a - model / rate)[inner].max()
    # measured 1.13e-8 m/s (3.19e-8 before the −2f sin²L term, which takes 2/3 of f + m at 55°)
    assert 0.8e-8 < raw < 1.5e-8
    assert corrected < 5e-9                                    # measured 2.1e-9 m/s (pyins splines)


def test_bad_motion_or_origin():
    with pytest.raises(ImunavError, match="origin must be"):
        EarthMotion(MOTION, (0.1, 0.2))
    with pytest.raises(ImunavError, match="latitude must be within ±90°"):
        EarthMotion(MOTION, (2.0, 0.0, 0.0))
    with pytest.raises(ImunavError, match="already on the Earth"):
        EarthMotion(EarthMotion(MOTION, ORIGIN), ORIGIN)
