"""Issue 18 faces: assess --method covariance, the inverse design command, and IMU models
fitted from a static log's Allan deviation."""

import json

import numpy as np
import pytest
from scipy import stats

from imunav import Motion
from imunav.analysis.assessment import assess_covariance
from imunav.analysis.covariance import covariance
from imunav.analysis.design import design
from imunav.cli import main
from imunav.core.constants import G0
from imunav.sensors.allan import fit_allan
from imunav.sensors.models import ImuModel, TriadModel, TriadStream
from imunav.sensors.presets import PRESETS

T = 20.0
STILL = Motion(duration=T, name="still")
STILL_TOML = f"duration = {T}\n"


@pytest.fixture
def still(tmp_path):
    p = tmp_path / "still.toml"
    p.write_text(STILL_TOML)
    return p


# ----------------------------------------------------------------------------- design


def test_design_limits_match_closed_forms():
    b0, n0, tol = 1e-3, 1e-4, 2.0
    base = ImuModel(TriadModel(noise_density=n0), TriadModel(bias=b0), "base")
    r = design(STILL, base, 50.0, tol)
    # accel bias b: each axis b·t²/2 → |δp| = (b t²/2)·χ₃, largest at the end
    want_b = tol / (T * T / 2 * stats.chi(3).ppf(0.95))
    assert r["terms"]["accel.bias"]["limit_si"] == pytest.approx(want_b, rel=1e-9)
    # gyro white noise N: horizontal only, each axis g·N·√(t⁵/20) → |δp| = σ·χ₂
    want_n = tol / (G0 * np.sqrt(T ** 5 / 20) * stats.chi(2).ppf(0.95))
    assert r["terms"]["gyro.noise_density"]["limit_si"] == pytest.approx(want_n, rel=1e-9)
    assert r["terms"]["accel.bias"]["limit"].endswith(" mg")
    assert float(r["terms"]["accel.bias"]["limit"].split()[0]) == pytest.approx(
        want_b / (1e-3 * G0), rel=2e-3)                          # printed to 3 digits


def _scaled(model: ImuModel, s: float) -> ImuModel:
    def tri(m: TriadModel) -> TriadModel:
        keep = {"range", "bandwidth", "internal_rate", "bias_correlation_time"}
        return TriadModel(**{k: (v * s if k not in keep and v else v)
                             for k, v in m.values().items()})
    return ImuModel(tri(model.gyro), tri(model.accel), f"{model.name}×{s:g}")


def test_common_scale_is_the_largest_that_meets_the_tolerance():
    from imunav.motion.catalog import figure_eight
    motion, tol = figure_eight(), 3.0
    base = ImuModel.load("ADIS16470")
    r = design(motion, base, 50.0, tol)
    s = r["common_scale"]
    # scale every datasheet value by s and assess independently: the worst p95 is the tolerance
    cov = covariance(motion, _scaled(base, s), 50.0)
    assert cov.max_position_quantile(0.95) == pytest.approx(tol, rel=1e-7)
    assert covariance(motion, _scaled(base, 1.01 * s), 50.0).max_position_quantile() > tol
    # presets: best first, each flag the covariance verdict for that preset
    finals = [p["final_p95_position_m"] for p in r["presets"]]
    assert finals == sorted(finals) and {p["name"] for p in r["presets"]} == set(PRESETS)
    for p in r["presets"]:
        v = assess_covariance(motion, ImuModel.load(p["name"]), 50.0, tol)
        assert p["suitable"] == v["suitable"], p["name"]


