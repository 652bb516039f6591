"""The estimation room (issue 24): the error model, its exact discretisation, the covariance
propagation and the Kalman steps, each against an independent truth — scipy's matrix
exponential (Van Loan), quadrature, closed forms of the error growth, and the textbook Kalman
filter written out here.
"""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

from imunav import Motion
from imunav.core.kernels import skew
from imunav.core.validation import ImunavError
from imunav.estimation import (
    DP,
    DV,
    FLAT,
    NAV,
    PHI,
    ErrorSource,
    Trajectory,
    linearise,
    phi_functions,
    predict,
    propagate,
    propagate_chunks,
    update,
    van_loan,
)
from imunav.motion.catalog import figure_eight
from imunav.sensors.models import ImuModel, TriadModel
from imunav.sensors.terms import SensorErrorStates


@pytest.mark.parametrize("d", [0.0, 1e-6, -3e-4, 0.049, -0.049, 0.051, 0.5, -2.0, 24.0, 26.0,
                               -24.0, -26.0, -40.0, -400.0])
def test_phi_functions_against_quadrature(d):
    """φ_i(d) = ∫_0^h (h−s)^i/i! e^{d s} ds by scipy quad, to 1e-13, on both sides of the switch
    from the series to the closed form (|d·h| = 0.5) and where the old switch (1e-3) was: the
    closed form for φ2 had lost 7 digits there (1.5e-7 at d·h = 1.02e-3), found by this test
    once pytest.approx's default abs=1e-12 no longer hid it."""
    h = 0.02
    got = phi_functions(np.array([d]), h)
    for i, fact in enumerate((1, 1, 2)):
        want = quad(lambda s, i=i, fact=fact: (h - s) ** i / fact * np.exp(d * s), 0, h,
                    epsabs=0, epsrel=1e-13)[0]
        assert got[i][0] == pytest.approx(want, rel=1e-13, abs=0), i   # (approx adds abs=1e-12)


def test_skew_is_the_cross_product():
    v = np.random.default_rng(2).normal(size=(4, 3))
    u = np.random.default_rng(3).normal(size=(4, 3))
    np.testing.assert_allclose(np.einsum("nij,nj->ni", skew(v), u), np.cross(v, u), atol=1e-15)


def _traj(rate=50.0, duration=4.0):
    return Trajectory.of(figure_eight(), rate, duration)


def test_continuous_dynamics_have_the_textbook_blocks():
    """φ̇ = −C δω, δv̇ = [f_n×] φ + C δf, δṗ = δv, written out here from the trajectory."""
    traj = _traj()
    (src,) = [s for s in linearise(ImuModel(TriadModel(bias=1e-3), TriadModel()), traj)[0]]
    F, Qc = FLAT.dynamics(traj, src)
    assert F.shape == (traj.steps, 12, 12) and Qc.shape == (12,)
    i = 7
    np.testing.assert_array_equal(F[i, PHI, :NAV], 0)
    np.testing.assert_allclose(F[i, DV, PHI] @ [1.0, 2.0, 3.0], np.cross(traj.f_n[i], [1, 2, 3]),
                               atol=1e-13)
    np.testing.assert_array_equal(F[i, DP, DV], np.eye(3))
    np.testing.assert_allclose(F[i, PHI, NAV:], -traj.C[i], atol=0)         # gyro bias → φ
    np.testing.assert_array_equal(F[i, NAV:, :], 0)                          # constant states
    G = FLAT.noise_input(traj)
    np.testing.assert_array_equal(G[i, PHI, 0:3], -traj.C[i])
    np.testing.assert_array_equal(G[i, DV, 3:6], traj.C[i])


@pytest.mark.parametrize("triad, model", [
    ("gyro", TriadModel(bias=1e-3)),
    ("gyro", TriadModel(bias_instability=1e-4, bias_correlation_time=2.0)),
    ("accel", TriadModel(bias_instability=1e-3)),                 # the 9-process flicker bank
    ("accel", TriadModel(scale_factor=1e-3, noise_density=1e-3)),
    ("gyro", TriadModel(g_sensitivity=1e-4, random_walk=1e-5)),
    ("accel", TriadModel(misalignment=1e-3)),
])
def test_exact_discretisation_equals_van_loan(triad, model):
    """The closed-form Φ (A³ = 0, diagonal sensor decay) and Gauss–Legendre Q_d against the
    matrix exponential of the continuous system (scipy expm), step by step."""
    traj = _traj().piece(0, 40)
    imu = ImuModel(model, TriadModel()) if triad == "gyro" else ImuModel(TriadModel(), model)
    sources, _ = linearise(imu, traj)
    assert sources
    for src in sources:
        h = traj.h / src.sub
        Phi, Qd = FLAT.discretise(traj, src)
        Phi2, Qd2 = FLAT.discretise_generic(traj, src, h)
        scale = np.abs(Phi2).max()
        np.testing.assert_allclose(Phi, Phi2, rtol=0, atol=1e-13 * scale, err_msg=src.name)
        qs = max(np.abs(Qd2).max(), 1e-300)
        np.testing.assert_allclose(Qd, Qd2, rtol=0, atol=1e-11 * qs, err_msg=src.name)
        # and Φ itself is expm(F h) of the continuous system
        F, _ = FLAT.dynamics(traj, src)
        np.testing.assert_allclose(Phi[5], expm(F[5] * h), rtol=0, atol=1e-13 * scale)


