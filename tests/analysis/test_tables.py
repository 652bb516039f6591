"""The tables behind notebooks 00 and 06 and ``imunav reproduce`` (run_family, convergence,
poly_sweep, the coning budget, round_trip, error_table, their text formatting) and the small
helpers they rest on, against truths computed here: scipy rotations for the attitude error,
the motion's own laws for the truth, closed-form coning increments, documented orders, and
hand-written table text. Found untested by the first mutation run (issue 19: 561 mutants with
no test reaching them)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from imunav import ImunavError, Motion, navigate, simulate_imu
from imunav.analysis.family import (
    coning_correction_budget,
    convergence,
    fmt_err,
    format_family,
    poly_sweep,
    run_family,
)
from imunav.analysis.metrics import NavErrors
from imunav.analysis.roundtrip import FLOOR_ATT, FLOOR_POS, _order, error_table, round_trip
from imunav.core.states import States
from imunav.core.validation import check_time
from imunav.motion.catalog import coning, figure_eight
from imunav.strapdown import ALGORITHMS

# Moves along and turns about all three axes (as in tests/strapdown/test_algorithms), shortened to 4 s.
MOTION = Motion(x="3*sin(0.4*t)", y="2*t + 0.1*t**2", z="-0.5*cos(0.6*t)",
                yaw="0.6*sin(0.5*t) + 0.1*t", pitch="0.25*sin(0.8*t)", roll="0.4*sin(1.2*t)",
                duration=4.0)


def _scipy_angle(q_a, q_b):
    """Angle (rad) between two attitude histories, by scipy (not imunav.core.rotations)."""
    ra = Rotation.from_quat(np.asarray(q_a), scalar_first=True)
    rb = Rotation.from_quat(np.asarray(q_b), scalar_first=True)
    return (rb.inv() * ra).magnitude()


def _errors_by_hand(motion, rate, kind, name, duration=None):
    """Navigate from the motion's state at t = 0 (both kinds start there: rates are sampled
    from 0, increments stamped at the interval ends) and compare with the laws."""
    sig = simulate_imu(motion, rate, duration, kind=kind)
    t0 = np.array([0.0])
    nav = navigate(sig, motion.attitude(t0)[0], motion.velocity(t0)[0], motion.position(t0)[0],
                   algorithm=name)
    att = _scipy_angle(nav.quaternion, motion.attitude(nav.t))
    vel = np.linalg.norm(nav.velocity - motion.velocity(nav.t), axis=-1)
    pos = np.linalg.norm(nav.position - motion.position(nav.t), axis=-1)
    return nav, att, vel, pos


# Attitude orders and causality of three algorithms, written from their definitions (the
# algorithm table of docs/algorithms.md): an Euler step on sampled rates is first order; on
# exact increments the one-step exponential errs only by the non-commutativity of the
# interval, second order; Magnus-4 on rates is fourth order and needs the next sample (not
# causal).
DOCUMENTED = {("rates", "first_order"): (1, True), ("increments", "first_order"): (2, True),
              ("rates", "magnus4"): (4, False)}


# --------------------------------------------------------------------------------- run_family
def test_run_family_rows_are_the_errors_against_the_laws():
    rows = run_family(MOTION, 50.0, algorithms=["first_order", "magnus4"])
    # magnus4 exists for rates only; first_order for both kinds: 3 rows, kinds in order
    assert [(r["kind"], r["algorithm"]) for r in rows] == [
        ("rates", "first_order"), ("rates", "magnus4"), ("increments", "first_order")]
    for r in rows:
        nav, att, vel, pos = _errors_by_hand(MOTION, 50.0, r["kind"], r["algorithm"])
        assert (r["order"], r["causal"]) == DOCUMENTED[(r["kind"], r["algorithm"])]
        # degrees at the API edge: 1 rad = 57.29577951308232° (180/π)
        # (atol: scipy's and imunav's angles differ by rounding, ~1e-16 rad)
        np.testing.assert_allclose(r["max_att_deg"], att.max() * 57.29577951308232, rtol=1e-9,
                                   atol=1e-13)
        np.testing.assert_allclose(r["final_att_deg"], att[-1] * 57.29577951308232, rtol=1e-9,
                                   atol=1e-13)
        np.testing.assert_allclose(r["max_vel"], vel.max(), rtol=1e-12)
        np.testing.assert_allclose(r["max_pos"], pos.max(), rtol=1e-12)
        assert 0 < r["seconds"] < 10
        assert isinstance(r["max_att_deg"], float)
    # the maximum is not the final value on this motion (the test above would not tell them
    # apart otherwise)
    assert rows[0]["max_att_deg"] > 1.05 * rows[0]["final_att_deg"]


def test_run_family_reports_the_attitude_order():
    # coning2's documented orders are (3, 2, 2): attitude 3, velocity and position 2
    (row,) = run_family(MOTION, 25.0, duration=1.0, kinds=("increments",), algorithms=["coning2"])
    assert row["order"] == 3 == ALGORITHMS["increments"]["coning2"].order[0]


def test_run_family_default_is_every_algorithm_of_every_kind():
    rows = run_family(MOTION, 25.0, duration=1.0, kinds=("rates",))
    assert [r["algorithm"] for r in rows] == list(ALGORITHMS["rates"])
    assert {r["kind"] for r in rows} == {"rates"}
    assert any(r["causal"] is False for r in rows) or all(r["causal"] for r in rows)
    causal = {r["algorithm"]: r["causal"] for r in rows}
    assert causal == {name: algo.causal for name, algo in ALGORITHMS["rates"].items()}
    # the duration is honoured: 1 s at 25 Hz navigates to t = 1
    nav, *_ = _errors_by_hand(MOTION, 25.0, "rates", "first_order", duration=1.0)
    assert nav.t[-1] == pytest.approx(1.0)


# -------------------------------------------------------------------------------- convergence
def test_convergence_fits_the_documented_orders():
    rates = (50, 100, 200)
    rows = convergence(MOTION, rates, "rates", algorithms=["first_order", "magnus4"])
    assert [r["algorithm"] for r in rows] == ["first_order", "magnus4"]
    for r in rows:
        assert r["kind"] == "rates" and r["rates"] == [50, 100, 200]
        assert r["documented"] == ALGORITHMS["rates"][r["algorithm"]].order
        by_hand = [_errors_by_hand(MOTION, rate, "rates", r["algorithm"]) for rate in rates]
        for key, i in (("max_att_rad", 1), ("max_vel", 2), ("max_pos", 3)):
            np.testing.assert_allclose(r[key], [h[i].max() for h in by_hand], rtol=1e-9,
                                       atol=1e-15)    # magnus4 reaches 1e-11 rad at 200 Hz
            # the slope of log error over log step, by numpy's least squares
            slope = np.polyfit(np.log([1 / 50, 1 / 100, 1 / 200]), np.log(r[key]), 1)[0]
            assert r["order_" + key.split("_")[1]] == pytest.approx(slope, rel=1e-12)
    first, magnus4 = rows
    # documented orders, within the pre-asymptotic drift of three rates (measured 0.99, 4.0)
    assert first["order_att"] == pytest.approx(1.0, abs=0.1)
    assert magnus4["order_att"] == pytest.approx(4.0, abs=0.3)


# ------------------------------------------------------------------------------ table text
def test_fmt_err_hand_written():
    assert fmt_err(1.234e-3) == "  1.2e-03"
    assert fmt_err(1e-11) == "  1.0e-11"                 # at the floor: still a number
    assert fmt_err(9.9e-12) == "   <1e-11"                # below it: the floor
    assert fmt_err(3e-9, floor=1e-8) == "   <1e-08"
    assert fmt_err(0.5, width=5) == "5.0e-01"             # width is a minimum
    assert fmt_err(2.0, width=12) == "     2.0e+00"


def test_format_family_hand_written():
    rows = [{"kind": "rates", "algorithm": "first_order", "order": 1, "causal": True,
             "max_att_deg": 0.0123, "final_att_deg": 5e-12, "max_vel": 1.5, "max_pos": 2.26e-3},
            {"kind": "increments", "algorithm": "poly8_m6", "order": 6, "causal": False,
             "max_att_deg": 3e-13, "final_att_deg": 2e-14, "max_vel": 4.4e-11, "max_pos": 7e-12}]
    assert format_family(rows).split("\n") == [
        "signals    algorithm          ord causal  max att (deg) final att (deg) max vel (m/s) "
        "max pos (m)",
        "rates      first_order          1   True        1.2e-02          <1e-11       1.5e+00 "
        "    2.3e-03",
        "increments poly8_m6             6  False         <1e-11          <1e-11       4.4e-11 "
        "     <1e-11",
    ]


# ------------------------------------------------------------------------------- poly sweep
def test_poly_sweep_matches_the_registered_configurations():
    rows = poly_sweep(MOTION, 50.0, [(6, 4, 1), (8, 6, 1), (6, 4, 3)])
    assert [(r["nodes"], r["magnus"], r["substeps"]) for r in rows] == [(6, 4, 1), (8, 6, 1),
                                                                        (6, 4, 3)]
    # rate evaluations per interval: nsub × order/2 (two Gauss nodes per 4th-order step)
    assert [r["evals_per_interval"] for r in rows] == [2, 3, 6]
    # (6, 4, 1) and (8, 6, 1) are the registered poly6_m4 and poly8_m6
    # (poly8_m6 is at the rounding floor here, 1.2e-13°, where the two code paths differ by
    # 5 %: hence the absolute tolerance; poly6_m4's 1e-8° is compared to 1e-6)
    for r, name in zip(rows[:2], ("poly6_m4", "poly8_m6"), strict=True):
        _, att, _, _ = _errors_by_hand(MOTION, 50.0, "increments", name)
        np.testing.assert_allclose(r["max_att_deg"], np.degrees(att.max()), rtol=1e-6,
                                   atol=1e-12)
        assert 0 < r["seconds"] < 60
    assert rows[0]["max_att_deg"] > 1e-10
    assert all(type(r["evals_per_interval"]) is int for r in rows)
    # three substeps of the 4th-order step: 3⁴ = 81 times smaller truncation error (± 30 %)
    assert rows[0]["max_att_deg"] / rows[2]["max_att_deg"] == pytest.approx(81, rel=0.3)


# ---------------------------------------------------------------------------- coning budget
def test_coning_budget_against_closed_form_increments():
    beta, f, rate, T = np.radians(5.0), 2.0, 100.0, 2.0
    m = coning(5.0, f, duration=T)
    out = coning_correction_budget(m, rate)
    # exact increments of ω_b = [−2W sin²(β/2), −W sin β sin Wt, W sin β cos Wt] (catalog
    # docstring; tests/strapdown/test_algorithms checks the rate itself), integrated by hand
    W, h = 2 * np.pi * f, 1 / rate
    tk = np.arange(0, round(T * rate) + 1) * h
    a, b = tk[:-1], tk[1:]
    th = np.stack([np.full(a.size, -2 * W * np.sin(beta / 2) ** 2 * h),
                   np.sin(beta) * (np.cos(W * b) - np.cos(W * a)),
                   np.sin(beta) * (np.sin(W * b) - np.sin(W * a))], -1)
    corr = np.cross(th[:-1], th[1:]) / 12
    np.testing.assert_allclose(out["sum_coning_terms_rad"], np.linalg.norm(corr.sum(0)),
                               rtol=1e-9)
    for key, kind, name in (("exact_exponential_increments_rad", "increments", "exact_exponential"),
                            ("exact_exponential_rates_rad", "rates", "exact_exponential"),
                            ("coning2_increments_rad", "increments", "coning2")):
        _, att, _, _ = _errors_by_hand(m, rate, kind, name)
        np.testing.assert_allclose(out[key], att[-1], rtol=1e-6, atol=1e-15)
    # the physics the budget is there to show: the uncorrected exponential of exact
    # increments drifts by about the accumulated coning terms (they are its leading error),
    # and the two-sample correction removes most of it
    assert out["exact_exponential_increments_rad"] == pytest.approx(
        out["sum_coning_terms_rad"], rel=0.05)
    assert out["coning2_increments_rad"] < 0.05 * out["exact_exponential_increments_rad"]


# ------------------------------------------------------------------------ round trip, table
def test_round_trip_defaults_and_errors():
    rt = round_trip(rate=50.0, duration=2.0)
    assert repr(rt.motion) == repr(figure_eight())          # the quickstart figure-eight
    assert rt.signals.kind == "increments" and rt.signals.dt == pytest.approx(0.02)
    assert rt.nav.algorithm == "poly8_m6"                   # the most accurate for increments
    _, att, vel, pos = _errors_by_hand(rt.motion, 50.0, "increments", "poly8_m6", 2.0)
    np.testing.assert_allclose(rt.errors.attitude, att, atol=1e-15)
    np.testing.assert_allclose(rt.errors.position, pos, rtol=1e-12, atol=1e-15)
    rt2 = round_trip(MOTION, 25.0, "rates", "first_order")
    _, att2, _, _ = _errors_by_hand(MOTION, 25.0, "rates", "first_order")
    assert rt2.nav.algorithm == "first_order" and rt2.signals.kind == "rates"
    np.testing.assert_allclose(rt2.errors.attitude, att2, rtol=1e-9)


def test_order_fit_skips_the_rounding_floor():
    # e = 0.3·h², h = 1/r: slope 2 exactly on the points above the floor
    rates = [10, 20, 40, 80]
    errs = [0.3 / r**2 for r in rates[:3]] + [1e-16]
    assert _order(rates, errs, 1e-13) == pytest.approx(2.0, abs=1e-12)
    assert _order(rates, errs, 1e-3) is None                 # only two points above 1e-3
    assert _order(rates[:3], [0.3 / r for r in rates[:3]], 0.0) == pytest.approx(1.0, abs=1e-12)
    assert _order(rates, [1e-3, 1e-3, 1e-3, 1e-3], 1e-3) is None   # at the floor is not above


def test_error_table_rows():
    rates = (25, 50, 100)
    rows = error_table(MOTION, rates=rates, duration=2.0)
    assert [(r["kind"], r["algorithm"]) for r in rows] == [
        (kind, name) for kind, table in ALGORITHMS.items() for name in table]
    row = next(r for r in rows if (r["kind"], r["algorithm"]) == ("rates", "first_order"))
    for rate in rates:
        _, att, _, pos = _errors_by_hand(MOTION, rate, "rates", "first_order", 2.0)
        np.testing.assert_allclose(row[f"att_{rate}"], att.max(), rtol=1e-9)
        np.testing.assert_allclose(row[f"pos_{rate}"], pos.max(), rtol=1e-12)
    assert row["order_att"] == pytest.approx(1.0, abs=0.1)
    assert row["order_pos"] == pytest.approx(1.0, abs=0.2)
    # magnus6 on rates: position errors near the rounding floor at 100 Hz are not fitted
    m6 = next(r for r in rows if (r["kind"], r["algorithm"]) == ("rates", "magnus6"))
    above = [m6[f"pos_{r}"] > FLOOR_POS for r in rates]
    assert (m6["order_pos"] is None) == (sum(above) < 3)
    assert FLOOR_ATT == 1e-13 and FLOOR_POS == 1e-10


# -------------------------------------------------------------------------- small helpers
def test_nav_errors_summary_hand_values():
    e = NavErrors(np.arange(3.0), np.array([0.1, 0.3, 0.2]), np.array([1.0, 0.5, 2.0]),
                  np.array([5.0, 4.0, 3.0]))
    assert e.summary() == {"final_attitude": 0.2, "max_attitude": 0.3,
                           "final_velocity": 2.0, "max_velocity": 2.0,
                           "final_position": 3.0, "max_position": 5.0}


def test_states_len_and_euler_against_scipy(rng):
    q = Rotation.random(5, random_state=7).as_quat(scalar_first=True)
    s = States(np.arange(5.0), np.zeros((5, 3)), np.zeros((5, 3)), q)
    assert len(s) == 5
    np.testing.assert_allclose(
        s.euler(), Rotation.from_quat(q, scalar_first=True).as_euler("ZYX"), atol=1e-12)


def test_check_time_messages():
    np.testing.assert_array_equal(check_time([0, 1, 2.5]), [0.0, 1.0, 2.5])
    assert check_time([3]).dtype == float
    with pytest.raises(ImunavError, match=r"^t must be strictly increasing; t\[2\] = 1 does not "
                                          r"exceed t\[1\] = 1$"):
        check_time([0, 1, 1, 2])
    with pytest.raises(ImunavError, match=r"^time must be strictly increasing; time\[1\] = 0\.5 "
                                          r"does not exceed time\[0\] = 2$"):
        check_time([2, 0.5, 3], "time")
    with pytest.raises(ImunavError, match="time"):
        check_time([[0, 1]], "time")


def test_nav_errors_against_states_truth_and_hand_values():
    from imunav.analysis.metrics import nav_errors

    t = np.array([0.0, 1.0])
    q = np.array([[1.0, 0, 0, 0], [np.cos(0.05), np.sin(0.05), 0, 0]])      # 0.1 rad about x
    nav = States(t, np.array([[0, 0, 0], [3.0, 4.0, 0]]), np.array([[1.0, 0, 0], [0, 0, 2.0]]),
                 q)
    truth = States(t, np.zeros((2, 3)), np.zeros((2, 3)), np.tile([1.0, 0, 0, 0], (2, 1)))
    e = nav_errors(nav, truth)
    np.testing.assert_array_equal(e.t, t)
    np.testing.assert_allclose(e.position, [0.0, 5.0], atol=0)
    np.testing.assert_allclose(e.velocity, [1.0, 2.0], atol=0)
    np.testing.assert_allclose(e.attitude, [0.0, 0.1], atol=1e-15)


def test_states_shape_checks_name_the_field():
    t = np.arange(3.0)
    good = dict(position=np.zeros((3, 3)), velocity=np.zeros((3, 3)),
                quaternion=np.tile([1.0, 0, 0, 0], (3, 1)))
    States(t, **good)
    for name, bad, want in (("position", np.zeros((3, 2)), "(3, 2)"),
                            ("velocity", np.zeros((2, 3)), "(2, 3)"),
                            ("quaternion", np.zeros((3, 3)), "(3, 3)")):
        last = 4 if name == "quaternion" else 3
        with pytest.raises(ImunavError) as e:
            States(t, **{**good, name: bad})
        assert str(e.value) == f"{name} must have shape (3, {last}) to match t, got {want}"
    with pytest.raises(ImunavError, match=r"^position must have shape \(None, 3\)"):
        States(0.0, np.zeros(3), np.zeros(3), np.array([1.0, 0, 0, 0]))
