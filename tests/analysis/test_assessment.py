"""The applicability verdict on hand-built Monte Carlo results (issue 19).

Every expected number below is computed by hand from the constructed error arrays (numpy's
default linear-interpolation percentile: the p-th percentile of n sorted values sits at index
p/100·(n−1)), never by the code under test.
"""

from pathlib import Path

import numpy as np
import pytest

from imunav import ImunavError
from imunav.analysis import assessment as A
from imunav.analysis.montecarlo import MonteCarloResult
from imunav.motion import Motion


def _mc(position, rate=1.0, saturated=None):
    position = np.asarray(position, float)
    runs, n = position.shape
    sat = np.zeros(runs, int) if saturated is None else np.asarray(saturated)
    return MonteCarloResult(np.arange(n) / rate, position, position / 10, position / 100, sat,
                            "hand", rate, "increments")


# 20 runs whose error grows linearly in time to finals 1, 2, …, 20 (t = 0..4 s).
RAMP = [[(r + 1) * k / 4 for k in range(5)] for r in range(20)]


def test_fraction_within_and_the_95_percent_boundary():
    # 19 of 20 runs stay within 19 m (95 %: SUITABLE); within 18.5 m only 18 (90 %: NOT)
    r = A.verdict(_mc(RAMP), 19.0, {}, None)
    assert r["fraction_within_tolerance"] == 0.95 and r["suitable"] is True
    r = A.verdict(_mc(RAMP), 18.5, {}, None)
    assert r["fraction_within_tolerance"] == 0.9 and r["suitable"] is False


def test_verdict_line_says_exactly_suitable_or_not():
    # 100 runs all within: the Clopper–Pearson interval (96.4–100 %) clears 95 %
    ramp100 = [[(r + 1) * k / 4 for k in range(5)] for r in range(100)]
    first = A.format_verdict(A.verdict(_mc(ramp100), 100.0, {}, None)).splitlines()[1].strip()
    assert first.split(":")[0] == "SUITABLE"
    first = A.format_verdict(A.verdict(_mc(RAMP), 18.5, {}, None)).splitlines()[1].strip()
    assert first.split(":")[0] == "NOT SUITABLE"
    # 19 of 20 within: 95 % as a point estimate, but 20 runs put it anywhere in 75–99.9 %
    text = A.format_verdict(A.verdict(_mc(RAMP), 19.0, {}, None))
    assert text.splitlines()[1].strip().split(":")[0] == "UNDECIDED"
    assert "95.0 % of runs" in text and "run more" in text


def test_within_tolerance_means_the_maximum_not_the_final_error():
    # errors that peak at t = 1 s (run r reaches r + 1 m) and settle back to 0.5 m
    peak = [[0.0, r + 1.0, 0.5, 0.5, 0.5] for r in range(20)]
    r = A.verdict(_mc(peak), 1.0, {}, None)
    assert r["fraction_within_tolerance"] == pytest.approx(1 / 20)   # only run 0 never exceeds


def test_envelope_is_the_95th_percentile_and_its_crossing_time():
    # the 95th percentile of 1..20 is at index 0.95·19 = 18.05: 19 + 0.05 = 19.05
    r = A.verdict(_mc(RAMP), 9.3, {}, None)
    assert r["final_p95_position_m"] == pytest.approx(19.05, rel=1e-12)
    # the envelope at t = 2 s is 19.05·2/4 = 9.525 > 9.3 (a 90th percentile, 9.05, would not be)
    assert r["time_p95_exceeds_s"] == 2.0
    assert A.verdict(_mc(RAMP), 100.0, {}, None)["time_p95_exceeds_s"] is None


