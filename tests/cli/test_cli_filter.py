"""``imunav simulate --aiding`` and ``imunav filter`` (issue 28): the files, the output, the
statistics printed, reproducibility, and every bad input as one line with exit status 2; a 100 m
GNSS outlier is rejected by the gate, not absorbed."""

from pathlib import Path

import numpy as np
import pytest

from imunav.cli import main
from imunav.io.files import load_motion

ROOT = Path(__file__).resolve().parents[2]
ROUTE = ROOT / "examples" / "route.toml"
AIDING = """[gnss]
rate = 1
position_sigma = 1.5
velocity_sigma = 0.1
lever_arm = [0.5, 0.0, -1.0]
[baro]
rate = 2
sigma = 0.5
bias_drift = 0.01
[heading]
rate = 1
sigma = "2 deg"
"""
HEADER = ("t,x,y,z,vx,vy,vz,qw,qx,qy,qz,sd_pn,sd_pe,sd_pd,sd_vn,sd_ve,sd_vd,sd_roll,sd_pitch,"
          "sd_yaw")


@pytest.fixture(scope="module")
def sim(tmp_path_factory):
    d = tmp_path_factory.mktemp("aided")
    (d / "aiding.toml").write_text(AIDING)
    assert main(["simulate", str(ROUTE), "--rate", "50", "--imu", "ADIS16470", "--output",
                 "increments", "--out", str(d / "imu.csv"), "--truth", str(d / "truth.csv"),
                 "--aiding", str(d / "aiding.toml"), "--aiding-out", str(d / "meas"),
                 "--seed", "5"]) == 0
    return d


def _filter(d, *extra, meas=None, out="nav.csv", imu=("--imu", "ADIS16470")):
    return main(["filter", str(d / "imu.csv"), "--initial", str(d / "truth.csv"), *imu,
                 "--aiding", str(d / "aiding.toml"), "--measurements", str(meas or d / "meas"),
                 "--out", str(d / out), *extra])


def test_simulate_writes_one_csv_per_sensor(sim, capsys):
    m = sim / "meas"
    assert sorted(p.name for p in m.iterdir()) == ["baro.csv", "gnss.csv", "heading.csv"]
    assert (m / "gnss.csv").read_text().splitlines()[0] == "t,x,y,z,vx,vy,vz"
    assert (m / "baro.csv").read_text().splitlines()[0] == "t,alt"
    assert (m / "heading.csv").read_text().splitlines()[0] == "t,yaw"
    assert len((m / "gnss.csv").read_text().splitlines()) == 61          # 1 Hz over 60 s
    assert len((m / "baro.csv").read_text().splitlines()) == 121


def test_simulate_aiding_is_reproducible_by_seed(sim, tmp_path):
    for seed, out in (("5", "a"), ("6", "b")):
        assert main(["simulate", str(ROUTE), "--rate", "50", "--out", str(tmp_path / "s.csv"),
                     "--aiding", str(sim / "aiding.toml"), "--aiding-out", str(tmp_path / out),
                     "--seed", seed]) == 0
    same = (tmp_path / "a" / "gnss.csv").read_bytes() == (sim / "meas" / "gnss.csv").read_bytes()
    assert same
    assert (tmp_path / "b" / "gnss.csv").read_bytes() != (sim / "meas" / "gnss.csv").read_bytes()


def test_filter_output_and_statistics(sim, capsys):
    assert _filter(sim) == 0
    out = capsys.readouterr().out
    assert "wrote 3001 navigation rows (poly8_m6" in out
    for sensor in ("gnss", "baro", "heading"):
        assert f"  {sensor} " in out
    lines = (sim / "nav.csv").read_text().splitlines()
    assert lines[0] == HEADER and len(lines) == 3002
    data = np.loadtxt(sim / "nav.csv", delimiter=",", skiprows=1)
    sd = data[:, 11:]
    assert np.all(sd[1:] > 0) and np.all(np.isfinite(sd))
    # against the exact route (not the truth file): within 4σ nearly everywhere, and a few m
    motion, _, _ = load_motion(ROUTE)
    tr = motion.states(data[:, 0])
    err = data[:, 1:4] - tr.position
    assert np.sqrt((err ** 2).mean()) < 2.0
    assert np.mean(np.abs(err[1:]) <= 4 * sd[1:, :3]) > 0.99


