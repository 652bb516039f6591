"""The report of an Allan fit: the ``IMU.toml`` text ``imunav allan`` writes and the lines it
prints, each value in SI and in the datasheet unit its term is shown in
(:meth:`~imunav.sensors.terms.Term.show`).

May import: ``imunav.core``, ``imunav.sensors.terms``, ``imunav.sensors.allan``.
"""

from __future__ import annotations

from imunav.sensors.allan import FIT_TERMS
from imunav.sensors.terms import TERMS

__all__ = ["format_allan", "imu_toml", "not_from_static"]


def not_from_static(triad: str) -> list[str]:
    """The error terms of ``triad`` an Allan fit of a static log does not give (the registry's,
    less the fitted ones): the turn-on bias (its spread from one power-up to the next), the
    scale factor, the misalignment, the g-sensitivity — they need turn-ons or motion — and the
    datasheet's resolution and range.

    Parameters
    ----------
    triad : {"gyro", "accel"}

    Returns
    -------
    list of str
    """
    return [name for name, term in TERMS.items()
            if term.is_error and triad in term.triads and name not in FIT_TERMS]


def _caveat(fits: dict) -> str:
    names = ", ".join(f"{triad}.{name}" for triad in fits for name in not_from_static(triad))
    return (f"a static log cannot give {names}: they are left out of the model — add them "
            "from the datasheet before an assessment, which is optimistic without them")


def _datasheet(triad: str, name: str, si: float) -> str:
    return TERMS[name].show(si, triad, digits=4, typographic=True)


def imu_toml(fits: dict, source: str) -> str:
    """The ``IMU.toml`` text of Allan fits.

    SI numbers, each with its unit, its datasheet equivalent and the τ range it was fitted on
    in a comment; terms the record cannot determine are left out, with the reason.

    Parameters
    ----------
    fits : dict
        ``{triad: fit}``, each fit from :func:`imunav.sensors.allan.fit_allan`.
    source : str
        What was fitted (a file name), for the header comment.

    Returns
    -------
    str
        TOML that :meth:`imunav.sensors.models.ImuModel.from_toml` reads.
    """
    f0 = next(iter(fits.values()))
    lines = [f"# Fitted by `imunav allan` from {source}: a static record of "
             f"{f0['samples'] / f0['rate']:.6g} s at {f0['rate']:.6g} Hz.",
             "# Model of the overlapping Allan variance: σ²(τ) = N²/τ + B² + K²τ/3, fitted by",
             "# weighted least squares (each τ weighted by its degrees of freedom). B is the Allan",
             "# floor, as datasheets quote bias instability (the IEEE 952 flicker coefficient is",
             "# B/0.664). Values are SI; ± is the Allan deviation's sampling error where the term",
             "# dominates.",
             f"# Warning: {_caveat(fits)}.",
             'name = "fitted"']
    for triad, fit in fits.items():
        lines.append(f"\n[{triad}]")
        for name, term in fit["terms"].items():
            if term["value"] is None:
                lines.append(f"# {name}: not determined — {term['why']}")
                continue
            unit = TERMS[name].si_unit(triad)
            lo, hi = term["tau_range"]
            lines.append(f"{name} = {term['value']:.6e}   # {unit} ± {term['se']:.2g}, "
                         f"= {_datasheet(triad, name, term['value'])}; τ = {lo:.3g}–{hi:.3g} s")
    return "\n".join(lines) + "\n"


def format_allan(fits: dict, path) -> str:
    """The lines ``imunav allan`` prints: each fitted term in its datasheet unit, its relative
    sampling error and τ range, or why it was not determined.

    Parameters
    ----------
    fits : dict
        ``{triad: fit}`` as for :func:`imu_toml`.
    path : str or Path
        Where the fitted model was written (named in the first line).

    Returns
    -------
    str
    """
    lines = [f"Allan fits (weighted least squares; written to {path}):"]
    for triad, fit in fits.items():
        for name, term in fit["terms"].items():
            if term["value"] is None:
                lines.append(f"  {triad + '.' + name:24s} not determined: {term['why']}")
            else:
                lo, hi = term["tau_range"]
                lines.append(f"  {triad + '.' + name:24s} {_datasheet(triad, name, term['value']):>16s}"
                             f"  ± {100 * term['se'] / term['value']:.1f} %   (τ {lo:.3g}–{hi:.3g} s)")
    lines.append(f"  Warning: {_caveat(fits)}.")
    return "\n".join(lines)