def test_error_budget_is_each_terms_95th_percentile_sorted():
    budget = {"gyro.bias": _mc(RAMP), "accel.bias": _mc(np.array(RAMP) / 2),
              "gyro.noise_density": _mc(np.array(RAMP) * 4)}
    r = A.verdict(_mc(RAMP), 1.0, budget, None)
    assert list(r["error_budget"]) == ["gyro.noise_density", "gyro.bias", "accel.bias"]
    assert r["error_budget"]["gyro.bias"] == pytest.approx(19.05)       # the mean would be 10.5
    assert r["error_budget"]["accel.bias"] == pytest.approx(9.525)
    text = A.format_verdict(r)
    assert "Dominant error: gyro.noise_density (76.2 m alone, 95th pct)" in text


def test_minimum_rate_needs_a_tenth_of_the_tolerance(monkeypatch):
    # sampling error 1/r² m: a tenth of 1 mm needs r ≥ 100 Hz (the whole tolerance: 50 Hz)
    monkeypatch.setattr(A, "sampling_error", lambda m, r, d, o: 1.0 / r**2)
    m = Motion(x="t", duration=20.0)
    assert A.min_sample_rate(m, 1e-3) == 100.0
    assert A.min_sample_rate(m, 1e-9) is None                 # not even 5 kHz
    text = A.format_verdict(A.verdict(_mc(RAMP), 1.0, {}, None))
    assert "no tested rate (≤ 5 kHz)" in text


def test_short_motions_skip_rates_with_too_few_samples(monkeypatch):
    seen = []
    monkeypatch.setattr(A, "sampling_error", lambda m, r, d, o: seen.append(r) or 0.0)
    A.min_sample_rate(Motion(x="t", duration=1.0), 1.0)
    assert seen == [10]                                        # 1, 2, 5 Hz give < 10 samples


def test_saturated_runs_counted_and_warned():
    r = A.verdict(_mc(RAMP[:4], saturated=[0, 3, 0, 1]), 100.0, {}, None)
    assert r["saturated_runs"] == 2
    assert "warning: 2 runs hit the sensor range" in A.format_verdict(r)


def test_assess_is_the_verdict_of_its_monte_carlo(monkeypatch):
    """The pipeline hands the verdict the Monte Carlo of all terms and of each term alone."""
    from imunav import ImuModel
    from imunav.analysis.montecarlo import monte_carlo

    m = Motion(x="t", yaw="0.1*sin(t)", duration=5.0, name="m")
    model = ImuModel.load("BMI088")
    monkeypatch.setattr(A, "min_sample_rate", lambda *a, **k: 10.0)
    got = A.assess(m, model, 20.0, 6, 0.5, seed=4, progress=False)
    mc = monte_carlo(m, model, 20.0, runs=6, seed=4, progress=False)
    budget = {t: monte_carlo(m, model.only(t), 20.0, runs=6, seed=4, progress=False)
              for t in model.terms()}
    expected = A.verdict(mc, 0.5, budget, 10.0, motion="m", imu="BMI088", seed=4)
    # and the warning of a model without an accelerometer bias instability (issue 38)
    expected["warnings"] += model.missing_term_warnings()
    assert got == expected and len(model.missing_term_warnings()) == 1


