"""One verdict ledger: ``figures/reproduction.json`` is the only place a verdict lives.

Each paper notebook's coverage table is an *output* rendered from the ledger
(:func:`imunav.papers.records.coverage_table`); these tests fail when a stored table and the
json disagree, when a record is shown nowhere, when a notebook states a verdict that no record
of the same id carries, or when a verdict is written by hand in a markdown table.
"""

import re
from pathlib import Path

import nbformat
import pytest

from imunav.papers import dickson_rae2021, marusenkova2020, plaksiy, tutorial
from imunav.papers import records as R

ROOT = Path(__file__).resolve().parents[2]
NB = ROOT / "notebooks"
LEDGER = R.load(ROOT / "figures" / "reproduction.json")

PAPERS = {  # notebook → (paper module, record-id prefix)
    "01_marusenkova2020": (marusenkova2020, "marusenkova2020."),
    "02_plaksiy_four_rotation_model": (plaksiy, "plaksiy."),
    "03_gyro_integration_tutorial": (tutorial, "tutorial."),
    "04_dickson_rae2021_blast": (dickson_rae2021, "dickson_rae2021."),
}
PREFIXES = ("quickstart", "marusenkova2020", "plaksiy", "tutorial", "dickson_rae2021")
RECORD_ID = re.compile(r"`((?:" + "|".join(PREFIXES) + r")\.[A-Za-z0-9_.]*[A-Za-z0-9_])`")
# A verdict stated as a verdict: bold, in backticks, in quotes, a table cell, or after the
# word "verdict". (Plain-prose "differs" or "reproduced" is English, not a verdict.)
_V = "|".join(re.escape(v) for v in sorted(R.VERDICTS, key=len, reverse=True))
STATED = re.compile(rf"\*\*({_V})\*\*|`({_V})`|[\"'“‘]({_V})[\"'”’]|\|\s*({_V})\s*\||"
                    rf"[Vv]erdict\W{{1,4}}({_V})\b")


def _notebook(stem):
    return nbformat.read(NB / f"{stem}.ipynb", as_version=4)


def _markdown_outputs(nb):
    for c in nb.cells:
        if c.cell_type != "code":
            continue
        for o in c.get("outputs", []):
            text = o.get("data", {}).get("text/markdown")
            if text:
                yield text if isinstance(text, str) else "".join(text)


def _stated(line):
    return [next(g for g in m.groups() if g) for m in STATED.finditer(line)]


def test_ledger_records_obey_the_rule():
    for rid, r in LEDGER.items():
        assert tuple(r) == R.KEYS, rid
        assert r["verdict"] in R.VERDICTS, rid
        if r["tolerance"] is not None and r["verdict"] in ("reproduced", "differs"):
            assert R.judge(r["paper"], r["imunav"], r["tolerance"]) == r["verdict"], rid
        if r["verdict"] == "consistent with bound":
            assert r["paper"] is not None and r["imunav"] <= r["paper"], rid
        if r["verdict"] == "no paper value":
            assert r["paper"] is None, rid


@pytest.mark.parametrize("stem", PAPERS)
def test_every_record_has_one_coverage_row(stem):
    module, prefix = PAPERS[stem]
    ids = [row[2] for row in module.COVERAGE if row[2] is not None]
    assert len(ids) == len(set(ids)), "a record on two rows"
    missing = set(ids) - set(LEDGER)
    assert not missing, f"coverage rows name records the ledger lacks: {sorted(missing)}"
    unshown = {i for i in LEDGER if i.startswith(prefix)} - set(ids)
    assert not unshown, f"records shown in no coverage row: {sorted(unshown)}"


@pytest.mark.parametrize("stem", PAPERS)
def test_stored_coverage_table_is_the_ledger(stem):
    module, _ = PAPERS[stem]
    tables = [t for t in _markdown_outputs(_notebook(stem)) if R.table_rows(t)]
    assert len(tables) == 1, f"expected one coverage table among the outputs, found {len(tables)}"
    rows = R.table_rows(tables[0])
    assert len(rows) == len(module.COVERAGE), "rows added or lost: re-execute the notebook"
    for cells, spec in zip(rows, module.COVERAGE, strict=True):
        assert len(cells) == len(R.HEADER), cells
        rid = spec[2]
        if rid is None:
            assert cells[4] == "—" and cells[5] == "—", cells
            continue
        r = LEDGER[rid]
        assert cells[4] == f"`{rid}`", cells          # the full record id, on the row
        assert cells[5] == r["verdict"], f"{rid}: table says {cells[5]!r}, ledger {r['verdict']!r}"
        assert cells[2] == R.format_value(r["paper"], r["unit"]), rid
        if r["imunav"] is not None:
            assert R.format_value(r["imunav"], r["unit"]) in cells[3], rid


