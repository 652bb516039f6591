"""Strapdown integration against the analytic truth (never against its own discretisation)."""

import numpy as np
import pytest

from imunav import ImunavError, Motion, navigate, simulate_imu
from imunav.assess import fit_order, nav_errors
from imunav.rotations import _mul, quat_normalize
from imunav.strapdown import ALGORITHMS, DEFAULT_ALGORITHM, cumulative_product

# Moves along and turns about all three axes; 10 s.
MOTION = Motion(x="3*sin(0.4*t)", y="2*t + 0.1*t**2", z="-0.5*cos(0.6*t)",
                yaw="0.6*sin(0.5*t) + 0.1*t", pitch="0.25*sin(0.8*t)", roll="0.4*sin(1.2*t)",
                duration=10.0)


def _run(kind, name, rate, motion=MOTION):
    sig = simulate_imu(motion, rate, output=kind)
    t0 = np.array([sig.t[0] if kind == "rates" else sig.t[0] - sig.dt])
    nav = navigate(sig, motion.attitude(t0)[0], motion.velocity(t0)[0], motion.position(t0)[0],
                   algorithm=name)
    return nav, nav_errors(nav, motion)


def test_cumulative_product_matches_plain_loop(rng):
    dq = quat_normalize(np.concatenate([np.ones((1001, 1)), 0.05 * rng.normal(size=(1001, 3))],
                                       axis=1))
    q0 = quat_normalize(rng.normal(size=4))
    ref = [q0]
    for d in dq:
        ref.append(_mul(ref[-1], d))
    ref = np.array(ref)
    for block in (None, 1, 7, 2000):
        np.testing.assert_allclose(cumulative_product(q0, dq, block=block), ref, atol=1e-12)


# Per-component thresholds at 100 Hz over 10 s, from the measured errors with a margin ≈ 3×.
THRESHOLDS = {  # (attitude rad, velocity m/s, position m); measured ×≈3, see closing note
    ("rates", "first_order"): (1.7e-2, 7e-1, 3.2),           # measured 5.7e-3, 2.3e-1, 1.05
    ("rates", "exact_exponential"): (3.6e-5, 9e-4, 4.3e-3),  # 1.2e-5, 3.0e-4, 1.4e-3
    ("rates", "magnus4"): (6e-10, 1.9e-8, 8.5e-8),           # 1.9e-10, 6.3e-9, 2.8e-8
    ("increments", "first_order"): (2.2e-5, 7.8e-4, 3.9e-3),  # 7.3e-6, 2.6e-4, 1.3e-3
    ("increments", "exact_exponential"): (1.5e-5, 6.4e-4, 3.2e-3),  # 5.1e-6, 2.1e-4, 1.1e-3
    ("increments", "coning2"): (2.6e-8, 6.3e-4, 3.3e-3),     # 8.5e-9, 2.1e-4, 1.1e-3
}


@pytest.mark.parametrize("kind, name", sorted(THRESHOLDS))
def test_round_trip_against_analytic_truth(kind, name):
    nav, err = _run(kind, name, 100.0)
    ta, tv, tp = THRESHOLDS[kind, name]
    assert nav.t.size == 1001 and nav.t[0] == 0.0 and nav.t[-1] == pytest.approx(10.0)
    assert err.attitude.max() < ta
    # per component, not only the norm
    dv = np.abs(nav.velocity - MOTION.velocity(nav.t)).max(axis=0)
    dp = np.abs(nav.position - MOTION.position(nav.t)).max(axis=0)
    assert np.all(dv < tv), dv
    assert np.all(dp < tp), dp


def test_every_algorithm_has_a_threshold():
    assert {(k, n) for k, t in ALGORITHMS.items() for n in t} == set(THRESHOLDS)


@pytest.mark.parametrize("kind, name", sorted(THRESHOLDS))
def test_convergence_order_matches_documented(kind, name):
    rates = [50.0, 100.0, 200.0]
    errs = [_run(kind, name, r) [1] for r in rates]
    doc = ALGORITHMS[kind][name].order
    for i, key in enumerate(("attitude", "velocity", "position")):
        e = [getattr(x, key).max() for x in errs]
        order = fit_order([1 / r for r in rates], e)
        assert abs(order - doc[i]) < 0.3, (key, order, doc[i])


def test_defaults_are_most_accurate():
    for kind, name in DEFAULT_ALGORITHM.items():
        best = min(ALGORITHMS[kind], key=lambda n: _run(kind, n, 100.0)[1].attitude.max())
        assert best == name


def test_stationary_stays_put():
    m = Motion(yaw="0.3", pitch="0.1", roll="-0.2", x="1", y="2", z="3", duration=10.0)
    for kind in ("rates", "increments"):
        nav, err = _run(kind, None, 50.0, m)
        assert err.position.max() < 1e-9 and err.attitude.max() < 1e-14


def test_wrong_kind_and_unknown_algorithm():
    sig = simulate_imu(MOTION, 50, output="rates")
    with pytest.raises(ImunavError, match="unknown algorithm 'coning2' for rates"):
        navigate(sig, [1, 0, 0, 0], algorithm="coning2")
    with pytest.raises(ImunavError, match="q0 must have shape"):
        navigate(sig, [1, 0, 0])
    with pytest.raises(ImunavError, match="v0 contains NaN"):
        navigate(sig, [1, 0, 0, 0], v0=[0, np.nan, 0])


def test_inputs_not_mutated():
    sig = simulate_imu(MOTION, 50, output="increments")
    g0, a0 = sig.gyro.copy(), sig.accel.copy()
    q0 = np.array([1.0, 0, 0, 0])
    navigate(sig, q0)
    assert np.array_equal(sig.gyro, g0) and np.array_equal(sig.accel, a0)
    assert np.array_equal(q0, [1.0, 0, 0, 0])
