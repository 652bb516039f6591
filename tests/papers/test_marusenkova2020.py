"""Marusenkova 2020: symbolic findings, the Part A/B schemes, and their physics."""

import numpy as np
import pytest
import sympy as sp

from imunav.papers import marusenkova2020 as M
from imunav.symbolic import marusenkova as S


def test_eq5_is_transpose_of_imunav_dcm(rng):
    assert S.eq5_is_transpose_of_zyx()
    from imunav.core.rotations import euler_to_quat, quat_to_dcm

    ypr = rng.uniform(-1, 1, (20, 3))
    np.testing.assert_allclose(M.eq5(ypr), np.swapaxes(quat_to_dcm(euler_to_quat(ypr)), 1, 2),
                               atol=1e-15)


def test_eq30_typo_is_element_33_only():
    mism = S.eq30_mismatches()
    assert [(i, j) for i, j, *_ in mism] == [(3, 3)]
    assert sp.simplify(mism[0][3] - sp.cos(S.ph0) * sp.cos(S.th0)) == 0


def test_printed_diagonal_terms_are_exact():
    f = S.diagonal_findings()
    assert f["omega11"] and f["omega22"] and f["omega33"]


def test_diagonal_kernel_matches_sympy_and_matrices(rng):
    ypr0 = rng.uniform(-1.5, 1.5, (50, 3))
    ypr1 = ypr0 + rng.uniform(-0.05, 0.05, (50, 3))
    h = 0.01
    got = M.omega_orig_diagonal(ypr0, ypr1, h)
    W = S.omega_orig_exact()
    f = sp.lambdify((S.psi0, S.th0, S.ph0, S.psi1, S.th1, S.ph1, S.dt),
                    [W[0, 0], W[1, 1], W[2, 2]], "numpy")
    ref = np.array(f(*ypr0.T, *ypr1.T, h)).T
    np.testing.assert_allclose(got, ref, atol=1e-11)
    # and against plain matrices, an independent numeric path
    C0, C1 = M.eq5(ypr0), M.eq5(ypr1)
    mat = (np.swapaxes(C0, 1, 2) @ C1 - np.eye(3)) / h
    np.testing.assert_allclose(got, np.diagonal(mat, axis1=1, axis2=2), atol=1e-11)
    f33 = S.omega33_lambdified()
    np.testing.assert_allclose(got[:, 2], f33(ypr0[:, 1], ypr1[:, 1], ypr1[:, 2] - ypr0[:, 2], h),
                               atol=1e-12)


def test_omega33_example():
    ex = S.omega33_example()
    # Paper: Ω_orig(3,3) = −2.63e−4 (printed to 3 digits): reproduced by sin θ ≈ θ (radians)
    assert ex["sin_as_angle"] == pytest.approx(-2.63e-4, abs=0.006e-4)
    # exact, independently from eq. (5) matrices in double precision (ψ arbitrary)
    r = np.radians
    C0 = M.eq5(np.array([0.7, r(30.0), 0.0]))
    C1 = M.eq5(np.array([0.9, r(30.1), r(0.1)]))
    exact = ((C0.T @ C1)[2, 2] - 1) / 0.01
    assert ex["exact"] == pytest.approx(exact, rel=1e-8)
    assert not np.isclose(ex["exact"], -2.63e-4, rtol=1e-2)   # 1.3 % away from the printed value


def test_amended_round_trip_closes_and_classic_is_first_order():
    for fig in M.TRAJECTORIES:
        assert M.round_trip(fig, 100, "quat_amended", "quat_amended")["max"] < 1e-9
    e1 = M.round_trip("fig1a", 100, "dcm", "dcm")["max"]
    e2 = M.round_trip("fig1a", 200, "dcm", "dcm")["max"]
    assert 1.8 < e1 / e2 < 2.2            # first order: no threshold frequency
    assert e1 > 0.5                        # measured 1.08 m


def test_arccos_vs_atan2_in_eq34():
    a = M.round_trip("fig1a", 1000, "quat_amended", "quat_amended", phi_from="arccos")["max"]
    b = M.round_trip("fig1a", 1000, "quat_amended", "quat_amended", phi_from="atan2")["max"]
    assert a < 1e-8 and b < 1e-9