def test_van_loan_on_a_scalar_gauss_markov_process():
    """ẋ = −x/T + w, PSD q: Φ = e^{−h/T}, Q_d = qT/2 (1 − e^{−2h/T}) (closed form)."""
    T, q, h = 3.0, 0.7, 0.25
    Phi, Qd = van_loan(np.array([[[-1 / T]]]), np.array([q]), h)
    assert Phi[0, 0, 0] == pytest.approx(np.exp(-h / T), rel=1e-14)
    assert Qd[0, 0, 0] == pytest.approx(q * T / 2 * (1 - np.exp(-2 * h / T)), rel=1e-13)


def test_propagation_of_a_gyro_bias_is_the_closed_form():
    """A gyro bias b on a level, still IMU: attitude σ = b·t on every axis (Titterton & Weston),
    and the horizontal position σ = g·b·t³/6."""
    b, g = 1e-4, 9.80665
    traj = Trajectory.of(Motion(duration=5.0), 100.0, 5.0)
    sources, _ = linearise(ImuModel(TriadModel(bias=b), TriadModel()), traj, "rates")
    (P,) = propagate(sources, traj)
    t = traj.t
    assert P.shape == (501, 9, 9)
    np.testing.assert_allclose(np.sqrt(np.diagonal(P[1:, PHI, PHI], axis1=-2, axis2=-1)),
                               np.stack([b * t[1:]] * 3, -1), rtol=1e-12)
    np.testing.assert_allclose(np.sqrt(P[1:, 6, 6]), g * b * t[1:] ** 3 / 6, rtol=1e-12)


def test_propagation_in_pieces_is_the_same_to_the_bit():
    """Chunked propagation (what a streaming analysis does) does not depend on the piece size."""
    traj = _traj(50.0, 6.0)
    model = ImuModel.from_toml("examples/my_imu.toml")
    sources, _ = linearise(model, traj, "increments", model.decimation(50.0))
    whole = propagate(sources, traj, chunk=10_000)
    for chunk in (1, 7, 64):
        parts = propagate(sources, traj, chunk=chunk)
        for a, b in zip(whole, parts, strict=True):
            np.testing.assert_array_equal(a, b)
    # the generator hands out each piece's step ends, once
    seen = [(lo, hi) for lo, hi, _ in propagate_chunks(sources, traj, chunk=100)]
    assert seen[0] == (0, 100) and seen[-1][1] == traj.steps
    assert all(a[1] == b[0] for a, b in zip(seen, seen[1:], strict=False))


def test_an_error_source_without_states_is_white_noise_on_its_rows():
    traj = _traj().piece(0, 10)
    src = ErrorSource(SensorErrorStates("accel.test", "accel", white_psd=4.0))
    q = src.noise_psd()
    np.testing.assert_array_equal(q, [0, 0, 0, 4, 4, 4, 0, 0, 0])
    Phi, Qd = FLAT.discretise(traj, src)
    # velocity random walk: δv variance q·h after one step
    np.testing.assert_allclose(np.diagonal(Qd[0, DV, DV]), 4.0 * traj.h, rtol=1e-14)


# ------------------------------------------------------------------------ the Kalman steps


def _textbook(x, P, z, H, R):
    """The Kalman update as every textbook prints it: K = P Hᵀ (H P Hᵀ + R)⁻¹, x + K(z − Hx),
    P = (I − K H) P."""
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    return x + K @ (z - H @ x), (np.eye(len(x)) - K @ H) @ P


