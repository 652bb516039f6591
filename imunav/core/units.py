"""The unit tables (one for all of imunav): datasheet quantities and recording columns → SI.

``parse("0.014 deg/s/sqrt(Hz)", "gyro.noise_density")`` → 2.443e-4 (rad/s/√Hz). Each error
parameter has a physical dimension; a unit of another dimension (e.g. ``"deg/s"`` for a noise
density) or an unknown unit is an :class:`~imunav.core.validation.ImunavError` naming the
parameter and the accepted units. Plain numbers are taken as SI. :func:`factor` gives the SI
factor of a unit of a named dimension (recording readers: ``factor("deg/s", "rate")``).

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
_RATE = {"rad/s": 1.0, "deg/s": DEG, "dps": DEG, "mdps": 1e-3 * DEG, "deg/h": DEG / 3600,
         "deg/hr": DEG / 3600, "mrad/s": 1e-3}
_ACCEL = {"m/s^2": 1.0, "m/s2": 1.0, "g": G, "mg": 1e-3 * G, "ug": 1e-6 * G, "µg": 1e-6 * G}
_DENSITY_RATE = {  # rad/s/√Hz  (= rad/√s, angle random walk)
    "rad/s/sqrt(Hz)": 1.0, "deg/s/sqrt(Hz)": DEG, "dps/sqrt(Hz)": DEG,
    "mdps/sqrt(Hz)": 1e-3 * DEG, "deg/h/sqrt(Hz)": DEG / 3600, "deg/sqrt(h)": DEG / 60,
    "deg/sqrt(hr)": DEG / 60, "rad/sqrt(s)": 1.0,
}
_DENSITY_ACCEL = {  # m/s²/√Hz (= m/s/√s, velocity random walk)
    "m/s^2/sqrt(Hz)": 1.0, "ug/sqrt(Hz)": 1e-6 * G, "µg/sqrt(Hz)": 1e-6 * G,
    "mg/sqrt(Hz)": 1e-3 * G, "g/sqrt(Hz)": G, "m/s/sqrt(h)": 1 / 60, "m/s/sqrt(hr)": 1 / 60,
    "m/s/sqrt(s)": 1.0,
}
_RW_RATE = {  # rad/s/√s (rate random walk)
    "rad/s/sqrt(s)": 1.0, "rad/s^1.5": 1.0, "deg/s/sqrt(s)": DEG, "deg/h/sqrt(h)": DEG / 3600 / 60,
    "deg/hr/sqrt(hr)": DEG / 3600 / 60, "deg/s/sqrt(h)": DEG / 60,
}
_RW_ACCEL = {  # m/s²/√s (acceleration random walk)
    "m/s^2/sqrt(s)": 1.0, "m/s^2.5": 1.0, "m/s^3/sqrt(Hz)": 1.0, "ug/sqrt(s)": 1e-6 * G,
    "mg/sqrt(h)": 1e-3 * G / 60, "m/s/h/sqrt(h)": 1 / 3600 / 60,
}
_TIME = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "min": 60.0, "h": 3600.0}
_FREQ = {"Hz": 1.0, "kHz": 1e3}
_FRACTION = {"": 1.0, "ppm": 1e-6, "%": 1e-2}
_ANGLE = {"rad": 1.0, "mrad": 1e-3, "deg": DEG, "%": 1e-2}   # % = cross-axis coupling
_GSENS = {"rad/s/(m/s^2)": 1.0, "deg/s/g": DEG / G, "deg/h/g": DEG / 3600 / G,
          "rad/s/g": 1 / G}

#: dimension → {unit spelling → SI factor}: the tables recording readers use (:func:`factor`).
DIMENSIONS = {"rate": _RATE, "accel": _ACCEL, "time": _TIME, "frequency": _FREQ}

#: parameter key → (accepted units, description) for the gyro and accel triads.
SPEC = {
    "gyro": {
        "noise_density": (_DENSITY_RATE, "rate noise density / angle random walk"),
        "bias": (_RATE, "turn-on bias (1σ)"),
        "bias_instability": (_RATE, "bias instability (Allan deviation floor)"),
        "bias_correlation_time": (_TIME, "bias correlation time"),
        "random_walk": (_RW_RATE, "rate random walk"),
        "scale_factor": (_FRACTION, "scale-factor error (1σ)"),
        "misalignment": (_ANGLE, "misalignment / cross-axis coupling (1σ)"),
        "g_sensitivity": (_GSENS, "g-sensitivity (1σ)"),
        "range": (_RATE, "measurement range"),
        "resolution": (_RATE, "quantisation step"),
        "bandwidth": (_FREQ, "anti-alias / bandwidth filter corner"),
        "internal_rate": (_FREQ, "internal sample rate"),
    },
    "accel": {
        "noise_density": (_DENSITY_ACCEL, "acceleration noise density / velocity random walk"),
        "bias": (_ACCEL, "turn-on bias (1σ)"),
        "bias_instability": (_ACCEL, "bias instability (Allan deviation floor)"),
        "bias_correlation_time": (_TIME, "bias correlation time"),
        "random_walk": (_RW_ACCEL, "acceleration random walk"),
        "scale_factor": (_FRACTION, "scale-factor error (1σ)"),
        "misalignment": (_ANGLE, "misalignment / cross-axis coupling (1σ)"),
        "range": (_ACCEL, "measurement range"),
        "resolution": (_ACCEL, "quantisation step"),
        "bandwidth": (_FREQ, "anti-alias / bandwidth filter corner"),
        "internal_rate": (_FREQ, "internal sample rate"),
    },
}


def _normalise(unit: str) -> str:
    u = unit.strip().replace(" ", "").replace("²", "^2").replace("μ", "µ")
    u = re.sub(r"√\(?([A-Za-z]+)\)?", r"sqrt(\1)", u)
    u = re.sub(r"(?<!sq)rt\(?(Hz|hr|h|s)\)?", r"sqrt(\1)", u)
    u = u.replace("°", "deg").replace("dph", "deg/h").replace("/√", "/sqrt")
    u = u.replace("sqrtHz", "sqrt(Hz)").replace("sqrthr", "sqrt(hr)").replace("sqrth", "sqrt(h)")
    u = u.replace("sqrts", "sqrt(s)")
    return u


def parse(value, key: str) -> float:
    """Convert ``value`` (a number in SI, or a string ``"<number> <unit>"``) for ``key``
    (``"gyro.noise_density"`` …) to SI."""
    triad, _, name = key.partition(".")
    if triad not in SPEC or name not in SPEC[triad]:
        known = ", ".join(f"{t}.{k}" for t in SPEC for k in SPEC[t])
        raise ImunavError(f"unknown error parameter {key!r}; known: {known}")
    units, what = SPEC[triad][name]
    if isinstance(value, bool):
        raise ImunavError(f"{key} must be a number or a string with units, got {show(value)}")
    if isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, np.bool_):
        v = float(value)
    elif isinstance(value, str):
        m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", value)
        if not m:
            raise ImunavError(f"{key} = {value!r}: expected '<number> <unit>'")
        unit = _normalise(m.group(2))
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
    if name in LIMITS and not LIMITS[name][0] <= v <= LIMITS[name][1]:
        lo, hi, why = LIMITS[name]
        raise ImunavError(f"{key} = {show(value)} is outside {lo:g}–{hi:g} (SI): {why}")
    return v


#: Physical bounds of parameters that size the work (SI): a value outside is a typo.
LIMITS = {
    "internal_rate": (1.0, 1e6, "no inertial sensor samples faster than 1 MHz internally"),
    "bandwidth": (1e-3, 1e6, "a filter corner between 1 mHz and 1 MHz"),
    "bias_correlation_time": (1e-3, 1e9, "a correlation time between 1 ms and 30 years"),
}


def factor(unit: str, dimension: str, what: str) -> float:
    """SI factor of ``unit`` (a spelling of :data:`DIMENSIONS` ``[dimension]``); ``what`` names
    the argument in the error (``"--gyro-units"``)."""
    table = DIMENSIONS[dimension]
    u = _normalise(unit) if isinstance(unit, str) else unit
    if u not in table:
        raise ImunavError(f"unknown {what} {unit!r}; expected one of {', '.join(table)}")
    return table[u]
