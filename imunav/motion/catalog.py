"""Named motions: the closed-form benchmarks of strapdown algorithms, and examples.

- :func:`coning` — classical coning: the body's rotation axis sweeps a cone; exact ``q`` and
  ``ω_b``. Savage 1998 (J. Guid. Control Dyn. 21(1)), Ignagni 1990.
- :func:`spinning_cone` — coning plus a spin about the body x axis.
- :func:`sculling` — angular oscillation about body x and linear oscillation along y, in phase
  (rectified specific force along z; the sculling test of Savage 1998 part 2).
- :func:`four_rotation` — the Plaksiy & Homozkova reference model.
- :func:`stationary` — at rest, tilted.

- :func:`figure_eight` — the README/quickstart example: a climbing horizontal figure-eight,
  turning about all three axes.
- :func:`~imunav.motion.foot.foot_walk` — a foot-mounted IMU on a walk: strides with exact
  stance phases (:mod:`imunav.motion.foot`).

:data:`CATALOG` names every one of them with its parameters and their units: what a
``MOTION.toml`` with ``catalog = "<name>"`` may set (:func:`imunav.io.files.load_motion`).

Attitude laws are SymPy quaternions; ``ω_b = vec(2 q* ⊗ q̇)`` is derived symbolically, so the
truth is exact to rounding.

May import: ``imunav.core``, ``imunav.motion``.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from imunav.motion.analytic import Motion
from imunav.motion.base import BaseMotion
from imunav.motion.foot import foot_walk
from imunav.motion.laws import T
from imunav.motion.quaternion_law import FourRotationMotion, QuaternionLawMotion


def _qmul(a, b):
    Q = sp.algebras.Quaternion
    r = Q(*a) * Q(*b)
    return [r.a, r.b, r.c, r.d]


def coning(half_angle_deg: float = 5.0, freq_hz: float = 2.0, duration: float = 60.0
           ) -> QuaternionLawMotion:
    """Classical coning: ``q = exp(β u(t))`` with ``u = [0, cos Ωt, sin Ωt]``, β the cone
    half-angle, Ω = 2π f. Exact body rate (derived)::

        ω_b = [−2Ω sin²(β/2), −Ω sin β sin Ωt, Ω sin β cos Ωt]

    The body x axis cones about the navigation x axis; the exact attitude drifts about x at
    ``−2Ω sin²(β/2)``, which is what coning algorithms must capture.
    """
    b = sp.Float(np.radians(half_angle_deg), 30)
    W = 2 * sp.pi * sp.Float(freq_hz, 30)
    q = [sp.cos(b / 2), 0, sp.sin(b / 2) * sp.cos(W * T), sp.sin(b / 2) * sp.sin(W * T)]
    return QuaternionLawMotion(q, duration=duration,
                               name=f"coning {half_angle_deg:g}° at {freq_hz:g} Hz")


def spinning_cone(half_angle_deg: float = 5.0, freq_hz: float = 2.0, spin_hz: float = 0.5,
                  duration: float = 60.0) -> QuaternionLawMotion:
    """Coning (as :func:`coning`) followed by a spin about the body x axis at ``spin_hz``."""
    b = sp.Float(np.radians(half_angle_deg), 30)
    W = 2 * sp.pi * sp.Float(freq_hz, 30)
    S = 2 * sp.pi * sp.Float(spin_hz, 30)
    cone = [sp.cos(b / 2), 0, sp.sin(b / 2) * sp.cos(W * T), sp.sin(b / 2) * sp.sin(W * T)]
    spin = [sp.cos(S * T / 2), sp.sin(S * T / 2), 0, 0]
    return QuaternionLawMotion(_qmul(cone, spin), duration=duration,
                               name=f"spinning cone {half_angle_deg:g}°, {freq_hz:g} Hz, "
                                    f"spin {spin_hz:g} Hz")


def sculling(angle_deg: float = 1.0, accel: float = 1.0, freq_hz: float = 2.0,
             duration: float = 60.0) -> Motion:
    """Sculling: roll ``A sin Ωt`` and a linear oscillation along east ``y`` with acceleration
    amplitude ``accel`` (m/s²), in phase. The body's y-accelerometer and x-gyro oscillate
    together, which rectifies into a steady specific-force component (the sculling effect)."""
    A = sp.Float(float(np.radians(angle_deg)), 30)
    W = 2 * sp.pi * sp.Float(freq_hz, 30)
    return Motion(y=-sp.Float(accel, 30) / W**2 * sp.sin(W * T), roll=A * sp.sin(W * T),
                  duration=duration, name=f"sculling {angle_deg:g}°, {accel:g} m/s², {freq_hz:g} Hz")


def four_rotation(duration: float = 60.0) -> BaseMotion:
    """The Plaksiy & Homozkova four-rotation model, k = (0.15, 1.55, 0.35, −1.55)."""
    return FourRotationMotion(duration=duration)


def stationary(duration: float = 60.0) -> Motion:
    """At rest with yaw 30°, pitch 10°, roll −20°."""
    return Motion(yaw="pi/6", pitch="pi/18", roll="-pi/9", duration=duration, name="stationary")


def figure_eight(duration: float = 20.0) -> Motion:
    """A 20 s motion that moves along all three axes and turns about all three (the quickstart's
    and ``examples/figure_eight.toml``'s): a horizontal figure-eight that climbs; yaw, pitch and
    roll oscillate at different frequencies."""
    return Motion(x="10*sin(0.3*t)", y="5*sin(0.6*t)", z="-0.05*t**2",
                  yaw="0.8*sin(0.25*t) + 0.1*t", pitch="0.3*sin(0.7*t)", roll="0.5*sin(1.1*t)",
                  duration=duration, name="quickstart")


#: name → factory of the benchmark motions.
BENCHMARKS = {"coning": coning, "spinning_cone": spinning_cone, "sculling": sculling,
              "four_rotation": four_rotation, "stationary": stationary}


#: name → ``(factory, {parameter: unit})`` of every catalog motion, for ``catalog = "<name>"``
#: in a ``MOTION.toml``: the factory takes ``duration`` and these keyword parameters. Units:
#: ``"count"`` a whole number; ``"angle"`` radians, or a string with its unit (``"90 deg"``);
#: any other a plain number in that unit.
CATALOG: dict[str, tuple] = {
    "coning": (coning, {"half_angle_deg": "deg", "freq_hz": "Hz"}),
    "spinning_cone": (spinning_cone, {"half_angle_deg": "deg", "freq_hz": "Hz", "spin_hz": "Hz"}),
    "sculling": (sculling, {"angle_deg": "deg", "accel": "m/s²", "freq_hz": "Hz"}),
    "four_rotation": (four_rotation, {}),
    "stationary": (stationary, {}),
    "figure_eight": (figure_eight, {}),
    "foot_walk": (foot_walk, {"stride_length": "m", "cadence": "steps/min",
                              "stance_fraction": "fraction", "rest": "s", "turn_every": "count",
                              "turn_angle": "angle", "turn_strides": "count",
                              "toe_off_pitch": "angle", "heel_strike_pitch": "angle",
                              "heading": "angle"}),
}
