"""A barometric altimeter: altitude ``−z`` (flat) or the height above the ellipsoid (WGS-84),
with a random-walk bias.

``[baro]`` of ``AIDING.toml``: ``rate`` (Hz), ``sigma`` (m, white), ``bias_drift`` (m/√s: a
random walk from 0; 0: no bias state). Prediction ``−(p_z + v_z dt) + b̂``.

May import: ``imunav.core``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.sensors.aids.base import (
    AidSpec,
    AidStates,
    Key,
    Measurement,
    Readings,
    TableConfig,
    reading_times,
    register,
)

__all__ = ["Baro", "BaroConfig"]


@dataclass(frozen=True)
class BaroConfig(TableConfig):
    """A barometric altimeter.

    Attributes
    ----------
    rate : float
        Hz.
    sigma : float
        White altitude noise (m).
    bias_drift : float
        Random-walk density of its bias (m/√s), from 0.
    """

    rate: float
    sigma: float
    bias_drift: float = 0.0

    TABLE = "baro"
    FIELDS = (Key("rate", "Hz", "barometer rate", required=True, hi=1000.0),
              Key("sigma", "m", "barometer σ", required=True, hi=1e3),
              Key("bias_drift", "m/√s", "bias random walk", default=0.0, positive=False,
                  hi=10.0))


class Baro(Measurement):
    """Barometric altitude ``−z`` with a random-walk bias.

    Parameters
    ----------
    sigma : float
        White noise (m).
    bias_drift : float
        Random-walk density of the bias (m/√s); 0: no bias state.
    """

    name, columns, batched = "baro", ("alt",), True

    def __init__(self, sigma: float, bias_drift: float = 0.0):
        super().__init__()
        self.sigma = float(sigma)
        if bias_drift > 0:
            self.states = [AidStates("baro.bias", np.zeros(1), np.zeros((1, 1)),
                                     np.array([bias_drift ** 2]))]

    def predict(self, nav):
        # ``−(p_z + v_z dt) + b̂``.
        sl = self.offsets.get("baro.bias")
        b = 0.0 if sl is None else nav.estimates[..., sl][..., 0]
        return (-(nav.p[..., 2] + nav.v[..., 2] * nav.dt) + b)[..., None]

    def jacobian(self, nav):
        # ``−δp_z − dt δv_z − x_b``.
        H = self.zeros_H(nav)
        H[..., 0, 8], H[..., 0, 5] = -1.0, -nav.dt
        sl = self.offsets.get("baro.bias")
        if sl is not None:
            H[..., 0, sl] = -1.0
        return H

    def noise(self):
        # ``σ²``.
        return np.array([[self.sigma ** 2]])


class BaroSpec(AidSpec):
    """The barometer aid (see the module docstring)."""

    name = "baro"
    summary = "barometric altitude with a random-walk bias"
    config = BaroConfig
    file = "baro.csv"
    headers = {"flat": (("t", "alt"),), "wgs84": (("t", "alt"),)}
    stream = 1

    def units(self, config):
        return ("m",)

    def measurement(self, config, *, truth=False):
        return Baro(config.sigma, config.bias_drift)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        c = config
        earth = getattr(motion, "frame", "flat") == "wgs84"
        t = reading_times(c.rate, duration, t0)
        dts = np.diff(np.concatenate([[t0], t]))
        bias = np.cumsum(rng.normal(0.0, 1.0, t.size) * c.bias_drift * np.sqrt(dts))
        alt = ((motion.position(t)[:, 2] if earth else -motion.position(t)[:, 2]) + bias
               + rng.normal(0.0, c.sigma, t.size))
        return Readings(t, alt[:, None])


register(BaroSpec())
