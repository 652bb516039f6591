"""The one state type: position, velocity and attitude at times ``t``.

:class:`States` holds the true states of a motion, the output of a navigation run and the rows
of a truth/navigation CSV alike (``imunav.io`` reads and writes it). ``NavResult`` and
``TruthStates`` are its former names.

May import: ``imunav.core.rotations``, ``imunav.core.validation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.rotations import FloatArray, quat_to_euler
from imunav.core.validation import ImunavError

#: The navigation frames: flat, non-rotating NED, or local NED on the rotating WGS-84 Earth.
FRAMES = ("flat", "wgs84")


@dataclass
class States:
    """States at times ``t_k``, k = 0..N-1.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Times (s).
    position : ndarray, shape (N, 3)
        ``r_n`` (m), NED — or, on the WGS-84 Earth (``frame == "wgs84"``), latitude,
        longitude (rad) and height above the ellipsoid (m).
    velocity : ndarray, shape (N, 3)
        ``v_n`` (m/s), NED (on the Earth: relative to the Earth, in the local NED frame at
        the current position).
    quaternion : ndarray, shape (N, 4)
        ``q_nb``, scalar first (on the Earth: relative to the local NED frame at the current
        position).
    algorithm : str, optional
        For navigation results, the strapdown algorithm that produced them; None for truth.
    frame : {"flat", "wgs84"}
        The navigation frame: the flat, non-rotating NED frame, or local NED on the rotating
        WGS-84 Earth (:mod:`imunav.earth`).

    Raises
    ------
    ImunavError
        If ``frame`` is not one of :data:`FRAMES`, or ``position``, ``velocity`` or
        ``quaternion`` does not have shape ``(N, 3)``, ``(N, 3)``, ``(N, 4)`` for the ``N``
        times of a 1-D ``t``. Values are not checked (the navigation output may drift far).

    Examples
    --------
    >>> import numpy as np
    >>> s = States(t=np.array([0.0, 0.1]), position=np.zeros((2, 3)),
    ...            velocity=np.zeros((2, 3)), quaternion=np.tile([1.0, 0, 0, 0], (2, 1)))
    >>> len(s), s.frame
    (2, 'flat')
    """

    t: FloatArray
    position: FloatArray
    velocity: FloatArray
    quaternion: FloatArray
    algorithm: str | None = None
    frame: str = "flat"

    def __post_init__(self):
        if self.frame not in FRAMES:
            raise ImunavError(f"frame must be one of {FRAMES}, got {self.frame!r}")
        n = np.shape(self.t)[0] if np.ndim(self.t) else None
        for name, last in (("position", 3), ("velocity", 3), ("quaternion", 4)):
            shape = np.shape(getattr(self, name))
            if n is None or shape[:1] != (n,) or shape[-1:] != (last,):
                raise ImunavError(f"{name} must have shape ({n}, {last}) to match t, got {shape}")

    def __len__(self) -> int:
        return int(np.shape(self.t)[0])

    def euler(self) -> FloatArray:
        """The attitude as Z-Y-X Euler angles.

        Returns
        -------
        ndarray, shape (N, 3)
            ``[yaw, pitch, roll]`` (rad) of each ``q_nb`` (yaw and roll in (−π, π], pitch in
            [−π/2, π/2]; see :func:`~imunav.core.rotations.quat_to_euler`, which warns with
            :class:`~imunav.core.rotations.GimbalLockWarning` at pitch ±90°).
        """
        return quat_to_euler(self.quaternion)

    def initial(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The first row, in the order :func:`~imunav.strapdown.registry.navigate` takes it.

        Returns
        -------
        q0 : ndarray, shape (4,)
            ``q_nb`` at ``t[0]``, scalar first.
        v0 : ndarray, shape (3,)
            Velocity at ``t[0]`` (m/s, NED).
        p0 : ndarray, shape (3,)
            Position at ``t[0]`` (m, NED; on the WGS-84 Earth latitude, longitude in rad and
            height in m).

        Examples
        --------
        >>> import numpy as np
        >>> s = States(t=np.array([0.0]), position=np.array([[1.0, 2.0, 3.0]]),
        ...            velocity=np.zeros((1, 3)), quaternion=np.array([[1.0, 0, 0, 0]]))
        >>> q0, v0, p0 = s.initial()
        >>> p0
        array([1., 2., 3.])
        """
        return self.quaternion[0], self.velocity[0], self.position[0]
