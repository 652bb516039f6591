"""The sensor error terms of the signal chain, after the errors are added: the saturation
(:class:`Range`), the quantisation (:class:`Resolution`), the anti-alias filter
(:class:`Bandwidth`) and the internal sample rate (:class:`InternalRate`), with the aliasing
gain they give the white noise of decimated rate samples (:func:`aliasing_gain`). Registered in
:data:`imunav.sensors.terms.TERMS`.

May import: ``imunav.core``, ``imunav.sensors.term_base``.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import butter, sosfilt, sosfilt_zi, sosfreqz

from imunav.core import units as U
from imunav.core.deprecation import renamed
from imunav.core.kernels import FloatArray
from imunav.sensors.term_base import (
    Parameter,
    SensorErrorStates,
    Term,
    both_triads,
    identity_input,
    main_parameter,
    per_triad,
)

__all__ = ["Bandwidth", "InternalRate", "Range", "Resolution", "aliasing_gain"]


class Range(Term):
    """Saturation: outputs beyond ±range are clipped and flagged."""

    name, stage, linear = "range", "saturation", False
    parameters_ = (Parameter("range", per_triad(U.RATE, U.ACCEL), both_triads("measurement range"), None,
                             positive=True),)
    display = {"gyro": ("deg/s", "°/s", "rad/s"), "accel": ("g", "g", "m/s²")}

    def saturate(self, model, y: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """``(clipped y, flag per sample)``."""
        over = np.abs(y) > model.range
        flags = over[:, 0] | over[:, 1] | over[:, 2]          # any axis (8× np.any's speed)
        np.clip(y, -model.range, model.range, out=y)
        return y, flags

    def linearise(self, model, ctx):
        """No linear model: a warning when the motion exceeds the range."""
        if self.present(model) and ctx.peak > model.range:
            what = "angular rate" if ctx.triad == "gyro" else "specific force"
            t = ctx.triad
            peak = self.show(ctx.peak, t, typographic=True)
            limit = self.show(model.range, t, typographic=True)
            ctx.warnings.append(f"the motion's {what} reaches {peak}, beyond the {t} range "
                                f"{limit}: clipping is not in the covariance; use Monte Carlo")
        return []


class Resolution(Term):
    """Quantisation to a step q; increments carry the rounding residual."""

    name, stage = "resolution", "quantisation"
    parameters_ = (main_parameter("resolution", per_triad(U.RATE, U.ACCEL), both_triads("quantisation step"),
                         None),)
    display = {"gyro": ("deg/s", "°/s", "rad/s"), "accel": ("mg", "mg", "m/s²")}

    def start(self, model, stream, rng):
        """Increments: ``[exact running sum, quantised running sum]``."""
        return [np.zeros(3), np.zeros(3)]

    def quantise(self, model, state, stream, y: FloatArray) -> FloatArray:
        """Output samples ``y`` (already in output units) rounded to the step."""
        if stream.kind == "increments":
            q = model.resolution * stream.dt * stream.k
            total = np.cumsum(y, axis=0)                             # residual carry: no loss
            total += state[0]
            qt = total / q
            np.round(qt, out=qt)
            qt *= q
            out = np.empty_like(qt)                                  # np.diff(qt, prepend=…)
            np.subtract(qt[:1], state[1], out=out[:1])
            np.subtract(qt[1:], qt[:-1], out=out[1:])
            state[0], state[1] = total[-1], qt[-1]
            return out
        return np.round(y / model.resolution) * model.resolution

    def linearise(self, model, ctx):
        """Rates: white noise of PSD q²h/12; increments: differenced white noise."""
        if not self.present(model):
            return []
        name = f"{ctx.triad}.{self.name}"
        if ctx.kind == "rates":
            return [SensorErrorStates(name, ctx.triad, white_psd=model.resolution ** 2 * ctx.h / 12)]
        return [SensorErrorStates(name, ctx.triad, input_matrix=identity_input,
                                  differenced_white=(model.resolution * ctx.h) ** 2 / 12)]


class Bandwidth(Term):
    """A 2nd-order Butterworth low-pass at the internal rate (steady state at the start)."""

    name, stage, linear = "bandwidth", "filter", False
    parameters_ = (main_parameter("bandwidth", per_triad(U.FREQ, U.FREQ),
                         both_triads("anti-alias / bandwidth filter corner"), None,
                         (1e-3, 1e6, "a filter corner between 1 mHz and 1 MHz")),)

    def start(self, model, stream, rng):
        """``[sos, filter state]`` if the corner is below the Nyquist rate, else None."""
        if model.bandwidth < 0.5 * stream.rate:
            return [butter(2, model.bandwidth, fs=stream.rate, output="sos"), None]
        return None

    def filter(self, model, state, stream, y: FloatArray) -> FloatArray:
        """``y`` through the filter, its state carried to the next chunk."""
        if state is None:
            return y
        sos, zi = state
        if zi is None:                # steady state for the first input (no start-up transient)
            zi = sosfilt_zi(sos)[:, :, None] * y[0]
        y, state[1] = sosfilt(sos, y, axis=0, zi=zi)
        return y

    def linearise(self, model, ctx):
        """No states: unit gain at low frequency; its effect on decimated rate noise is in
        :func:`aliasing_gain` (the white-noise term)."""
        return []


class InternalRate(Term):
    """The sensor's internal sample rate: the simulation runs there and decimates."""

    name, stage, is_error, linear = "internal_rate", "decimation", False, False
    parameters_ = (main_parameter("internal_rate", per_triad(U.FREQ, U.FREQ),
                         both_triads("internal sample rate"), None,
                         (1.0, 1e6, "no inertial sensor samples faster than 1 MHz internally")),)

    def linearise(self, model, ctx):
        """No error of its own: it sets the decimation the white noise's aliasing gain uses."""
        return []


@renamed(output="kind")
def aliasing_gain(model, rate: float, decimate: int, kind: str) -> float:
    """Factor on the white-noise density of ``kind`` samples at ``rate`` taken every
    ``decimate``-th of the sensor's internal samples.

    Increments sum the internal ones, so the integrated noise is unchanged (1). Rate samples
    decimated by k keep every k-th sample: the noise above the output Nyquist folds onto low
    frequencies, and the density is multiplied by ``√(Σ_{m<k} |H(m·rate)|²)`` (H the anti-alias
    filter; 1 without one, so √k).

    Parameters
    ----------
    model : TriadModel
    rate : float
        Output rate (Hz).
    decimate : int
        Internal samples per output sample.
    kind : {"increments", "rates"}

    Returns
    -------
    float
    """
    if kind != "rates" or decimate <= 1:
        return 1.0
    fi = rate * decimate
    f = np.arange(decimate) * rate
    if model.bandwidth and model.bandwidth < 0.5 * fi:
        sos = butter(2, model.bandwidth, fs=fi, output="sos")
        h2 = np.abs(sosfreqz(sos, worN=f, fs=fi)[1]) ** 2
    else:
        h2 = np.ones(decimate)
    return float(np.sqrt(h2.sum()))