def test_paper_gyro_is_minus_nav_rate_and_accel_is_mirrored():
    d = M.convention_demo()
    # within O(dt) of −ω_n, far from the body rate
    assert np.abs(d["paper_gyro"] - d["minus_nav_rate"]).max() < 5e-3
    assert np.abs(d["paper_gyro"] - d["body_rate"]).max() > 0.3
    np.testing.assert_allclose(d["paper_accel_rolled_30"] * [1, -1, 1], d["real_accel_rolled_30"],
                               atol=1e-12)
    assert d["paper_accel_rolled_30"][1] > 0 > d["real_accel_rolled_30"][1]


def test_physical_signals_favour_imunav():
    m = M.motion_for("fig1a")
    paper = M.restore_physical(m, 100, 10.0, "increments", "quat_amended")["max"]
    best = M.restore_physical(m, 100, 10.0, "increments", "imunav:poly8_m6")["max"]
    assert paper > 0.1 and best < 1e-9      # measured 0.40 m and 6.5e-13 m


def test_fig3_ratio():
    _, omc, ams = M.fig3_data()
    assert omc[-1] / ams[-1] == pytest.approx(3 / np.radians(5), rel=2e-3)  # ≈ 3/α for small α


# ------------------------------------------------------------------ the claims (issue 15)


def test_rodrigues_and_log_against_scipy(rng):
    from scipy.spatial.transform import Rotation

    th = rng.normal(size=(50, 3)) * rng.choice([1e-7, 1e-3, 1.0], size=(50, 1))
    np.testing.assert_allclose(M.rodrigues(th), Rotation.from_rotvec(th).as_matrix(), atol=1e-15)
    inside = np.linalg.norm(th, axis=1) < 3.0        # the logarithm's principal branch: |θ| < π
    np.testing.assert_allclose(M.rotation_vector(M.rodrigues(th[inside])), th[inside], atol=1e-14)


def test_exact_dcm_update_restores_every_trajectory():
    """Conclusion 2 ("DCMs can scarcely be amended") settled: the DCM counterpart of the
    amendment — matrix log in A, Rodrigues in B — closes the round trip to rounding, and mixes
    with the amended quaternions either way (same rotation vectors)."""
    for fig in ("fig1a", "fig1b", "fig2"):
        for a, b in (("dcm_amended", "dcm_amended"), ("dcm_amended", "quat_amended"),
                     ("quat_amended", "dcm_amended")):
            assert M.round_trip(fig, 100, a, b)["max"] < 1e-10, (fig, a, b)
        assert M.round_trip(fig, 100, "dcm", "dcm")["max"] > 1e-2


def test_part_a_gyro_follows_minus_nav_rate_at_3s():
    g = M.gyro_vs_rates(3.0, 100.0)
    # the forward difference is centred at the midpoint: O(dt²·ω̈) ≈ 1e-3 rad/s here
    assert g["to_minus_omega_n"] < 2e-3
    assert g["to_omega_b"] > 0.5                      # far from the body rate


def test_yaw_only_restores_z_but_not_xy():
    for r in M.xy_coincidence():
        assert r["z"] < 1e-12
        assert r["xy"] > 1e-2


def test_omega_asymmetry_ordering_depends_on_attitude():
    a = M.omega_asymmetry(samples=4000)
    assert 0.2 < a["holds"] < 0.5                   # measured 0.31 (20000 samples)
    lv = a["level"]
    assert lv["23"] > lv["12"] > lv["13"]            # reversed from the level attitude
    # independently of eq. (5): C_nbᵀ from scipy, Ω = (C_kᵀ C_{k+1} − I)/dt
    from scipy.spatial.transform import Rotation
    C0 = Rotation.from_euler("ZYX", [0, 0, 0]).as_matrix().T
    C1 = Rotation.from_euler("ZYX", np.radians([0.2, 0.3, 0.1])).as_matrix().T
    Om = (C0.T @ C1 - np.eye(3)) * 100
    assert abs(abs(Om[1, 2]) - abs(Om[2, 1])) == pytest.approx(lv["23"], rel=1e-9)


