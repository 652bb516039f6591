"""Reproduction records — the one verdict ledger — and the coverage tables rendered from it.

A record is ``{"id", "quantity", "paper", "imunav", "unit", "tolerance", "verdict", "why",
"note"}``: one number (or one conclusion) of a paper beside imunav's. ``paper`` is None (JSON
null) where the paper prints no number; ``tolerance`` is the relative tolerance of a numeric
comparison (None where nothing numeric is compared). Every paper module's ``reproduce(out)``
returns its records; :mod:`imunav.reproduce` writes them all to ``figures/reproduction.json``,
the single source of every verdict. The notebooks' coverage tables and verdict lines are
rendered from that file (:func:`coverage_table`, :func:`verdict_line`), never written by hand.

The verdict rule (:data:`VERDICTS`; the same text is in the README):

``reproduced``
    A paper *number*: imunav's agrees within the record's ``tolerance``, fixed before the
    comparison. The tolerance is the printed precision of the paper's number (half a unit of
    its last digit) or, where the paper leaves part of its method open (a drift measure, an
    update form), wider — but never wider than the differences the paper's own conclusion
    rests on: at most half the smallest gap between values it ranks or compares, so that any
    values within tolerance keep the paper's order. :func:`judge` applies it. Only a record
    with the paper's number *and* a tolerance can say ``reproduced`` (issue 38).
``holds``
    A paper *statement* that gives no number to compare within a tolerance — a conclusion, a
    ranking, a sign, an identity ("exact", "not zero"), one of its caveats, an equation once
    its typesetting slips are restored: the computation shows it holds. The ``why`` says
    what holds, with the deciding number (a paper ratio beside it is context, not compared).
``consistent with bound``
    The paper's value is an upper bound, not a measurement, on a quantity imunav computes for
    the same case: imunav's value is below it. A bound is not reproduced by a number below
    it; :func:`judge_bound`. A bound on the paper's own unpublished data (Dickson & Rae's
    "< 3°" on their event) is ``not reproducible``: a synthetic event meets or breaks it as
    its design decides.
``differs``
    Outside the tolerance, or the computation reverses the conclusion or contradicts the
    statement.
``not reproducible``
    The paper lacks what would settle it (its data, a motion law, a method): whatever imunav
    computes with its own choice is shown, but it cannot confirm or refute the paper, so it is
    never ``differs``.
``no paper value``
    imunav's own number beside a figure, equation or claim that gives none.

``why`` is one sentence saying what settles the verdict, with the deciding number.

May import: nothing from imunav.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

VERDICTS = ("reproduced", "holds", "consistent with bound", "differs", "not reproducible",
            "no paper value")
KEYS = ("id", "quantity", "paper", "imunav", "unit", "tolerance", "verdict", "why", "note")

#: The stored ledger of a source checkout (``imunav reproduce --out figures`` writes it).
LEDGER = Path(__file__).resolve().parents[2] / "figures" / "reproduction.json"

_ID = re.compile(r"^[a-z0-9_]+(\.[A-Za-z0-9_]+)+$")


def relative_difference(paper: float, imunav: float) -> float:
    """|imunav − paper| / |paper| (inf when the paper's value is 0 and imunav's is not)."""
    if paper == 0:
        return 0.0 if imunav == 0 else math.inf
    return abs(imunav - paper) / abs(paper)


def judge(paper: float, imunav: float, tolerance: float) -> str:
    """``reproduced`` if imunav's number is within ``tolerance`` (relative) of the paper's,
    else ``differs`` — the rule for a paper number."""
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0 (relative), got {tolerance!r}")
    return "reproduced" if relative_difference(paper, imunav) <= tolerance else "differs"


def judge_bound(bound: float, imunav: float, kind: str = "upper") -> str:
    """``consistent with bound`` if imunav's value satisfies the paper's bound (``kind``
    ``"upper"``: imunav ≤ bound; ``"lower"``: imunav ≥ bound), else ``differs``."""
    if kind not in ("upper", "lower"):
        raise ValueError(f"kind must be 'upper' or 'lower', got {kind!r}")
    ok = imunav <= bound if kind == "upper" else imunav >= bound
    return "consistent with bound" if ok else "differs"


def printed_precision(value: float, digits: int) -> float:
    """Half a unit of the last printed digit of ``value`` printed with ``digits`` significant
    digits, relative to the value: −2.63e−4 (3 digits) → 0.005e−4 / 2.63e−4 = 0.19 %."""
    if value == 0 or digits < 1:
        raise ValueError("need a non-zero value and at least one digit")
    exponent = math.floor(math.log10(abs(value))) - digits + 1
    return 0.5 * 10.0**exponent / abs(value)


def record(id: str, quantity: str, paper, imunav, unit: str, verdict: str, why: str,
           note: str = "", tolerance: float | None = None) -> dict:
    """One reproduction record (numbers as plain floats), checked against the verdict rule:
    a numeric ``reproduced``/``differs`` with a ``tolerance`` must be what :func:`judge`
    says, and ``consistent with bound`` needs a paper bound that imunav's value satisfies."""
    if not _ID.match(id):
        raise ValueError(f"id must be dotted lower-case words like 'paper.table1.ordering', "
                         f"got {id!r}")
    if verdict not in VERDICTS:
        raise ValueError(f"verdict must be one of {VERDICTS}, got {verdict!r}")
    if verdict == "reproduced" and (paper is None or tolerance is None):
        raise ValueError(f"{id}: 'reproduced' needs the paper's number and a tolerance; a "
                         "statement the computation bears out without one 'holds'")
    if verdict == "no paper value" and paper is not None:
        raise ValueError(f"{id}: 'no paper value' with a paper value")
    if not why.strip():
        raise ValueError(f"{id}: a verdict needs its why")
    if tolerance is not None:
        if paper is None or imunav is None:
            raise ValueError(f"{id}: a tolerance needs a paper value and imunav's value")
        if verdict in ("reproduced", "differs") and judge(paper, imunav, tolerance) != verdict:
            raise ValueError(f"{id}: verdict {verdict!r} contradicts the tolerance "
                             f"{tolerance:.3g} (relative difference "
                             f"{relative_difference(paper, imunav):.3g})")
    if verdict == "consistent with bound":
        if paper is None or imunav is None:
            raise ValueError(f"{id}: 'consistent with bound' needs the bound and a value")
        if judge_bound(paper, imunav, "upper") != verdict:
            raise ValueError(f"{id}: {imunav!r} does not satisfy the upper bound {paper!r}")

    def num(x):
        return None if x is None else float(x)

    return {"id": id, "quantity": quantity, "paper": num(paper), "imunav": num(imunav),
            "unit": unit, "tolerance": num(tolerance), "verdict": verdict, "why": why,
            "note": note}