def test_verdict_record_in_full():
    """Every key of the record ``imunav assess --json`` writes, with the thinned envelope: 401
    output times become the 201 even ones; each point the 95th percentile over runs (by numpy
    here, from the hand-built ramps)."""
    n = 401
    pos = [[(r + 1) * k / (n - 1) for k in range(n)] for r in range(20)]
    mc = _mc(pos, rate=2.0)
    r = A.verdict(mc, 30.0, {}, None)
    # 20 runs all within: the Clopper–Pearson interval is [0.025^(1/20), 1] ∋ 95 % — warned
    lo = 0.025 ** (1 / 20)
    assert r == {**r, "motion": "motion", "imu": "imu", "seed": 0, "rate_hz": 2.0,
                 "tolerance_m": 30.0, "runs": 20, "method": "montecarlo",
                 "warnings": [f"20 runs cannot support a 95 % verdict: the fraction of runs "
                              f"within 30 m is between {100 * lo:.1f} % and 100.0 % (95 % "
                              "confidence, Clopper–Pearson); at least 72 runs are needed, more "
                              "when some exceed"],
                 "min_rate_hz": None, "saturated_runs": 0, "error_budget": {},
                 "time_p95_exceeds_s": None, "suitable": True, "conclusive": False,
                 "fraction_within_tolerance": 1.0}
    assert r["fraction_ci95"] == pytest.approx([lo, 1.0], rel=1e-12)
    assert set(r) == {"motion", "imu", "rate_hz", "tolerance_m", "runs", "seed",
                      "fraction_within_tolerance", "fraction_ci95", "suitable", "conclusive",
                      "time_p95_exceeds_s", "final_p95_position_m", "error_budget",
                      "min_rate_hz", "saturated_runs", "method", "warnings", "envelope"}
    env = r["envelope"]
    assert set(env) == {"t", "position_p95_m", "attitude_p95_rad"}
    k = np.arange(0, n, 2)
    np.testing.assert_allclose(env["t"], k / 2.0, rtol=0, atol=0)
    np.testing.assert_allclose(env["position_p95_m"], 19.05 * k / (n - 1), rtol=1e-12)
    np.testing.assert_allclose(env["attitude_p95_rad"], 0.1905 * k / (n - 1), rtol=1e-12)
    r = A.verdict(mc, 30.0, {}, 50.0, motion="walk", imu="cheap", seed=7)
    assert (r["motion"], r["imu"], r["seed"], r["min_rate_hz"]) == ("walk", "cheap", 7, 50.0)
    with pytest.raises(ImunavError, match="^tolerance must be"):
        A.verdict(mc, 0.0, {}, None)


def test_crossing_means_strictly_above_the_tolerance():
    # at t = 2 s the envelope equals the tolerance: not yet exceeded; at t = 3 s it is
    at2 = float(np.percentile([(r + 1) * 2 / 4 for r in range(20)], 95))
    assert A.verdict(_mc(RAMP), at2, {}, None)["time_p95_exceeds_s"] == 3.0


def _record(**kw):
    r = {"motion": "walk", "imu": "cheap", "rate_hz": 100.0, "tolerance_m": 2.5, "runs": 500,
         "seed": 3, "fraction_within_tolerance": 0.962, "suitable": True,
         "time_p95_exceeds_s": None, "final_p95_position_m": 1.234,
         "error_budget": {"accel.bias": 1.1, "gyro.noise_density": 0.25, "accel.resolution": 1e-12},
         "min_rate_hz": 50.0, "saturated_runs": 0, "method": "montecarlo", "warnings": []}
    r.update(kw)
    return r


def test_format_verdict_hand_written():
    assert A.format_verdict(_record()).split("\n") == [
        "IMU cheap on motion walk at 100 Hz, 500 runs (seed 3), tolerance 2.5 m:",
        "  SUITABLE: 96.2 % of runs stay within 2.5 m over the whole motion (needed: 95 %).",
        "  The 95th percentile of the position error never exceeds the tolerance (final 1.23 m).",
        "  Dominant error: accel.bias (1.1 m alone, 95th pct).",
        "  Error budget (each term alone, final 95th-percentile position error):",
        "    accel.bias                          1.1 m",
        "    gyro.noise_density                 0.25 m",
        "    accel.resolution                 < 1e-9 m",
        "  Sampling alone stays below 0.1 × the tolerance from 50 Hz.",
    ]
    text = A.format_verdict(_record(
        fraction_within_tolerance=0.5, suitable=False, time_p95_exceeds_s=12.345,
        error_budget={}, min_rate_hz=None, saturated_runs=4, warnings=["filter lag 3 m"]))
    assert text.split("\n")[1:] == [
        "  NOT SUITABLE: 50.0 % of runs stay within 2.5 m over the whole motion (needed: 95 %).",
        "  The 95th percentile crosses 2.5 m at t = 12.35 s (final 1.23 m).",
        "  Sampling alone stays below 0.1 × the tolerance from no tested rate (≤ 5 kHz).",
        "  warning: 4 runs hit the sensor range (clipped).",
        "  warning: filter lag 3 m.",
    ]
    # without a "suitable" key the fraction decides (95 % needed)
    r = _record(fraction_within_tolerance=0.949)
    del r["suitable"]
    assert A.format_verdict(r).split("\n")[1].startswith("  NOT SUITABLE: 94.9 %")


