"""``imunav simulate --earth wgs84 --aiding`` and ``imunav filter --earth wgs84`` (issue 28): the
WGS-84 measurement files (gnss.csv ``t,lat,lon,alt,vn,ve,vd`` in degrees), the navigation CSV
``t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz`` plus the σ in metres, its errors against the exact truth
within its σ, the smoother, and the frame mismatches as one line with exit status 2."""

from pathlib import Path

import numpy as np
import pytest

from imunav.cli import main
from imunav.earth import ned_difference
from imunav.io.csvio import read_header
from imunav.io.files import read_states

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
ORIGIN = "48.1,11.6,520"
HEADER = ("t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz,sd_pn,sd_pe,sd_pd,sd_vn,sd_ve,sd_vd,sd_roll,"
          "sd_pitch,sd_yaw")


def _one_line_exit_2(capsys, args, fragment):
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("imunav: error: "), err
    assert fragment in err[0], err[0]


@pytest.fixture(scope="module")
def sim(tmp_path_factory):
    d = tmp_path_factory.mktemp("aided_earth")
    (d / "aiding.toml").write_text(AIDING)
    assert main(["simulate", str(ROUTE), "--rate", "50", "--imu", "ADIS16470", "--output",
                 "increments", "--out", str(d / "imu.csv"), "--truth", str(d / "truth.csv"),
                 "--aiding", str(d / "aiding.toml"), "--aiding-out", str(d / "meas"),
                 "--seed", "5", "--earth", "wgs84", "--origin", ORIGIN]) == 0
    return d


def _filter(d, *extra, out="nav.csv"):
    return main(["filter", str(d / "imu.csv"), "--initial", str(d / "truth.csv"), "--imu",
                 "ADIS16470", "--aiding", str(d / "aiding.toml"), "--measurements",
                 str(d / "meas"), "--out", str(d / out), "--earth", "wgs84", *extra])


def test_simulate_writes_wgs84_gnss(sim):
    m = sim / "meas"
    assert sorted(p.name for p in m.iterdir()) == ["baro.csv", "gnss.csv", "heading.csv"]
    lines = (m / "gnss.csv").read_text().splitlines()
    assert lines[0] == "t,lat,lon,alt,vn,ve,vd" and len(lines) == 61
    gnss = np.loadtxt(m / "gnss.csv", delimiter=",", skiprows=1)
    truth = read_states(sim / "truth.csv")
    k = np.searchsorted(truth.t, gnss[:, 0])
    lla = np.column_stack([np.radians(gnss[:, 1]), np.radians(gnss[:, 2]), gnss[:, 3]])
    d = ned_difference(lla, truth.position[k])
    # the antenna 0.5 m ahead of and 1 m above the IMU, plus 1.5 m noise per axis
    assert np.all(np.abs(d) < 8.0) and 0.8 < np.std(d[:, 2] + 1.0) < 2.5
    baro = np.loadtxt(m / "baro.csv", delimiter=",", skiprows=1)
    assert abs(np.median(baro[:, 1]) - 520.0) < 20.0                    # heights, not −z


@pytest.mark.parametrize("smooth", [False, True])
def test_filter_on_wgs84_writes_geodetic_states_within_sigma(sim, capsys, smooth):
    assert _filter(sim, *(["--smooth"] if smooth else []), out=f"nav{smooth}.csv") == 0
    out = capsys.readouterr().out
    assert "innovations" in out and "gnss" in out
    path = sim / f"nav{smooth}.csv"
    assert ",".join(read_header(path, "nav")) == HEADER
    nav = np.loadtxt(path, delimiter=",", skiprows=1)
    truth = read_states(sim / "truth.csv")
    assert nav.shape[0] == truth.t.size
    lla = np.column_stack([np.radians(nav[:, 1]), np.radians(nav[:, 2]), nav[:, 3]])
    err = ned_difference(lla, truth.position)[50:]
    sd = nav[50:, 11:14]
    # position errors within 3σ at nearly every node (a single run), σ of metres
    assert np.mean(np.abs(err) <= 3 * sd) > 0.95, np.abs(err / sd).max(axis=0)
    assert np.all(sd < 3.0)


def test_wgs84_frame_mismatches_exit_2(sim, tmp_path, capsys):
    base = ["filter", str(sim / "imu.csv"), "--initial", str(sim / "truth.csv"), "--imu",
            "ADIS16470", "--aiding", str(sim / "aiding.toml"), "--measurements",
            str(sim / "meas"), "--out", str(tmp_path / "n.csv")]
    _one_line_exit_2(capsys, base, "is a wgs84 truth but --earth is flat")
    flat = tmp_path / "flat"
    flat.mkdir()
    for f in ("baro.csv", "heading.csv"):
        (flat / f).write_text((sim / "meas" / f).read_text())
    (flat / "gnss.csv").write_text("t,x,y,z,vx,vy,vz\n1,0,0,0,0,0,0\n")
    args = base[:9] + [str(flat)] + base[10:] + ["--earth", "wgs84"]
    _one_line_exit_2(capsys, args, "(a flat file: the filter's frame is wgs84)")
    (flat / "gnss.csv").write_text("t,lat,lon,alt,vn,ve,vd\n1,95,0,0,0,0,0\n")
    _one_line_exit_2(capsys, args, "is outside ±90°")
    (flat / "gnss.csv").write_text("t,lat,lon,alt,vn,ve,vd\n1,45,400,0,0,0,0\n")
    _one_line_exit_2(capsys, args, "lon = 400° is outside ±180°")
    _one_line_exit_2(capsys, base + ["--earth", "wgs84", "--g", "9.8"],
                     "--g belongs to the flat frame")
