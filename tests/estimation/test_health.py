"""The filter that notices when it stops listening (issue 37): each aid's health, the warnings,
and the recovery from a lock-out."""

from pathlib import Path

import numpy as np
import pytest

from imunav.estimation.filters import Innovations, run_filter
from imunav.estimation.health import MAX_LAG1, assess_health
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig, Readings, simulate_aiding
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import simulate_imu

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: Issue 37's case: BMI088 at 100 Hz on the example drive, GNSS 1 Hz position only (σ 2 m)
#: with an outage at 30–47 s, plus NHC.
CASE = {"gnss": {"rate": 1, "position_sigma": 2.0, "outages": [[30, 47]]}, "nhc": {"sigma": 0.1}}


@pytest.fixture(scope="module")
def drive():
    m, dur, _ = load_motion(EXAMPLES / "drive.toml")
    return m, dur


def _run(drive, seed, **kw):
    m, dur = drive
    imu = ImuModel.load("BMI088")
    cfg = AidingConfig.from_dict(CASE)
    sig = simulate_imu(m, 100.0, dur, kind="increments", imu=imu, seed=seed)
    data = simulate_aiding(m, cfg, dur, seed=seed, imu_rate=100.0)
    st = m.states(np.array([0.0]))
    res = run_filter(sig, st.quaternion[0], st.velocity[0], st.position[0], cfg, data, imu=imu,
                     **kw)
    err = res.states.position[-1] - m.position(res.t[-1:])[0]
    return res, err


def test_a_locked_out_filter_recovers_and_says_so(drive):
    """Seed 1 diverges early (its yaw, unobservable while the car stands, is beyond the EKF's
    linear range once it drives off): with the gate alone it rejects nearly every fix and ends
    kilometres off, silently before issue 37. With the recovery (the default) it re-admits a fix
    with the covariance inflated, ends within 5σ on every axis, and warns."""
    locked, err0 = _run(drive, 1, recover=None)
    assert np.abs(err0).max() > 1e3
    h0 = locked.health.aids["gnss"]
    assert h0["gated_share"] > 0.5 and h0["readmitted"] == 0
    assert any("rejected" in w for w in locked.warnings)
    res, err = _run(drive, 1)
    assert np.all(np.abs(err) <= 5 * res.sd[-1, :3]), (err, res.sd[-1, :3])
    assert res.health.aids["gnss"]["readmitted"] >= 1
    assert any("locked out" in w for w in res.warnings)


@pytest.mark.parametrize("seed", [9, 12])
def test_seeded_runs_end_within_five_sigma(drive, seed):
    res, err = _run(drive, seed)
    assert np.all(np.abs(err) <= 5 * res.sd[-1, :3]), (err, res.sd[-1, :3])


def test_readings_in_the_wrong_frame_are_filtered_with_a_warning(drive):
    """GNSS written east-north-up instead of north-east-down: the filter runs to the end (exit 0
    in the CLI), and its health says the readings disagree."""
    m, dur = drive
    cfg = AidingConfig.from_dict(CASE)
    imu = ImuModel.load("BMI088")
    sig = simulate_imu(m, 100.0, dur, kind="increments", imu=imu, seed=1)
    data = simulate_aiding(m, cfg, dur, seed=1, imu_rate=100.0)
    g = data.gnss
    data.gnss = Readings(g.t, g.values[:, [1, 0, 2]] * [1.0, 1.0, -1.0])
    st = m.states(np.array([0.0]))
    res = run_filter(sig, st.quaternion[0], st.velocity[0], st.position[0], cfg, data, imu=imu)
    assert res.health.warnings
    assert any("gnss" in w and ("rejected" in w or "NIS" in w or "locked out" in w)
               for w in res.warnings)


def _innovations(nu, S=1.0):
    k, m = nu.shape
    return Innovations("x", np.arange(k, dtype=float), nu, np.broadcast_to(S * np.eye(m),
                                                                           (k, m, m)).copy(),
                       np.einsum("ki,ki->k", nu, nu) / S, np.ones(k, dtype=bool))


def test_health_of_white_consistent_innovations_is_quiet():
    rng = np.random.default_rng(0)
    h = assess_health({"x": _innovations(rng.standard_normal((2000, 2)))})
    assert not h.warnings
    assert h.aids["x"]["gated"] == 0 and h.aids["x"]["longest_rejection_run"] == 0
    lo, hi = h.aids["x"]["nis_band"]
    assert lo < h.aids["x"]["mean_nis"] < hi


def test_health_flags_correlated_and_oversized_innovations():
    """An AR(1) innovation of coefficient 0.9 (a correlated error modelled as white), and
    innovations three times their σ (an optimistic filter): each its warning."""
    rng = np.random.default_rng(1)
    e = rng.standard_normal((3000, 1))
    ar = np.empty_like(e)
    ar[0] = e[0]
    for i in range(1, e.shape[0]):
        ar[i] = 0.9 * ar[i - 1] + np.sqrt(1 - 0.81) * e[i]
    h = assess_health({"x": _innovations(ar)})
    assert h.aids["x"]["lag1"][0] > MAX_LAG1
    assert any("correlated" in w for w in h.warnings)
    h = assess_health({"x": _innovations(3 * rng.standard_normal((500, 2)))}, ideal_imu=True)
    assert any("optimistic" in w for w in h.warnings)
    assert any("ideal IMU" in w for w in h.warnings)