def test_format_verdict_covariance_hand_written():
    r = _record(method="covariance", runs=None, seed=None, fraction_within_tolerance=0.97)
    assert A.format_verdict(r).split("\n")[:2] == [
        "IMU cheap on motion walk at 100 Hz, covariance analysis, tolerance 2.5 m:",
        "  SUITABLE: P(position error ≤ 2.5 m) is at least 97.0 % at every time (needed: 95 %).",
    ]
    r = _record(method="covariance", runs=None, seed=None, fraction_within_tolerance=0.4,
                suitable=False)
    assert A.format_verdict(r).split("\n")[1] == (
        "  NOT SUITABLE: P(position error ≤ 2.5 m) drops to 40.0 % (needed: 95 % at every time).")


def test_assess_passes_every_setting_through(monkeypatch):
    """What ``assess`` asks of the Monte Carlo and of the rate search: the duration, signal kind,
    seed, scheduler and progress of the call (recorded, then run for real without the
    scheduler), the budget run count min(runs, 200), and the motion's name."""
    from imunav import ImuModel
    from imunav.analysis.montecarlo import monte_carlo
    from imunav.sensors.models import TriadModel

    calls, rates = [], []

    def recording_mc(motion, model, rate, duration, runs, seed, output, *, scheduler, progress,
                     vertical):
        assert vertical == "free"                         # the flat frame's (no height aid)
        calls.append((model.name, duration, runs, seed, output, scheduler, progress))
        return monte_carlo(motion, model, rate, duration, runs, seed, output, progress=False)

    monkeypatch.setattr(A, "monte_carlo", recording_mc)
    monkeypatch.setattr(A, "min_sample_rate", lambda *a: rates.append(a) or 40.0)
    m = Motion(x="t", yaw="0.1*sin(t)", duration=5.0, name="m")
    model = ImuModel(TriadModel(noise_density=1e-3), TriadModel(bias=1e-2), "two")
    got = A.assess(m, model, 20.0, 201, 0.5, duration=0.5, kind="rates", scheduler="tcp://x:1")
    assert calls[0] == ("two", 0.5, 201, 0, "rates", "tcp://x:1", True)
    assert len(calls) == 1 + len(model.terms())
    assert all(c[1:] == (0.5, 200, 0, "rates", "tcp://x:1", False) for c in calls[1:])
    assert rates == [(m, 0.5, 0.5, "rates")]
    assert (got["motion"], got["imu"], got["seed"], got["runs"]) == ("m", "two", 0, 201)
    calls.clear()
    A.assess(m, model, 20.0, 3, 0.5, seed=9, duration=0.5, budget_runs=2, progress=False)
    assert calls[0][1:] == (0.5, 3, 9, "increments", None, False)
    assert calls[1][2] == 2
    with pytest.raises(ImunavError, match="^tolerance must be"):
        A.assess(m, model, 20.0, 3, -0.5)


def _cov_result(sigma_p, sigma_a, t, terms_share, warnings=()):
    """A covariance result with isotropic position and attitude blocks σ²·I (per time)."""
    from imunav.analysis.covariance import CovarianceResult

    def blocks(sp, sa):
        P = np.zeros((t.size, 9, 9))
        P[:, 0:3, 0:3] = np.eye(3) * (sa ** 2)[:, None, None]
        P[:, 6:9, 6:9] = np.eye(3) * (sp ** 2)[:, None, None]
        return P

    terms = {k: blocks(np.sqrt(s) * sigma_p, np.sqrt(s) * sigma_a) for k, s in terms_share.items()}
    return CovarianceResult(t, terms, blocks(sigma_p, sigma_a), 2.0, "hand", 1.0, 9.8,
                            list(warnings))


