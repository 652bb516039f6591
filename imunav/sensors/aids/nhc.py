"""The non-holonomic constraint of a wheeled vehicle: zero lateral and vertical velocity in the
body frame.

``[nhc]`` of ``AIDING.toml``: ``sigma`` (m/s: how well the constraint holds, the slip per
component), ``rate`` (Hz, default 10: how often the filter applies it). Without a file
(``nhc.csv``) the filter applies the constraint (reading zero) at its rate; the simulation
writes the slip the sigma stands for. Prediction ``(Cᵀ v)_{y,z}``.

May import: ``imunav.core``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import skew
from imunav.core.layout import DV, PHI
from imunav.sensors.aids.base import (
    AidSpec,
    Key,
    Measurement,
    Readings,
    TableConfig,
    reading_times,
    register,
)

__all__ = ["Nhc", "NhcConfig"]


@dataclass(frozen=True)
class NhcConfig(TableConfig):
    """The non-holonomic constraint of a wheeled vehicle: zero lateral and vertical body velocity.

    Attributes
    ----------
    sigma : float
        How well the constraint holds (m/s): the slip, per component.
    rate : float
        How often it is applied (Hz).
    """

    sigma: float
    rate: float = 10.0

    TABLE = "nhc"
    FIELDS = (Key("sigma", "m/s", "constraint σ", required=True, hi=100.0),
              Key("rate", "Hz", "constraint rate", default=10.0, hi=1000.0))


class Nhc(Measurement):
    """The non-holonomic constraint: zero lateral and vertical velocity in the body frame.

    Parameters
    ----------
    sigma : float
        How well it holds (m/s).
    """

    name, columns, batched = "nhc", ("vy", "vz"), True

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``(Cᵀ v)_{y,z}``.
        return (np.swapaxes(nav.C, -1, -2) @ nav.v[..., None])[..., 1:3, 0]

    def jacobian(self, nav):
        # Rows y, z of ``−Cᵀ [v×] φ + Cᵀ δv``.
        H = self.zeros_H(nav)
        CT = np.swapaxes(nav.C, -1, -2)
        H[..., :, PHI] = (-CT @ skew(nav.v))[..., 1:3, :]
        H[..., :, DV] = CT[..., 1:3, :]
        return H

    def noise(self):
        # ``σ² I₂``.
        return self.sigma ** 2 * np.eye(2)


class NhcSpec(AidSpec):
    """The NHC aid (see the module docstring)."""

    name = "nhc"
    summary = "zero lateral and vertical body velocity (a wheeled vehicle)"
    config = NhcConfig
    file = "nhc.csv"
    headers = {"flat": (("t", "vy", "vz"),), "wgs84": (("t", "vy", "vz"),)}
    stream = 3

    def units(self, config):
        return ("m/s", "m/s")

    def measurement(self, config, *, truth=False):
        return Nhc(config.sigma)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        t = reading_times(config.rate, duration, t0)
        return Readings(t, rng.normal(0.0, config.sigma, (t.size, 2)))

    def file_needed(self, config):
        return False

    def readings(self, config, data, signals):
        r = data.get(self.name)
        if r is not None:
            return r
        tn = signals.state_times()
        t = reading_times(config.rate, float(tn[-1] - tn[0]), float(tn[0]))
        return Readings(t, np.zeros((t.size, 2)))


register(NhcSpec())
