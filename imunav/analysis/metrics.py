"""Error metrics of a navigation result against the truth, and fitted convergence orders.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import quat_angle
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import ImunavError
from imunav.earth import ned_difference
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
    :class:`States` at the same times. On the WGS-84 Earth (``frame="wgs84"``) the position
    error is the distance in metres (:func:`imunav.earth.ned_difference`), the velocity and
    attitude errors are taken in the local NED frame of the truth."""
    ref = truth.states(nav.t) if isinstance(truth, BaseMotion) else truth
    if nav.frame != ref.frame:
        raise ImunavError(f"nav is in the {nav.frame} frame but the truth in the {ref.frame} "
                          "frame", argument="truth")
    if nav.frame == "wgs84":
        dp = np.linalg.norm(ned_difference(nav.position, ref.position), axis=-1)
    else:
        dp = np.linalg.norm(nav.position - ref.position, axis=-1)
    return NavErrors(
        nav.t,
        quat_angle(nav.quaternion, ref.quaternion),
        np.linalg.norm(nav.velocity - ref.velocity, axis=-1),
        dp,
    )


def fit_order(steps, errors) -> float:
    """Least-squares slope of log(error) vs log(step): the convergence order."""
    x = np.log(np.asarray(steps, dtype=float))
    y = np.log(np.asarray(errors, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