def test_verdict_covariance_record_in_full():
    """The covariance verdict on hand-built isotropic covariances: the norm of an isotropic
    3-D Gaussian is σ·χ₃, so every percentile and probability below comes from scipy's χ
    distribution, not from imunav's norm quantiles."""
    from scipy import stats

    chi3 = stats.chi(3)
    t = np.arange(11) * 0.5
    sp, sa = 0.1 + t, 0.01 * t
    # shares chosen so that value order (big first) differs from name order
    cov = _cov_result(sp, sa, t, {"a.small": 0.36, "b.big": 0.64}, warnings=["w1"])
    c95 = chi3.ppf(0.95)
    tol = c95 * (sp[4] + sp[5]) / 2          # the 95th percentile passes it between t = 2, 2.5
    r = A.verdict_covariance(cov, tol, 25.0)
    assert r["time_p95_exceeds_s"] == 2.5
    assert r["fraction_within_tolerance"] == pytest.approx(chi3.cdf(tol / sp[-1]), rel=1e-9)
    assert r["suitable"] is False
    assert r["final_p95_position_m"] == pytest.approx(c95 * sp[-1], rel=1e-9)
    assert list(r["error_budget"]) == ["b.big", "a.small"]
    assert r["error_budget"]["b.big"] == pytest.approx(0.8 * c95 * sp[-1], rel=1e-9)
    assert r["error_budget"]["a.small"] == pytest.approx(0.6 * c95 * sp[-1], rel=1e-9)
    assert {k: r[k] for k in ("motion", "imu", "rate_hz", "tolerance_m", "method", "runs", "seed",
                              "min_rate_hz", "saturated_runs", "warnings")} == {
        "motion": "motion", "imu": "imu", "rate_hz": 2.0, "tolerance_m": tol,
        "method": "covariance", "runs": None, "seed": None, "min_rate_hz": 25.0,
        "saturated_runs": 0, "warnings": ["w1"]}
    assert set(r) == set(A.verdict(_mc(RAMP), 1.0, {}, None))      # the same keys as Monte Carlo
    env = r["envelope"]
    np.testing.assert_array_equal(env["t"], t)
    np.testing.assert_allclose(env["position_p95_m"], c95 * sp, rtol=1e-9)
    np.testing.assert_allclose(env["attitude_p95_rad"], c95 * sa, rtol=1e-9, atol=1e-15)
    # within the tolerance everywhere: suitable, never crossed; names passed through
    r = A.verdict_covariance(cov, 10 * c95 * sp[-1], None, motion="walk", imu="cheap")
    assert r["suitable"] is True and r["time_p95_exceeds_s"] is None
    assert (r["motion"], r["imu"]) == ("walk", "cheap")
    with pytest.raises(ImunavError, match="^tolerance must be"):
        A.verdict_covariance(cov, -1.0, None)