def test_joseph_update_equals_the_textbook_filter_on_a_linear_problem():
    """A constant-acceleration target tracked from noisy positions (3 states, 1 measurement)
    over 200 steps: the Joseph-form filter and the textbook one agree to round-off."""
    rng = np.random.default_rng(24)
    h, q, r = 0.1, 0.05, 0.5
    Phi = np.array([[1, h, h * h / 2], [0, 1, h], [0, 0, 1]])
    Qd = q * np.array([[h**5 / 20, h**4 / 8, h**3 / 6], [h**4 / 8, h**3 / 3, h**2 / 2],
                       [h**3 / 6, h**2 / 2, h]])
    H, R = np.array([[1.0, 0, 0]]), np.array([[r]])
    truth = np.array([0.0, 1.0, 0.2])
    x1 = x2 = np.zeros(3)
    P1 = P2 = np.diag([10.0, 10.0, 10.0])
    for _ in range(200):
        truth = Phi @ truth + rng.multivariate_normal(np.zeros(3), Qd)
        z = H @ truth + rng.normal(0, np.sqrt(r), 1)
        x1, P1 = predict(x1, P1, Phi, Qd)
        x2, P2 = Phi @ x2, Phi @ P2 @ Phi.T + Qd
        u = update(x1, P1, z, H, R)
        x1, P1 = u.x, u.P
        x2, P2 = _textbook(x2, P2, z, H, R)
        assert u.accepted
    np.testing.assert_allclose(x1, x2, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(P1, P2, rtol=1e-9, atol=1e-14)
    assert abs(x1[0] - truth[0]) < 4 * np.sqrt(P1[0, 0])            # and it tracks


def test_joseph_form_stays_symmetric_positive_with_a_suboptimal_gain_history():
    """Two measurements, large prior: the update stays symmetric PSD, and a rejected (gated)
    outlier leaves the state untouched; the NIS is χ²-distributed's νᵀS⁻¹ν, written out."""
    x, P = np.zeros(2), np.diag([1e6, 1e-6])
    H, R = np.eye(2), np.diag([1e-8, 1.0])
    u = update(x, P, [1.0, 2.0], H, R)
    assert np.allclose(u.P, u.P.T, atol=0) and np.all(np.linalg.eigvalsh(u.P) > 0)
    S = P + R
    assert u.nis == pytest.approx(np.array([1.0, 2.0]) @ np.linalg.solve(S, [1.0, 2.0]),
                                  rel=1e-12)
    out = update(np.zeros(2), np.eye(2), [100.0, 0.0], H, np.eye(2), gate=0.999)
    assert not out.accepted and np.all(out.x == 0) and np.all(out.P == np.eye(2))
    assert out.nis == pytest.approx(100.0**2 / 2, rel=1e-12)
    ok = update(np.zeros(2), np.eye(2), [1.0, 0.0], H, np.eye(2), gate=0.999)
    assert ok.accepted and ok.x[0] == pytest.approx(0.5)


@pytest.mark.parametrize("kw, msg", [
    (dict(H=np.eye(3)), "update needs"),
    (dict(R=-np.eye(2)), "not positive definite"),
    (dict(gate=1.5), "gate must be a probability"),
])
def test_update_refuses_bad_input(kw, msg):
    from imunav import ImunavError

    args = dict(x=np.zeros(2), P=np.eye(2), z=np.zeros(2), H=np.eye(2), R=np.eye(2))
    args.update(kw)
    with pytest.raises(ImunavError, match=msg):
        update(**args)


@pytest.mark.parametrize("m", [1, 2, 3, 6])
def test_batched_update_is_the_textbook_joseph_update(m):
    """Issue 39: ``update_batch`` (its closed-form Cholesky up to three components, its
    Joseph form as ``P + (U + Uᵀ)``) equals the gain ``P Hᵀ S⁻¹`` and Joseph's
    ``(I − K H) P (I − K H)ᵀ + K R Kᵀ`` written out with numpy's inverse, to round-off; a
    filter whose ``S`` is not positive definite keeps its state with ``robust``, and an
    error names it without."""
    from imunav.estimation.kalman import update_batch

    rng = np.random.default_rng(m)
    R_, n = 5, 8
    A = rng.standard_normal((R_, n, n))
    P = A @ np.swapaxes(A, 1, 2) + np.eye(n)
    H = rng.standard_normal((R_, m, n))
    Rm = np.diag(rng.uniform(0.5, 2.0, m))
    x = rng.standard_normal((R_, n))
    z = rng.standard_normal((R_, m))
    u = update_batch(x, P, z, H, Rm)
    for r in range(R_):
        S = H[r] @ P[r] @ H[r].T + Rm
        K = P[r] @ H[r].T @ np.linalg.inv(S)
        IKH = np.eye(n) - K @ H[r]
        nu = z[r] - H[r] @ x[r]
        np.testing.assert_allclose(u.x[r], x[r] + K @ nu, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(u.P[r], IKH @ P[r] @ IKH.T + K @ Rm @ K.T, rtol=1e-9,
                                   atol=1e-11)
        assert u.nis[r] == pytest.approx(nu @ np.linalg.solve(S, nu), rel=1e-10)
    assert np.array_equal(u.P, np.swapaxes(u.P, 1, 2))           # exactly symmetric
    Pbad = P.copy()
    Pbad[2] = -10.0 * np.eye(n)                                  # S not positive definite
    v = update_batch(x, Pbad, z, H, Rm, robust=True)
    assert np.isnan(v.nis[2]) and not v.accepted[2]
    assert np.array_equal(v.P[2], Pbad[2]) and np.array_equal(v.x[2], x[2])
    np.testing.assert_allclose(v.P[[0, 1, 3, 4]], u.P[[0, 1, 3, 4]], rtol=1e-12)
    with pytest.raises(ImunavError, match="not positive definite"):
        update_batch(x, Pbad, z, H, Rm)
