"""The unit tables (one for all of imunav): every spelling of a unit, by dimension, → SI factor.

A datasheet quantity is converted by :func:`convert` with the table of its dimension (the sensor
error terms of :mod:`imunav.sensors.terms` name the table of each of their parameters); a
recording's columns by :func:`factor` (``factor("deg/s", "rate", "gyro units")``). A unit of
another dimension (``"deg/s"`` for a noise density) or an unknown unit is an
:class:`~imunav.core.validation.ImunavError` naming the quantity and the accepted units; plain
numbers are taken as SI.

May import: ``imunav.core.constants``, ``imunav.core.validation``.
"""

from __future__ import annotations

import math
import re

import numpy as np

from imunav.core.constants import DEG
from imunav.core.constants import G0 as G
from imunav.core.validation import ImunavError, show

# Units by dimension: spelling (normalised: no spaces, "√X" → "sqrt(X)") → SI factor.
RATE = {"rad/s": 1.0, "deg/s": DEG, "dps": DEG, "mdps": 1e-3 * DEG, "deg/h": DEG / 3600,
        "deg/hr": DEG / 3600, "mrad/s": 1e-3}
ACCEL = {"m/s^2": 1.0, "m/s2": 1.0, "g": G, "mg": 1e-3 * G, "ug": 1e-6 * G, "µg": 1e-6 * G}
DENSITY_RATE = {  # rad/s/√Hz  (= rad/√s, angle random walk)
    "rad/s/sqrt(Hz)": 1.0, "deg/s/sqrt(Hz)": DEG, "dps/sqrt(Hz)": DEG,
    "mdps/sqrt(Hz)": 1e-3 * DEG, "deg/h/sqrt(Hz)": DEG / 3600, "deg/sqrt(h)": DEG / 60,
    "deg/sqrt(hr)": DEG / 60, "rad/sqrt(s)": 1.0,
}
DENSITY_ACCEL = {  # m/s²/√Hz (= m/s/√s, velocity random walk)
    "m/s^2/sqrt(Hz)": 1.0, "ug/sqrt(Hz)": 1e-6 * G, "µg/sqrt(Hz)": 1e-6 * G,
    "mg/sqrt(Hz)": 1e-3 * G, "g/sqrt(Hz)": G, "m/s/sqrt(h)": 1 / 60, "m/s/sqrt(hr)": 1 / 60,
    "m/s/sqrt(s)": 1.0,
}
RW_RATE = {  # rad/s/√s (rate random walk)
    "rad/s/sqrt(s)": 1.0, "rad/s^1.5": 1.0, "deg/s/sqrt(s)": DEG, "deg/h/sqrt(h)": DEG / 3600 / 60,
    "deg/hr/sqrt(hr)": DEG / 3600 / 60, "deg/s/sqrt(h)": DEG / 60,
}
RW_ACCEL = {  # m/s²/√s (acceleration random walk)
    "m/s^2/sqrt(s)": 1.0, "m/s^2.5": 1.0, "m/s^3/sqrt(Hz)": 1.0, "ug/sqrt(s)": 1e-6 * G,
    "mg/sqrt(h)": 1e-3 * G / 60, "m/s/h/sqrt(h)": 1 / 3600 / 60,
}
TIME = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "min": 60.0, "h": 3600.0}
FREQ = {"Hz": 1.0, "kHz": 1e3}
FRACTION = {"": 1.0, "ppm": 1e-6, "%": 1e-2}
ANGLE = {"rad": 1.0, "mrad": 1e-3, "deg": DEG, "%": 1e-2}   # % = cross-axis coupling
GSENS = {"rad/s/(m/s^2)": 1.0, "deg/s/g": DEG / G, "deg/h/g": DEG / 3600 / G,
         "rad/s/g": 1 / G}

#: dimension → {unit spelling → SI factor}: the tables recording readers use (:func:`factor`).
DIMENSIONS = {"rate": RATE, "accel": ACCEL, "time": TIME, "frequency": FREQ}


def normalise(unit: str) -> str:
    """A unit spelling in the tables' form: no spaces, ``²`` → ``^2``, ``√X``/``rtX`` →
    ``sqrt(X)``, ``°`` → ``deg``, ``dph`` → ``deg/h``, the Greek μ → the micro sign µ."""
    u = unit.strip().replace(" ", "").replace("²", "^2").replace("μ", "µ")
    u = re.sub(r"√\(?([A-Za-z]+)\)?", r"sqrt(\1)", u)
    u = re.sub(r"(?<!sq)rt\(?(Hz|hr|h|s)\)?", r"sqrt(\1)", u)
    u = u.replace("°", "deg").replace("dph", "deg/h").replace("/√", "/sqrt")
    u = u.replace("sqrtHz", "sqrt(Hz)").replace("sqrthr", "sqrt(hr)").replace("sqrth", "sqrt(h)")
    u = u.replace("sqrts", "sqrt(s)")
    return u


def convert(value, units: dict[str, float], key: str, what: str) -> float:
    """``value`` (a number in SI, or a string ``"<number> <unit>"`` with a spelling of ``units``)
    in SI, finite and non-negative.

    Parameters
    ----------
    value : float or str
    units : dict
        ``{spelling: SI factor}``, one of this module's tables.
    key : str
        The quantity's name in error messages (``"gyro.noise_density"``).
    what : str
        What the quantity is, in error messages ("rate noise density / angle random walk").

    Returns
    -------
    float

    Raises
    ------
    ImunavError
        For a boolean or another type, a malformed string, a unit not in ``units``, or a
        negative or non-finite value.
    """
    if isinstance(value, bool):
        raise ImunavError(f"{key} must be a number or a string with units, got {show(value)}")
    if isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, np.bool_):
        v = float(value)
    elif isinstance(value, str):
        m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", value)
        if not m:
            raise ImunavError(f"{key} = {value!r}: expected '<number> <unit>'")
        unit = normalise(m.group(2))
        if unit not in units:
            raise ImunavError(
                f"{key} = {value!r}: unit {m.group(2)!r} is not a unit of {what}; "
                f"accepted: {', '.join(k for k in units if k) or 'a plain number'}"
            )
        v = float(m.group(1)) * units[unit]
    else:
        raise ImunavError(f"{key} must be a number or a string with units, got "
                          f"{type(value).__name__}")
    if not math.isfinite(v) or v < 0:
        raise ImunavError(f"{key} must be a finite non-negative value, got {show(value)}")
    return v


def factor(unit: str, dimension: str, what: str) -> float:
    """SI factor of ``unit``, a spelling of :data:`DIMENSIONS` ``[dimension]``.

    Parameters
    ----------
    unit : str
    dimension : {"rate", "accel", "time", "frequency"}
    what : str
        The argument in the error message (``"gyro units"``).

    Returns
    -------
    float

    Raises
    ------
    ImunavError
        If ``unit`` is not a spelling of that dimension.
    """
    table = DIMENSIONS[dimension]
    u = normalise(unit) if isinstance(unit, str) else unit
    if u not in table:
        raise ImunavError(f"unknown {what} {unit!r}; expected one of {', '.join(table)}")
    return table[u]