def test_deterministic_error_runs_only_filter_and_range(monkeypatch):
    """One noise-free run of the filter and range alone, for the duration and signals asked;
    none where neither can act on the motion."""
    from imunav import ImuModel
    from imunav.analysis.montecarlo import monte_carlo
    from imunav.sensors.models import TriadModel

    seen = []
    run_errors = A.run_errors

    def recording(motion, rate, duration, output, imu):
        seen.append((imu, duration, output))
        return run_errors(motion, rate, duration, output, imu=imu)

    monkeypatch.setattr(A, "run_errors", recording)
    m = Motion(x="0.5*sin(3*t)", yaw="0.4*sin(2*t)", duration=4.0, name="m")
    model = ImuModel(TriadModel(noise_density=1e-3, bias=1e-3, range=0.5, bandwidth=5.0,
                                internal_rate=400.0),
                     TriadModel(noise_density=1e-3, range=30.0, bandwidth=8.0,
                                internal_rate=400.0), "cheap")
    out = A.deterministic_error(m, model, 50.0, 2.0, "rates")
    (det, duration, output), = seen
    assert (duration, output) == (2.0, "rates")
    assert det.name == "cheap:deterministic"
    assert det.gyro == TriadModel(range=0.5, bandwidth=5.0, internal_rate=400.0)
    assert det.accel == TriadModel(range=30.0, bandwidth=8.0, internal_rate=400.0)
    assert out[0] > 0 and out[1] > 0
    # the streamed run is the one-run Monte Carlo of the same model (an independent path)
    mc = monte_carlo(m, det, 50.0, 2.0, runs=1, kind="rates", progress=False)
    assert out == pytest.approx((mc.position.max(), mc.attitude.max()), rel=1e-9)
    seen.clear()
    A.deterministic_error(m, model, 50.0)
    assert seen[0][1:] == (None, "increments")
    assert A.deterministic_error(m, ImuModel(TriadModel(bias=1.0), TriadModel(), "b"), 50.0) is None
    # a range alone, the motion far inside it (peaks given): no run, nothing to measure
    seen.clear()
    ranged = ImuModel(TriadModel(range=10.0), TriadModel(range=200.0), "r")
    assert A.deterministic_error(m, ranged, 50.0, peaks=(4.9, 99.0)) is None and not seen
    assert A.deterministic_error(m, ranged, 50.0, peaks=(5.1, 99.0)) is not None and seen


def test_monte_carlo_envelope_is_over_runs_at_each_time():
    # 20 runs × 5 times: the percentiles go across runs (axis 0), one value per time
    mc = _mc(RAMP)
    env = mc.envelope()
    assert sorted(env) == [50, 68, 95]
    np.testing.assert_allclose(env[95], [19.05 * k / 4 for k in range(5)], rtol=1e-12)
    np.testing.assert_allclose(env[50], [10.5 * k / 4 for k in range(5)], rtol=1e-12)
    att = mc.envelope("attitude", q=(95,))
    np.testing.assert_allclose(att[95], [0.1905 * k / 4 for k in range(5)], rtol=1e-12)


def test_assess_covariance_passes_every_setting_through(monkeypatch):
    from imunav import ImuModel
    from imunav.analysis.covariance import covariance_summary
    from imunav.sensors.models import TriadModel

    seen = {}

    def rec_cov(motion, imu, rate, duration, *, kind, tolerance, level, progress, vertical):
        assert vertical == "free"                         # the flat frame's
        seen["cov"] = (duration, kind, tolerance, level)
        return covariance_summary(motion, imu, rate, duration, kind=kind,
                                  tolerance=tolerance, level=level, progress=progress)

    monkeypatch.setattr(A, "covariance_summary", rec_cov)
    monkeypatch.setattr(A, "min_sample_rate", lambda *a: seen.setdefault("rate", a) and 40.0)
    monkeypatch.setattr(A, "deterministic_error",
                        lambda *a, peaks: seen.setdefault("det", a) and (0.05, 0.01))
    m = Motion(x="t", yaw="0.1*sin(t)", duration=5.0, name="m")
    model = ImuModel(TriadModel(noise_density=1e-3), TriadModel(bias=1e-2), "two")
    r = A.assess_covariance(m, model, 20.0, 0.4, duration=2.0, kind="rates")
    assert seen["cov"] == (2.0, "rates", 0.4, 0.95)
    assert seen["rate"] == (m, 0.4, 2.0, "rates")
    assert seen["det"] == (m, model, 20.0, 2.0, "rates")
    assert (r["motion"], r["imu"], r["min_rate_hz"]) == ("m", "two", 40.0)
    assert r["deterministic_position_m"] == 0.05
    # 0.05 m > a tenth of 0.4 m: warned, with the position (not the attitude) error
    assert r["warnings"][-1].startswith("the filter and range alone, without noise, give a "
                                        "0.05 m position error")
    assert r["warnings"][-1].endswith("Check with --method montecarlo")
    # exactly a tenth of 0.5 m (0.1 × 0.5 = 0.05 in binary too) is not over it
    r = A.assess_covariance(m, model, 20.0, 0.5, duration=2.0, kind="rates")
    assert not any("filter and range" in w for w in r["warnings"])
    with pytest.raises(ImunavError, match="^tolerance must be"):
        A.assess_covariance(m, model, 20.0, -0.5)


