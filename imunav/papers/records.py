"""Reproduction records: one number of a paper beside imunav's, with a verdict.

A record is ``{"id", "quantity", "paper", "imunav", "unit", "note"}`` with ``paper`` None
(JSON null) where the paper gives no number. Every paper module's ``reproduce(out)`` returns a
list of them; :mod:`imunav.reproduce` collects them into ``figures/reproduction.json``.

May import: nothing from imunav.
"""

from __future__ import annotations


def record(id: str, quantity: str, paper, imunav, unit: str, note: str = "") -> dict:
    """One reproduction record (numbers as plain floats)."""
    def num(x):
        return None if x is None else float(x)

    return {"id": id, "quantity": quantity, "paper": num(paper), "imunav": num(imunav),
            "unit": unit, "note": note}
