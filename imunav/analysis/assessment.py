"""The applicability verdict: can this IMU track this motion? Percentiles of the Monte Carlo
position error against a tolerance, the error budget per term, the minimum useful rate, and the
text a non-specialist can act on.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.analysis``.
"""

from __future__ import annotations

import numpy as np

from imunav.analysis.metrics import nav_errors
from imunav.analysis.montecarlo import monte_carlo
from imunav.analysis.roundtrip import initial_state
from imunav.core.validation import check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown.registry import navigate

RATE_CANDIDATES = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)


def min_sample_rate(motion: BaseMotion, tolerance: float, duration: float | None = None,
                    output: str = "increments", candidates=RATE_CANDIDATES) -> float | None:
    """Smallest candidate rate at which the sampling error alone (ideal sensor, default
    algorithm) stays below a tenth of ``tolerance`` over the whole motion."""
    duration = duration or motion.duration
    for r in candidates:
        if r * duration < 10:
            continue
        sig = simulate_imu(motion, r, duration, output=output)
        nav = navigate(sig, *initial_state(motion, sig))
        if nav_errors(nav, motion).position.max() <= tolerance / 10:
            return float(r)
    return None


def assess(motion: BaseMotion, model: ImuModel, rate: float, runs: int, tolerance: float,
           seed: int = 0, duration: float | None = None, output: str = "increments",
           budget_runs: int | None = None, scheduler: str | None = None,
           progress: bool = True) -> dict:
    """The applicability verdict: the numbers of ``imunav assess`` (see :func:`format_verdict`).

    ``error_budget``: each error term alone (same seed, ``budget_runs`` runs, default
    min(runs, 200)) → final 95th-percentile position error (m).
    """
    tolerance = check_positive(tolerance, "tolerance")
    mc = monte_carlo(motion, model, rate, duration, runs, seed, output, scheduler=scheduler,
                     progress=progress)
    within = float(np.mean(mc.position.max(axis=1) <= tolerance))
    p95 = np.percentile(mc.position, 95, axis=0)
    over = np.nonzero(p95 > tolerance)[0]
    budget = {}
    br = budget_runs or min(runs, 200)
    for term in model.terms():
        b = monte_carlo(motion, model.only(term), rate, duration, br, seed, output,
                        scheduler=scheduler, progress=False)
        budget[term] = float(np.percentile(b.position[:, -1], 95))
    return {
        "motion": getattr(motion, "name", "motion"), "imu": model.name, "rate_hz": float(rate),
        "tolerance_m": tolerance, "runs": runs, "seed": seed,
        "fraction_within_tolerance": within,
        "time_p95_exceeds_s": float(mc.t[over[0]]) if over.size else None,
        "final_p95_position_m": float(p95[-1]),
        "error_budget": dict(sorted(budget.items(), key=lambda kv: -kv[1])),
        "min_rate_hz": min_sample_rate(motion, tolerance, duration, output),
        "saturated_runs": int(np.sum(mc.saturated > 0)),
    }


def format_verdict(r: dict) -> str:
    """A verdict a non-specialist can act on."""
    pct = 100 * r["fraction_within_tolerance"]
    lines = [f"IMU {r['imu']} on motion {r['motion']} at {r['rate_hz']:g} Hz, "
             f"{r['runs']} runs (seed {r['seed']}), tolerance {r['tolerance_m']:g} m:"]
    ok = pct >= 95
    lines.append(f"  {'SUITABLE' if ok else 'NOT SUITABLE'}: {pct:.1f} % of runs stay within "
                 f"{r['tolerance_m']:g} m over the whole motion.")
    if r["time_p95_exceeds_s"] is None:
        lines.append("  The 95th percentile of the position error never exceeds the tolerance "
                     f"(final {r['final_p95_position_m']:.3g} m).")
    else:
        lines.append(f"  The 95th percentile crosses {r['tolerance_m']:g} m at "
                     f"t = {r['time_p95_exceeds_s']:.2f} s (final {r['final_p95_position_m']:.3g} m).")
    if r["error_budget"]:
        top = next(iter(r["error_budget"]))
        lines.append(f"  Dominant error: {top} ({r['error_budget'][top]:.3g} m alone, 95th pct).")
        lines.append("  Error budget (each term alone, final 95th-percentile position error):")
        for k, v in r["error_budget"].items():
            val = f"{v:10.3g}" if v >= 1e-9 else f"{'< 1e-9':>10s}"   # below: rounding
            lines.append(f"    {k:28s} {val} m")
    mr = r["min_rate_hz"]
    lines.append("  Sampling alone stays below a tenth of the tolerance from "
                 + (f"{mr:g} Hz." if mr else "no tested rate (≤ 5 kHz)."))
    if r["saturated_runs"]:
        lines.append(f"  Warning: {r['saturated_runs']} runs hit the sensor range (clipped).")
    return "\n".join(lines)