def test_sampling_error_and_minimum_rate_for_the_duration_and_signals_asked():
    from imunav import navigate, simulate_imu

    m = Motion(x="3*sin(2*t)", yaw="0.8*sin(1.5*t)", duration=8.0, name="m")
    for kind, algo in (("rates", "magnus6"), ("increments", "poly8_m6")):
        sig = simulate_imu(m, 10.0, 3.0, kind=kind)
        nav = navigate(sig, m.attitude([0.0])[0], m.velocity([0.0])[0], m.position([0.0])[0])
        assert nav.algorithm == algo and nav.t[-1] == pytest.approx(3.0)
        want = np.linalg.norm(nav.position - m.position(nav.t), axis=-1).max()
        assert A.sampling_error(m, 10.0, 3.0, kind) == pytest.approx(want, rel=1e-12)
    assert A.sampling_error(m, 10.0, 3.0) == A.sampling_error(m, 10.0, 3.0, "increments")
    # the minimum rate is the first candidate whose sampling error is within a tenth of the
    # tolerance, for the duration and signals asked; a run needs 10 samples at least
    tol = 10 * A.sampling_error(m, 20.0, 3.0, "rates")
    assert A.sampling_error(m, 10.0, 3.0, "rates") > tol / 10
    assert A.min_sample_rate(m, tol, 3.0, "rates", candidates=(2, 5, 10, 20, 50)) == 20.0
    assert A.min_sample_rate(m, tol, 3.0, "rates", candidates=(2, 3)) is None   # < 10 samples
    assert A.min_sample_rate(m, 1e-30, 3.0, "rates", candidates=(20,)) is None
    # no duration anywhere: no rate can be judged (not an error)
    assert A.min_sample_rate(Motion(x="t"), 1.0, candidates=(20,)) is None


# ------------------------------------------------------------------------ issue 25, round 2


def test_few_runs_give_a_verdict_with_its_caveat():
    """7. `assess --runs 1` said "SUITABLE: 100.0 % of runs" with no warning that one run cannot
    support a 95 % verdict. The interval is scipy's exact (Clopper–Pearson) binomial one."""
    from scipy.stats import binomtest

    from imunav import ImuModel

    m = Motion(x="t", yaw="0.1*sin(t)", duration=2.0, name="m")
    r = A.assess(m, ImuModel.load("tactical"), 20.0, 1, 100.0, progress=False)
    assert r["suitable"] is True and r["fraction_within_tolerance"] == 1.0
    ci = binomtest(1, 1).proportion_ci(0.95, method="exact")
    assert r["fraction_ci95"] == pytest.approx([ci.low, ci.high], rel=1e-9)
    assert r["warnings"][0].startswith("1 run cannot support a 95 % verdict: the fraction of "
                                       "runs within 100 m is between 2.5 % and 100.0 %")
    assert "  warning: 1 run cannot support a 95 % verdict" in A.format_verdict(r)
    # 72 runs all within clear 95 %; 1000 runs at 92.4 % are clearly below: no caveat
    for inside, runs in ((72, 72), (924, 1000)):
        ci = binomtest(inside, runs).proportion_ci(0.95, method="exact")
        assert A.runs_interval(inside, runs) == pytest.approx((ci.low, ci.high), rel=1e-9)
        assert not (ci.low < 0.95 <= ci.high)
    assert A.MIN_RUNS == 72 and 0.95 ** 71 > 0.025 >= 0.95 ** 72