def test_smoothed_output_has_the_same_header_and_smaller_sigma(sim, capsys):
    assert _filter(sim, out="forward.csv") == 0
    assert _filter(sim, "--smooth", out="smooth.csv") == 0
    assert "wrote 3001 smoothed navigation rows" in capsys.readouterr().out
    lines = (sim / "smooth.csv").read_text().splitlines()
    assert lines[0] == HEADER and len(lines) == 3002
    f = np.loadtxt(sim / "forward.csv", delimiter=",", skiprows=1)
    s = np.loadtxt(sim / "smooth.csv", delimiter=",", skiprows=1)
    assert np.all(s[:, 11:] <= f[:, 11:] * (1 + 1e-9) + 1e-12)
    assert s[1500, 11] < f[1500, 11]


def test_filter_without_imu_assumes_a_stated_model_and_says_so(sim, capsys):
    """Without --imu the filter no longer assumes an ideal IMU (every σ column 0 while the error
    grows: issue 37): it assumes the stated model of an unknown IMU, says so, and its σ are
    not zero; --imu ideal keeps the ideal model on request."""
    assert _filter(sim, imu=(), out="unknown.csv") == 0
    out = capsys.readouterr().out
    assert "no --imu given: the filter assumes the unknown IMU" in out
    nav = np.loadtxt(sim / "unknown.csv", delimiter=",", skiprows=1)
    assert np.all(nav[1:, -9:-6] > 0)


def _copy_meas(sim, meas):
    meas.mkdir()
    for p in (sim / "meas").iterdir():
        (meas / p.name).write_bytes(p.read_bytes())
    return meas


def test_heading_in_degrees_is_filtered_with_warnings_not_a_crash(sim, tmp_path, capsys):
    """A heading file written in degrees (read as radians): named by the reader, the run ends
    with its health (a covariance the bad readings inflated no longer crashes the report),
    and --check fails on the warnings."""
    meas = _copy_meas(sim, tmp_path / "deg")
    t, yaw = np.loadtxt(meas / "heading.csv", delimiter=",", skiprows=1, unpack=True)
    np.savetxt(meas / "heading.csv", np.column_stack([t, np.degrees(yaw)]), delimiter=",",
               header="t,yaw", comments="", fmt="%.9g")
    capsys.readouterr()
    assert _filter(sim, "--check", meas=meas, out="deg.csv") == 1
    err = capsys.readouterr().err
    assert "heading.csv: yaw reaches" in err and "degrees?" in err
    assert "Traceback" not in err


def test_an_empty_aid_file_fails_check(sim, tmp_path, capsys):
    meas = _copy_meas(sim, tmp_path / "empty")
    (meas / "heading.csv").write_text("t,yaw\n")
    capsys.readouterr()
    assert _filter(sim, "--check", meas=meas, out="empty.csv") == 1
    out, err = capsys.readouterr()
    assert "heading: configured but no reading" in err
    assert "(no readings)" in out


def test_gnss_outlier_of_100_m_is_rejected(sim, tmp_path, capsys):
    """One fix moved by 100 m north: the gate rejects it (counted), and the estimate is the one
    without that fix at all (to round-off), within 3 m of the truth there."""
    runs = {}
    for case in ("outlier", "removed"):
        meas = tmp_path / case
        meas.mkdir()
        for p in (sim / "meas").iterdir():
            (meas / p.name).write_bytes(p.read_bytes())
        lines = (meas / "gnss.csv").read_text().splitlines()
        cells = lines[31].split(",")                               # the fix at t = 31 s
        assert cells[0] == "31"
        if case == "outlier":
            cells[1] = repr(float(cells[1]) + 100.0)
            lines[31] = ",".join(cells)
        else:
            del lines[31]
        (meas / "gnss.csv").write_text("\n".join(lines) + "\n")
        capsys.readouterr()
        assert _filter(sim, meas=meas, out=f"{case}.csv") == 0
        out = capsys.readouterr().out
        gnss = next(line for line in out.splitlines() if line.strip().startswith("gnss"))
        runs[case] = (gnss.split()[1:3], np.loadtxt(sim / f"{case}.csv", delimiter=",",
                                                    skiprows=1))
    assert runs["outlier"][0] == ["60", "59"] and runs["removed"][0] == ["59", "59"]  # readings, used
    np.testing.assert_allclose(runs["outlier"][1], runs["removed"][1], rtol=0, atol=1e-9)
    motion, _, _ = load_motion(ROUTE)
    k = 31 * 50
    assert np.linalg.norm(runs["outlier"][1][k, 1:4] - motion.position(np.array([31.0]))[0]) < 3


def _one_line_exit_2(capsys, args, fragment):
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("imunav: error: "), err
    assert fragment in err[0], err[0]


def _copy(sim, tmp_path):
    meas = tmp_path / "m"
    meas.mkdir()
    for p in (sim / "meas").iterdir():
        (meas / p.name).write_bytes(p.read_bytes())
    return meas


