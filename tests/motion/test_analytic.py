"""Motion laws and the ideal IMU, checked against independent truths.

Oracles: ω_b from a SymPy derivative of the attitude quaternion itself (2 q* ⊗ q̇, not the
Euler-rate formula the library uses); f_b through scipy's rotations; increments through
``scipy.integrate.quad`` at tight tolerance.
"""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad
from scipy.spatial.transform import Rotation

from imunav import G0, ImunavError, Motion, simulate_imu
from imunav.sensors.simulate import sample_times

LAWS = dict(x="t**2", y="t*sin(t)**2", z="2*t", yaw="0.5*sin(0.7*t) + 0.2*t",
            pitch="0.3*sin(1.1*t)", roll="0.4*cos(0.9*t) + 0.1*t")


@pytest.fixture(scope="module")
def motion():
    return Motion(**LAWS, duration=5.0)


def _oracle_omega():
    """ω_b = vec(2 q* ⊗ q̇) with q = q_z(ψ) q_y(θ) q_x(φ) written as SymPy quaternions."""
    t = sp.Symbol("t", real=True)
    psi, th, ph = (sp.sympify(LAWS[k], locals={"t": t}) for k in ("yaw", "pitch", "roll"))
    Q = sp.algebras.Quaternion
    q = (Q(sp.cos(psi / 2), 0, 0, sp.sin(psi / 2)) * Q(sp.cos(th / 2), 0, sp.sin(th / 2), 0)
         * Q(sp.cos(ph / 2), sp.sin(ph / 2), 0, 0))
    qd = Q(*(sp.diff(c, t) for c in (q.a, q.b, q.c, q.d)))
    w = 2 * Q(q.a, -q.b, -q.c, -q.d) * qd
    return sp.lambdify(t, [w.b, w.c, w.d], "numpy")


def test_body_rate_matches_quaternion_derivative(motion, rng):
    t = rng.uniform(0, 5, 200)
    ref = np.array(_oracle_omega()(t)).T
    got = motion.angular_rate(t)
    assert np.max(np.abs(got - ref) / np.linalg.norm(ref, axis=1, keepdims=True)) < 1e-9


def test_specific_force_matches_scipy(motion, rng):
    t = rng.uniform(0, 5, 200)
    ypr = motion.euler(t)
    ts = sp.Symbol("t")
    acc = [sp.lambdify(ts, sp.diff(sp.sympify(LAWS[k]), ts, 2), "numpy") for k in "xyz"]
    a = np.stack([np.broadcast_to(f(t), t.shape) for f in acc], -1)
    ref = Rotation.from_euler("ZYX", ypr).inv().apply(a - [0, 0, G0])
    got = motion.specific_force(t)
    assert np.max(np.abs(got - ref) / np.linalg.norm(ref, axis=1, keepdims=True)) < 1e-9


def test_simulated_rates_match_analytic(motion, rng):
    rate = rng.uniform(57.0, 173.0)  # an odd rate puts the samples at "random" times
    sig = simulate_imu(motion, rate, kind="rates")
    np.testing.assert_array_equal(sig.t, np.arange(sig.t.size) / rate)
    ref = np.array(_oracle_omega()(sig.t)).T
    rel = np.abs(sig.gyro - ref) / np.linalg.norm(ref, axis=1, keepdims=True)
    assert rel.max() < 1e-9
    assert sig.t.size == int(round(5.0 * rate)) + 1


def test_level_at_rest_reads_minus_g():
    sig = simulate_imu(Motion(), 10, 1.0)
    np.testing.assert_allclose(sig.accel, np.tile([0, 0, -G0], (11, 1)), atol=1e-15)
    np.testing.assert_allclose(sig.gyro, 0, atol=0)


def test_rolled_30deg_at_rest():
    sig = simulate_imu(Motion(roll="pi/6"), 10, 1.0, g=9.81)
    s, c = np.sin(np.pi / 6), np.cos(np.pi / 6)
    np.testing.assert_allclose(sig.accel, np.tile([0, -9.81 * s, -9.81 * c], (11, 1)),
                               atol=1e-14)


def test_pitched_nose_up_at_rest():
    # nose up 20°: the support force (up) has a forward body component +g sin θ
    sig = simulate_imu(Motion(pitch=np.radians(20)), 10, 0.5)
    th = np.radians(20)
    np.testing.assert_allclose(sig.accel[0], [G0 * np.sin(th), 0, -G0 * np.cos(th)], atol=1e-14)


def test_increments_match_quad(motion, rng):
    sig = simulate_imu(motion, 20.0, kind="increments")
    assert sig.t.size == 100 and sig.t[0] == pytest.approx(0.05)
    for k in rng.choice(sig.t.size, 8, replace=False):
        a, b = sig.t[k] - 0.05, sig.t[k]
        for i in range(3):
            ref_th = quad(lambda s, i=i: motion.angular_rate(np.array([s]))[0, i], a, b,
                          epsabs=1e-14, epsrel=1e-13, limit=200)[0]
            ref_v = quad(lambda s, i=i: motion.specific_force(np.array([s]))[0, i], a, b,
                         epsabs=1e-14, epsrel=1e-13, limit=200)[0]
            assert abs(sig.gyro[k, i] - ref_th) < 1e-10
            assert abs(sig.accel[k, i] - ref_v) < 1e-10


def test_increments_sum_to_total_rotation_about_fixed_axis():
    # yaw only: Δθ_z sums exactly to the yaw change (independent closed form)
    m = Motion(yaw="sin(3*t) + t**3/7")
    sig = simulate_imu(m, 37.0, 2.0, kind="increments")
    total = np.sin(3 * sig.t[-1]) + sig.t[-1] ** 3 / 7
    assert abs(sig.gyro[:, 2].sum() - total) < 1e-12
    assert np.all(np.abs(sig.gyro[:, :2]) < 1e-15)


@pytest.mark.parametrize("kwargs, msg", [
    (dict(x="t*q"), "unknown name 'q'"),
    (dict(yaw="sin(t"), "cannot be parsed"),
    (dict(z="1/0"), "divides by zero"),
    (dict(roll=[1, 2]), "must be a string"),
])
def test_bad_laws_named(kwargs, msg):
    with pytest.raises(ImunavError, match=msg):
        Motion(**kwargs)


def test_constants_allowed():
    m = Motion(x="pi*t + E", roll="pi/4")
    np.testing.assert_allclose(m.position([1.0])[0], [np.pi + np.e, 0, 0])


@pytest.mark.parametrize("rate, dur, msg", [(0, 1, "rate"), (-5, 1, "rate"), (10, 0, "duration"),
                                            (np.nan, 1, "rate"), (10, 0.01, "at least one")])
def test_bad_rate_duration(rate, dur, msg):
    with pytest.raises(ImunavError, match=msg):
        sample_times(rate, dur)


def test_bad_output_kind(motion):
    with pytest.raises(ImunavError, match="kind must be one of"):
        simulate_imu(motion, 100, kind="deltas")
