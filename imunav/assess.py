"""Error metrics of a navigation result against the truth."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.motion import BaseMotion
from imunav.rotations import FloatArray, _angle
from imunav.strapdown import NavResult


@dataclass
class NavErrors:
    """Errors vs time: attitude angle (rad), position and velocity error norms (m, m/s)."""

    t: FloatArray
    attitude: FloatArray
    velocity: FloatArray
    position: FloatArray

    def summary(self) -> dict[str, float]:
        """Final and maximum of each error."""
        out = {}
        for k in ("attitude", "velocity", "position"):
            a = getattr(self, k)
            out[f"final_{k}"] = float(a[-1])
            out[f"max_{k}"] = float(a.max())
        return out


def nav_errors(nav: NavResult, motion: BaseMotion) -> NavErrors:
    """Compare ``nav`` with the analytic truth of ``motion`` at the navigation times."""
    qt = motion.attitude(nav.t)
    return NavErrors(
        nav.t,
        _angle(nav.quaternion, qt),
        np.linalg.norm(nav.velocity - motion.velocity(nav.t), axis=1),
        np.linalg.norm(nav.position - motion.position(nav.t), axis=1),
    )


def fit_order(steps, errors) -> float:
    """Least-squares slope of log(error) vs log(step): the convergence order."""
    x = np.log(np.asarray(steps, dtype=float))
    y = np.log(np.asarray(errors, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