def test_python_assess_offers_both_methods_as_the_command_line():
    """12. The Python assess() ran Monte Carlo only while the CLI defaults to covariance."""
    from imunav import ImuModel

    m = Motion(x="t", yaw="0.1*sin(t)", duration=2.0, name="m")
    model = ImuModel.load("BMI088")
    r = A.assess(m, model, 20.0, tolerance=1.0)
    assert r["method"] == "covariance" and r == A.assess_covariance(m, model, 20.0, 1.0)
    assert A.assess(m, model, 20.0, 3, 1.0, progress=False)["method"] == "montecarlo"
    assert A.assess(m, model, 20.0, 3, 1.0, method="montecarlo", progress=False)["runs"] == 3
    with pytest.raises(ImunavError, match="^runs applies to the Monte Carlo method only"):
        A.assess(m, model, 20.0, 3, 1.0, method="covariance")
    with pytest.raises(ImunavError, match="^runs is required for the Monte Carlo method"):
        A.assess(m, model, 20.0, tolerance=1.0, method="montecarlo")
    with pytest.raises(ImunavError, match="^method must be one of covariance, montecarlo"):
        A.assess(m, model, 20.0, tolerance=1.0, method="exact")


def test_no_suitable_from_a_covariance_outside_its_linear_range():
    """issue 37: a gyro bias of 2 °/s on a 60 s still motion turns the attitude by radians; the
    covariance's own check (p95 attitude beyond LINEAR_LIMIT) fails, so its verdict is not
    SUITABLE whatever its numbers say, and method="auto" answers with a Monte Carlo."""
    from imunav import Motion, assess
    from imunav.analysis.covariance import LINEAR_LIMIT
    from imunav.sensors.models import ImuModel

    m = Motion(duration=60.0)
    imu = ImuModel.from_dict({"gyro": {"bias": "2 deg/s"}})
    r = assess(m, imu, 20.0, tolerance=1e9, progress=False)
    assert r["max_p95_attitude_rad"] > LINEAR_LIMIT and not r["linear"]
    assert r["suitable"] is False and r["outside_linearisation"]
    a = assess(m, imu, 20.0, 10, tolerance=1e9, method="auto", progress=False)
    assert a["method_chosen"] == "montecarlo" and a["runs"] == 10
    assert "linear range" in a["warnings"][0]
    ok = assess(m, ImuModel.from_dict({"gyro": {"bias": "0.01 deg/s"}}), 20.0, tolerance=1e9,
                method="auto", progress=False)
    assert ok["method_chosen"] == "covariance" and ok["linear"] and ok["suitable"]


def test_covariance_verdict_counts_the_sampling_a_perfect_sensor_suffers():
    """The covariance models the sensor's noise, not the algorithm's sampling error: a perfect
    IMU on the figure-eight at 0.5 Hz has hundreds of metres of error (against the analytic
    motion), and the verdict must not say SUITABLE at "0 m" (a user's report)."""
    from imunav import ImuModel
    from imunav.io.files import load_motion

    m = load_motion(Path(__file__).resolve().parents[2] / "examples" / "figure_eight.toml")[0]
    r = A.assess_covariance(m, ImuModel.load("ideal"), 0.5, 5.0, progress=False)
    assert r["suitable"] is False and r["sampling_exceeds"] is True
    assert r["sampling_position_m"] > 50.0                     # measured 518 m
    assert A.format_verdict(r).splitlines()[1].startswith("  NOT SUITABLE: at 0.5 Hz the sampling")
    r = A.assess_covariance(m, ImuModel.load("ideal"), 100.0, 5.0, progress=False)
    assert r["suitable"] is True and "sampling_position_m" not in r
