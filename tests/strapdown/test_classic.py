"""Strapdown details pinned by independent truths (issue 19): one step of each classic algorithm
against its formula written out here (with ω_{k−1} ≠ ω_k, so that using the wrong sample shows),
exactness on motions the documented schemes integrate exactly, the closed-form position error of
the increment trapezoid, and navigation that starts at t0 ≠ 0 with g ≠ 9.80665.

Rotations in the expected values come from scipy (``Rotation.from_rotvec``), an independent
implementation; quaternion products from the multiplication-table-tested ``quat_mul``.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from imunav import ImuSignals, Motion, nav_errors, navigate, simulate_imu
from imunav.core.rotations import quat_angle, quat_mul, quat_normalize, quat_rotate

H, G = 0.1, 9.80665
Q0 = quat_normalize([0.9, 0.1, -0.3, 0.2])
W0, W1 = np.array([0.3, -0.2, 0.5]), np.array([1.1, 0.4, -0.7])          # ω_{k−1} ≠ ω_k
F0, F1 = np.array([0.5, -1.0, -9.0]), np.array([1.5, 0.2, -10.5])
V0, P0 = np.array([1.0, -2.0, 0.5]), np.array([10.0, 3.0, -1.0])


def _exp(rotvec):
    """Quaternion of a rotation vector, from scipy (scalar first)."""
    return Rotation.from_rotvec(rotvec).as_quat(scalar_first=True)


def _rates(algorithm):
    sig = ImuSignals([0.0, H], [W0, W1], [F0, F1], "rates", 1 / H)
    return navigate(sig, Q0, V0, P0, algorithm=algorithm)


def _trapezoid(q1):
    a0 = quat_rotate(Q0, F0) + [0, 0, G]
    a1 = quat_rotate(q1, F1) + [0, 0, G]
    return V0 + H / 2 * (a0 + a1), P0 + H * V0 + H * H / 6 * (2 * a0 + a1)


def test_rates_first_order_one_step_uses_the_previous_sample():
    nav = _rates("first_order")
    expect = quat_normalize(Q0 + 0.5 * H * quat_mul(Q0, np.r_[0.0, W0]))     # ω_{k−1}, not ω_k
    assert quat_angle(nav.quaternion[1], expect) < 1e-15
    v1, p1 = _trapezoid(nav.quaternion[1])
    np.testing.assert_allclose(nav.velocity[1], v1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(nav.position[1], p1, rtol=0, atol=1e-14)


def test_rates_exponential_one_step_is_the_mean_rate_exponential():
    nav = _rates("exact_exponential")
    expect = quat_mul(Q0, _exp(H * (W0 + W1) / 2))
    assert quat_angle(nav.quaternion[1], expect) < 1e-15
    v1, p1 = _trapezoid(nav.quaternion[1])
    np.testing.assert_allclose(nav.velocity[1], v1, rtol=0, atol=1e-14)
    np.testing.assert_allclose(nav.position[1], p1, rtol=0, atol=1e-14)


TH = np.array([[0.02, -0.01, 0.03], [0.05, 0.02, -0.01], [-0.01, 0.04, 0.02],
               [0.03, 0.03, 0.03]])
DV = np.array([[0.1, -0.2, -0.98], [0.2, 0.0, -1.0], [0.0, 0.1, -0.95], [0.1, 0.1, -0.9]])


def _increments(algorithm, n=2):
    sig = ImuSignals(H * np.arange(1, n + 1), TH[:n], DV[:n], "increments", 1 / H)
    return navigate(sig, Q0, V0, P0, algorithm=algorithm)


def _inc_velocity(q_prev, body):
    dvn = quat_rotate(q_prev, body) + [0, 0, G * H]
    return dvn


@pytest.mark.parametrize("algorithm, factor", [
    ("first_order", lambda th: quat_normalize(np.r_[1.0, th / 2])),
    ("exact_exponential", _exp),
])
def test_increment_one_step_attitude_and_rotation_compensated_velocity(algorithm, factor):
    nav = _increments(algorithm)
    q1 = quat_mul(Q0, factor(TH[0]))
    assert quat_angle(nav.quaternion[1], q1) < 1e-15
    dvn = _inc_velocity(Q0, DV[0] + 0.5 * np.cross(TH[0], DV[0]))
    np.testing.assert_allclose(nav.velocity[1], V0 + dvn, rtol=0, atol=1e-14)
    np.testing.assert_allclose(nav.position[1], P0 + H * V0 + 0.5 * H * dvn, rtol=0, atol=1e-14)


def test_coning2_first_interval_uses_the_next_pair_and_sculling():
    nav = _increments("coning2", 2)
    c = np.cross(TH[0], TH[1]) / 12          # the first interval borrows (θ0, θ1): no θ_{−1}
    q1 = quat_mul(Q0, _exp(TH[0] + c))
    q2 = quat_mul(q1, _exp(TH[1] + c))
    assert quat_angle(nav.quaternion[1], q1) < 1e-15
    assert quat_angle(nav.quaternion[2], q2) < 1e-15
    scull = (np.cross(TH[0], DV[1]) + np.cross(DV[0], TH[1])) / 12
    dvn0 = _inc_velocity(Q0, DV[0] + 0.5 * np.cross(TH[0], DV[0]) + scull)
    dvn1 = _inc_velocity(nav.quaternion[1], DV[1] + 0.5 * np.cross(TH[1], DV[1]) + scull)
    np.testing.assert_allclose(nav.velocity[2], V0 + dvn0 + dvn1, rtol=0, atol=1e-14)


def test_miller3_is_plaksiy_eq2_per_major_interval():
    nav = _increments("miller3", 3)
    a, b = 33 / 80, 57 / 80
    t1, t2, t3 = TH[:3]
    phi = t1 + t2 + t3 + a * np.cross(t1, t3) + b * np.cross(t2, t3 - t1)     # eq. (2)
    assert quat_angle(nav.quaternion[3], quat_mul(Q0, _exp(phi))) < 1e-15


# --------------------------------------------------------------- exact motions, closed forms

TRANSLATION = dict(x="t**3/6 + 2*t", y="0.5*t**3 - t**2", z="-0.2*t**3", yaw="0.4",
                   pitch="-0.2", roll="0.7")


@pytest.mark.parametrize("kind, algorithm", [("rates", "first_order"),
                                             ("rates", "exact_exponential"),
                                             ("rates", "magnus4"), ("rates", "magnus6"),
                                             ("increments", "poly6_m4"),
                                             ("increments", "poly8_m6")])
def test_acceleration_linear_in_time_is_integrated_exactly(kind, algorithm):
    """At constant attitude with a_n linear in t, the rate trapezoid (velocity) with the
    h²/6·(2a_{k−1} + a_k) position term, and every polynomial-fit algorithm, are exact."""
    m = Motion(**TRANSLATION, duration=10.0)
    sig = simulate_imu(m, 20.0, kind=kind)
    e = nav_errors(navigate(sig, *m.states([sig.t0]).initial(), algorithm=algorithm), m)
    assert e.attitude.max() < 1e-15
    assert e.velocity.max() < 1e-11 and e.position.max() < 1e-10     # |r| ≈ 100 m: rounding


@pytest.mark.parametrize("algorithm", ["first_order", "exact_exponential", "coning2"])
def test_increment_trapezoid_position_error_is_the_closed_form(algorithm):
    """Exact Δv, then p_k = p_{k−1} + h v_{k−1} + ½h Δv_n: for a constant jerk j the trapezoid
    adds h³j/4 per step where the exact double integral adds h³j/6, so after T seconds x is
    ahead by T·h²·j/12 (and exact for constant acceleration)."""
    m = Motion(x="t**3/6", y="0.3*t**2", duration=10.0)          # j = 1 along x, none along y
    h = 0.01
    sig = simulate_imu(m, 1 / h, kind="increments")
    nav = navigate(sig, *m.states([sig.t0]).initial(), algorithm=algorithm)
    err = nav.position[-1] - m.position(nav.t[-1:])[0]
    assert err[0] == pytest.approx(10 * h * h / 12, rel=1e-6)
    assert abs(err[1]) < 1e-11 and abs(err[2]) < 1e-12      # measured 3.6e-15, 5.0e-14


def test_start_time_and_gravity_other_than_the_defaults():
    m = Motion(x="sin(t)", yaw="0.3*t", roll="0.1*sin(2*t)")
    g = 9.78
    for kind in ("rates", "increments"):
        sig = simulate_imu(m, 50.0, 4.0, kind=kind, g=g, t0=3.7)
        assert sig.t0 == pytest.approx(3.7, abs=1e-12) and sig.g == g
        nav = navigate(sig, *m.states([sig.t0]).initial())
        assert nav.t[0] == pytest.approx(3.7, abs=1e-12)
        e = nav_errors(nav, m)
        # default algorithms at 50 Hz over 4 s: measured ≤ 9.6e-11 m and 2.4e-12 rad
        assert e.position.max() < 5e-10 and e.attitude.max() < 1e-11
    # navigating with another g drifts by exactly ½·Δg·t² downwards
    still = Motion(yaw="0.2", pitch="0.1", duration=4.0)
    sig = simulate_imu(still, 50.0, kind="increments", g=g)
    nav = navigate(sig, *still.states([sig.t0]).initial(), g=G)
    assert nav.position[-1, 2] == pytest.approx(0.5 * (G - g) * 16.0, rel=1e-9)
    np.testing.assert_allclose(nav.position[-1, :2], 0, atol=1e-12)
