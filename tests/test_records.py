"""Reproduction records: the format every paper module writes, and the stored file."""

import json
from pathlib import Path

import pytest

from imunav.papers.records import VERDICTS, record

STORED = Path(__file__).resolve().parents[1] / "figures" / "reproduction.json"
REQUIRED = {  # ids issue 15 names: each must be in the stored file with its verdict
    "plaksiy.table1.ordering": "differs",
    "marusenkova2020.partA.gyro_is_minus_omega_n": "differs",
    "marusenkova2020.claim.xy_coincidence": "differs",
    "marusenkova2020.claim.omega_asymmetry": "differs",
    "marusenkova2020.claim.dcm_amendable": "differs",
    "marusenkova2020.claim.quaternion_beats_dcm": "reproduced",
}
PREFIXES = ("dickson_rae2021.multi_event.", "dickson_rae2021.large_shift.",
            "tutorial.unnormalised.")


def test_record_rejects_what_is_not_a_verdict():
    with pytest.raises(ValueError, match="verdict"):
        record("x", "q", 1.0, 1.0, "m", "reproduces", "because")
    with pytest.raises(ValueError, match="no paper value"):
        record("x", "q", 1.0, 1.0, "m", "no paper value", "because")
    with pytest.raises(ValueError, match="why"):
        record("x", "q", None, 1.0, "m", "no paper value", " ")


def test_stored_records():
    recs = json.loads(STORED.read_text())
    ids = [r["id"] for r in recs]
    assert len(ids) == len(set(ids)), "duplicate ids"
    for r in recs:
        assert set(r) == {"id", "quantity", "paper", "imunav", "unit", "verdict", "why", "note"}
        assert r["verdict"] in VERDICTS and r["why"].strip(), r["id"]
        assert r["verdict"] != "no paper value" or r["paper"] is None, r["id"]
        assert "reproduces" not in r["why"] or r["verdict"] == "reproduced", r["id"]
    by = {r["id"]: r for r in recs}
    for rid, verdict in REQUIRED.items():
        assert by[rid]["verdict"] == verdict, rid
    for p in PREFIXES:
        assert any(i.startswith(p) for i in ids), p
