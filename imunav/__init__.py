"""imunav — simulate inertial sensors from prescribed motion and navigate back.

Glossary (one set of conventions, everywhere in the API)
--------------------------------------------------------
Frames
    ``n``: navigation frame, NED: x north, y east, z down; flat, non-rotating; gravity
    ``g_n = [0, 0, +g]`` with ``g = 9.80665`` m/s² unless overridden. On the WGS-84 Earth
    (``earth="wgs84"``, :mod:`imunav.earth`): the local NED frame at the current position,
    positions as latitude, longitude (rad) and height above the ellipsoid (m), normal gravity.
    ``b``: body (sensor) frame: x forward, y right, z down.
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


Floors
------
``core`` (constants, units, checks, rotations and their kernels, states) and ``symbolic`` →
``motion`` → ``sensors`` (signals, simulation, the error terms and models) → ``io`` (files,
readers of recordings) and ``strapdown`` (scan, algorithms, registry) → ``estimation`` (the
navigation error model, discretisation, propagation, Kalman steps) → ``analysis`` (metrics,
round trips, Monte Carlo, covariance, verdict, design, recordings) → ``papers`` → faces
(``plotting``, ``reproduce``, ``cli``). A module imports only from lower floors
(``tests/package/test_layering.py``; ``docs/architecture.md`` says where a change goes).

May import: anything in imunav (this is the package's facade: it exports what the README uses).
"""

from imunav import _aliases
from imunav.analysis.aided_assessment import assess_aided, format_aided_verdict
from imunav.analysis.aided_design import design_aided, format_outage_design
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.analysis.assessment import assess, format_verdict
from imunav.analysis.assessment import assess_covariance as _assess_covariance
from imunav.analysis.covariance import covariance
from imunav.analysis.design import design, format_design
from imunav.analysis.family import run_family
from imunav.analysis.metrics import NavErrors, nav_errors
from imunav.analysis.montecarlo import monte_carlo
from imunav.analysis.outage import find_outage
from imunav.analysis.roundtrip import round_trip
from imunav.core.constants import G0
from imunav.core.deprecation import deprecated_names
from imunav.core.rotations import (
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
from imunav.core.states import States
from imunav.core.threads import blas_threads, set_blas_threads
from imunav.core.validation import ImunavError
from imunav.earth import normal_gravity
from imunav.estimation.filters import FilterResult, run_filter, run_filter_batch, run_smoother
from imunav.io.realdata import read_generic, read_ximu, read_ximu3
from imunav.motion import BaseMotion, EarthMotion, Motion, PoseMotion, WaypointMotion
from imunav.sensors import PRESETS, ImuModel, ImuSignals, simulate_imu, truth_states
from imunav.sensors.aids import (
    Aid,
    AidingConfig,
    AidingData,
    Measurement,
    NavPoint,
    aids_from,
    simulate_aiding,
)
from imunav.strapdown import ALGORITHMS, DEFAULT_ALGORITHM, navigate

_aliases.install()

#: Old names of the facade (issue 35): ``NavResult`` (one name for the navigation result:
#: :class:`States`); ``assess_covariance`` (one entry for the verdict: :func:`assess`, whose
#: default method it is; it stays in :mod:`imunav.analysis.assessment`).
__getattr__ = deprecated_names(__name__, {
    "NavResult": (States, "imunav.States"),
    "assess_covariance": (_assess_covariance, "imunav.analysis.assessment.assess_covariance")},
    advice={"assess_covariance": "or imunav.assess, whose method it is without runs"})

__version__ = "0.2.0"

__all__ = [
    "Aid",
    "aided_monte_carlo",
    "AidingConfig",
    "AidingData",
    "aids_from",
    "ALGORITHMS",
    "assess",
    "assess_aided",
    "BaseMotion",
    "blas_threads",
    "covariance",
    "DEFAULT_ALGORITHM",
    "design",
    "design_aided",
    "EarthMotion",
    "euler_to_quat",
    "FilterResult",
    "find_outage",
    "format_aided_verdict",
    "format_design",
    "format_outage_design",
    "format_verdict",
    "from_scipy",
    "G0",
    "ImuModel",
    "ImunavError",
    "ImuSignals",
    "Measurement",
    "monte_carlo",
    "Motion",
    "nav_errors",
    "NavErrors",
    "navigate",
    "NavPoint",
    "normal_gravity",
    "PoseMotion",
    "PRESETS",
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
    "read_generic",
    "read_ximu",
    "read_ximu3",
    "round_trip",
    "run_family",
    "run_filter",
    "run_filter_batch",
    "run_smoother",
    "set_blas_threads",
    "simulate_aiding",
    "simulate_imu",
    "States",
    "to_scipy",
    "truth_states",
    "WaypointMotion",
]
