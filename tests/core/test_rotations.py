"""The rotations core, pinned by algebra, literal matrices, round trips and scipy as oracle."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from imunav import ImunavError
from imunav.core.rotations import (
    GimbalLockWarning,
    euler_to_quat,
    from_scipy,
    quat_angle,
    quat_conj,
    quat_exp,
    quat_from_dcm,
    quat_log,
    quat_mul,
    quat_normalize,
    quat_rotate,
    quat_to_dcm,
    quat_to_euler,
    skew,
    to_scipy,
)

ONE, I, J, K = np.eye(4)


def test_multiplication_table():
    assert np.array_equal(quat_mul(I, J), K)
    assert np.array_equal(quat_mul(J, I), -K)
    assert np.array_equal(quat_mul(J, K), I)
    assert np.array_equal(quat_mul(K, J), -I)
    assert np.array_equal(quat_mul(K, I), J)
    assert np.array_equal(quat_mul(I, K), -J)
    for u in (I, J, K):
        assert np.array_equal(quat_mul(u, u), -ONE)
    assert np.array_equal(quat_mul(quat_mul(I, J), K), -ONE)


def test_elementary_rotations_are_literal_matrices():
    a = 0.3
    c, s = np.cos(a), np.sin(a)
    Rx = [[1, 0, 0], [0, c, -s], [0, s, c]]
    Ry = [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    Rz = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    np.testing.assert_allclose(quat_to_dcm([np.cos(a / 2), np.sin(a / 2), 0, 0]), Rx, atol=1e-15)
    np.testing.assert_allclose(quat_to_dcm([np.cos(a / 2), 0, np.sin(a / 2), 0]), Ry, atol=1e-15)
    np.testing.assert_allclose(quat_to_dcm([np.cos(a / 2), 0, 0, np.sin(a / 2)]), Rz, atol=1e-15)
    # 90° yaw takes body x (forward) to north-east... east: v_n = C_nb v_b.
    q = euler_to_quat([np.pi / 2, 0, 0])
    np.testing.assert_allclose(quat_rotate(q, [1, 0, 0]), [0, 1, 0], atol=1e-15)


def _unit_quats(rng, n):
    return quat_normalize(rng.normal(size=(n, 4)))


def test_rotate_matches_dcm_and_scipy(rng):
    q = _unit_quats(rng, 50)
    v = rng.normal(size=(50, 3))
    r = quat_rotate(q, v)
    np.testing.assert_allclose(r, np.einsum("kij,kj->ki", quat_to_dcm(q), v), atol=1e-14)
    np.testing.assert_allclose(r, to_scipy(q).apply(v), atol=1e-14)
    # explicit q ⊗ [0, v] ⊗ q*
    vq = np.concatenate([np.zeros((50, 1)), v], axis=1)
    np.testing.assert_allclose(quat_mul(quat_mul(q, vq), quat_conj(q))[:, 1:], r, atol=1e-14)


def test_product_composes_like_matrices(rng):
    p, q = _unit_quats(rng, 20), _unit_quats(rng, 20)
    np.testing.assert_allclose(quat_to_dcm(quat_mul(p, q)), quat_to_dcm(p) @ quat_to_dcm(q),
                               atol=1e-14)


def test_scipy_boundary_is_scalar_first(rng):
    q = _unit_quats(rng, 10)
    np.testing.assert_allclose(to_scipy(q).as_quat(scalar_first=False)[:, 3], q[:, 0])
    np.testing.assert_allclose(from_scipy(to_scipy(q)), q, atol=1e-15)
    # scipy's own default order is scalar last: the flag matters.
    r = Rotation.from_quat([0, 0, 0, 1])  # identity in scipy's scalar-last default
    np.testing.assert_allclose(from_scipy(r), [1, 0, 0, 0])


def test_euler_matches_scipy_intrinsic_zyx(rng):
    ypr = rng.uniform([-np.pi, -1.5, -np.pi], [np.pi, 1.5, np.pi], size=(100, 3))
    q = euler_to_quat(ypr)
    ref = Rotation.from_euler("ZYX", ypr)
    assert np.all(quat_angle(q, from_scipy(ref)) < 1e-14)
    np.testing.assert_allclose(quat_to_euler(q), ypr, atol=1e-12)
    np.testing.assert_allclose(quat_to_euler(q), ref.as_euler("ZYX"), atol=1e-12)


def test_gimbal_lock_warns_and_keeps_rotation():
    ypr = np.array([[0.7, np.pi / 2, 0.2], [0.3, -np.pi / 2, -0.4]])
    q = euler_to_quat(ypr)
    with pytest.warns(GimbalLockWarning):
        e = quat_to_euler(q)
    np.testing.assert_allclose(e[:, 2], 0.0)
    np.testing.assert_allclose(e[:, 1], ypr[:, 1])
    assert np.all(quat_angle(euler_to_quat(e), q) < 1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quat_to_euler(euler_to_quat([0.1, 1.0, 0.2]))  # no warning away from the lock


def test_dcm_round_trip_and_scipy(rng):
    q = _unit_quats(rng, 200)
    q = np.where(q[:, :1] < 0, -q, q)
    np.testing.assert_allclose(quat_from_dcm(quat_to_dcm(q)), q, atol=1e-14)
    np.testing.assert_allclose(quat_to_dcm(q), to_scipy(q).as_matrix(), atol=1e-14)
    # rotations by π (trace = −1) take the non-trace branches
    for ax in np.eye(3):
        qpi = quat_exp(np.pi * ax)
        assert quat_angle(quat_from_dcm(quat_to_dcm(qpi)), qpi) < 1e-14


def test_dcm_rejects_non_rotation():
    with pytest.raises(ImunavError, match="proper rotation"):
        quat_from_dcm(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ImunavError, match=r"shape \(\.\.\., 3, 3\)"):
        quat_from_dcm(np.eye(4))


def test_exp_log_small_angles_full_precision():
    for a in (1e-3, 1e-8, 1e-12, 1e-20):
        v = np.array([a, -2 * a, 0.5 * a])
        np.testing.assert_allclose(quat_log(quat_exp(v)), v, rtol=1e-15, atol=0)
    assert np.array_equal(quat_log([1.0, 0, 0, 0]), np.zeros(3))
    assert np.array_equal(quat_exp(np.zeros(3)), [1.0, 0, 0, 0])


def test_log_short_way_and_w_above_one():
    v = np.array([0.0, 0.0, 0.3])
    np.testing.assert_allclose(quat_log(-quat_exp(v)), v, atol=1e-15)
    # |w| marginally above 1 (a slightly unnormalised identity) → a finite zero, never NaN
    assert np.all(np.isfinite(quat_log([1.0 + 1e-15, 1e-17, 0, 0])))
    # 2·arccos(w) would give 0 here; atan2 keeps the tiny angle
    tiny = quat_exp([1e-10, 0, 0])
    assert abs(quat_log(tiny)[0] - 1e-10) < 1e-25


def test_exp_matches_scipy(rng):
    v = rng.normal(size=(100, 3))
    assert np.all(quat_angle(quat_exp(v), from_scipy(Rotation.from_rotvec(v))) < 1e-14)


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, 3, elements=st.floats(-3.0, 3.0)))
def test_rotvec_round_trip(v):
    # within the principal ball |v| < π the log inverts the exp
    if np.linalg.norm(v) >= np.pi - 1e-6:
        v = v * (np.pi - 1e-3) / np.linalg.norm(v)
    np.testing.assert_allclose(quat_log(quat_exp(v)), v, atol=1e-13)


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, 4, elements=st.floats(-1.0, 1.0)).filter(
    lambda q: np.linalg.norm(q) > 1e-3))
def test_quat_round_trips(q):
    q = quat_normalize(q)
    assert quat_angle(quat_from_dcm(quat_to_dcm(q)), q) < 1e-12
    assert quat_angle(quat_exp(quat_log(q)), q) < 1e-12
    # Euler angles are ill-conditioned near ±90° pitch: the round trip loses ~eps/cos θ,
    # and inside the lock band (cos θ < 1e-9) roll is set to 0 at a cost ≤ π·cos θ.
    cos_pitch = np.hypot(1 - 2 * (q[2] ** 2 + q[3] ** 2), 2 * (q[1] * q[2] + q[0] * q[3]))
    tol = 1e-12 + (4e-9 if cos_pitch < 1e-9 else 2e-15 / cos_pitch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GimbalLockWarning)
        assert quat_angle(euler_to_quat(quat_to_euler(q)), q) < tol


def test_angle_metric(rng):
    p, q = _unit_quats(rng, 100), _unit_quats(rng, 100)
    np.testing.assert_allclose(quat_angle(p, q), quat_angle(q, p), atol=1e-15)
    assert np.all(quat_angle(q, -q) < 1e-15)
    assert np.all(quat_angle(q, q) < 1e-15)
    np.testing.assert_allclose(quat_angle(p, q), to_scipy(p).inv().__mul__(to_scipy(q)).magnitude(),
                               atol=1e-13)
    # resolves angles far below the arccos floor
    assert abs(quat_angle([1, 0, 0, 0], quat_exp([3e-12, 0, 0])) - 3e-12) < 1e-26


def test_skew_is_cross(rng):
    a, b = rng.normal(size=(2, 10, 3))
    np.testing.assert_allclose(np.einsum("kij,kj->ki", skew(a), b), np.cross(a, b), atol=1e-15)


@pytest.mark.parametrize("bad, msg", [
    (np.zeros(3), r"shape \(\.\.\., 4\)"),
    ([1.0, np.nan, 0, 0], "NaN or inf"),
    ([0.0, 0, 0, 0], "non-zero norm"),
    ("abc", "numeric"),
])
def test_bad_quaternions_named(bad, msg):
    with pytest.raises(ImunavError, match=msg):
        quat_to_dcm(bad)
