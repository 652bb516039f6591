"""``imunav reproduce``: every reproduction figure and ``reproduction.json``.

Each reproduction is a function ``(out_dir: Path) → list[record]`` registered in
:data:`REPRODUCTIONS` (records: :mod:`imunav.papers.records`).

May import: anything in imunav (a face of the package).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from imunav import plotting
from imunav.analysis.roundtrip import error_table, round_trip
from imunav.papers import dickson_rae2021, marusenkova2020, plaksiy, tutorial
from imunav.papers.records import record


def _quickstart(out: Path) -> list[dict]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    recs = []
    res = round_trip(rate=100.0, kind="increments")
    fig = plotting.plot_run(res)
    fig.savefig(out / "quickstart_round_trip.png", dpi=150)
    plt.close(fig)
    s = res.errors.summary()
    alg = plotting.name(f"increments/{res.nav.algorithm}")
    recs.append(record("quickstart.increments_100hz.max_position_error", "max position error, "
                       f"ideal increments at 100 Hz, {alg}", None,
                       s["max_position"], "m", "no paper value",
                       "imunav's own round trip of ideal increments (rounding level)",
                       "quickstart motion, 20 s"))
    recs.append(record("quickstart.increments_100hz.max_attitude_error", "max attitude error, "
                       f"ideal increments at 100 Hz, {alg}", None,
                       s["max_attitude"], "rad", "no paper value",
                       "imunav's own round trip of ideal increments (rounding level)",
                       "quickstart motion, 20 s"))
    rows = error_table()
    fig = plotting.plot_error_vs_rate(rows)
    fig.savefig(out / "quickstart_error_vs_rate.png", dpi=150)
    plt.close(fig)
    for row in rows:
        if row["order_att"] is None:  # at rounding level at 50–400 Hz on this motion
            continue
        recs.append(record(f"quickstart.order.{row['kind']}.{row['algorithm']}",
                           "fitted convergence order of max attitude error (50–400 Hz)", None,
                           row["order_att"], "1", "no paper value",
                           "the documented order of the algorithm, measured on an analytic motion",
                           "quickstart motion, 20 s; errors < 1e-10 (rounding) excluded from the "
                           "fit"))
    return recs


#: name → reproduction function.
REPRODUCTIONS: dict[str, Callable[[Path], list[dict]]] = {
    "quickstart": _quickstart,
    "marusenkova2020": marusenkova2020.reproduce,
    "plaksiy": plaksiy.reproduce,
    "tutorial": tutorial.reproduce,
    "dickson_rae2021": dickson_rae2021.reproduce,
}


def reproduce_all(out: str | Path = "figures", only: list[str] | None = None) -> list[dict]:
    """Run every registered reproduction, write figures and ``out/reproduction.json``."""
    import matplotlib

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    records: list[dict] = []
    with matplotlib.rc_context(plotting.BOOK_RC):     # the book's figure style (150 dpi, 8 pt)
        for name, fn in REPRODUCTIONS.items():
            if only and name not in only:
                continue
            records.extend(fn(out))
    with (out / "reproduction.json").open("w") as fh:
        json.dump(records, fh, indent=1)
        fh.write("\n")
    return records


def format_table(records: list[dict]) -> str:
    """Plain-text table: id, paper, imunav, unit, verdict (the verdict rule:
    :mod:`imunav.papers.records`)."""
    def f(x):
        return "null" if x is None else f"{x:.4g}"

    w = max([len(r["id"]) for r in records] + [2])
    lines = [f"{'id':<{w}}  {'paper':>11}  {'imunav':>11}  {'unit':6s} verdict"]
    lines += [f"{r['id']:<{w}}  {f(r['paper']):>11}  {f(r['imunav']):>11}  {r['unit']:6s} "
              f"{r['verdict']}" for r in records]
    return "\n".join(lines)
