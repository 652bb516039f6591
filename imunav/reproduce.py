"""``imunav reproduce``: every reproduction figure and ``reproduction.json``.

Each reproduction is a function ``(out_dir: Path) → list[record]`` registered in
:data:`REPRODUCTIONS`; a record is ``{"id", "quantity", "paper", "imunav", "unit", "note"}``
with ``paper`` None (JSON null) where the paper gives no number.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path


def record(id: str, quantity: str, paper, imunav, unit: str, note: str = "") -> dict:
    """One reproduction record (numbers as plain floats)."""
    def num(x):
        return None if x is None else float(x)

    return {"id": id, "quantity": quantity, "paper": num(paper), "imunav": num(imunav),
            "unit": unit, "note": note}


def _quickstart(out: Path) -> list[dict]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from imunav import quickstart as qs

    recs = []
    res = qs.run(rate=100.0, output="increments")
    fig = qs.plot_run(res)
    fig.savefig(out / "quickstart_round_trip.png", dpi=110)
    plt.close(fig)
    s = res.errors.summary()
    recs.append(record("quickstart.increments_100hz.max_position_error", "max position error, "
                       f"ideal increments at 100 Hz, {res.nav.algorithm}", None,
                       s["max_position"], "m", "quickstart motion, 20 s"))
    recs.append(record("quickstart.increments_100hz.max_attitude_error", "max attitude error, "
                       f"ideal increments at 100 Hz, {res.nav.algorithm}", None,
                       s["max_attitude"], "rad", "quickstart motion, 20 s"))
    rows = qs.error_table()
    fig = qs.plot_error_vs_rate(rows)
    fig.savefig(out / "quickstart_error_vs_rate.png", dpi=110)
    plt.close(fig)
    for row in rows:
        if row["order_att"] is None:  # at rounding level at 50–400 Hz on this motion
            continue
        recs.append(record(f"quickstart.order.{row['kind']}.{row['algorithm']}",
                           "fitted convergence order of max attitude error (50–400 Hz)", None,
                           row["order_att"], "1", "quickstart motion, 20 s; errors < 1e-10 "
                           "(rounding) excluded from the fit"))
    return recs


#: name → reproduction function; paper modules add theirs here.
def _plaksiy(out: Path) -> list[dict]:
    from imunav.papers import plaksiy

    return plaksiy.reproduce(out)


def _marusenkova(out: Path) -> list[dict]:
    from imunav.papers import marusenkova2020

    return marusenkova2020.reproduce(out)


def _tutorial(out: Path) -> list[dict]:
    from imunav.papers import tutorial

    return tutorial.reproduce(out)


def _dickson_rae(out: Path) -> list[dict]:
    from imunav.papers import dickson_rae2021

    return dickson_rae2021.reproduce(out)


REPRODUCTIONS: dict[str, Callable[[Path], list[dict]]] = {
    "quickstart": _quickstart,
    "marusenkova2020": _marusenkova,
    "plaksiy": _plaksiy,
    "tutorial": _tutorial,
    "dickson_rae2021": _dickson_rae,
}


def reproduce_all(out: str | Path = "figures", only: list[str] | None = None) -> list[dict]:
    """Run every registered reproduction, write figures and ``out/reproduction.json``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    records: list[dict] = []
    for name, fn in REPRODUCTIONS.items():
        if only and name not in only:
            continue
        records.extend(fn(out))
    with (out / "reproduction.json").open("w") as fh:
        json.dump(records, fh, indent=1)
        fh.write("\n")
    return records


def format_table(records: list[dict]) -> str:
    """Plain-text table: id, paper, imunav, unit."""
    def f(x):
        return "null" if x is None else f"{x:.4g}"

    w = max([len(r["id"]) for r in records] + [2])
    lines = [f"{'id':<{w}}  {'paper':>11}  {'imunav':>11}  unit"]
    lines += [f"{r['id']:<{w}}  {f(r['paper']):>11}  {f(r['imunav']):>11}  {r['unit']}"
              for r in records]
    return "\n".join(lines)
