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

    The class attributes below are what the simulation reads from a motion; a subclass sets
    the ones that differ from the defaults.

    Examples
    --------
    A constant turn rate about the vertical, at rest in position:

    >>> import numpy as np
    >>> from imunav.core.rotations import euler_to_quat
    >>> class Turn(BaseMotion):
    ...     rate = 0.1                                          # rad/s
    ...     def position(self, t):
    ...         return np.zeros(np.shape(t) + (3,))
    ...     velocity = acceleration = position
    ...     def attitude(self, t):
    ...         z = np.zeros(np.shape(t))
    ...         return euler_to_quat(np.stack([self.rate * np.asarray(t), z, z], -1))
    ...     def angular_rate(self, t):
    ...         return np.zeros(np.shape(t) + (3,)) + [0.0, 0.0, self.rate]
    >>> Turn().specific_force([0.0, 1.0])                       # level at rest: [0, 0, -g]
    array([[ 0.     ,  0.     , -9.80665],
           [ 0.     ,  0.     , -9.80665]])
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
        """Position ``r_n`` (m) in the NED navigation frame.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            North, east, down (m).
        """
        raise NotImplementedError

    def velocity(self, t: npt.ArrayLike) -> FloatArray:
        """Velocity ``v_n = ṙ_n`` (m/s) in the NED navigation frame.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            The exact time derivative of :meth:`position` (m/s).
        """
        raise NotImplementedError

    def acceleration(self, t: npt.ArrayLike) -> FloatArray:
        """Kinematic acceleration ``a_n = r̈_n`` (m/s²) in the NED navigation frame.

        Gravity is not included: the accelerometer reading is :meth:`specific_force`.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            The exact second time derivative of :meth:`position` (m/s²).
        """
        raise NotImplementedError

    def attitude(self, t: npt.ArrayLike) -> FloatArray:
        """Attitude quaternion ``q_nb`` (Hamilton, scalar first, unit norm).

        ``q_nb`` takes body vectors to the navigation frame: ``v_n = q ⊗ v_b ⊗ q*``.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (4,)``
            ``[w, x, y, z]``.
        """
        raise NotImplementedError

    def angular_rate(self, t: npt.ArrayLike) -> FloatArray:
        """Body angular rate ``ω_b`` (rad/s): the vector part of ``2 q* ⊗ q̇``.

        What an ideal gyroscope triad reads (the navigation frame does not rotate).

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            Body-frame rates about x (forward), y (right), z (down), rad/s.
        """
        raise NotImplementedError

    def specific_force(self, t: npt.ArrayLike, g: float = G0) -> FloatArray:
        """Specific force ``f_b = C_bn (a_n − g_n)`` (m/s²), with ``g_n = [0, 0, +g]``.

        What an ideal accelerometer triad reads: level at rest ``[0, 0, −g]``.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.
        g : float, default G0
            Gravity magnitude (m/s²); 9.80665 unless overridden.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            Body-frame specific force (m/s²).

        Raises
        ------
        ImunavError
            If ``t`` is not a finite numeric array, or ``g`` is not a finite number > 0.
        """
        t = times(t)
        g = check_gravity(g)
        a = self.acceleration(t)
        a = a - np.array([0.0, 0.0, g])
        return quat_rotate(quat_conj(self.attitude(t)), a)

    def euler(self, t: npt.ArrayLike) -> FloatArray:
        """Z-Y-X Euler angles of :meth:`attitude`.

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            ``[yaw, pitch, roll]`` (rad), yaw and roll wrapped to (−π, π], pitch in [−π/2, π/2]
            (:func:`~imunav.core.rotations.quat_to_euler`; a subclass given Euler laws may
            return them unwrapped).
        """
        return quat_to_euler(self.attitude(t))

    def dcm(self, t: npt.ArrayLike) -> FloatArray:
        """Direction cosine matrix ``C_nb`` of :meth:`attitude` (``v_n = C_nb @ v_b``).

        Parameters
        ----------
        t : array_like
            Times (s), any shape, measured from the motion's start.

        Returns
        -------
        ndarray, shape ``t.shape + (3, 3)``
        """
        return quat_to_dcm(self.attitude(t))

    def states(self, t: npt.ArrayLike) -> States:
        """True position, velocity and attitude at the times ``t``.

        Parameters
        ----------
        t : array_like, shape (N,)
            Times (s).

        Returns
        -------
        States
            ``position``, ``velocity`` and ``quaternion`` of shape ``(N, 3)``, ``(N, 3)``,
            ``(N, 4)``; ``algorithm`` None, ``frame`` ``"flat"`` (a motion on the Earth
            returns its own frame).

        Raises
        ------
        ImunavError
            If ``t`` is not a 1-D finite numeric array.
        """
        t = as_float_array(t, "t", ndim=1)
        return States(t, self.position(t), self.velocity(t), self.attitude(t))


def span(motion: BaseMotion, rate: float, duration: float | None = None) -> float:
    """The duration to run ``motion`` at ``rate`` Hz: ``duration``, else the motion's own.

    A motion defined only on ``[0, motion.duration]`` (``bounded``: data — poses, waypoints)
    is never run past its end: the number of intervals is at most ``⌊duration × rate⌋``, so
    the last sample falls inside the data (the usual rule elsewhere is ``round``).

    Parameters
    ----------
    motion : BaseMotion
        The motion (its ``duration`` and ``bounded`` are read).
    rate : float
        Sample rate (Hz), > 0.
    duration : float, optional
        Requested duration (s), > 0. Default: ``motion.duration``.

    Returns
    -------
    float
        The duration (s): ``duration`` itself for an unbounded motion, a whole number of
        intervals ``n / rate`` inside the data for a bounded one.

    Raises
    ------
    ImunavError
        If ``rate`` or the duration is not a finite number > 0, neither ``duration`` nor
        ``motion.duration`` is given, or a bounded motion's data hold no whole interval at
        ``rate``.
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
    """Times as a finite float array (any shape).

    Parameters
    ----------
    t : array_like
        Times (s).

    Returns
    -------
    ndarray of float64
        ``t``, same shape.

    Raises
    ------
    ImunavError
        Naming ``t``, if it is not numeric or contains NaN or inf.
    """
    return as_float_array(t, "t")
