"""The command line on the rotating Earth: --earth wgs84 --origin, the WGS-84 truth and
navigation CSVs (latitude and longitude in degrees, full precision), and one-line errors with
exit 2 for a bad origin, --g with wgs84, or a truth file of the other frame."""

import numpy as np
import pytest

from imunav import Motion
from imunav import earth as E
from imunav.cli import main
from imunav.io import read_states
from imunav.motion import EarthMotion

MOTION_TOML = """duration = 4.0
[position]
x = "t**2"
y = "t*sin(t)**2"
z = "2*t"
[attitude]
yaw = "0.3*sin(t)"
pitch = "0.2*sin(0.5*t)"
roll = "0.1*t"
"""
ORIGIN = "55.75,37.61,150"


@pytest.fixture
def motion_file(tmp_path):
    p = tmp_path / "motion.toml"
    p.write_text(MOTION_TOML)
    return p


@pytest.mark.parametrize("output", ["rates", "increments"])
def test_simulate_and_navigate_on_the_earth(tmp_path, motion_file, output):
    sig, truth, nav = tmp_path / "s.csv", tmp_path / "truth.csv", tmp_path / "nav.csv"
    assert main(["simulate", str(motion_file), "--rate", "50", "--out", str(sig), "--output",
                 output, "--truth", str(truth), "--earth", "wgs84", "--origin", ORIGIN]) == 0
    lines = truth.read_text().splitlines()
    assert lines[0] == "t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz"
    lat, lon, alt = (float(x) for x in lines[1].split(",")[1:4])     # degrees at the edge
    # the truth goes through ECEF (the last bit of 6.4e6 m is 0.9 nm): measured 2.7e-10 m
    assert (lat, lon) == (55.75, 37.61) and alt == pytest.approx(150.0, abs=1e-9)
    tr = read_states(truth)
    assert tr.frame == "wgs84" and tr.position[0, 0] == np.radians(55.75)
    m = EarthMotion(Motion(x="t**2", y="t*sin(t)**2", z="2*t", yaw="0.3*sin(t)",
                           pitch="0.2*sin(0.5*t)", roll="0.1*t"),
                    (np.radians(55.75), np.radians(37.61), 150.0))
    exact = m.states(tr.t)
    # the file keeps every bit: latitudes read back to the last place (17 digits)
    np.testing.assert_array_equal(tr.position[:, :2], np.radians(np.degrees(exact.position[:, :2])))
    assert main(["navigate", str(sig), "--initial", str(truth), "--out", str(nav),
                 "--earth", "wgs84"]) == 0
    st = read_states(nav)
    assert nav.read_text().splitlines()[0] == "t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz"
    assert st.frame == "wgs84" and st.t.size == 201
    d = np.linalg.norm(E.ned_difference(st.position, exact.position), axis=1)
    # measured 3.2e-9 m for both kinds: the position representation's floor (0.9 nm a bit)
    assert d.max() < 1e-7


@pytest.mark.parametrize("args, message", [
    (["--earth", "wgs84"], "--earth wgs84 needs --origin LAT,LON,ALT"),
    (["--earth", "wgs84", "--origin", "91,0,0"], "argument --origin: latitude must be within "
                                                 "±90°, got 91°"),
    (["--earth", "wgs84", "--origin", "55,east,0"], "argument --origin: --origin must be "
                                                    "LAT,LON,ALT"),
    (["--earth", "wgs84", "--origin", "55,37"], "--origin must be LAT,LON,ALT"),
    (["--earth", "wgs84", "--origin", "55,37,nan"], "height must be finite, got nan"),
    (["--earth", "wgs84", "--origin", "-91,37,0"], "latitude must be within ±90°, got -91°"),
    (["--earth", "wgs84", "--origin", "55,37,1e9"], "height must be at most 100000 m"),
    (["--earth", "wgs84", "--origin", ORIGIN, "--g", "9.8"], "--g belongs to the flat frame"),
    (["--origin", ORIGIN], "--origin applies to --earth wgs84 only"),
    (["--earth", "round"], "argument --earth: invalid choice: 'round'"),
])
def test_bad_earth_options_exit_2_with_one_line(tmp_path, motion_file, capsys, args, message):
    code = main(["simulate", str(motion_file), "--rate", "50", "--out", str(tmp_path / "s.csv"),
                 *args])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "s.csv").exists()


def test_a_southern_or_western_origin_is_read_as_given(tmp_path, motion_file, capsys):
    """--origin -33.9,-70.6,500 (a negative first value) is the origin, not an unknown option,
    spelled either way."""
    for i, spelled in enumerate((["--origin", "-33.9,-70.6,500"], ["--origin=-33.9,-70.6,500"])):
        truth = tmp_path / f"t{i}.csv"
        assert main(["simulate", str(motion_file), "--rate", "50", "--out",
                     str(tmp_path / f"s{i}.csv"), "--truth", str(truth), "--earth", "wgs84",
                     *spelled]) == 0, capsys.readouterr().err
        lat, lon, alt = read_states(truth).position[0]
        assert np.degrees(lat) == pytest.approx(-33.9, abs=1e-12)
        assert np.degrees(lon) == pytest.approx(-70.6, abs=1e-12)
        assert alt == pytest.approx(500.0, abs=1e-6)


