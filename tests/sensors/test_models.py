"""Sensor error models: units, Allan self-check of every preset, reproducibility, chain."""

import json

import numpy as np
import pytest

from imunav import ImunavError, Motion
from imunav.analysis.assessment import assess
from imunav.analysis.montecarlo import monte_carlo
from imunav.sensors.allan import allan_deviation
from imunav.sensors.models import ImuModel, TriadModel, apply_triad, measure
from imunav.sensors.terms import parse


@pytest.mark.parametrize("value, key, si", [
    ("0.014 deg/s/sqrt(Hz)", "gyro.noise_density", 0.014 * np.pi / 180),
    ("0.34 °/√h", "gyro.noise_density", 0.34 * np.pi / 180 / 60),
    ("150 ug/sqrt(Hz)", "accel.noise_density", 150e-6 * 9.80665),
    ("10 deg/h", "gyro.bias_instability", 10 * np.pi / 180 / 3600),
    ("2000 deg/s", "gyro.range", 2000 * np.pi / 180),
    ("16 g", "accel.range", 16 * 9.80665),
    ("150 ppm", "gyro.scale_factor", 150e-6),
    ("1 kHz", "accel.internal_rate", 1000.0),
    (0.5, "gyro.bias", 0.5),
])
def test_units(value, key, si):
    assert parse(value, key) == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize("value, key, msg", [
    ("0.014 deg/s", "gyro.noise_density", "not a unit of"),
    ("3 furlongs", "accel.bias", "not a unit of"),
    ("fast", "gyro.range", "expected '<number> <unit>'"),
    ("1 g", "gyro.wobble", "unknown error parameter"),
    (-1.0, "gyro.bias", "non-negative"),
])
def test_unit_errors(value, key, msg):
    with pytest.raises(ImunavError, match=msg):
        parse(value, key)


def test_bias_instability_floor_and_rrw_slope():
    B = parse("10 deg/h", "gyro.bias_instability")
    m = TriadModel(bias_instability=B)
    y, _ = apply_triad(m, np.zeros((72_000, 3)), "rates", 10.0, np.random.default_rng(1))
    taus, adev = allan_deviation(y, 10.0, np.logspace(0, 2.7, 12))
    floor = adev.mean(axis=1).max()
    assert floor == pytest.approx(B, rel=0.2)            # the Allan floor is the specified B
    K = parse("1 deg/h/sqrt(h)", "gyro.random_walk")
    y, _ = apply_triad(TriadModel(random_walk=K), np.zeros((72_000, 3)), "rates", 10.0,
                       np.random.default_rng(2))
    taus, adev = allan_deviation(y, 10.0, [30, 100, 300])
    slope = np.polyfit(np.log(taus), np.log(adev.mean(axis=1)), 1)[0]
    assert slope == pytest.approx(0.5, abs=0.1)           # rate random walk: +1/2
    np.testing.assert_allclose(adev.mean(axis=1), K * np.sqrt(taus / 3), rtol=0.25)


def test_reproducible_and_independent():
    model = ImuModel.load("BMI088")
    z = np.zeros((500, 3))
    a = measure(model, z, z, "rates", 100.0, np.random.default_rng(5))
    b = measure(model, z, z, "rates", 100.0, np.random.default_rng(5))
    c = measure(model, z, z, "rates", 100.0, np.random.default_rng(6))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert abs(np.corrcoef(a[0][:, 0], c[0][:, 0])[0, 1]) < 0.2


def test_quantisation_carries_residual_in_increments():
    m = TriadModel(resolution=0.01)                # rad/s step → 1e-4 rad at 100 Hz
    x = np.full((1000, 3), 0.00123)                # 0.123 rad/s, not a multiple of the step
    y, _ = apply_triad(m, x * 0.01, "increments", 100.0, np.random.default_rng(0))
    assert np.allclose(y / 1e-4, np.round(y / 1e-4))   # every output is a whole number of LSB
    assert abs(y.sum(axis=0) - x.sum(axis=0) * 0.01).max() <= 1e-4   # nothing lost overall


