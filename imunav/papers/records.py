"""Reproduction records: one number of a paper beside imunav's, with a verdict.

A record is ``{"id", "quantity", "paper", "imunav", "unit", "verdict", "why", "note"}`` with
``paper`` None (JSON null) where the paper gives no number and ``verdict`` one of
:data:`VERDICTS`:

``reproduced``       the paper's number or conclusion comes out (within the stated tolerance)
``differs``          imunav's computation gives a different number, or reverses the conclusion
``not reproducible`` the paper does not give what is needed to compute it (data, law, method)
``no paper value``   imunav's own number, beside a figure or claim that has none

``why`` is one sentence saying what settles the verdict. Every paper module's
``reproduce(out)`` returns a list of records; :mod:`imunav.reproduce` collects them into
``figures/reproduction.json``.

May import: nothing from imunav.
"""

from __future__ import annotations

VERDICTS = ("reproduced", "differs", "not reproducible", "no paper value")


def record(id: str, quantity: str, paper, imunav, unit: str, verdict: str, why: str,
           note: str = "") -> dict:
    """One reproduction record (numbers as plain floats)."""
    if verdict not in VERDICTS:
        raise ValueError(f"verdict must be one of {VERDICTS}, got {verdict!r}")
    if verdict == "no paper value" and paper is not None:
        raise ValueError(f"{id}: 'no paper value' with a paper value")
    if not why.strip():
        raise ValueError(f"{id}: a verdict needs its why")

    def num(x):
        return None if x is None else float(x)

    return {"id": id, "quantity": quantity, "paper": num(paper), "imunav": num(imunav),
            "unit": unit, "verdict": verdict, "why": why, "note": note}
