"""The aided design (issue 29): the limit of each IMU term with these aids and every preset
ranked, as the unaided design gives them.

A term's limit (the filter retuned to it) is checked against an independent analysis: a fresh
aided covariance of the IMU with that term set to its limit — the filter built from that IMU,
as ``imunav filter --imu`` would — whose largest p95 through the outage must be the tolerance
within 1 %. The limit with the filter kept at the IMU's own tuning is checked by a pass with
weights built here (the term's variances times k², the filter's untouched). The presets'
table is checked against each preset's own pass and outage search.

Reduced in size (the first 60 s of the example drive at 50 Hz, one 15 s outage).
"""

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from imunav.analysis import aided_assessment as A
from imunav.analysis import aided_design as D
from imunav.analysis import outage as O
from imunav.analysis.gaussnorm import norm_quantile
from imunav.cli import main
from imunav.estimation.error_model import DP
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel

ROOT = Path(__file__).resolve().parents[1]
RATE, DURATION = 50.0, 60.0
OUTAGE = (20.0, 35.0)


@pytest.fixture(scope="module")
def drive():
    return load_motion(ROOT / "examples" / "drive.toml")[0]


@pytest.fixture(scope="module")
def aiding():
    return AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                            "velocity_sigma": 0.1, "outages": [list(OUTAGE)]}})


@pytest.fixture(scope="module")
def adis(drive, aiding):
    imu = ImuModel.load("ADIS16470")
    at = A.aided_covariance(drive, imu, aiding, RATE, DURATION, terms=True)
    return imu, at, D.term_limits(at, 10.0, [OUTAGE])


def _with(imu: ImuModel, term: str, value: float) -> ImuModel:
    triad, _, name = term.partition(".")
    return dataclasses.replace(imu, **{triad: getattr(imu, triad).replace(**{name: value})})


@pytest.mark.parametrize("term", ["gyro.bias_instability", "accel.noise_density"])
def test_a_term_at_its_limit_meets_the_tolerance_in_a_fresh_analysis(drive, aiding, adis, term):
    imu, _, limits = adis
    lim = limits[term]
    base = getattr(getattr(imu, term.split(".")[0]), term.split(".")[1])
    assert lim["limit_si"] > base                # this IMU passes (5.7 m), so it may be worse
    at = A.aided_covariance(drive, _with(imu, term, lim["limit_si"]), aiding, RATE, DURATION)
    worst = A.outage_p95(at, [OUTAGE])[1].max()
    assert 0.99 * 10.0 <= worst <= 10.0, (term, lim, worst)
    assert lim["max_p95_at_limit_m"] == pytest.approx(worst, rel=1e-6)


def test_the_limit_with_the_filter_kept_at_the_base_tuning(adis):
    imu, at, limits = adis
    names = [i.name for i in at.ingredients]
    act = A.active_fixes(at, [[OUTAGE]])
    for term in ("gyro.bias_instability", "accel.noise_density"):
        lim = limits[term]
        triad, _, name = term.partition(".")
        k = lim["limit_base_tuning_si"] / getattr(getattr(imu, triad), name)
        # the filter at this IMU's tuning: every ingredient at 1 (no aid state to leave out);
        # the truth starts at zero (the runs start at the true state) with the term times k²
        assert all(i.kind != "aid" for i in at.ingredients)
        wf = np.ones(len(names))
        wt = np.array([[0.0 if i.kind == "initial" else (k * k if n == term else 1.0)
                        for n, i in zip(names, at.ingredients, strict=True)]])
        worst = norm_quantile(at.propagate(wf, wt, act).truth_post[0, 0][:, DP, DP],
                              0.95).max()
        assert worst == pytest.approx(10.0, rel=1e-4), term
        # retuned to the worse term, the filter does at least as well: its limit is larger
        assert lim["limit_si"] >= 0.99 * lim["limit_base_tuning_si"]


