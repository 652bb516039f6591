"""The applicability verdict on hand-built Monte Carlo results (issue 19).

Every expected number below is computed by hand from the constructed error arrays (numpy's
default linear-interpolation percentile: the p-th percentile of n sorted values sits at index
p/100·(n−1)), never by the code under test.
"""

import numpy as np
import pytest

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
    first = A.format_verdict(A.verdict(_mc(RAMP), 19.0, {}, None)).splitlines()[1].strip()
    assert first.split(":")[0] == "SUITABLE"
    first = A.format_verdict(A.verdict(_mc(RAMP), 18.5, {}, None)).splitlines()[1].strip()
    assert first.split(":")[0] == "NOT SUITABLE"
    assert "95.0 % of runs" in A.format_verdict(A.verdict(_mc(RAMP), 19.0, {}, None))


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
    assert "Warning: 2 runs hit the sensor range" in A.format_verdict(r)


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
    assert got == A.verdict(mc, 0.5, budget, 10.0, motion="m", imu="BMI088", seed=4)
