"""The measurement contract of the aided filter, and imunav's own aids' measurement models.

A measurement knows its **prediction** from the navigation state (and the estimates of its own
error states), its **Jacobian** ``H`` with respect to the error state (``φ``, ``δv``, ``δp`` at
:data:`~imunav.core.layout.PHI`, :data:`~imunav.core.layout.DV`,
:data:`~imunav.core.layout.DP`, then the sensor states, then the aids' own states), its
**noise** ``R``, and its lever arm where it has one. The filter forms
``z = predicted − measured`` and hands ``(z, H, R)`` to the Kalman core. A user's subclass of
:class:`Measurement`, given to the filter with its readings as an
:class:`~imunav.sensors.aids.Aid`, runs through the filter, the smoother, the aided covariance
analysis and the aided Monte Carlo with no change to imunav.

Each aid lives, with its ``AIDING.toml`` table, its file and its simulation, in its module of
:mod:`imunav.sensors.aids`; this module gathers their measurement models under the names they
have always had.

=========  ===============================  ============================================
class      reading (SI)                     prediction
=========  ===============================  ============================================
GnssFix    antenna position [, velocity]    ``p + v dt + C l + ĉ`` [, ``v + C (ω × l)``]
Baro       altitude                         ``−(p_z + v_z dt) + b̂``
Heading    yaw                              ``atan2(C₁₀, C₀₀)`` (innovation wrapped)
Nhc        lateral, vertical body velocity  ``(Cᵀ v)_{y,z}``
Zupt       velocity                         ``v``
Odometer   forward speed                    ``(1 + k̂) (Cᵀ v)_x``
=========  ===============================  ============================================

May import: ``imunav.core``, ``imunav.sensors``.
"""

from imunav.sensors.aids import (
    Aid,
    AidStates,
    Baro,
    GnssFix,
    Heading,
    Measurement,
    NavPoint,
    Nhc,
    Odometer,
    Zupt,
    euler_jacobian,
    yaw_of,
)

__all__ = ["Aid", "AidStates", "Baro", "GnssFix", "Heading", "Measurement", "NavPoint", "Nhc",
           "Odometer", "Zupt", "euler_jacobian", "yaw_of"]