def test_no_limit_when_the_other_sources_alone_exceed_the_tolerance(drive, aiding):
    imu = ImuModel.load("BMI088")
    at = A.aided_covariance(drive, imu, aiding, RATE, DURATION, terms=True)
    limits = D.term_limits(at, 15.0, [OUTAGE])
    lim = limits["gyro.noise_density"]
    assert lim["limit_si"] == 0.0 and "alone exceed" in lim["note"]
    # the term nearly gone, the filter tuned to it, the rest still exceeds 15 m
    tiny = A.aided_covariance(drive, _with(imu, "gyro.noise_density", 1e-9), aiding, RATE,
                              DURATION)
    assert A.outage_p95(tiny, [OUTAGE])[1].max() > 15.0


def test_presets_ranked_through_the_outages(drive, aiding):
    names = ["BMI088", "tactical", "ADIS16470"]
    rows = D.rank_presets(drive, aiding, RATE, 10.0, DURATION, presets=names, find="outage")
    assert [r["name"] for r in rows] == ["tactical", "ADIS16470", "BMI088"]
    for r in rows:
        imu = ImuModel.load(r["name"])
        at = A.aided_covariance(drive, imu, aiding, RATE, DURATION)
        _, truth, _, _ = A.outage_p95(at, [OUTAGE])
        assert r["max_p95_position_m"] == pytest.approx(truth.max(), rel=1e-9)
        assert r["final_p95_position_m"] == pytest.approx(truth[-1], rel=1e-9)
        assert r["suitable"] == (truth.max() <= 10.0)
        f = O.find_outage(drive, imu, aiding, RATE, 10.0, DURATION, budget=False)
        assert r["max_outage_s"] == f["max_outage_s"]
    assert rows[0]["suitable"] and not rows[-1]["suitable"]


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
"""
AIDING = """[gnss]
rate = 1
position_sigma = 1.5
velocity_sigma = 0.1
outages = [[20, 28]]
"""


def test_cli_design_aiding_prints_and_writes_the_unaided_keys(tmp_path, capsys):
    (tmp_path / "m.toml").write_text(MOTION)
    (tmp_path / "a.toml").write_text(AIDING)
    code = main(["design", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "8", "--aiding", str(tmp_path / "a.toml"), "--find", "outage",
                 "--json", str(tmp_path / "d.json")])
    out = capsys.readouterr().out
    assert code == 0
    r = json.loads((tmp_path / "d.json").read_text())
    assert r["max_outage_s"] > 0
    # the keys of the unaided design's JSON, so one script reads both
    assert r["terms"] and all({"limit_si", "limit", "base"} <= set(v)
                              for v in r["terms"].values())
    assert [p["name"] for p in r["presets"]][0] in ("ideal", "tactical")
    assert all({"name", "final_p95_position_m", "suitable", "warnings", "max_p95_position_m",
                "max_outage_s"} <= set(p) for p in r["presets"])
    assert len(r["presets"]) == 6
    assert "Largest value of each IMU term" in out and "Presets, best first" in out
    for p in r["presets"]:
        assert any(line.split()[:1] == [p["name"]] for line in out.splitlines())


def test_a_preset_beyond_the_linearisation_ranks_last(drive):
    """Through the drive's 60 s tunnel the MPU-6050's covariance says 14 m, the BNO055's 23 m;
    but the MPU-6050's attitude error leaves the linearisation (its turn-on bias), so its
    small number is not the real EKF's: it ranks last, flagged."""
    aiding = AidingConfig.from_toml(ROOT / "examples" / "drive_aiding.toml")
    rows = D.rank_presets(drive, aiding, 20.0, 10.0, 240.0, presets=["MPU-6050", "BNO055"])
    assert [r["name"] for r in rows] == ["BNO055", "MPU-6050"]
    assert rows[1]["outside_linearisation"] and not rows[0]["outside_linearisation"]
    assert rows[1]["max_p95_position_m"] < rows[0]["max_p95_position_m"]


def test_a_gain_error_beyond_the_small_error_model_is_flagged(adis):
    _, _, limits = adis
    acc = limits["accel.misalignment"]
    assert acc["limit_si"] > D.GAIN_VALID and "small-error model" in acc["note"]
    assert limits["gyro.noise_density"]["note"] is None


