"""A heading reference (magnetometer-like): the yaw, with white noise.

``[heading]`` of ``AIDING.toml``: ``rate`` (Hz), ``sigma`` (rad, or a string with its unit,
``"2 deg"``). Prediction ``atan2(C₁₀, C₀₀)``, the innovation wrapped to [−π, π).

May import: ``imunav.core``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import quat_to_dcm
from imunav.core.layout import PHI
from imunav.sensors.aids.base import (
    AidSpec,
    Key,
    Measurement,
    Readings,
    TableConfig,
    euler_jacobian,
    reading_times,
    register,
    wrap_angle,
    yaw_of,
)

__all__ = ["Heading", "HeadingConfig"]


@dataclass(frozen=True)
class HeadingConfig(TableConfig):
    """A yaw reference (magnetometer-like).

    Attributes
    ----------
    rate : float
        Hz.
    sigma : float
        White yaw noise (rad).
    """

    rate: float
    sigma: float

    TABLE = "heading"
    FIELDS = (Key("rate", "Hz", "heading rate", required=True, hi=1000.0),
              Key("sigma", "rad", "heading σ", kind="angle", required=True, hi=np.pi))


class Heading(Measurement):
    """A yaw reference.

    Parameters
    ----------
    sigma : float
        White noise (rad).
    """

    name, columns, angular, batched = "heading", ("yaw",), True, True

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``atan2(C₁₀, C₀₀)``.
        return yaw_of(nav.C)[..., None]

    def jacobian(self, nav):
        # The yaw row of :func:`euler_jacobian`.
        H = self.zeros_H(nav)
        H[..., 0, PHI] = euler_jacobian(nav.C)[..., 0, :]
        return H

    def noise(self):
        # ``σ²``.
        return np.array([[self.sigma ** 2]])


class HeadingSpec(AidSpec):
    """The heading aid (see the module docstring)."""

    name = "heading"
    summary = "a yaw reference (magnetometer-like)"
    config = HeadingConfig
    file = "heading.csv"
    headers = {"flat": (("t", "yaw"),), "wgs84": (("t", "yaw"),)}
    stream = 2

    def units(self, config):
        return ("rad",)

    def measurement(self, config, *, truth=False):
        return Heading(config.sigma)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        t = reading_times(config.rate, duration, t0)
        yaw = yaw_of(quat_to_dcm(motion.attitude(t)))
        return Readings(t, wrap_angle(yaw + rng.normal(0.0, config.sigma, t.size))[:, None])


register(HeadingSpec())