@pytest.mark.parametrize("edit, fragment", [
    (lambda m: (m / "baro.csv").write_text("t,altitude\n1,2\n"), "unrecognised header"),
    (lambda m: (m / "gnss.csv").write_text("t,x,y\n1,2,3\n"), "unrecognised header"),
    (lambda m: (m / "baro.csv").write_text("t,alt\n1,2\n2,nan\n"), "line 3"),
    (lambda m: (m / "baro.csv").write_text("t,alt\n1,2\n3,2\n2,1\n"),
     "line 4: column t must be strictly increasing; t = 2 s is out of order"),
    (lambda m: (m / "heading.csv").write_text("t,yaw\n1,0.1\n1,0.2\n"),
     "line 3: column t must be strictly increasing; t = 1 s is repeated"),
    (lambda m: (m / "baro.csv").write_text("t,alt\n1,2\n70,1\n"),
     "baro.csv, line 3: t = 70 s lies outside the IMU record (0 … 60 s)"),
    (lambda m: (m / "baro.csv").write_text("t,alt\n-1,2\n"), "lies outside the IMU record"),
    (lambda m: (m / "heading.csv").unlink(), "heading.csv not found"),
    (lambda m: (m / "baro.csv").write_text("t,alt\n1,abc\n"), "'abc' is not a number"),
])
def test_bad_measurement_files(sim, tmp_path, capsys, edit, fragment):
    meas = _copy(sim, tmp_path)
    edit(meas)
    _one_line_exit_2(capsys, ["filter", str(sim / "imu.csv"), "--initial", str(sim / "truth.csv"),
                              "--aiding", str(sim / "aiding.toml"), "--measurements", str(meas),
                              "--out", str(tmp_path / "nav.csv")], fragment)


@pytest.mark.parametrize("text, fragment", [
    (AIDING.replace("sigma = 0.5", "sigma = 0"), "[baro] sigma must be a positive number (m)"),
    (AIDING.replace("position_sigma = 1.5", "position_sigma = -1.5"),
     "[gnss] position_sigma must be a positive number"),
    (AIDING + "speed = 3\n", "unknown key(s) in [heading]: speed"),
    (AIDING + "[magnetometer]\nsigma = 1\n", "unknown table(s) in AIDING file: magnetometer"),
    ("[gnss]\nrate = 1\n", "[gnss] position_sigma (m) is required"),
    ("", "has no aiding sensor"),
    ("[gnss\n", "malformed TOML"),
])
def test_bad_aiding_files(sim, tmp_path, capsys, text, fragment):
    p = tmp_path / "a.toml"
    p.write_text(text)
    _one_line_exit_2(capsys, ["filter", str(sim / "imu.csv"), "--initial", str(sim / "truth.csv"),
                              "--aiding", str(p), "--measurements", str(sim / "meas"),
                              "--out", str(tmp_path / "nav.csv")], fragment)


def test_other_usage_errors(sim, tmp_path, capsys):
    base = ["filter", str(sim / "imu.csv"), "--initial", str(sim / "truth.csv"), "--aiding",
            str(sim / "aiding.toml"), "--measurements", str(sim / "meas")]
    _one_line_exit_2(capsys, base + ["--out", str(sim / "meas" / "gnss.csv")],
                     "would overwrite the input file")
    _one_line_exit_2(capsys, base[:6] + ["--measurements", str(tmp_path / "none"), "--out",
                                          str(tmp_path / "n.csv")],
                     "measurements folder not found")
    _one_line_exit_2(capsys, base + ["--out", str(tmp_path / "n.csv"), "--gate", "1.5"],
                     "--gate must be a probability in (0, 1]")
    _one_line_exit_2(capsys, ["simulate", str(ROUTE), "--rate", "50", "--out",
                              str(tmp_path / "s.csv"), "--aiding", str(sim / "aiding.toml")],
                     "--aiding and --aiding-out go together")
    _one_line_exit_2(capsys, ["simulate", str(ROUTE), "--rate", "50", "--out",
                              str(tmp_path / "s.csv"), "--aiding", str(sim / "aiding.toml"),
                              "--aiding-out", str(sim / "aiding.toml")], "is a file; give a folder")
    (tmp_path / "earth.csv").write_text("t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz\n0,45,7,300,0,0,0,1,0,0,0\n")
    _one_line_exit_2(capsys, base[:3] + [str(tmp_path / "earth.csv")] + base[4:] +
                     ["--out", str(tmp_path / "n.csv")], "is a wgs84 truth but --earth is flat")
    _one_line_exit_2(capsys, ["simulate", str(ROUTE), "--rate", "50", "--out",
                              str(sim / "meas" / "baro.csv"), "--aiding",
                              str(sim / "aiding.toml"), "--aiding-out", str(sim / "meas")],
                     "is the same file as")
