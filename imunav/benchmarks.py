"""Closed-form benchmark motions for strapdown algorithms (all usable as imunav Motions).

- :func:`coning` — classical coning: the body's rotation axis sweeps a cone; exact ``q`` and
  ``ω_b``. Savage 1998 (J. Guid. Control Dyn. 21(1)), Ignagni 1990.
- :func:`spinning_cone` — coning plus a spin about the body x axis.
- :func:`sculling` — angular oscillation about body x and linear oscillation along y, in phase
  (rectified specific force along z; the sculling test of Savage 1998 part 2).
- :func:`four_rotation` — the Plaksiy & Homozkova reference model.
- :func:`stationary` — at rest, tilted.

Attitude laws are SymPy quaternions; ``ω_b = vec(2 q* ⊗ q̇)`` is derived symbolically, so the
truth is exact to rounding.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from imunav.errors import ImunavError, as_float_array
from imunav.laws import T, evaluate, lambdify, parse_law
from imunav.motion import POSITION_KEYS, BaseMotion, Motion
from imunav.rotations import FloatArray


class QuaternionLawMotion(BaseMotion):
    """A motion whose attitude is a closed-form quaternion ``q_nb(t)`` (SymPy, scalar first).

    Parameters
    ----------
    q : 4 SymPy expressions in ``imunav.motion.T``
        The attitude law; it must be a unit quaternion for every t (checked at sample times).
    x, y, z : position laws (m), as for :class:`imunav.Motion`.
    """

    def __init__(self, q, x=0, y=0, z=0, *, duration: float | None = None, name: str = "motion"):
        q = [parse_law(c, f"q{i}") for i, c in enumerate(q)]
        qd = [sp.diff(c, T) for c in q]
        Q = sp.algebras.Quaternion
        w = 2 * Q(q[0], -q[1], -q[2], -q[3]) * Q(*qd)
        self.expressions = {"quaternion": q, "angular_rate": [w.b, w.c, w.d]}
        pos = [parse_law(v, k) for k, v in zip(POSITION_KEYS, (x, y, z), strict=True)]
        vel = [sp.diff(e, T) for e in pos]
        acc = [sp.diff(e, T) for e in vel]
        self.expressions.update(position=pos, velocity=vel, acceleration=acc)
        self._f = {k: [lambdify(e) for e in v] for k, v in self.expressions.items()}
        self.duration = duration
        self.name = name
        tt = np.linspace(0, duration or 1.0, 17)
        n = np.linalg.norm(self._eval("quaternion", tt), axis=-1)
        if np.max(np.abs(n - 1)) > 1e-12:
            raise ImunavError("q must be a unit quaternion law (|q| = 1 at every t)")

    def _eval(self, key, t) -> FloatArray:
        t = as_float_array(t, "t")
        return np.stack([evaluate(f, t, f"{key}[{i}] of {self.name}")
                         for i, f in enumerate(self._f[key])], axis=-1)

    def attitude(self, t):
        return self._eval("quaternion", t)

    def angular_rate(self, t):
        return self._eval("angular_rate", t)

    def position(self, t):
        return self._eval("position", t)

    def velocity(self, t):
        return self._eval("velocity", t)

    def acceleration(self, t):
        return self._eval("acceleration", t)


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
    from imunav.papers.plaksiy import FourRotationMotion

    return FourRotationMotion(duration=duration)


def stationary(duration: float = 60.0) -> Motion:
    """At rest with yaw 30°, pitch 10°, roll −20°."""
    return Motion(yaw="pi/6", pitch="pi/18", roll="-pi/9", duration=duration, name="stationary")


#: name → factory of the benchmark motions.
BENCHMARKS = {"coning": coning, "spinning_cone": spinning_cone, "sculling": sculling,
              "four_rotation": four_rotation, "stationary": stationary}
