"""The aided design (issues 29 and 38): the limit of each IMU term with these aids and every
preset ranked, as the unaided design gives them; the longest outage as the gap from the last
fix used to the next, its verdict by the probability over the whole outage, and the search
that reuses one walk keeping the old search's per-epoch numbers.

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
from imunav.analysis import crossing as X
from imunav.analysis import outage as O
from imunav.analysis.assessment import runs_interval
from imunav.analysis.gaussnorm import norm_quantile
from imunav.cli import main
from imunav.estimation.error_model import DP
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel

ROOT = Path(__file__).resolve().parents[2]
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
        _, truth, _, (o,), _ = A.outage_pass(at, [OUTAGE], tolerance=10.0)
        assert r["max_p95_position_m"] == pytest.approx(truth.max(), rel=1e-9)
        assert r["final_p95_position_m"] == pytest.approx(truth[-1], rel=1e-9)
        # suitable: the p95 within at every epoch and the outage within at every epoch with
        # a probability of at least 95 %
        assert r["suitable"] == (truth.max() <= 10.0 and o["p_within_whole_outage"] >= 0.95)
        assert r["p_within_whole_outages"] == [o["p_within_whole_outage"]]
        f = O.find_outage(drive, imu, aiding, RATE, 10.0, DURATION, budget=False)
        assert r["max_outage_s"] == f["max_outage_s"]
        assert r["max_outage_s"] == r["next_fix_s"] - r["last_fix_s"]
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


def _objects_with(obj, key):
    """Every dict in a JSON document that carries ``key``."""
    if isinstance(obj, dict):
        yield from ([obj] if key in obj else [])
        for v in obj.values():
            yield from _objects_with(v, key)
    elif isinstance(obj, list):
        for v in obj:
            yield from _objects_with(v, key)


def test_max_outage_s_is_the_gap_from_the_last_fix_to_the_next(tmp_path, capsys):
    """Issue 38: "max_outage_s = 30 s" removed the fixes from 30 to 60 s inclusive, a gap of
    32 s between the last fix used and the next. Now every object of the JSON that carries
    max_outage_s carries last_fix_s and next_fix_s, fixes of the record, with max_outage_s ==
    next_fix_s − last_fix_s; the fixes lost are those between them, and written as the aiding
    file's outage they give the same window in an independent assessment."""
    (tmp_path / "m.toml").write_text(MOTION)
    (tmp_path / "a.toml").write_text(AIDING)
    assert main(["design", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "8", "--aiding", str(tmp_path / "a.toml"), "--find", "outage",
                 "--json", str(tmp_path / "d.json")]) == 0
    out = capsys.readouterr().out
    r = json.loads((tmp_path / "d.json").read_text())
    objs = list(_objects_with(r, "max_outage_s"))
    assert len(objs) == 1 + 6                             # the answer and each preset's
    for o in objs:
        assert o["max_outage_s"] == o["next_fix_s"] - o["last_fix_s"], o
        assert o["last_fix_s"] == int(o["last_fix_s"])     # 1 Hz fixes from 1 s on
        assert 0 <= o["p_within_whole_outage"] <= 1
    assert not r["limited_by_motion"] and r["max_outage_s"] >= 2
    assert r["tolerance_on"].startswith("3-D")            # the JSON says which error
    assert r["gnss_outage_s"] == [r["last_fix_s"] + 1, r["next_fix_s"] - 1]
    assert r["outage_start_s"] == r["gnss_outage_s"][0]
    assert f"max_outage_s = {r['max_outage_s']:g} s, from the last fix at " \
           f"{r['last_fix_s']:g} s to the next at {r['next_fix_s']:g} s" in out
    # the outage written into the aiding file: the same window, within the tolerance
    (tmp_path / "b.toml").write_text(AIDING.replace("[[20, 28]]", str([r["gnss_outage_s"]])))
    assert main(["assess", str(tmp_path / "m.toml"), "--imu", "ADIS16470", "--rate", "20",
                 "--tolerance", "8", "--aiding", str(tmp_path / "b.toml"), "--json",
                 str(tmp_path / "s.json")]) == 0
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["tolerance_on"] == r["tolerance_on"]
    (o,) = s["outages"]
    assert (o["last_fix_s"], o["next_fix_s"]) == (r["last_fix_s"], r["next_fix_s"])
    assert o["within_tolerance"] and o["p_within_whole_outage"] >= 0.95
    assert o["position_p95_end_m"] == pytest.approx(r["position_p95_end_m"], rel=1e-9)


def _old_search(at, cand, tol):
    """The outage search before issue 38 (imunav 2a84d81 ``lost_from`` and ``find_outage``),
    kept as the reference: per start, the p95 criterion, the outage ``[s, s + L]`` (fixes
    ``s ≤ t ≤ s + L`` lost). Returns each start's ``L`` (None when the motion cuts it)."""
    wf, wt, _ = at.weights()
    E = at.t.size - 1
    base = A.active_fixes(at, [[]])
    step = max(1, int(round(10.0 / np.diff(at.t).mean())))
    out, e0, P = [], 0, None
    for s0 in cand:
        e_b = max(0, int(np.searchsorted(at.t, s0 - 1e-9)) - 1)
        P = (at.propagate(wf, wt, base, stop=e_b, keep=False).final if P is None else
             at.propagate(wf, wt, base, start=e0, stop=e_b, P_start=P, keep=False).final)
        e0 = e_b
        act = A.active_fixes(at, [[(float(s0), float(at.t[-1]) + 1.0)]])
        Pc, e, t_over = P, e_b, None
        while e < E and t_over is None:
            stop = min(E, e + step)
            res = at.propagate(wf, wt, act, start=e, stop=stop, P_start=Pc)
            over = O.exceeds(res.truth_post[0, 0][1:][:, DP, DP], tol)
            if over.any():
                t_over = res.t[1:][np.nonzero(over)[0][0]]
            Pc, e = res.final, stop
        out.append(None if t_over is None else
                   max(int(np.floor((t_over - s0) / 1.0 + 1e-9)) - 1, -1) * 1.0)
    return out