# ------------------------------------------------------------------ the ledger, rendered


def load(path: str | Path | None = None) -> dict[str, dict]:
    """The stored ledger (default :data:`LEDGER`) as ``{id: record}``."""
    p = Path(path) if path is not None else LEDGER
    if not p.is_file():
        raise FileNotFoundError(f"no ledger at {p}: run `imunav reproduce --out figures`")
    recs = json.loads(p.read_text(encoding="utf-8"))
    return {r["id"]: r for r in recs}


#: Values below this (in the record's unit) are rounding: printed as a floor, so that a
#: table does not change when round-off does.
ROUNDING_FLOOR = 1e-10


def format_value(x, unit: str = "") -> str:
    """A record's number for a table: 4 significant digits with its unit, ``< 1e-10`` for
    round-off-level values, ``—`` for none."""
    if x is None:
        return "—"
    u = "" if unit in ("", "1") else f" {unit}"
    if x != 0 and abs(x) < ROUNDING_FLOOR:
        return f"< 1e-10{u}"
    s = f"{x:.4g}"
    if "e" in s:
        m, e = s.split("e")
        s = f"{m}e{int(e)}"
    return s.replace("-", "−") + u


def small(x: float, unit: str = "", fmt: str = ".1e") -> str:
    """A number for a sentence (a record's ``why``), with round-off-level values as the floor
    ``< 1e-10`` so that the text does not change when round-off does."""
    u = f" {unit}" if unit else ""
    if abs(x) < ROUNDING_FLOOR:
        return f"< 1e-10{u}"
    return f"{x:{fmt}}{u}"