def test_saturation_flags():
    m = TriadModel(range=1.0)
    x = np.zeros((10, 3))
    x[3, 1] = 2.5
    y, flags = apply_triad(m, x, "rates", 100.0, np.random.default_rng(0))
    assert flags.sum() == 1 and flags[3] and y[3, 1] == 1.0


def test_internal_rate_chain_decimates():
    motion = Motion(roll="0.3*sin(2*t)", duration=2.0)
    model = ImuModel.load("ideal")
    model = ImuModel(TriadModel(internal_rate=1000.0, bandwidth=200.0), TriadModel(), "x")
    mc = monte_carlo(motion, model, 100.0, runs=2, seed=0, kind="increments", progress=False)
    assert mc.t.size == 201
    # what remains is the filter's lag: a 2nd-order Butterworth delays by √2/(2π·200 Hz) at low
    # frequency, and the sensor was at steady state (ω(0) = 0.6 rad/s) before t0, so the angle
    # error is about (ω(t) − ω(0))·delay, at most 1.2 rad/s × 1.13 ms = 1.35e-3 rad
    est = 1.2 * np.sqrt(2) / (2 * np.pi * 200.0)
    assert 0.7 * est < mc.attitude.max() < 1.05 * est


def test_imu_toml_and_bad_keys(tmp_path):
    from pathlib import Path

    m = ImuModel.from_toml(Path(__file__).parents[2] / "examples" / "my_imu.toml")
    assert "gyro.g_sensitivity" in m.terms() and m.internal_rate == 1000.0
    p = tmp_path / "bad.toml"
    p.write_text('[gyro]\nnoise = "1 deg/s"\n')
    with pytest.raises(ImunavError, match="unknown key"):
        ImuModel.from_toml(p)
    with pytest.raises(ImunavError, match="neither a preset"):
        ImuModel.load("BNO999")


WALK = Motion(x="2*sin(0.5*t)", y="t", yaw="0.3*sin(t)", roll="0.1*sin(2*t)", duration=20.0,
              name="walk")


def test_monte_carlo_ideal_is_exact_and_errors_grow():
    mc0 = monte_carlo(WALK, ImuModel.load("ideal"), 50.0, runs=3, progress=False)
    assert mc0.position.max() < 1e-11     # an ideal IMU: rounding only, measured 1.35e-12 m
    mc = monte_carlo(WALK, ImuModel.load("tactical"), 50.0, runs=20, seed=1, progress=False)
    env = mc.envelope()
    assert env[50][-1] < env[68][-1] < env[95][-1] and env[95][-1] > 0.01


def test_monte_carlo_chunking_does_not_change_results():
    a = monte_carlo(WALK, ImuModel.load("BNO055"), 50.0, runs=6, seed=4, chunk=6, progress=False)
    b = monte_carlo(WALK, ImuModel.load("BNO055"), 50.0, runs=6, seed=4, chunk=2, progress=False)
    assert np.array_equal(a.position, b.position)


def test_assess_same_verdict_twice():
    r1 = assess(WALK, ImuModel.load("tactical"), 50.0, 20, 1.0, seed=3, progress=False)
    r2 = assess(WALK, ImuModel.load("tactical"), 50.0, 20, 1.0, seed=3, progress=False)
    assert r1 == r2
    assert set(r1) >= {"fraction_within_tolerance", "time_p95_exceeds_s", "min_rate_hz",
                       "error_budget", "runs"}
    assert next(iter(r1["error_budget"])) in ("accel.bias", "gyro.bias", "accel.scale_factor",
                                              "gyro.noise_density", "accel.bias_instability",
                                              "gyro.bias_instability", "accel.noise_density",
                                              "gyro.scale_factor")


