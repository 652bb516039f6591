"""Layer 1 — motions: what a rigid body does at any time (position, velocity, acceleration,
attitude, body rate, specific force), from analytic laws, closed-form quaternion laws, named
benchmarks, or data (timed poses and waypoint routes as splines).

Modules: :mod:`~imunav.motion.base` (the interface), :mod:`~imunav.motion.laws` (the safe law
parser), :mod:`~imunav.motion.analytic` (:class:`Motion`), :mod:`~imunav.motion.quaternion_law`,
:mod:`~imunav.motion.catalog` (coning, sculling, … and examples),
:mod:`~imunav.motion.trajectory` (:class:`PoseMotion`, :class:`WaypointMotion`),
:mod:`~imunav.motion.geodetic` (:class:`EarthMotion`: any of them on the rotating WGS-84 Earth).

May import: ``imunav.core``, ``imunav.earth``.
"""

from imunav.core.constants import G0
from imunav.motion.analytic import ATTITUDE_KEYS, POSITION_KEYS, Motion
from imunav.motion.base import BaseMotion
from imunav.motion.geodetic import EarthMotion
from imunav.motion.laws import T, parse_law
from imunav.motion.quaternion_law import FourRotationMotion, QuaternionLawMotion
from imunav.motion.trajectory import PoseMotion, WaypointMotion

__all__ = ["ATTITUDE_KEYS", "BaseMotion", "EarthMotion", "FourRotationMotion", "G0", "Motion",
           "POSITION_KEYS", "PoseMotion", "QuaternionLawMotion", "T", "WaypointMotion", "parse_law"]
