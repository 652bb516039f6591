"""Inverse design: the worst IMU that still tracks a motion within a tolerance.

In the linear covariance model (:mod:`~imunav.analysis.covariance`) the nav-error covariance of
each error term is proportional to the square of its datasheet parameter (noise density, bias,
bias instability, random walk, scale factor, misalignment, g-sensitivity, resolution), and the
percentiles of the error norm to the parameter itself. So the largest value of a term that alone
keeps the 95th-percentile position error within a tolerance over the whole motion is exact:
``value · tolerance / max_t p95(t)``; likewise the largest common scale of all terms together.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis``.
"""

from __future__ import annotations

from imunav.analysis.assessment import PERCENTILE, SUITABLE_FRACTION, min_sample_rate
from imunav.analysis.covariance import covariance_summary
from imunav.core.validation import check_positive
from imunav.estimation.error_model import LazyTrajectory
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS
from imunav.sensors.terms import TERMS

__all__ = ["design", "format_design", "in_datasheet_units"]


def in_datasheet_units(term: str, si: float) -> str:
    """``"0.12 deg/sqrt(h)"``: an SI value of ``term`` (``"gyro.noise_density"``) in the
    datasheet unit its :class:`~imunav.sensors.terms.Term` is shown in.

    Parameters
    ----------
    term : str
        ``"<triad>.<term>"``.
    si : float

    Returns
    -------
    str
    """
    triad, _, name = term.partition(".")
    return TERMS[name].show(si, triad)


def design(motion: BaseMotion, base: ImuModel, rate: float, tolerance: float,
           duration: float | None = None, output: str = "increments",
           progress: bool = True, vertical: str = "free") -> dict:
    """Limits of each error term of ``base``, the common scale, the minimum rate and every
    preset ranked (the numbers of ``imunav design``; the JSON it writes). On the WGS-84 Earth
    ``vertical="hold"`` holds the vertical channel at the true height."""
    tolerance = check_positive(tolerance, "tolerance")
    p = PERCENTILE / 100
    duration = span(motion, rate, duration)
    traj = LazyTrajectory(motion, rate, duration)
    cov = covariance_summary(motion, base, rate, duration, output=output, p=p, maxima=True,
                             trajectory=traj, progress=progress, vertical=vertical)
    terms = {}
    for term in cov.terms:
        triad, _, name = term.partition(".")
        value = getattr(getattr(base, triad), name)
        worst = cov.max_position_quantile(p, term=term)
        if worst <= 0:
            continue
        limit = value * tolerance / worst
        terms[term] = {"limit_si": limit, "limit": in_datasheet_units(term, limit),
                       "base": in_datasheet_units(term, value),
                       "max_p95_position_m": worst}
    worst_total = cov.max_position_quantile(p) if cov.terms else 0.0
    presets = []
    for name in PRESETS:
        pc = covariance_summary(motion, ImuModel.load(name), rate, duration, output=output,
                                tolerance=tolerance, trajectory=traj, progress=progress,
                                vertical=vertical)
        final = float(pc.position_quantile(p, index=-1)) if pc.terms else 0.0
        within = pc.min_position_within(tolerance) if pc.terms else 1.0
        presets.append({"name": name, "final_p95_position_m": final,
                        "suitable": within >= SUITABLE_FRACTION,
                        "warnings": pc.warnings})
    presets.sort(key=lambda r: r["final_p95_position_m"])
    return {
        "motion": motion.name, "imu": base.name, "rate_hz": float(rate),
        "tolerance_m": tolerance,
        "terms": terms,
        "common_scale": (tolerance / worst_total) if worst_total > 0 else None,
        "min_rate_hz": min_sample_rate(motion, tolerance, duration, output),
        "presets": presets,
        "warnings": cov.warnings,
    }


def format_design(r: dict) -> str:
    lines = [f"Design for motion {r['motion']} at {r['rate_hz']:g} Hz, tolerance "
             f"{r['tolerance_m']:g} m (95th percentile of the position error, whole motion), "
             f"from IMU {r['imu']}:"]
    lines.append("  Largest value of each term that alone stays within the tolerance:")
    for k, v in sorted(r["terms"].items()):
        lines.append(f"    {k:24s} {v['limit']:>22s}   (this IMU: {v['base']})")
    cs = r["common_scale"]
    lines.append("  All terms together: " + ("no error term" if cs is None else
                 f"within the tolerance up to {cs:.3g} × this IMU's values"
                 + (" (it already meets it)." if cs >= 1 else
                    f" (its errors must shrink {1 / cs:.3g}-fold).")))
    mr = r["min_rate_hz"]
    lines.append("  Minimum sample rate (sampling alone below a tenth of the tolerance): "
                 + (f"{mr:g} Hz." if mr else "none up to 5 kHz."))
    lines.append("  Presets, best first (final 95th-percentile position error):")
    for p in r["presets"]:
        flag = "SUITABLE    " if p["suitable"] else "NOT SUITABLE"
        note = " (outside the linear model: check with Monte Carlo)" if p["warnings"] else ""
        lines.append(f"    {p['name']:10s} {flag} {p['final_p95_position_m']:10.3g} m{note}")
    for w in r["warnings"]:
        lines.append(f"  Warning: {w}.")
    return "\n".join(lines)
