"""imunav — simulate inertial sensors from prescribed motion and navigate back.

Glossary (one set of conventions, everywhere in the API)
--------------------------------------------------------
Frames
    ``n``  navigation frame, NED: x north, y east, z down; flat, non-rotating.
           Gravity is ``g_n = [0, 0, +g]`` with ``g = 9.80665`` m/s² unless overridden.
    ``b``  body (sensor) frame: x forward, y right, z down.
Quaternions
    Hamilton product, scalar first ``q = [w, x, y, z]``, arrays of shape ``(..., 4)``.
    ``q_nb`` takes body vectors to the navigation frame: ``v_n = q ⊗ v_b ⊗ q*``.
Matrices
    ``C_nb`` (``mat_nb``) projects b onto n: ``v_n = C_nb @ v_b``; ``C_bn = C_nbᵀ``.
Euler angles
    yaw ψ, pitch θ, roll φ, intrinsic Z-Y-X: ``q = q_z(ψ) ⊗ q_y(θ) ⊗ q_x(φ)``,
    the same rotation as ``scipy Rotation.from_euler("ZYX", [ψ, θ, φ])``.
Sensors
    gyro: body angular rate ``ω_b`` (vector part of ``2 q* ⊗ q̇``), rad/s;
    accelerometer: specific force ``f_b = C_bn (a_n − g_n)``, m/s² — level at rest it
    reads ``[0, 0, −g]``. Increments: ``Δθ = ∫ω_b dt`` (rad), ``Δv = ∫f_b dt`` (m/s) over
    each sample interval, stamped with the interval end.
Units
    SI and radians in the API; degrees and g only at the edges (plots, CSV loaders).
    Where a paper uses another convention, the module ``imunav.papers.<paper>`` converts
    at its boundary.
"""

from imunav.errors import ImunavError
from imunav.motion import BaseMotion, Motion
from imunav.rotations import (
    euler_to_quat,
    from_scipy,
    quat_angle,
    quat_conj,
    quat_exp,
    quat_from_dcm,
    quat_log,
    quat_mul,
    quat_normalize,
    quat_rotate,
    quat_to_dcm,
    quat_to_euler,
    to_scipy,
)
from imunav.simulate import G0, ImuSignals, simulate_imu, truth_states
from imunav.strapdown import ALGORITHMS, NavResult, navigate

__version__ = "0.1.0"

__all__ = [
    "ALGORITHMS",
    "BaseMotion",
    "G0",
    "ImuSignals",
    "ImunavError",
    "Motion",
    "NavResult",
    "euler_to_quat",
    "from_scipy",
    "navigate",
    "quat_angle",
    "quat_conj",
    "quat_exp",
    "quat_from_dcm",
    "quat_log",
    "quat_mul",
    "quat_normalize",
    "quat_rotate",
    "quat_to_dcm",
    "quat_to_euler",
    "simulate_imu",
    "to_scipy",
    "truth_states",
]