def test_the_search_keeps_the_old_search_per_epoch_numbers(drive):
    """Issue 39: the search walks every start in one loop from one baseline pass (no pass per
    start). Its per-epoch p95 lengths are the old search's, start by start, in the new
    semantics: the old outage [s, s + L] is the gap from the fix before s to the one after
    s + L, L + 2 GNSS intervals."""
    imu = ImuModel.load("BMI088")
    aiding = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                              "velocity_sigma": 0.1},
                                     "nhc": {"sigma": 0.1, "rate": 10}})
    at = A.aided_covariance(drive, imu, aiding, RATE, 150.0)
    tol = 10.0
    cand = np.array([20.0, 31.0, 47.0, 60.0, 85.0, 100.0])
    old = _old_search(at, cand, tol)
    tg = A.gnss_times(at)
    e = np.searchsorted(at.t, cand - 1.0 - 1e-9)
    wins = X.walk(at, e, O.baseline_states(at, e), tol, samples=64, decide=True)
    checked = 0
    for s0, L_old, w in zip(cand, old, wins, strict=True):
        new = O.outage_lengths(w, s0 - 1.0, s0, tg, float(at.t[-1]))
        if L_old is None:
            assert new["limited_by_motion_p95"]
            continue
        assert new["next_fix_p95_s"] - (s0 - 1.0) == L_old + 2.0, (s0, L_old, new)
        checked += 1
    assert checked >= 4


def test_the_verdict_uses_the_whole_outage_probability(drive):
    """A 46 s outage (GNSS and NHC, the filter settled) at a tolerance just above its largest
    p95: within the tolerance at every epoch by the per-epoch reading — the old verdict — but
    the probability of staying within it at every epoch is below 95 %: BEYOND, NOT SUITABLE;
    and the longest outage from that start is shorter than the per-epoch p95's."""
    imu = ImuModel.load("BMI088")
    out = (31.0, 75.0)
    aiding = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                              "velocity_sigma": 0.1, "outages": [list(out)]},
                                     "nhc": {"sigma": 0.1, "rate": 10}})
    at = A.aided_covariance(drive, imu, aiding, RATE, 77.0)
    (o0,) = A.outage_p95(at, [out])[3]
    tol = 1.001 * o0["position_p95_max_m"]
    r = A.assess_aided(drive, imu, aiding, RATE, tol, 77.0, budget=False, progress=False)
    (o,) = r["outages"]
    assert o["position_p95_max_m"] <= tol and r["max_p95_position_m"] <= tol   # per epoch: in
    assert o["p_within_whole_outage"] < 0.95 - 3 * o["p_within_whole_outage_se"]
    assert not o["within_tolerance"] and not r["suitable"]
    assert not r["outages_within_tolerance"]
    text = A.format_aided_verdict(r)
    assert "NOT SUITABLE" in text and "BEYOND the tolerance" in text
    assert f"probability {100 * o['p_within_whole_outage']:.1f} %" in text
    f = O.find_outage(drive, imu, aiding, RATE, tol, 77.0, at=at, start=31.0, budget=False)
    assert f["last_fix_s"] == 30.0 and f["max_outage_p95_s"] >= 46.0
    assert f["max_outage_s"] < f["max_outage_p95_s"] and f["p_within_whole_outage"] >= 0.95


def test_assess_monte_carlo_prints_its_intervals(tmp_path, capsys):
    """Every Monte Carlo confirmation prints its 95 % interval: the fraction of runs within
    the tolerance at every epoch of the outage with its Clopper–Pearson interval, the p95 at
    its end with its order-statistic one (none above it from 40 runs: said so, null in the
    JSON); the covariance's sampled probability with its standard error."""
    (tmp_path / "m.toml").write_text(MOTION)
    (tmp_path / "a.toml").write_text(AIDING)
    assert main(["assess", str(tmp_path / "m.toml"), "--imu", "BMI088", "--rate", "20",
                 "--tolerance", "4", "--aiding", str(tmp_path / "a.toml"), "--runs", "40",
                 "--json", str(tmp_path / "r.json")]) == 0
    out = capsys.readouterr().out
    r = json.loads((tmp_path / "r.json").read_text())
    (o,) = r["outages"]
    k = round(o["p_within_whole_outage"] * 40)
    assert o["p_within_whole_outage"] == k / 40
    lo, hi = runs_interval(k, 40)
    assert o["p_within_whole_outage_interval"] == [lo, hi]
    assert f"[{100 * lo:.1f}–{100 * hi:.1f} %, 95 % Clopper–Pearson]" in out
    qlo, qhi = o["position_p95_end_interval_m"]
    assert qhi is None and qlo <= o["position_p95_end_m"]
    assert "95 % order statistics; too few runs for a bound on each side" in out
    assert "covariance_p_within_whole_outage" in o
    assert main(["assess", str(tmp_path / "m.toml"), "--imu", "BMI088", "--rate", "20",
                 "--tolerance", "4", "--aiding", str(tmp_path / "a.toml")]) == 0
    out = capsys.readouterr().out
    assert "% (± " in out and "sampled)" in out
