"""Initial alignment at rest: roll and pitch from gravity, and static bias removal.

General strapdown practice (coarse levelling); Dickson & Rae 2021 use both steps in their
processing chain (:mod:`imunav.papers.dickson_rae2021` calls these), and so do the readers of
real recordings when no initial state is given.

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.kernels import quat_conj, quat_rotate
from imunav.core.rotations import FloatArray, euler_to_quat
from imunav.core.validation import ImunavError, as_float_array, check_gravity


def level_attitude(accel: npt.ArrayLike, g: float = G0, tol: float = 0.05,
                   yaw: float = 0.0) -> FloatArray:
    """``q_nb`` from the mean resting specific force (m/s²): roll and pitch from gravity, yaw given.

    Level at rest the accelerometer reads ``[0, 0, −g]``, so θ = atan2(f_x, √(f_y² + f_z²)) and
    φ = atan2(−f_y, −f_z). Raises if |f| differs from g by more than ``tol`` (relative): the
    accelerometer is then not measuring gravity alone (the body is not at rest).
    """
    f = as_float_array(accel, "accel", last=3)
    g = check_gravity(g)
    f = f.reshape(-1, 3).mean(axis=0)
    n = float(np.linalg.norm(f))
    if abs(n - g) > tol * g:
        raise ImunavError(f"accel at rest has |a| = {n:.4g} m/s², not ≈ g = {g:.4g} "
                          f"(tolerance {tol:.0%}): cannot take the initial orientation from it")
    theta = np.arctan2(f[0], np.hypot(f[1], f[2]))
    phi = np.arctan2(-f[1], -f[2])
    return euler_to_quat([yaw, theta, phi])


def gravity_reading(q: npt.ArrayLike, g: float = G0) -> FloatArray:
    """What an ideal accelerometer at rest reads at attitude ``q_nb``: ``C_bn (−g_n)``."""
    q = as_float_array(q, "q", last=4)
    return quat_rotate(quat_conj(q), np.array([0.0, 0.0, -g]))


def remove_static_biases(gyro: FloatArray, accel: FloatArray, window: slice, q0: FloatArray,
                         g: float = G0) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Subtract the offsets measured over a stationary ``window`` at attitude ``q0``: the gyro's
    mean, and the accelerometer's mean minus the gravity reading :func:`gravity_reading`.
    Returns ``(gyro, accel, gyro_bias, accel_bias)``."""
    bg = gyro[window].mean(axis=0)
    ba = accel[window].mean(axis=0) - gravity_reading(q0, g)
    return gyro - bg, accel - ba, bg, ba