def test_a_long_run_of_rejections_is_timed():
    rng = np.random.default_rng(2)
    inn = _innovations(rng.standard_normal((100, 2)))
    inn.accepted[40:52] = False
    h = assess_health({"x": inn})
    assert h.aids["x"]["longest_rejection_run"] == 12
    assert h.aids["x"]["longest_rejection_s"] == pytest.approx(12.0)
    assert any("12 consecutive readings" in w for w in h.warnings)


# ----------------------------------------------------------------------------- a log from the CLI

def _walk_log(tmp_path, seconds=40.0):
    """A foot walk's IMU (ADIS16470 errors) written as a log of another layout: a header with
    spaces and parentheses, degrees per second, g, milliseconds."""
    from imunav.motion.foot import foot_walk

    m = foot_walk(seconds)
    sig = simulate_imu(m, 200.0, seconds, kind="rates", imu=ImuModel.load("ADIS16470"), seed=4)
    path = tmp_path / "walk.csv"
    cols = np.column_stack([sig.t * 1000.0, np.degrees(sig.gyro), sig.accel / 9.80665])
    header = "Time (ms),Gyro X (deg/s),Gyro Y (deg/s),Gyro Z (deg/s),Acc X (g),Acc Y (g),Acc Z (g)"
    np.savetxt(path, cols, delimiter=",", header=header, comments="")
    (tmp_path / "foot.toml").write_text('[zupt]\nsigma = 0.01\ndetector = "shoe"\n')
    return m, sig, path


def _log_args(tmp_path, path, **over):
    args = {"--format": "generic", "--time-column": "Time (ms)", "--time-units": "ms",
            "--gyro-columns": "Gyro X (deg/s),Gyro Y (deg/s),Gyro Z (deg/s)",
            "--gyro-units": "deg/s", "--accel-columns": "Acc X (g),Acc Y (g),Acc Z (g)",
            "--accel-units": "g", "--align": "static",
            "--aiding": str(tmp_path / "foot.toml"), "--out": str(tmp_path / "nav.csv")}
    args.update(over)
    return ["filter", str(path)] + [x for k, v in args.items() for x in (k, v)]


def test_a_foot_log_runs_from_the_cli_without_imu_or_measurements(tmp_path, capsys):
    """issue 36: `imunav filter walk.csv --format generic … --align static --aiding foot.toml
    --out nav.csv`: one row per input sample from the first (the still start included), starting
    at 0 with heading 0, no --imu (the stated foot model), no --measurements; the walk ends
    within 1 % of its path of the truth (rotated by the walk's initial heading, 0 here)."""
    from imunav.cli import main

    m, sig, path = _walk_log(tmp_path)
    assert main(_log_args(tmp_path, path)) == 0
    out = capsys.readouterr().out
    assert "no --imu given" in out and "foot-mounted IMU" in out
    nav = np.loadtxt(tmp_path / "nav.csv", delimiter=",", skiprows=1)
    assert nav.shape[0] == len(sig)
    np.testing.assert_allclose(nav[0, 0], sig.t[0], atol=1e-9)
    np.testing.assert_allclose(nav[0, 1:4], 0.0, atol=1e-12)
    truth = m.position(sig.t)
    path_len = np.sum(np.linalg.norm(np.diff(truth[:, :2], axis=0), axis=1))
    end = np.linalg.norm(nav[-1, 1:3] - (truth[-1, :2] - truth[0, :2]))
    assert end <= 0.01 * path_len, (end, path_len)


def test_a_log_read_in_the_wrong_units_is_refused_in_one_line(tmp_path, capsys):
    from imunav.cli import main

    _, _, path = _walk_log(tmp_path, 10.0)
    assert main(_log_args(tmp_path, path, **{"--accel-units": "m/s^2"})) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--accel-units" in err[0], err


# ------------------------------------------------------------------- a run that lost its meaning

def test_an_aid_without_readings_is_warned():
    """An aid configured but with no reading in the run (an empty file) is named: the filter
    ran without it, and ``filter --check`` fails on the warning."""
    empty = Innovations("heading", np.zeros(0), np.zeros((0, 1)), np.zeros((0, 1, 1)),
                        np.zeros(0), np.zeros(0, dtype=bool))
    h = assess_health({"heading": empty})
    assert h.aids["heading"]["readings"] == 0
    assert any(w.startswith("heading: configured but no reading") for w in h.warnings)


def test_an_indefinite_innovation_covariance_gives_nan_not_a_crash():
    """A covariance inflated by orders of magnitude (heading readings in degrees) can leave S
    numerically indefinite: those readings' whitened innovations are NaN, the others whitened,
    and the mean NIS is over the finite ones (no "nan outside its band" warning)."""
    rng = np.random.default_rng(3)
    inn = _innovations(rng.standard_normal((50, 2)))
    inn.S[7] = np.array([[1.0, 2.0], [2.0, 1.0]])            # eigenvalues 3 and −1
    inn.nis[7] = np.nan
    z = inn.normalised
    assert np.isnan(z[7]).all() and np.isfinite(np.delete(z, 7, axis=0)).all()
    np.testing.assert_allclose(z[8], inn.innovation[8] / np.sqrt(np.diag(inn.S[8])))
    h = assess_health({"x": inn})
    assert np.isfinite(h.aids["x"]["mean_nis"])
    assert not any("nan" in w for w in h.warnings)
