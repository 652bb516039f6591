"""The error state's reset at a feedback (issue 38 item 4): ``AidedSystem.reset_jacobian`` against
the exact rotation algebra — the attitude error left after ``q ← exp(φ̂) ⊗ q``, differentiated
numerically with quaternions, not with the formula under test."""

import numpy as np
import pytest

from imunav.core.kernels import quat_conj, quat_exp, quat_log, quat_mul
from imunav.estimation.system import AidedSystem


def _error_after(phi_hat, delta, q_true):
    """The attitude error after the feedback of ``phi_hat`` when the error before it was
    ``phi_hat + delta`` (``C_est = (I − [φ×]) C``: ``q_est = exp(−φ) ⊗ q``), exactly."""
    q_est = quat_mul(quat_exp(-(phi_hat + delta)), q_true)
    q_new = quat_mul(quat_exp(phi_hat), q_est)
    return -quat_log(quat_mul(q_new, quat_conj(q_true)))


@pytest.mark.parametrize("size", [0.02, 0.2, 0.5])
def test_reset_jacobian_is_the_derivative_of_the_exact_reset(size):
    rng = np.random.default_rng(7)
    q_true = quat_exp(rng.normal(size=3))
    phi_hat = size * rng.normal(size=3) / np.sqrt(3)
    eps = 1e-6
    J = np.column_stack([(_error_after(phi_hat, eps * e, q_true)
                          - _error_after(phi_hat, -eps * e, q_true)) / (2 * eps)
                         for e in np.eye(3)])
    G = AidedSystem.reset_jacobian(np.concatenate([phi_hat, np.ones(6)]))
    ang = np.linalg.norm(phi_hat)
    # first order in φ̂: the exact Jacobian differs from G by O(|φ̂|²) (its next BCH term is
    # |φ̂|²/12), and from the identity (no reset) by |φ̂|/2
    assert np.abs(J - G[:3, :3]).max() < ang ** 2 / 6
    assert np.abs(J - np.eye(3)).max() > 0.2 * ang
    np.testing.assert_array_equal(G[3:, 3:], np.eye(6))
    np.testing.assert_array_equal(G[:3, 3:], 0.0)


def test_reset_is_g_p_gt_for_a_batch():
    rng = np.random.default_rng(3)
    n, R = 12, 4
    A = rng.normal(size=(R, n, n))
    P = A @ np.swapaxes(A, -1, -2)
    x = 0.3 * rng.normal(size=(R, n))
    G = AidedSystem.reset_jacobian(x)
    want = G @ P @ np.swapaxes(G, -1, -2)
    sysm = AidedSystem(None, [], h=0.01)
    got = sysm.reset(P, x)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(got, np.swapaxes(got, -1, -2), rtol=0, atol=0)
    np.testing.assert_allclose(sysm.reset(P, np.zeros((R, n))), P, rtol=0, atol=1e-15)
