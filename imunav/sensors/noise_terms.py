"""The sensor error terms that are random processes, drawn afresh along a run: white noise
(:class:`WhiteNoise`), the bias instability as Gauss–Markov processes (:class:`BiasInstability`,
:func:`bias_instability_sigma`) and the random walk (:class:`RandomWalk`). Registered in
:data:`imunav.sensors.terms.TERMS`.

May import: ``imunav.core``, ``imunav.sensors.allan``, ``imunav.sensors.term_base``,
``imunav.sensors.signal_terms``.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from imunav.core import units as U
from imunav.core.kernels import FloatArray
from imunav.sensors.allan import gauss_markov_allan_variance
from imunav.sensors.signal_terms import aliasing_gain
from imunav.sensors.term_base import (
    Parameter,
    SensorErrorStates,
    Term,
    both_triads,
    identity_input,
    main_parameter,
    per_triad,
)

__all__ = ["BiasInstability", "RandomWalk", "WhiteNoise", "bias_instability_sigma",
           "flicker_bank"]


class WhiteNoise(Term):
    """White noise of density N: ``N·√rate`` per sample."""

    name, stage = "noise_density", "white"
    parameters_ = (main_parameter("noise_density", per_triad(U.DENSITY_RATE, U.DENSITY_ACCEL),
                         {"gyro": "rate noise density / angle random walk",
                          "accel": "acceleration noise density / velocity random walk"}),)
    display = {"gyro": ("deg/sqrt(h)", "°/√h", "rad/s/√Hz (= rad/√s)"),
               "accel": ("ug/sqrt(Hz)", "µg/√Hz", "m/s²/√Hz (= m/s/√s)")}

    def start(self, model, stream, rng):
        """A child generator for the noise."""
        return rng.spawn(1)[0]

    def add_white(self, model, state, stream, y: FloatArray) -> FloatArray:
        """``y`` plus this run's white noise (rate units)."""
        y += state.normal(0.0, model.noise_density * np.sqrt(stream.rate), y.shape)
        return y

    def linearise(self, model, ctx):
        """White noise of PSD ``(N · aliasing gain)²`` on the output."""
        if not self.present(model):
            return []
        gain = aliasing_gain(model, 1 / ctx.h, ctx.decimate, ctx.kind)
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad,
                                  white_psd=(model.noise_density * gain) ** 2)]


def flicker_bank(T: float | None) -> list[float]:
    """Correlation times (s) of the Gauss–Markov components of a bias instability: ``[T]`` if
    a correlation time is given, else the flicker bank (9 times from 0.3 to 3000 s)."""
    return [T] if T else list(np.logspace(np.log10(0.3), np.log10(3000.0), 9))


def bias_instability_sigma(B: float, T: float | None) -> float:
    """Std of each Gauss–Markov component so the Allan-deviation maximum equals ``B``.

    Parameters
    ----------
    B : float
        The bias instability (Allan-deviation floor), SI.
    T : float or None
        The correlation time (s), or None for the flicker bank.

    Returns
    -------
    float
    """
    taus = np.logspace(-3, 5, 4000)
    var = sum(gauss_markov_allan_variance(taus, 1.0, t) for t in flicker_bank(T))
    return B / float(np.sqrt(var.max()))


class BiasInstability(Term):
    """Gauss–Markov processes whose Allan maximum is the datasheet's bias instability."""

    name, stage = "bias_instability", "drift"
    parameters_ = (
        main_parameter("bias_instability", per_triad(U.RATE, U.ACCEL),
              both_triads("bias instability (Allan deviation floor)")),
        Parameter("bias_correlation_time", per_triad(U.TIME, U.TIME),
                  both_triads("bias correlation time"), None,
                  (1e-3, 1e9, "a correlation time between 1 ms and 30 years"), qualifier=True),
    )
    display = {"gyro": ("deg/h", "°/h", "rad/s"), "accel": ("ug", "µg", "m/s²")}

    def start(self, model, stream, rng):
        """Per component: ``[child generator, a = e^{−dt/T}, innovation σ, previous value]``,
        the value before the first sample drawn from the stationary distribution."""
        sd = bias_instability_sigma(model.bias_instability, model.bias_correlation_time)
        out = []
        for T in flicker_bank(model.bias_correlation_time):
            child = rng.spawn(1)[0]
            a = float(np.exp(-stream.dt / T))
            out.append([child, a, sd * np.sqrt(1 - a * a), child.normal(0.0, sd, 3)])
        return out

    def add_drift(self, model, state, stream, drift: FloatArray) -> None:
        """Add the next ``len(drift)`` samples of each component to ``drift`` (in place)."""
        n = drift.shape[0]
        for st in state:
            child, a, sw, prev = st
            w = child.normal(0.0, sw, (n, 3))
            y, _ = lfilter([1.0], [1.0, -a], w, axis=0, zi=(a * prev)[None])
            drift += y
            st[3] = y[-1]

    def linearise(self, model, ctx):
        """3 states per component: decay 1/T, stationary variance s², driving PSD 2s²/T."""
        if not self.present(model):
            return []
        s = bias_instability_sigma(model.bias_instability, model.bias_correlation_time)
        bank = flicker_bank(model.bias_correlation_time)
        k = 3 * len(bank)
        D = np.repeat([-1.0 / T for T in bank], 3)
        Qs = np.repeat([2 * s * s / T for T in bank], 3)

        def each_component(u, f):
            """δ = Σ components: the identity once per component."""
            return np.tile(np.broadcast_to(np.eye(3), (u.shape[0], 3, 3)), (1, 1, len(bank)))

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, D, s * s * np.eye(k),
                                  Qs, each_component)]


class RandomWalk(Term):
    """Integrated white noise of density K."""

    name, stage = "random_walk", "drift"
    parameters_ = (main_parameter("random_walk", per_triad(U.RW_RATE, U.RW_ACCEL),
                         {"gyro": "rate random walk", "accel": "acceleration random walk"}),)
    display = {"gyro": ("deg/h/sqrt(h)", "°/h/√h", "rad/s/√s"),
               "accel": ("m/s/h/sqrt(h)", "m/s/h/√h", "m/s²/√s")}

    def start(self, model, stream, rng):
        """``[child generator, the walk's last value]``."""
        return [rng.spawn(1)[0], np.zeros(3)]

    def add_drift(self, model, state, stream, drift: FloatArray) -> None:
        """Add the next ``len(drift)`` samples of the walk to ``drift`` (in place)."""
        child, last = state
        walk = np.cumsum(child.normal(0.0, model.random_walk * np.sqrt(stream.dt),
                                      drift.shape), axis=0) + last
        state[1] = walk[-1]
        drift += walk

    def linearise(self, model, ctx):
        """3 states of integrated white noise (PSD K²), starting at 0."""
        if not self.present(model):
            return []
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  np.zeros((3, 3)), np.full(3, model.random_walk ** 2),
                                  identity_input)]