def test_arccos_keeps_about_ten_digits_and_does_not_matter():
    d = M.arccos_digits()
    assert 8 < d["digits_kept"] < 12                # ≈ log10(Φ²/4ε) at 4e-3 rad steps
    assert d["round_trip_arccos"] < 1e-10 and d["round_trip_atan2"] < 1e-10


# ------------------------------------------------------------------ the claims (issue 23)


def test_eq5_eq30_and_the_diagonal_numerically():
    e5 = M.eq5_check()
    assert e5["to_transpose"] < 1e-15 and e5["to_body_to_inertial"] > 1.0
    e30 = M.eq30_check()
    assert e30["corrected"] < 1e-14 and e30["printed"] > 0.5
    assert M.diagonal_check()["max_difference"] < 1e-11


def test_omega_orig_is_never_skew_symmetric_and_its_closed_form():
    """Ω + Ωᵀ = −2(1 − cos α)(I − nnᵀ)/dt: the symmetric/skew ratio is tan(α/2) (Rodrigues);
    checked here on one step built independently with scipy."""
    from scipy.spatial.transform import Rotation

    d = M.omega_skew_defect()
    assert d["closed_form_error"] < 1e-12 and d["min_ratio"] > 1e-4
    R = Rotation.from_rotvec([0.01, -0.02, 0.015]).as_matrix()
    W = (R - np.eye(3)) * 100.0
    a = np.linalg.norm([0.01, -0.02, 0.015])
    ratio = np.linalg.norm(W + W.T) / np.linalg.norm(W - W.T)
    assert ratio == pytest.approx(np.tan(a / 2), rel=1e-9)


def test_observations_and_threshold():
    o = M.observations(scales=(1.0,))
    assert o["fig2_over_fig1a"] > 5                     # measured 12.6: the trajectory matters
    assert o["worst_fig"] == "fig1b" and 0.1 < o["worst_relative"] < 0.2   # measured 0.15
    thr = M.threshold_order(rates=(50, 200, 800, 3200))
    assert abs(thr["order"] - 1) < 0.02 and thr["min_local_order"] > 0.95   # no threshold


def test_omega_difference_orders_the_discrepancy():
    od = M.omega_difference_vs_discrepancy(rates=(50, 200, 800), scales=(0.5, 2.0))
    assert od["tau"]["fig1a"] == pytest.approx(1.0) and od["tau"]["fig1b"] == pytest.approx(1.0)
    assert od["min_tau"] > 0.6
    # Ω difference is first order in the step: halving the step halves it
    a = M.omega_difference("fig1a", 100)
    b = M.omega_difference("fig1a", 200)
    assert a / b == pytest.approx(2.0, rel=0.02)


def test_amended_part_b_from_rate_samples_is_first_order_in_attitude():
    """From rate samples the paper's Part B turns by ω(t_k)·dt (left point): even the exact
    exponential (36) is first order in attitude; from increments it is imunav's exponential of
    Δθ, and the rectangle sums alone set the position error."""
    m = M.motion_for("fig1a")

    def run(kind, scheme, rate=100):
        return M.restore_physical(m, rate, 10.0, kind, scheme)

    a100 = run("rates", "quat_amended")["att_max"]
    a1000 = run("rates", "quat_amended", 1000)["att_max"]
    assert 9 < a100 / a1000 < 11                                   # measured 10.0
    assert a100 > 100 * run("rates", "imunav:exact_exponential")["att_max"]   # measured 412×
    assert a100 == pytest.approx(run("rates", "dcm")["att_max"], rel=0.02)   # 0.213° vs 0.212°
    assert run("increments", "quat_amended")["att_max"] == pytest.approx(
        run("increments", "imunav:exact_exponential")["att_max"], rel=1e-6)
    # position: from rates the attitude costs most (0.89 m vs 0.14 m with the true attitude);
    # from increments the rectangle sums cost all (0.400 m both)
    assert run("rates", "quat_amended")["max"] > 5 * run("rates", "true_attitude")["max"]
    assert run("increments", "quat_amended")["max"] == pytest.approx(
        run("increments", "true_attitude")["max"], rel=0.01)