def test_a_truth_of_the_other_frame_is_refused(tmp_path, motion_file, capsys):
    sig, flat, geo = tmp_path / "s.csv", tmp_path / "flat.csv", tmp_path / "geo.csv"
    assert main(["simulate", str(motion_file), "--rate", "50", "--out", str(sig), "--truth",
                 str(flat)]) == 0
    assert main(["simulate", str(motion_file), "--rate", "50", "--out", str(tmp_path / "x.csv"),
                 "--truth", str(geo), "--earth", "wgs84", "--origin", ORIGIN]) == 0
    capsys.readouterr()
    assert main(["navigate", str(sig), "--initial", str(flat), "--out", str(tmp_path / "n.csv"),
                 "--earth", "wgs84"]) == 2
    assert "is a flat truth but --earth is wgs84" in capsys.readouterr().err
    assert main(["navigate", str(sig), "--initial", str(geo), "--out", str(tmp_path / "n.csv")]) == 2
    assert "is a wgs84 truth but --earth is flat" in capsys.readouterr().err
    assert main(["navigate", str(sig), "--initial", str(geo), "--out", str(tmp_path / "n.csv"),
                 "--earth", "wgs84", "--g", "9.8"]) == 2
    assert "--g belongs to the flat frame" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz\n0,95,0,0,0,0,0,1,0,0,0\n")
    assert main(["navigate", str(sig), "--initial", str(bad), "--out", str(tmp_path / "n.csv"),
                 "--earth", "wgs84"]) == 2
    assert "column lat must be within ±90°" in capsys.readouterr().err


def test_assess_montecarlo_on_the_earth(tmp_path, motion_file, capsys):
    out = tmp_path / "a.json"
    assert main(["assess", str(motion_file), "--imu", "ADIS16470", "--rate", "50", "--tolerance",
                 "5", "--runs", "20", "--earth", "wgs84", "--origin", ORIGIN, "--json",
                 str(out)]) == 0
    text = capsys.readouterr().out
    assert "20 runs" in text and out.exists()


def test_assess_with_the_vertical_held_and_the_dominance_note(tmp_path, capsys):
    """Free, an accelerometer bias's error is mostly vertical and the verdict says so; held (a
    perfect height aid) only the horizontal part remains."""
    motion = tmp_path / "still.toml"
    motion.write_text("duration = 1800.0\n")
    imu = tmp_path / "imu.toml"
    imu.write_text('[gyro]\n[accel]\nbias = "1 mg"\n')
    args = ["assess", str(motion), "--imu", str(imu), "--rate", "1", "--tolerance", "5",
            "--runs", "30", "--earth", "wgs84", "--origin", "45,7,100"]
    out = tmp_path / "a.json"
    assert main(args + ["--json", str(out)]) == 0
    free = capsys.readouterr().out
    assert "the vertical channel dominates" in free
    import json

    r = json.loads(out.read_text())
    assert r["vertical"] == "free" and r["final_p95_position_m"] > 2 * r["final_p95_horizontal_m"]
    assert main(args + ["--vertical", "hold", "--json", str(out)]) == 0
    held = capsys.readouterr().out
    assert "dominates" not in held
    r2 = json.loads(out.read_text())
    assert r2["final_p95_position_m"] == pytest.approx(r2["final_p95_horizontal_m"], rel=1e-3)
    assert main(["assess", str(motion), "--imu", str(imu), "--rate", "1", "--tolerance", "5",
                 "--runs", "3", "--vertical", "hold"]) == 2
    assert "--vertical applies to --earth wgs84 only" in capsys.readouterr().err


def test_assess_and_design_by_covariance_on_the_earth(tmp_path, capsys):
    """The covariance assessment on the Earth (the Earth error model, streamed) against the
    Monte Carlo verdict of the same command, free and held; design runs on it too."""
    import json

    motion = tmp_path / "still.toml"
    motion.write_text("duration = 1800.0\n")
    imu = tmp_path / "imu.toml"
    imu.write_text('[gyro]\n[accel]\nbias = "1 mg"\n')
    base = ["assess", str(motion), "--imu", str(imu), "--rate", "1", "--tolerance", "5",
            "--earth", "wgs84", "--origin", "45,7,100"]
    got = {}
    for vertical in ("free", "hold"):
        for method, extra in (("covariance", []), ("montecarlo", ["--runs", "300"])):
            out = tmp_path / f"{vertical}-{method}.json"
            assert main(base + extra + ["--vertical", vertical, "--json", str(out)]) == 0
            got[vertical, method] = json.loads(out.read_text())
    text = capsys.readouterr().out
    assert "covariance analysis" in text and "the vertical channel dominates" in text
    for vertical in ("free", "hold"):
        cov, mc = got[vertical, "covariance"], got[vertical, "montecarlo"]
        assert cov["final_p95_position_m"] == pytest.approx(mc["final_p95_position_m"], rel=0.1)
        assert cov["final_p95_horizontal_m"] == pytest.approx(mc["final_p95_horizontal_m"],
                                                              rel=0.1)
    assert got["hold", "covariance"]["final_p95_position_m"] < 0.5 * got["free", "covariance"][
        "final_p95_position_m"]
    out = tmp_path / "d.json"
    assert main(["design", str(motion), "--imu", str(imu), "--rate", "1", "--tolerance", "50",
                 "--earth", "wgs84", "--origin", "45,7,100", "--vertical", "hold", "--json",
                 str(out)]) == 0
    d = json.loads(out.read_text())
    assert "accel.bias" in d["terms"]


@pytest.mark.parametrize("earth", [[], ["--earth", "wgs84", "--origin", ORIGIN]])
def test_a_huge_duration_is_refused_in_one_line_not_run_for_years(tmp_path, capsys, earth):
    """A 1e12 s motion at 100 Hz: the covariance assessment and the design refuse at once (it used to scan
    the motion silently for hours before the first progress bar) — flat frame and Earth."""
    p = tmp_path / "long.toml"
    p.write_text(MOTION_TOML.replace("duration = 4.0", "duration = 1e12"))
    for command in ("assess", "design"):
        assert main([command, str(p), "--imu", "tactical", "--rate", "100", "--tolerance", "5",
                     *earth]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "the covariance analysis of 1e+14 steps" in err, err
