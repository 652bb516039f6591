"""``imunav assess --aiding`` and ``imunav design --aiding --find outage`` (issue 29): the JSON
keys the issue names (``outages: [{start, end, position_p95_max_m}]``, top-level
``max_outage_s``), the verdict through every outage, ``--outage-start``, the Monte Carlo of the
filter beside the covariance, and every bad combination as one line with exit status 2."""

import json

import pytest

from imunav.cli import main

MOTION = """name = "short drive"
orientation = "follow"
[[waypoint]]
t = 0
x = 0
y = 0
z = 0
[[waypoint]]
t = 20
x = 200
y = 20
z = 0
[[waypoint]]
t = 40
x = 380
y = 150
z = -1
[[waypoint]]
t = 60
x = 500
y = 350
z = -1
"""
AIDING = """[gnss]
rate = 1
position_sigma = 1.5
velocity_sigma = 0.1
outages = [[30, 40]]
"""


@pytest.fixture
def files(tmp_path):
    m = tmp_path / "drive.toml"
    m.write_text(MOTION)
    a = tmp_path / "aiding.toml"
    a.write_text(AIDING)
    return m, a, tmp_path


def _run(capsys, *argv):
    code = main([str(x) for x in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_assess_aided_json_has_the_outages_and_the_verdict(files, capsys):
    m, a, d = files
    code, out, _ = _run(capsys, "assess", m, "--imu", "BMI088", "--rate", 20, "--tolerance",
                        5, "--aiding", a, "--json", d / "r.json")
    assert code == 0
    r = json.loads((d / "r.json").read_text())
    (o,) = r["outages"]
    assert (o["start"], o["end"]) == (30.0, 40.0)
    assert o["position_p95_max_m"] > 0 and o["within_tolerance"] == (
        o["position_p95_max_m"] <= 5)
    assert r["method"] == "covariance" and r["aiding"] == ["gnss"]
    assert r["suitable"] == (r["max_p95_position_m"] <= 5)
    assert len(r["envelope"]["t"]) == len(r["envelope"]["position_p95_m"])
    assert r["error_budget"] and "GNSS outage 30–40 s" in out
    # a tolerance above the largest p95 passes, one below it fails, through the outage
    big = o["position_p95_max_m"] * 2
    code, out, _ = _run(capsys, "assess", m, "--imu", "BMI088", "--rate", 20, "--tolerance",
                        max(big, r["max_p95_position_m"] * 1.01), "--aiding", a)
    assert code == 0 and "within the tolerance" in out and "NOT SUITABLE" not in out


def test_assess_aided_monte_carlo_puts_the_covariance_beside(files, capsys):
    m, a, d = files
    code, _, _ = _run(capsys, "assess", m, "--imu", "BMI088", "--rate", 20, "--tolerance", 5,
                      "--aiding", a, "--runs", 4, "--json", d / "r.json")
    assert code == 0
    r = json.loads((d / "r.json").read_text())
    assert r["method"] == "montecarlo" and r["runs"] == 4
    (o,) = r["outages"]
    assert {"position_p95_max_m", "covariance_p95_max_m", "covariance_p95_end_m"} <= set(o)


def test_design_find_outage(files, capsys):
    m, a, d = files
    code, out, _ = _run(capsys, "design", m, "--imu", "BMI088", "--rate", 20, "--tolerance", 8,
                        "--aiding", a, "--find", "outage", "--json", d / "d.json")
    assert code == 0
    r = json.loads((d / "d.json").read_text())
    assert r["max_outage_s"] > 0 and "max_outage_s" in out
    assert r["common_scale"] > 0 and r["error_budget"]
    code, _, _ = _run(capsys, "design", m, "--imu", "BMI088", "--rate", 20, "--tolerance", 8,
                      "--aiding", a, "--find", "outage", "--outage-start", 25,
                      "--json", d / "d2.json")
    r2 = json.loads((d / "d2.json").read_text())
    assert code == 0 and r2["outage_start_s"] == 25.0
    assert r2["max_outage_s"] >= r["max_outage_s"]        # the default is the worst place


@pytest.mark.parametrize("extra, fragment", [
    (["--find", "outage"], "--find and --outage-start need --aiding"),
    (["--aiding", "A", "--outage-start", "3"], "--outage-start applies to --find outage"),
    (["--aiding", "A", "--find", "outage", "--outage-start", "500"], "--outage-start must be"),
    (["--aiding", "EMPTY"], "no aiding sensor"),
    (["--aiding", "A", "--find", "walk"], "invalid choice"),
])
def test_design_usage_errors(files, capsys, extra, fragment):
    m, a, d = files
    (d / "empty.toml").write_text("")
    extra = [{"A": a, "EMPTY": d / "empty.toml"}.get(x, x) for x in extra]
    code, _, err = _run(capsys, "design", m, "--imu", "BMI088", "--rate", 20, "--tolerance", 8,
                        *extra)
    assert code == 2 and fragment in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("extra, fragment", [
    (["--aiding", "A", "--seed", "3"], "--seed applies to --method montecarlo"),
    (["--aiding", "A", "--method", "montecarlo"], "--method montecarlo needs --runs"),
    (["--covariance-step", "0.5"], "--covariance-step applies with --aiding"),
    (["--aiding", "A", "--json", "A"], "aiding.toml"),
])
def test_assess_usage_errors(files, capsys, extra, fragment):
    m, a, d = files
    extra = [a if x == "A" else x for x in extra]
    code, _, err = _run(capsys, "assess", m, "--imu", "BMI088", "--rate", 20, "--tolerance", 8,
                        *extra)
    assert code == 2 and fragment in err and len(err.strip().splitlines()) == 1, err


def test_assess_aided_on_the_rotating_earth_says_so_and_differs_from_flat(files, capsys):
    """issue 35: `assess --aiding --earth wgs84 --origin …` answers (it was refused), its report
    and JSON name the frame, and its outage answer is the Earth's own (not the flat one's to
    the last digit: Earth rate, transport rate and the gravity gradient are in it)."""
    m, a, d = files
    out = {}
    for frame, extra in (("flat", []), ("wgs84", ["--earth", "wgs84", "--origin", "45,7,300"])):
        code, text, err = _run(capsys, "assess", m, "--imu", "ADIS16470", "--rate", 20,
                               "--tolerance", 5, "--aiding", a, "--json", d / f"{frame}.json",
                               *extra)
        assert code == 0, err
        out[frame] = (text, json.loads((d / f"{frame}.json").read_text()))
    assert "rotating WGS-84 Earth" in out["wgs84"][0] and "(flat frame)" in out["flat"][0]
    assert out["wgs84"][1]["earth"] == "wgs84" and out["flat"][1]["earth"] == "flat"
    e, f = (out[k][1]["outages"][0]["position_p95_max_m"] for k in ("wgs84", "flat"))
    assert e != f and abs(e / f - 1) < 0.5
