"""A wheel odometer: the speed along the body's x axis (forward), with an optional scale-factor
error of its own.

``[odometer]`` of ``AIDING.toml``: ``rate`` (Hz), ``sigma`` (m/s, white), ``scale_factor_sigma``
(a fraction, e.g. 0.01 for 1 %: the σ of a constant scale-factor error, carried by the filter as
one state; 0, the default: none). Reading ``speed`` (m/s, ``odometer.csv``: ``t,speed``).

Model: ``speed = (1 + k) (C_nbᵀ v)_x + w`` — the vehicle's forward velocity at the IMU (the
wheel's lever arm is not modelled: mount the IMU over the wheels' axis, or add the arm's
``ω × l`` to the readings). Prediction ``(1 + k̂) (Cᵀ v)_x``; with ``u = (Cᵀ v)_x`` and the
scale state ``x = k − k̂``, ``predicted − true ≈ (1 + k̂) (−(Cᵀ [v×])_x φ + (Cᵀ)_x δv) − u x``.

May import: ``imunav.core``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import quat_conj, quat_rotate, skew
from imunav.core.layout import DV, PHI
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

__all__ = ["Odometer", "OdometerConfig"]


@dataclass(frozen=True)
class OdometerConfig(TableConfig):
    """A wheel odometer.

    Attributes
    ----------
    rate : float
        Hz.
    sigma : float
        White speed noise (m/s).
    scale_factor_sigma : float
        σ of its constant scale-factor error (a fraction); 0: none.
    """

    rate: float
    sigma: float
    scale_factor_sigma: float = 0.0

    TABLE = "odometer"
    FIELDS = (Key("rate", "Hz", "odometer rate", required=True, hi=1000.0),
              Key("sigma", "m/s", "odometer σ", required=True, hi=100.0),
              Key("scale_factor_sigma", "", "scale-factor σ (a fraction)", default=0.0,
                  positive=False, hi=0.5))


class Odometer(Measurement):
    """The forward speed of the body, ``(1 + k)(C_nbᵀ v)_x``.

    Parameters
    ----------
    sigma : float
        White noise (m/s).
    scale_factor_sigma : float
        σ of a constant scale-factor error, carried as one state; 0: none.
    """

    name, columns, batched = "odometer", ("speed",), True

    def __init__(self, sigma: float, scale_factor_sigma: float = 0.0):
        super().__init__()
        self.sigma = float(sigma)
        if scale_factor_sigma > 0:
            self.states = [AidStates("odometer.scale", np.zeros(1),
                                     np.array([[scale_factor_sigma ** 2]]), np.zeros(1))]

    def _scale(self, nav):
        sl = self.offsets.get("odometer.scale")
        return 0.0 if sl is None else nav.estimates[..., sl][..., 0]

    def predict(self, nav):
        # ``(1 + k̂) (Cᵀ v)_x``.
        u = (np.swapaxes(nav.C, -1, -2) @ nav.v[..., None])[..., 0, 0]
        return ((1.0 + self._scale(nav)) * u)[..., None]

    def jacobian(self, nav):
        # ``(1 + k̂)(−(Cᵀ [v×])_x φ + (Cᵀ)_x δv) − u x_k``.
        H = self.zeros_H(nav)
        CT = np.swapaxes(nav.C, -1, -2)
        k = np.asarray(1.0 + self._scale(nav))[..., None]
        H[..., 0, PHI] = k * (-CT @ skew(nav.v))[..., 0, :]
        H[..., 0, DV] = k * CT[..., 0, :]
        sl = self.offsets.get("odometer.scale")
        if sl is not None:
            H[..., 0, sl] = -(CT @ nav.v[..., None])[..., 0, :]
        return H

    def noise(self):
        # ``σ²``.
        return np.array([[self.sigma ** 2]])


class OdometerSpec(AidSpec):
    """The odometer aid (see the module docstring)."""

    name = "odometer"
    summary = "wheel speed along the body's x axis, with a scale-factor error"
    config = OdometerConfig
    file = "odometer.csv"
    headers = {"flat": (("t", "speed"),), "wgs84": (("t", "speed"),)}
    stream = 5

    def units(self, config):
        return ("m/s",)

    def measurement(self, config, *, truth=False):
        return Odometer(config.sigma, config.scale_factor_sigma)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        t = reading_times(config.rate, duration, t0)
        k = rng.normal(0.0, config.scale_factor_sigma) if config.scale_factor_sigma else 0.0
        u = quat_rotate(quat_conj(motion.attitude(t)), motion.velocity(t))[:, 0]
        return Readings(t, ((1.0 + k) * u + rng.normal(0.0, config.sigma, t.size))[:, None])


register(OdometerSpec())
