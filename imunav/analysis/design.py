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
from imunav.analysis.covariance import check_steps, covariance_summary
from imunav.core.deprecation import renamed
from imunav.core.validation import check_positive
from imunav.estimation.alignment import WINDOW
from imunav.estimation.error_model import LazyTrajectory
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS
from imunav.sensors.terms import TERMS, printed

__all__ = ["design", "format_design", "in_datasheet_units"]


def in_datasheet_units(term: str, si: float, *, typographic: bool = False) -> str:
    """``"0.12 deg/sqrt(h)"``: an SI value of ``term`` (``"gyro.noise_density"``) in the
    datasheet unit its :class:`~imunav.sensors.terms.Term` is shown in.

    Parameters
    ----------
    term : str
        ``"<triad>.<term>"``.
    si : float
    typographic : bool, default False
        The unit as printed for people (``"0.12 °/√h"``, as every report of the command line
        spells it) rather than as spelt in files and in the JSON of :func:`design`.

    Returns
    -------
    str
    """
    triad, _, name = term.partition(".")
    return TERMS[name].show(si, triad, typographic=typographic)


@renamed(base="imu", output="kind")
def design(motion: BaseMotion, imu: ImuModel, rate: float, tolerance: float,
           duration: float | None = None, kind: str = "increments",
           progress: bool = True, vertical: str = "free", *, alignment: str = "truth",
           align_window: float = WINDOW) -> dict:
    """The worst IMU that still tracks ``motion`` within ``tolerance``.

    Limits of each error term of ``imu``, the common scale, the minimum rate and every
    preset ranked: the numbers of ``imunav design`` (the JSON it writes). Exact in the linear
    covariance model, where the position error's percentiles scale with each parameter (see
    the module's description).

    Parameters
    ----------
    motion : BaseMotion
        The motion to track.
    imu : ImuModel
        The IMU whose terms are scaled (its values set the mix of terms).
    rate : float
        Output sample rate (Hz).
    tolerance : float
        The largest acceptable 95th-percentile position error (m) over the whole motion.
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"increments", "rates"}, default "increments"
        The signal kind.
    progress : bool, default True
        Show progress bars on long analyses.
    vertical : {"free", "hold"}, default "free"
        On the WGS-84 Earth: the vertical channel free or held at the true height.
    alignment : {"truth", "level"}, default "truth"
        The initial attitude: the truth, or levelled from the accelerometer at rest over
        ``align_window`` seconds before the motion (as :func:`~imunav.analysis.assessment.assess_covariance`);
        each term's covariance still scales with the square of its value, so the limits stay
        exact.
    align_window : float, default WINDOW
        The levelling window (s), > 0.

    Returns
    -------
    dict
        ``motion``, ``imu``, ``rate_hz``, ``tolerance_m``; ``terms``: for each term of
        ``imu`` with an effect, ``limit_si`` (SI), ``limit`` and ``base`` (its value in ``imu``; in datasheet
        units, spelt as in files: ``"0.12 deg/sqrt(h)"``; the printed report writes them
        ``"0.12 °/√h"``) and ``max_p95_position_m``; ``common_scale`` (the factor on all of ``imu``'s
        values together that meets the tolerance, or None without error terms);
        ``min_rate_hz`` (:func:`~imunav.analysis.assessment.min_sample_rate`); ``presets``
        (``name``, ``final_p95_position_m``, ``suitable``, ``warnings``), best first; and
        ``warnings``.

    Raises
    ------
    ImunavError
        If ``tolerance`` is not a finite number > 0, or for the reasons of the covariance
        analysis (a ``rate`` or ``duration`` that is not a finite number > 0, an unknown
        ``kind`` or ``vertical``, …).
        Also if ``alignment`` is not ``"truth"`` or ``"level"``, ``align_window`` is not
        a finite number > 0, or ``"level"`` is asked on the WGS-84 Earth.
    """
    tolerance = check_positive(tolerance, "tolerance")
    p = PERCENTILE / 100
    duration = span(motion, rate, duration)
    check_steps(rate, duration)
    traj = LazyTrajectory(motion, rate, duration)
    al = {"alignment": alignment, "align_window": align_window}
    cov = covariance_summary(motion, imu, rate, duration, kind=kind, p=p, maxima=True,
                             trajectory=traj, progress=progress, vertical=vertical, **al)
    terms = {}
    for term in cov.terms:
        triad, _, name = term.partition(".")
        value = getattr(getattr(imu, triad), name)
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
        pc = covariance_summary(motion, ImuModel.load(name), rate, duration, kind=kind,
                                tolerance=tolerance, trajectory=traj, progress=progress,
                                vertical=vertical, **al)
        final = float(pc.position_quantile(p, index=-1)) if pc.terms else 0.0
        within = pc.min_position_within(tolerance) if pc.terms else 1.0
        presets.append({"name": name, "final_p95_position_m": final,
                        "suitable": within >= SUITABLE_FRACTION,
                        "warnings": pc.warnings})
    presets.sort(key=lambda r: r["final_p95_position_m"])
    out = {
        "motion": motion.name, "imu": imu.name, "rate_hz": float(rate),
        "tolerance_m": tolerance,
        "terms": terms,
        "common_scale": (tolerance / worst_total) if worst_total > 0 else None,
        "min_rate_hz": min_sample_rate(motion, tolerance, duration, kind),
        "presets": presets,
        "warnings": cov.warnings,
    }
    if alignment == "level":           # the truth start, the default, adds nothing
        out["alignment"] = {"method": "level", "window_s": float(align_window)}
    return out


def format_design(r: dict) -> str:
    """The plain-text report of :func:`design` (what ``imunav design`` prints).

    Parameters
    ----------
    r : dict
        A result of :func:`design`.

    Returns
    -------
    str
        Lines: each term's limit beside this IMU's value (units as printed: ``°/√h``,
        ``µg``), the common scale, the minimum
        rate, the presets ranked (SUITABLE or NOT SUITABLE) and the warnings.
    """
    lines = [f"Design for motion {r['motion']} at {r['rate_hz']:g} Hz, tolerance "
             f"{r['tolerance_m']:g} m (95th percentile of the position error, whole motion), "
             f"from IMU {r['imu']}:"]
    if r.get("alignment"):
        lines.append(f"  Initial attitude levelled from the accelerometer at rest over "
                     f"{r['alignment']['window_s']:g} s before the motion (heading given).")
    lines.append("  Largest value of each term that alone stays within the tolerance:")
    for k, v in sorted(r["terms"].items()):
        lines.append(f"    {k:24s} {printed(k, v['limit']):>22s}   "
                     f"(this IMU: {printed(k, v['base'])})")
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
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)