def test_limit_words_agree_between_text_and_json(adis):
    """A newcomer read 'none' in the table where the JSON said '0 deg/h', and 'unbounded' in
    the table where the JSON said 'none': one word per meaning, in both."""
    imu, at, _ = adis
    zero = D.term_limits(at, 0.5, [OUTAGE])                 # far below what any term allows
    big = D.term_limits(at, 1e9, [OUTAGE])                  # far above the whole error
    z = zero["gyro.noise_density"]
    assert z["limit_si"] == 0.0 and z["limit"].startswith("0 ")
    u = big["gyro.noise_density"]
    assert u["limit_si"] is None and u["limit"] == "unbounded"
    r = {"motion": "m", "imu": imu.name, "rate_hz": RATE, "tolerance_m": 0.5, "aiding": ["gnss"],
         "terms": {"gyro.noise_density": z, "accel.noise_density": big["accel.noise_density"]},
         "warnings": []}
    text = D.format_outage_design(r)
    row = [ln for ln in text.splitlines() if "gyro.noise_density" in ln][0]
    assert " none " not in row and "0 °/√h" in row                  # the printed spelling
    row = [ln for ln in text.splitlines() if "accel.noise_density" in ln][0]
    assert "unbounded" in row and "µg/√Hz" in row


def test_an_outage_start_with_no_fix_after_it_is_refused(tmp_path, capsys):
    """`--outage-start 19.5` on a 20 s record with 1 Hz fixes ran 'max_outage_s = 0 s … the
    whole rest of the motion' and exit 0; and it is refused before the term limits' passes."""
    (tmp_path / "m.toml").write_text(MOTION)
    (tmp_path / "a.toml").write_text(AIDING.replace("outages = [[20, 28]]\n", ""))
    code = main(["design", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "8", "--aiding", str(tmp_path / "a.toml"), "--find", "outage",
                 "--outage-start", "39.5", "--json", str(tmp_path / "d.json")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "--outage-start" in err and "no GNSS fix after it" in err
    assert not (tmp_path / "d.json").exists()


def test_outages_that_cover_every_fix_are_said_and_design_outages_carry_within(tmp_path):
    """`outages = [[0, 20]]` on a 20 s record passed as 'GNSS outage 0–20 s … within the
    tolerance' with no word that GNSS never helped; design's outages lacked assess'
    `within_tolerance`."""
    (tmp_path / "m.toml").write_text(MOTION)
    end = float(load_motion(tmp_path / "m.toml")[0].duration)
    (tmp_path / "a.toml").write_text(AIDING.replace("[[20, 28]]", f"[[0, {end:g}]]"))
    assert main(["design", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "50", "--aiding", str(tmp_path / "a.toml"), "--json",
                 str(tmp_path / "d.json")]) == 0
    r = json.loads((tmp_path / "d.json").read_text())
    assert any("cover every fix" in w for w in r["warnings"])
    assert all("within_tolerance" in o for o in r["outages"])
    assert main(["assess", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "50", "--aiding", str(tmp_path / "a.toml"), "--json",
                 str(tmp_path / "s.json")]) == 0
    assert any("cover every fix" in w for w in json.loads((tmp_path / "s.json").read_text())
               ["warnings"])


def test_an_aid_faster_than_the_imu_is_refused(tmp_path, capsys):
    """`[gnss] rate = 25` beside a 20 Hz IMU ran (exit 0, a better p95 from readings the filter
    cannot take one by one); 40 Hz gave a message about 'node 0' without the key."""
    (tmp_path / "m.toml").write_text(MOTION)
    (tmp_path / "a.toml").write_text(AIDING.replace("rate = 1\n", "rate = 25\n"))
    code = main(["assess", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "8", "--aiding", str(tmp_path / "a.toml")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "[gnss] rate = 25 Hz is above the IMU rate of 20 Hz" in err and "a.toml" in err
