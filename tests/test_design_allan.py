"""Issue 18 faces: assess --method covariance, the inverse design command, and IMU models
fitted from a static log's Allan deviation."""

import json
from dataclasses import fields, replace

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
        return replace(m, **{f.name: getattr(m, f.name) * s for f in fields(m)
                             if f.name not in keep and getattr(m, f.name)})
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
