"""The real recordings with truth (issue 36), smallest piece: one outage of the rtklibexplorer
drive and two PyShoe walks through ``benchmarks/realdata.py``'s pipeline (what ``imunav filter``
runs on a log). The recordings are not part of the repository: the test runs when
``../shared/data`` holds them and is skipped, with the reason, otherwise."""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data"

pytestmark = pytest.mark.skipif(
    not ((DATA / "rtklib_drive").is_dir() and (DATA / "pyshoe_vicon").is_dir()),
    reason=f"the real recordings are not in {DATA} (not part of the repository)")


def _bench():
    spec = importlib.util.spec_from_file_location("realdata", ROOT / "benchmarks" / "realdata.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_first_outage_of_the_drive_and_two_walks():
    """The first outage within the author's worst (12.8 m) and inside the filter's own 95 %
    ellipse; the smoother within his velocity matching's worst (0.68 m); on the two walks the
    dataset's labels within 1.25 × the authors' per-walk tuned SHOE and imunav's own detector
    (one parameter set) within twice it — a gross-failure check: the issue's targets are on all
    19 walks (benchmarks/results_realdata.json)."""
    b = _bench()
    d = b.drive(DATA, quick=True)
    assert d["outage_max_horizontal_m"]["worst"] <= 12.8
    assert d["smoother_outage_max_horizontal_m"]["worst"] <= 0.68
    assert d["inside_95"] >= 0.8
    w = b.walks(DATA, quick=True)
    assert len(w["per_walk"]) == 2
    assert w["armse2d_labels"]["median"] <= 1.25 * w["paper_shoe"]["median"]
    assert w["armse2d_own"]["median"] <= 2.0 * w["paper_shoe"]["median"]