def test_cli_assess_and_simulate_imu(tmp_path, capsys):
    from imunav.cli import main
    from imunav.io import read_signals

    motion = tmp_path / "m.toml"
    motion.write_text('duration = 10\n[position]\nx = "t"\n[attitude]\nyaw = "0.2*sin(t)"\n')
    out = tmp_path / "a.json"
    args = ["assess", str(motion), "--imu", "BMI088", "--rate", "50", "--runs", "8",
            "--tolerance", "2", "--seed", "1", "--json", str(out)]
    assert main(args) == 0
    first = capsys.readouterr().out
    r1 = json.loads(out.read_text())
    assert main(args) == 0
    assert capsys.readouterr().out == first and json.loads(out.read_text()) == r1
    assert "SUITABLE" in first
    sig = tmp_path / "s.csv"
    assert main(["simulate", str(motion), "--rate", "50", "--out", str(sig), "--imu", "MPU-6050",
                 "--seed", "2"]) == 0
    s = read_signals(sig)
    assert np.abs(s.gyro).max() > 0.01                       # a 20 °/s-class bias is visible
    assert main(["assess", str(motion), "--imu", "nope", "--rate", "50", "--runs", "2",
                 "--tolerance", "1"]) == 2


def test_dask_local_cluster_matches_local():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        d = monte_carlo(WALK, ImuModel.load("BNO055"), 50.0, runs=4, seed=9, chunk=2,
                        scheduler=cluster.scheduler_address, progress=False)
    loc = monte_carlo(WALK, ImuModel.load("BNO055"), 50.0, runs=4, seed=9, progress=False)
    assert np.array_equal(d.position, loc.position)


@pytest.mark.parametrize("kind", ["rates", "increments"])
def test_error_stream_does_not_depend_on_chunking(kind, rng):
    """Every term (Gauss–Markov bank, random walk, noise, filter, quantisation carry,
    decimation) carries its state: a run fed in pieces equals the run fed at once."""
    from pathlib import Path

    from imunav.sensors.models import MeasureStream

    model = ImuModel.from_toml(Path(__file__).parents[2] / "examples" / "my_imu.toml")
    k = model.decimation(100.0)                                    # 1 kHz internal → 10
    n = 30 * k
    ideal_g = 0.01 * rng.normal(size=(n, 3)) + 0.2
    ideal_a = 0.05 * rng.normal(size=(n, 3)) + [0.0, 0.0, -9.8]
    if kind == "increments":
        ideal_g, ideal_a = ideal_g / 1000, ideal_a / 1000
    whole = measure(model, ideal_g, ideal_a, kind, 1000.0, np.random.default_rng(3), k)
    stream = MeasureStream(model, kind, 1000.0, np.random.default_rng(3), k)
    parts, i = [], 0
    for size in (k, 7 * k, 2 * k, 20 * k):
        parts.append(stream.process(ideal_g[i:i + size], ideal_a[i:i + size]))
        i += size
    for j in range(3):
        np.testing.assert_allclose(np.concatenate([p[j] for p in parts]), whole[j], rtol=1e-15,
                                   atol=1e-18)


def test_triad_model_replace_changes_only_what_is_asked():
    m = TriadModel(noise_density=2e-4, bias=1e-3, bias_correlation_time=100.0)
    r = m.replace(bias=5e-3, range=4.0)
    assert (r.bias, r.range, r.noise_density, r.bias_correlation_time) == (5e-3, 4.0, 2e-4, 100.0)
    assert m.bias == 1e-3 and m.range is None            # the original is untouched
    assert r.replace(bias=1e-3, range=None) == m
    with pytest.raises(TypeError, match="unexpected keyword"):
        m.replace(bias_drift=1.0)


# --------------------------------------------------------------------- presets and their sources
# (issue 38: presets a datasheet would recognise; a term the datasheet is silent on is not zero)

def test_the_preset_page_is_the_table_generated_from_the_preset_data():
    from pathlib import Path

    from imunav.sensors.presets import preset_table

    page = Path(__file__).parents[2] / "docs" / "presets.md"
    assert page.read_text(encoding="utf-8") == preset_table(), (
        "docs/presets.md differs from the preset data: regenerate it with preset_table()")


