"""The motion interface: what every motion answers at any time.

:class:`BaseMotion` is implemented by analytic laws (:mod:`imunav.motion.analytic`),
closed-form quaternion laws (:mod:`imunav.motion.quaternion_law`) and any user motion. The
specific force, Euler angles, DCMs and :class:`~imunav.core.states.States` follow from the five
methods a subclass implements.

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.kernels import quat_conj, quat_rotate, quat_to_dcm
from imunav.core.rotations import FloatArray, quat_to_euler
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array, check_gravity, check_positive


class BaseMotion:
    """A rigid-body motion in the NED navigation frame.

    Subclasses implement :meth:`position`, :meth:`velocity`, :meth:`acceleration`,
    :meth:`attitude` and :meth:`angular_rate`; the specific force and Euler angles follow.
    All methods take times ``t`` (s, array_like, any shape) and return arrays of shape
    ``t.shape + (3,)`` (or ``(4,)`` for quaternions).
    """

    #: Default duration (s) used by the CLI and notebooks when none is given.
    duration: float | None = None
    #: A name for reports and plots.
    name: str = "motion"
    #: True for a motion defined only on ``[0, duration]`` (data: poses, waypoints): it is never
    #: run past its end (:func:`span`).
    bounded: bool = False
    #: Times (s) where the motion is only piecewise smooth (a spline's knots), or None: the
    #: exact increments are integrated piece by piece between them.
    breakpoints: FloatArray | None = None
    #: Time (s) in the source data of the motion's t = 0 (the first pose or waypoint).
    time_offset: float = 0.0
    #: The navigation frame it is given in: ``"flat"`` (non-rotating NED) or ``"wgs84"`` (the
    #: rotating Earth, :class:`~imunav.motion.geodetic.EarthMotion`).
    frame: str = "flat"

    def position(self, t: npt.ArrayLike) -> FloatArray:
        """Position ``r_n`` (m)."""
        raise NotImplementedError

    def velocity(self, t: npt.ArrayLike) -> FloatArray:
        """Velocity ``v_n = ṙ_n`` (m/s)."""
        raise NotImplementedError

    def acceleration(self, t: npt.ArrayLike) -> FloatArray:
        """Kinematic acceleration ``a_n = r̈_n`` (m/s²)."""
        raise NotImplementedError

    def attitude(self, t: npt.ArrayLike) -> FloatArray:
        """Attitude quaternion ``q_nb`` (scalar first, unit norm)."""
        raise NotImplementedError

    def angular_rate(self, t: npt.ArrayLike) -> FloatArray:
        """Body angular rate ``ω_b`` (rad/s): vector part of ``2 q* ⊗ q̇``."""
        raise NotImplementedError

    def specific_force(self, t: npt.ArrayLike, g: float = G0) -> FloatArray:
        """Specific force ``f_b = C_bn (a_n − g_n)`` (m/s²), ``g_n = [0, 0, +g]``."""
        t = times(t)
        g = check_gravity(g)
        a = self.acceleration(t)
        a = a - np.array([0.0, 0.0, g])
        return quat_rotate(quat_conj(self.attitude(t)), a)

    def euler(self, t: npt.ArrayLike) -> FloatArray:
        """``[yaw, pitch, roll]`` (rad) of :meth:`attitude`."""
        return quat_to_euler(self.attitude(t))

    def dcm(self, t: npt.ArrayLike) -> FloatArray:
        """``C_nb`` at times ``t``; shape ``t.shape + (3, 3)``."""
        return quat_to_dcm(self.attitude(t))

    def states(self, t: npt.ArrayLike) -> States:
        """True position, velocity and attitude at the times ``t`` (1-D)."""
        t = as_float_array(t, "t", ndim=1)
        return States(t, self.position(t), self.velocity(t), self.attitude(t))


def span(motion: BaseMotion, rate: float, duration: float | None = None) -> float:
    """The duration to run ``motion`` at ``rate`` Hz: ``duration``, else the motion's own.

    A motion defined only on ``[0, motion.duration]`` (``bounded``: data — poses, waypoints)
    is never run past its end: the number of intervals is at most ``⌊duration × rate⌋``, so
    the last sample falls inside the data (the usual rule elsewhere is ``round``).
    """
    rate = check_positive(rate, "rate")
    d = motion.duration if duration is None else duration
    if d is None:
        raise ImunavError("duration must be given (the motion has no default duration)")
    d = check_positive(d, "duration")
    if motion.bounded:
        n_max = int(np.floor(motion.duration * rate + 1e-9))
        n = min(int(round(d * rate)), n_max)
        if n < 1:
            raise ImunavError(f"{motion.name}: {motion.duration:g} s of "
                              f"data hold no whole sample interval at {rate:g} Hz")
        d = n / rate
    return d


def times(t: npt.ArrayLike) -> FloatArray:
    """Times as a finite float array (any shape), or an ImunavError naming ``t``."""
    return as_float_array(t, "t")
