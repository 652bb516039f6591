"""Layer 1 — motions: what a rigid body does at any time (position, velocity, acceleration,
attitude, body rate, specific force), from analytic laws, closed-form quaternion laws or named
benchmarks.

Modules: :mod:`~imunav.motion.base` (the interface), :mod:`~imunav.motion.laws` (the safe law
parser), :mod:`~imunav.motion.analytic` (:class:`Motion`), :mod:`~imunav.motion.quaternion_law`,
:mod:`~imunav.motion.catalog` (coning, sculling, … and examples).

May import: ``imunav.core``.
"""

from imunav.core.constants import G0
from imunav.motion.analytic import ATTITUDE_KEYS, POSITION_KEYS, Motion
from imunav.motion.base import BaseMotion
from imunav.motion.laws import T, parse_law
from imunav.motion.quaternion_law import FourRotationMotion, QuaternionLawMotion

__all__ = ["ATTITUDE_KEYS", "BaseMotion", "FourRotationMotion", "G0", "Motion", "POSITION_KEYS",
           "QuaternionLawMotion", "T", "parse_law"]
