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
    """Errors vs time: attitude angle (rad), position and velocity error norms (m, m/s).

    Attributes
    ----------
    t : ndarray, shape (N,)
        The navigation times (s).
    attitude : ndarray, shape (N,)
        Angle of the rotation between the navigated and true ``q_nb`` (rad), ≥ 0.
    velocity : ndarray, shape (N,)
        Norm of the velocity error (m/s).
    position : ndarray, shape (N,)
        Norm of the position error (m; on the WGS-84 Earth the distance in local NED).
    """

    t: FloatArray
    attitude: FloatArray
    velocity: FloatArray
    position: FloatArray

    def summary(self) -> dict[str, float]:
        """Final and maximum of each error.

        Returns
        -------
        dict of str to float
            ``final_attitude``, ``max_attitude`` (rad), ``final_velocity``, ``max_velocity``
            (m/s), ``final_position``, ``max_position`` (m).
        """
        out = {}
        for k in ("attitude", "velocity", "position"):
            a = getattr(self, k)
            out[f"final_{k}"] = float(a[-1])
            out[f"max_{k}"] = float(a.max())
        return out


def nav_errors(nav: States, truth: BaseMotion | States) -> NavErrors:
    """Compare a navigation result with the truth at the navigation times.

    On the WGS-84 Earth (``frame="wgs84"``) the position error is the distance in metres
    (:func:`imunav.earth.ned_difference`), the velocity and attitude errors are taken in the
    local NED frame of the truth.

    Parameters
    ----------
    nav : States
        The navigation result.
    truth : BaseMotion or States
        A motion (evaluated at ``nav.t``) or states at the same times as ``nav``, in the same
        frame.

    Returns
    -------
    NavErrors
        The error norms at ``nav.t``.

    Raises
    ------
    ImunavError
        If ``nav`` and ``truth`` are in different frames (flat vs WGS-84), or (a motion) it
        cannot be evaluated at ``nav.t``.

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> truth = Motion(x="2*t")
    >>> nav = Motion(x="2.1*t").states([0.0, 1.0, 2.0])
    >>> nav_errors(nav, truth).position.round(12)
    array([0. , 0.1, 0.2])
    """
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
    """Least-squares slope of log(error) vs log(step): the convergence order.

    Parameters
    ----------
    steps : array_like, shape (n,)
        Step sizes (e.g. sample intervals, s), > 0; at least two.
    errors : array_like, shape (n,)
        The errors at those steps (any unit), > 0.

    Returns
    -------
    float
        The fitted order p of ``error ≈ C · step^p``.

    Examples
    --------
    >>> round(fit_order([0.1, 0.05, 0.025], [1e-2, 2.5e-3, 6.25e-4]), 12)
    2.0
    """
    x = np.log(np.asarray(steps, dtype=float))
    y = np.log(np.asarray(errors, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
