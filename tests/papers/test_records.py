"""Reproduction records: the format every paper module writes, and the stored file."""

import json
from pathlib import Path

import pytest

from imunav.papers.records import (
    KEYS,
    VERDICTS,
    judge,
    judge_bound,
    printed_precision,
    record,
)

STORED = Path(__file__).resolve().parents[2] / "figures" / "reproduction.json"
REQUIRED = {  # ids issues 15 and 23 name: each must be in the stored file with its verdict
    "plaksiy.table1.ordering": "differs",
    "plaksiy.table1.ordering.exact": "differs",
    "marusenkova2020.partA.gyro_is_minus_omega_n": "differs",
    "marusenkova2020.claim.xy_coincidence": "differs",
    "marusenkova2020.claim.omega_asymmetry": "differs",
    "marusenkova2020.claim.dcm_amendable": "differs",
    # issue 38: a conclusion without a paper number and a tolerance "holds" (no longer
    # "reproduced"); the judgement is the same
    "marusenkova2020.claim.quaternion_beats_dcm": "holds",
    # issue 23's re-judged verdicts
    "dickson_rae2021.synthetic.final_orientation_error_deg": "not reproducible",  # its own event
    "plaksiy.table1.miller_33_57.series4": "differs",
    "plaksiy.claim.chi_minus_psi_vibration": "holds",
    "marusenkova2020.conclusion1.classic_erroneous_at_1000hz": "holds",
    "marusenkova2020.observation3.threshold_frequency": "not reproducible",
}
PREFIXES = ("dickson_rae2021.multi_event.", "dickson_rae2021.large_shift.",
            "tutorial.unnormalised.")


def test_record_rejects_what_is_not_a_verdict():
    with pytest.raises(ValueError, match="verdict"):
        record("x.y", "q", 1.0, 1.0, "m", "reproduces", "because")
    with pytest.raises(ValueError, match="no paper value"):
        record("x.y", "q", 1.0, 1.0, "m", "no paper value", "because")
    with pytest.raises(ValueError, match="why"):
        record("x.y", "q", None, 1.0, "m", "no paper value", " ")


def test_reproduced_needs_a_paper_number_and_a_tolerance():
    """Issue 38: 26 of 35 'reproduced' verdicts had no paper value or tolerance behind them."""
    with pytest.raises(ValueError, match="needs the paper's number and a tolerance"):
        record("x.y", "q", None, 1.0, "m", "reproduced", "the claim holds")
    with pytest.raises(ValueError, match="needs the paper's number and a tolerance"):
        record("x.y", "q", 1.0, 1.0, "m", "reproduced", "as printed")
    assert record("x.y", "q", None, 1.0, "m", "holds", "the claim holds")["verdict"] == "holds"
    recs = json.loads(STORED.read_text())
    for r in recs:
        if r["verdict"] == "reproduced":
            assert r["paper"] is not None and r["tolerance"] is not None, r["id"]
            assert judge(r["paper"], r["imunav"], r["tolerance"]) == "reproduced", r["id"]


def test_record_enforces_the_verdict_rule():
    # a numeric verdict must be what the tolerance says
    assert judge(1.0, 1.004, 0.005) == "reproduced" and judge(1.0, 1.006, 0.005) == "differs"
    record("x.y", "q", 1.0, 1.004, "m", "reproduced", "within", tolerance=0.005)
    with pytest.raises(ValueError, match="contradicts the tolerance"):
        record("x.y", "q", 1.0, 1.006, "m", "reproduced", "within", tolerance=0.005)
    with pytest.raises(ValueError, match="tolerance needs"):
        record("x.y", "q", None, 1.0, "m", "differs", "why", tolerance=0.01)
    # a bound is satisfied or it is not
    assert judge_bound(3.0, 0.45) == "consistent with bound" and judge_bound(3.0, 4.0) == "differs"
    with pytest.raises(ValueError, match="does not satisfy"):
        record("x.y", "q", 3.0, 4.0, "deg", "consistent with bound", "why")
    with pytest.raises(ValueError, match="id must be"):
        record("No Dots", "q", None, 1.0, "m", "no paper value", "why")
    # printed precision: half a unit of the last digit
    assert printed_precision(-2.63e-4, 3) == pytest.approx(0.005 / 2.63, rel=1e-12)
    assert printed_precision(1.616e-3, 4) == pytest.approx(0.0005 / 1.616, rel=1e-12)


def test_stored_records():
    recs = json.loads(STORED.read_text())
    ids = [r["id"] for r in recs]
    assert len(ids) == len(set(ids)), "duplicate ids"
    for r in recs:
        assert tuple(r) == KEYS
        assert r["verdict"] in VERDICTS and r["why"].strip(), r["id"]
        assert r["verdict"] != "no paper value" or r["paper"] is None, r["id"]
        assert "reproduces" not in r["why"] or r["verdict"] == "reproduced", r["id"]
    by = {r["id"]: r for r in recs}
    for rid, verdict in REQUIRED.items():
        assert by[rid]["verdict"] == verdict, rid
    for p in PREFIXES:
        assert any(i.startswith(p) for i in ids), p