def test_cli_design_json(tmp_path, still, capsys):
    out = tmp_path / "d.json"
    assert main(["design", str(still), "--imu", "BMI088", "--rate", "50", "--tolerance", "5",
                 "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Largest value of each term" in text and "Presets, best first" in text
    d = json.loads(out.read_text())
    assert set(d) >= {"terms", "common_scale", "min_rate_hz", "presets"}
    assert set(d["terms"]["gyro.noise_density"]) >= {"limit_si", "limit"}
    assert all(set(p) >= {"name", "final_p95_position_m", "suitable"} for p in d["presets"])


# ----------------------------------------------------------------------------- assess


def test_cli_assess_methods(tmp_path, still, capsys):
    out = tmp_path / "a.json"
    base = ["assess", str(still), "--imu", "tactical", "--rate", "50", "--tolerance", "1"]
    assert main(base + ["--json", str(out)]) == 0                 # covariance by default
    text = capsys.readouterr().out
    assert "covariance analysis" in text and "Error budget" in text
    d = json.loads(out.read_text())
    assert d["method"] == "covariance"
    env = d["envelope"]
    assert len(env["t"]) == len(env["position_p95_m"]) == len(env["attitude_p95_rad"]) > 100
    assert env["t"][-1] == pytest.approx(T)
    assert env["position_p95_m"][-1] == pytest.approx(d["final_p95_position_m"])
    assert set(d["error_budget"]) == set(ImuModel.load("tactical").terms())
    assert main(base + ["--runs", "4", "--json", str(out)]) == 0  # --runs → Monte Carlo
    d = json.loads(out.read_text())
    assert d["method"] == "montecarlo" and d["runs"] == 4 and "envelope" in d
    capsys.readouterr()
    for extra, fragment in ((["--method", "montecarlo"], "needs --runs"),
                            (["--method", "covariance", "--runs", "3"], "--runs applies"),
                            (["--seed", "3"], "--seed applies")):
        assert main(base + extra) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and fragment in err[0], err


def test_assess_covariance_warns_outside_linear_model(still, capsys):
    assert main(["assess", str(still), "--imu", "MPU-6050", "--rate", "50",
                 "--tolerance", "1"]) == 0
    out = capsys.readouterr().out
    assert "NOT SUITABLE" in out and "small-angle" in out and "--method montecarlo" in out


# ----------------------------------------------------------------------------- Allan fits

N, B, K = 6e-5, 2e-5, 2e-6      # rad/s/√Hz, rad/s, rad/s/√s: crossovers at ~9 s and ~300 s
RATE = 10.0


GYRO = TriadModel(noise_density=N, bias_instability=B, random_walk=K)


def _static(hours, seed):
    n = int(hours * 3600 * RATE)
    y, _ = TriadStream(GYRO, "rates", RATE, np.random.default_rng(seed)).process(np.zeros((n, 3)))
    return y


def test_fit_recovers_white_noise_flicker_and_random_walk():
    """Eight 8-hour records (each term dominating over at least half a decade of τ)."""
    fits = [fit_allan(_static(8, seed), RATE)["terms"] for seed in range(8)]
    got = {k: np.array([f[k]["value"] for f in fits]) for k in fits[0]}
    se = {k: np.array([f[k]["se"] for f in fits]) for k in fits[0]}
    assert np.all(np.abs(got["noise_density"] / N - 1) < 0.05)               # the 5 %
    for k, true in (("bias_instability", B), ("random_walk", K)):
        # each record within twice its stated uncertainty (the Allan deviation's sampling
        # error where the term dominates most: √(1/2ν) from the degrees of freedom)
        assert np.all(np.abs(got[k] - true) <= 2 * se[k]), (k, got[k], se[k])
        # and that uncertainty is honest: not smaller than the scatter between records
        assert np.mean(se[k]) >= 0.8 * np.std(got[k], ddof=1), k
    # the τ ranges reported are where each term was read
    lo, hi = fits[0]["random_walk"]["tau_range"]
    assert lo > 100 and hi == pytest.approx(8 * 3600 / 10, rel=0.05)


def test_short_records_say_what_they_cannot_determine():
    half = fit_allan(_static(0.5, 1), RATE)["terms"]
    assert half["noise_density"]["value"] == pytest.approx(N, rel=0.05)
    assert half["random_walk"]["value"] is None and "record" in half["random_walk"]["why"]
    short = fit_allan(_static(3 / 60, 2), RATE)["terms"]
    assert short["bias_instability"]["value"] is None
    assert short["random_walk"]["value"] is None


IMU_TOML = f"""[gyro]
noise_density = {N}
bias_instability = {B}
random_walk = {K}
[accel]
noise_density = 4e-4
"""


def test_cli_allan_round_trip(tmp_path, capsys):
    motion = tmp_path / "still.toml"
    motion.write_text("duration = 10800\n")
    imu = tmp_path / "imu.toml"
    imu.write_text(IMU_TOML)
    log = tmp_path / "log.csv"
    assert main(["simulate", str(motion), "--rate", "10", "--imu", str(imu), "--seed", "4",
                 "--out", str(log)]) == 0
    fit, png = tmp_path / "fitted.toml", tmp_path / "adev.png"
    assert main(["allan", str(log), "--fit", str(fit), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "gyro.noise_density" in out
    text = fit.read_text()
    assert "0.664" in text and "rad/s" in text and "τ =" in text
    m = ImuModel.from_toml(fit)                                  # the other commands accept it
    assert m.gyro.noise_density == pytest.approx(N, rel=0.05)
    assert m.accel.noise_density == pytest.approx(4e-4, rel=0.05)
    assert m.accel.random_walk == 0.0                            # absent, not invented
    assert "accel" in text and "not determined" in text
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["assess", str(motion), "--imu", str(fit), "--rate", "1",
                 "--tolerance", "1000"]) == 0


def test_cli_allan_errors(tmp_path, capsys):
    motion = tmp_path / "m.toml"
    motion.write_text("duration = 5\n")
    inc = tmp_path / "inc.csv"
    assert main(["simulate", str(motion), "--rate", "10", "--output", "increments",
                 "--out", str(inc)]) == 0
    rates = tmp_path / "r.csv"
    assert main(["simulate", str(motion), "--rate", "10", "--out", str(rates)]) == 0
    capsys.readouterr()
    before = rates.read_bytes()
    for args, fragment in ((["allan", str(inc), "--fit", str(tmp_path / "f.toml")], "rate samples"),
                           (["allan", str(rates), "--fit", str(tmp_path / "f.toml")], "too few"),
                           (["allan", str(rates), "--fit", str(rates)], "--fit")):
        assert main(args) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and fragment in err[0], err
    assert rates.read_bytes() == before


def test_design_numbers_are_the_covariance_of_the_requested_run():
    """Every number of ``design`` is the covariance model's for the motion, duration and signal
    kind asked for (rates here, 5 s of a 20 s motion), term by term and preset by preset."""
    from imunav.analysis.assessment import min_sample_rate

    motion = Motion(x="0.5*sin(0.8*t)", yaw="0.3*sin(0.5*t)", duration=20.0, name="wiggle")
    base = ImuModel(TriadModel(noise_density=2e-4, resolution=1e-3),
                    TriadModel(bias=1e-3, resolution=2e-3), "base")
    tol, rate, dur = 0.05, 20.0, 5.0
    r = design(motion, base, rate, tol, duration=dur, kind="rates")
    cov = covariance(motion, base, rate, dur, kind="rates")
    assert cov.t[-1] == pytest.approx(5.0)
    inc = covariance(motion, base, rate, dur, kind="increments")
    assert set(r["terms"]) == set(cov.terms)
    for term, row in r["terms"].items():
        worst = cov.max_position_quantile(0.95, term=term)
        triad, name = term.split(".")
        assert row["max_p95_position_m"] == pytest.approx(worst, rel=1e-12)
        assert row["limit_si"] == pytest.approx(getattr(getattr(base, triad), name) * tol / worst,
                                                rel=1e-12)
    # resolution: white on rates, bounded on increments: the signal kind matters
    assert (inc.max_position_quantile(0.95, term="gyro.resolution")
            < 0.5 * r["terms"]["gyro.resolution"]["max_p95_position_m"])
    # the base values in datasheet units, by hand: 1e-3 m/s² = 0.10197 mg; 2e-4 rad/√s =
    # 2e-4·(180/π)·60 deg/√h = 0.6875 deg/√h
    assert r["terms"]["accel.bias"]["base"] == "0.102 mg"
    assert r["terms"]["gyro.noise_density"]["base"] == "0.688 deg/sqrt(h)"
    assert r["common_scale"] == pytest.approx(tol / cov.max_position_quantile(0.95), rel=1e-12)
    assert r["min_rate_hz"] == min_sample_rate(motion, tol, dur, "rates")
    assert (r["motion"], r["imu"], r["rate_hz"], r["tolerance_m"]) == ("wiggle", "base", 20.0, tol)
    assert r["warnings"] == cov.warnings
    for p in r["presets"][:3]:
        pc = covariance(motion, ImuModel.load(p["name"]), rate, dur, kind="rates")
        assert p["final_p95_position_m"] == pytest.approx(
            float(pc.position_quantile(0.95, index=-1)), rel=1e-12)
        assert p["suitable"] == (pc.min_position_within(tol) >= 0.95)
        assert p["warnings"] == pc.warnings


def test_design_of_an_ideal_imu_and_a_bad_tolerance():
    from imunav import ImunavError

    r = design(Motion(duration=2.0, name="still"), ImuModel(TriadModel(), TriadModel(), "ideal"),
               10.0, 1.0)
    assert r["terms"] == {} and r["common_scale"] is None
    # the "ideal" preset has no error term: zero error, suitable; it ranks first
    assert r["presets"][0] == {"name": "ideal", "final_p95_position_m": 0.0, "suitable": True,
                               "warnings": []}
    assert all(p["final_p95_position_m"] > 0 for p in r["presets"][1:])
    with pytest.raises(ImunavError, match="^tolerance must be"):
        design(STILL, ImuModel.load("BMI088"), 10.0, -1.0)


def test_format_design_hand_written():
    """The text of ``imunav design`` for a hand-made result, written out by hand: both branches
    of every sentence (meets / must shrink, a rate / none, suitable / not, a warning note)."""
    from imunav.analysis.design import format_design

    r = {"motion": "walk", "imu": "cheap", "rate_hz": 100.0, "tolerance_m": 2.5,
         "terms": {"gyro.bias": {"limit": "3.1 deg/h", "base": "10 deg/h"},
                   "accel.bias": {"limit": "0.5 mg", "base": "2 mg"}},
         "common_scale": 0.25, "min_rate_hz": 50.0,
         "presets": [{"name": "tactical", "final_p95_position_m": 0.0123, "suitable": True,
                      "warnings": []},
                     {"name": "MPU-6050", "final_p95_position_m": 1234.5, "suitable": False,
                      "warnings": ["attitude error 0.3 rad"]}],
         "warnings": ["filter lag 3 m"]}
    assert format_design(r).split("\n") == [
        "Design for motion walk at 100 Hz, tolerance 2.5 m (95th percentile of the position "
        "error, whole motion), from IMU cheap:",
        "  Largest value of each term that alone stays within the tolerance:",
        "    accel.bias                               0.5 mg   (this IMU: 2 mg)",
        "    gyro.bias                               3.1 °/h   (this IMU: 10 °/h)",
        "  All terms together: within the tolerance up to 0.25 × this IMU's values (its errors "
        "must shrink 4-fold).",
        "  Minimum sample rate (sampling alone below a tenth of the tolerance): 50 Hz.",
        "  Presets, best first (final 95th-percentile position error):",
        "    tactical   SUITABLE         0.0123 m",
        "    MPU-6050   NOT SUITABLE   1.23e+03 m (outside the linear model: check with Monte "
        "Carlo)",
        "  warning: filter lag 3 m.",
    ]
    r.update(common_scale=1.0, min_rate_hz=None, terms={}, warnings=[])
    lines = format_design(r).split("\n")
    assert lines[2:4] == [
        "  All terms together: within the tolerance up to 1 × this IMU's values (it already "
        "meets it).",
        "  Minimum sample rate (sampling alone below a tenth of the tolerance): none up to 5 kHz."]
    r.update(common_scale=None)
    assert format_design(r).split("\n")[2] == "  All terms together: no error term"


def test_design_skips_a_term_that_cannot_move_the_position():
    # free fall (z = g t²/2, NED down): the specific force is zero, so neither g-sensitivity
    # nor a tilt (gyro noise) moves the position: no limit for them; the accelerometer term
    # after them is still designed
    fall = Motion(z=f"{G0 / 2!r}*t**2", duration=2.0, name="fall")
    base = ImuModel(TriadModel(g_sensitivity=1e-4, noise_density=1e-4),
                    TriadModel(bias=1e-3), "base")
    r = design(fall, base, 20.0, 1.0)
    assert set(covariance(fall, base, 20.0).terms) == {
        "gyro.g_sensitivity", "gyro.noise_density", "accel.bias"}
    assert set(r["terms"]) == {"accel.bias"}