def format_tolerance(tol) -> str:
    """``within 0.46 %`` for a record's relative tolerance (empty when it has none)."""
    if tol is None:
        return ""
    pct = 100 * tol
    return f"tolerance {pct:.2g} %"


#: Header of every coverage table (the ledger test finds the tables by it).
HEADER = ("the paper says", "here", "paper", "imunav", "record", "verdict")


def _cell(text: str) -> str:
    """A table cell: a '|' would split the row (a norm |x| in a claim), so it becomes '∣'
    (U+2223), which reads the same."""
    return str(text).replace("|", "∣").replace("\n", " ")


def coverage_table(rows, ledger: dict[str, dict] | None = None) -> str:
    """A paper notebook's coverage table in Markdown, rendered from the ledger.

    ``rows``: ``(what the paper says, where it is settled, record id or None, imunav text)``;
    the record's paper value, imunav value (with its tolerance) and verdict fill the other
    cells verbatim. A row without a record (an erratum read off the text, nothing to compute)
    shows ``—`` for the record and the verdict. ``imunav text`` replaces imunav's number when
    given (e.g. "drawn", or a short statement), the number still shown after it."""
    ledger = load() if ledger is None else ledger
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    for row in rows:
        claim, where, rid, text = (tuple(row) + (None,) * 4)[:4]
        if rid is None:
            cells = [claim, where, "—", text or "—", "—", "—"]
        else:
            if rid not in ledger:
                raise KeyError(f"coverage row {claim!r} names {rid!r}, which the ledger lacks: "
                               "run `imunav reproduce --out figures`")
            r = ledger[rid]
            value = format_value(r["imunav"], r["unit"])
            if r.get("tolerance") is not None:
                value += f" ({format_tolerance(r['tolerance'])})"
            if text:
                value = text if r["imunav"] is None else f"{text}: {value}"
            cells = [claim, where, format_value(r["paper"], r["unit"]), value, f"`{rid}`",
                     r["verdict"]]
        lines.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(lines)


def verdict_line(rid: str, ledger: dict[str, dict] | None = None) -> str:
    """One Markdown line stating a record's verdict and its why, from the ledger."""
    ledger = load() if ledger is None else ledger
    if rid not in ledger:
        raise KeyError(f"{rid!r} is not in the ledger: run `imunav reproduce --out figures`")
    r = ledger[rid]
    tol = f" ({format_tolerance(r['tolerance'])})" if r.get("tolerance") is not None else ""
    nums = ""
    if r["paper"] is not None or r["imunav"] is not None:
        nums = (f" Paper {format_value(r['paper'], r['unit'])}, imunav "
                f"{format_value(r['imunav'], r['unit'])}{tol}.")
    return f"**Verdict** `{rid}`: **{r['verdict']}** — {r['why']}.{nums}"


def table_rows(markdown: str) -> list[list[str]]:
    """The body rows of every coverage table in a Markdown text, as lists of cells (the
    inverse of :func:`coverage_table`, used by the ledger test)."""
    out, inside = [], False
    for line in markdown.splitlines():
        if not line.startswith("|"):
            inside = False
            continue
        cells = [c.strip() for c in line.strip().split("|")[1:-1]]
        if tuple(cells) == HEADER:
            inside = True
            continue
        if inside and not set("".join(cells)) <= set("-: "):
            out.append(cells)
    return out