@pytest.mark.parametrize("stem", PAPERS)
def test_no_verdict_without_its_record(stem):
    """Markdown cells and generated text: a verdict stated on a line needs a record id on the
    same line whose verdict it is; no markdown cell holds a hand-written verdict table."""
    nb = _notebook(stem)
    texts = [("markdown", c.source) for c in nb.cells if c.cell_type == "markdown"]
    texts += [("output", t) for t in _markdown_outputs(nb)]
    for kind, text in texts:
        for line in text.splitlines():
            cells = [c.strip() for c in line.split("|")] if line.startswith("|") else []
            if kind == "markdown":
                assert not any(c in R.VERDICTS for c in cells), \
                    f"hand-written verdict in a markdown table: {line[:100]}"
            stated = _stated(line)
            if not stated:
                continue
            ids = RECORD_ID.findall(line)
            assert ids, f"{kind} states {stated} with no record id: {line[:120]}"
            verdicts = {LEDGER[i]["verdict"] for i in ids if i in LEDGER}
            for v in stated:
                assert v in verdicts, f"{kind} says {v!r} but {ids} say {verdicts}: {line[:120]}"


@pytest.mark.parametrize("stem", PAPERS)
def test_every_record_id_a_notebook_names_exists(stem):
    nb = _notebook(stem)
    text = "\n".join([c.source for c in nb.cells] + list(_markdown_outputs(nb)))
    unknown = {i for i in RECORD_ID.findall(text) if i not in LEDGER}
    assert not unknown, f"{stem} names records the ledger lacks: {sorted(unknown)}"


def test_rendering_round_trips():
    rows = [("a claim with |x|", "§1", next(iter(LEDGER)), None), ("no record", "§2", None, "x")]
    md = R.coverage_table(rows, LEDGER)
    cells = R.table_rows(md)
    assert [len(c) for c in cells] == [6, 6]
    assert cells[0][5] == LEDGER[rows[0][2]]["verdict"] and cells[1][5] == "—"
    with pytest.raises(KeyError, match="ledger lacks"):
        R.coverage_table([("c", "§", "plaksiy.no_such_record", None)], LEDGER)


def test_the_checks_catch_a_disagreement():
    """The detectors themselves: a wrong verdict on a line, a verdict with no id."""
    rid = "plaksiy.table1.ordering"
    wrong = "reproduced" if LEDGER[rid]["verdict"] != "reproduced" else "differs"
    line = f"The ranking `{rid}` is **{wrong}**."
    assert _stated(line) == [wrong]
    assert wrong not in {LEDGER[i]["verdict"] for i in RECORD_ID.findall(line)}
    assert _stated('Figs. 1–2 are "not reproducible" as numbers.') == ["not reproducible"]
    assert _stated("| claim | 3 | reproduced |") == ["reproduced"]
    assert _stated("the verdict: differs") == ["differs"]
    assert _stated("the exact value differs by 1.3 %") == []
    assert _stated("the rule: *consistent with bound* where the paper gives a bound") == []


@pytest.mark.parametrize("module", [tutorial, plaksiy], ids=lambda m: m.__name__.rsplit(".", 1)[1])
def test_the_stored_ledger_is_what_the_code_computes(module, tmp_path):
    """`imunav reproduce` was re-run after the last change: every record the paper module
    computes now is the stored one (numbers to 1e-9 relative or below the rounding floor,
    verdict and why verbatim). The two quick modules here (7 s); the records of Marusenkova and
    Dickson & Rae (30 s) are held to the ledger by the check cells of notebooks 01 and 04,
    which nbval re-runs."""
    fresh = module.reproduce(tmp_path)
    for r in fresh:
        s = LEDGER.get(r["id"])
        assert s is not None, f"{r['id']} is computed but not stored: run imunav reproduce"
        for k in ("verdict", "why", "unit", "paper", "tolerance"):
            assert r[k] == s[k], f"{r['id']}: {k} {r[k]!r} ≠ stored {s[k]!r}"
        a, b = r["imunav"], s["imunav"]
        if a is None or b is None:
            assert a is b, r["id"]
        elif max(abs(a), abs(b)) >= R.ROUNDING_FLOOR:
            assert a == pytest.approx(b, rel=1e-9), f"{r['id']}: imunav {a!r} ≠ stored {b!r}"
    prefix = module.__name__.rsplit(".", 1)[1] + "."
    stored = {i for i in LEDGER if i.startswith(prefix)}
    assert stored <= {r["id"] for r in fresh}, "stored records the code no longer computes"