def test_every_preset_term_has_a_basis_a_source_and_a_value_imunav_reads():
    from imunav.sensors.presets import BASES, PRESET_SPECS, PRESETS

    assert set(PRESET_SPECS) == set(PRESETS)
    for name, p in PRESET_SPECS.items():
        assert p.document and p.grade in ("consumer", "industrial", "tactical", "ideal"), name
        for triad in ("gyro", "accel"):
            specs = getattr(p, triad)
            assert PRESETS[name][triad] == {k: s.value for k, s in specs.items()}
            for key, s in specs.items():
                assert s.basis in BASES, (name, triad, key)
                assert len(s.source) > 10, (name, triad, key)      # says where, not just "—"
                assert parse(s.value, f"{triad}.{key}") > 0, (name, triad, key)
                if s.basis == "typical":         # a characterisation of that part, named
                    assert "Allan" in s.source and name.replace("-", "") in s.source.replace(
                        "-", ""), (name, triad, key)
        model = ImuModel.load(name)
        assert set(model.terms()) >= {f"{t}.{k}" for t in ("gyro", "accel")
                                      for k in getattr(p, t) if k != "bias_correlation_time"}


def test_every_consumer_preset_has_a_bias_instability_or_its_answers_warn():
    from imunav.sensors.presets import PRESET_SPECS

    consumer = [n for n, p in PRESET_SPECS.items() if p.grade == "consumer"]
    assert {"MPU-6050", "BMI088", "BNO055"} <= set(consumer)
    for name in PRESET_SPECS:
        model = ImuModel.load(name)
        w = model.missing_term_warnings()
        lacking = [t for t in ("gyro", "accel")
                   if getattr(model, t).active() and not getattr(model, t).bias_instability]
        if name in consumer:
            assert not lacking or (len(w) == 1 and "bias instability" in w[0]), name
        # the warning exactly when a triad lacks it, naming that triad's key
        assert bool(w) == bool(lacking), name
        for t in lacking:
            assert f"{t}.bias_instability" in w[0], (name, t)
    # the MPU-6050's gyro carries the published value; its accelerometer has none, and says so
    mpu = ImuModel.load("MPU-6050")
    assert mpu.gyro.bias_instability == pytest.approx(0.0012 * np.pi / 180, rel=1e-12)
    assert "accelerometer has no bias instability" in mpu.missing_term_warnings()[0]
    # no warning for a triad without errors, nor for one with only a range
    assert ImuModel(TriadModel(range=30.0), TriadModel()).missing_term_warnings() == []


def test_an_imu_toml_with_bias_instability_parses(tmp_path):
    p = tmp_path / "imu.toml"
    p.write_text('[gyro]\nnoise_density = "0.005 deg/s/sqrt(Hz)"\nbias = "20 deg/s"\n'
                 'bias_instability = "4.3 deg/h"\nbias_correlation_time = "100 s"\n'
                 '[accel]\nbias = "50 mg"\n')
    m = ImuModel.from_toml(p)
    assert m.gyro.bias_instability == pytest.approx(4.3 * np.pi / 180 / 3600, rel=1e-12)
    assert m.gyro.bias_correlation_time == 100.0
    assert "gyro.bias_instability" in m.terms()
    (w,) = m.missing_term_warnings()
    assert "imu: the accelerometer has no bias instability" in w and "gyro" not in w.split(";")[0]


def test_an_assessment_without_bias_instability_says_so():
    model = ImuModel(TriadModel(bias=1e-3), TriadModel(noise_density=1e-3), "toy")
    for method, runs in (("covariance", None), ("montecarlo", 4)):
        r = assess(WALK, model, 50.0, runs, 1.0, seed=1, progress=False, method=method)
        assert sum("bias instability" in w for w in r["warnings"]) == 1, (method, r["warnings"])
    r = assess(WALK, ImuModel.load("tactical"), 50.0, None, 1.0, progress=False)
    assert not any("bias instability" in w for w in r["warnings"])
