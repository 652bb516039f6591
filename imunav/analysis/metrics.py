"""Error metrics of a navigation result against the truth, and fitted convergence orders.

May import: ``imunav.core``, ``imunav.motion``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import quat_angle
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.motion.base import BaseMotion


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


def nav_errors(nav: States, truth: BaseMotion | States) -> NavErrors:
    """Compare ``nav`` with the truth at the navigation times: a motion (evaluated there) or
    :class:`States` at the same times."""
    ref = truth.states(nav.t) if isinstance(truth, BaseMotion) else truth
    return NavErrors(
        nav.t,
        quat_angle(nav.quaternion, ref.quaternion),
        np.linalg.norm(nav.velocity - ref.velocity, axis=-1),
        np.linalg.norm(nav.position - ref.position, axis=-1),
    )


def fit_order(steps, errors) -> float:
    """Least-squares slope of log(error) vs log(step): the convergence order."""
    x = np.log(np.asarray(steps, dtype=float))
    y = np.log(np.asarray(errors, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
