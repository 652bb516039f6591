"""Prescribed motions: true position, velocity, acceleration, attitude, ω_b and f_b at any time.

:class:`BaseMotion` is the interface every motion implements (analytic laws, closed-form
benchmark motions, paper reference models). :class:`Motion` builds one from analytic laws —
position ``x(t), y(t), z(t)`` in metres (NED) and attitude ``yaw(t), pitch(t), roll(t)`` in
radians (intrinsic Z-Y-X) — given as SymPy expressions or strings in ``t``. Derivatives are
exact (SymPy ``diff``, then ``lambdify``), never finite differences.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import numpy.typing as npt
import sympy as sp

from imunav.errors import ImunavError, as_float_array, check_gravity, check_positive
from imunav.laws import T, evaluate, lambdify, parse_law
from imunav.rotations import FloatArray, _dcm, _rotate, euler_to_quat

#: Standard gravity (m/s²), the default magnitude of ``g_n = [0, 0, +g]``.
G0 = 9.80665

__all__ = ["ATTITUDE_KEYS", "BaseMotion", "G0", "Motion", "POSITION_KEYS", "T", "parse_law"]

POSITION_KEYS = ("x", "y", "z")
ATTITUDE_KEYS = ("yaw", "pitch", "roll")


class BaseMotion:
    """A rigid-body motion in the NED navigation frame.

    Subclasses implement :meth:`position`, :meth:`velocity`, :meth:`acceleration`,
    :meth:`attitude` and :meth:`angular_rate`; the specific force and Euler angles follow.
    All methods take times ``t`` (s, array_like, any shape) and return arrays of shape
    ``t.shape + (3,)`` (or ``(4,)`` for quaternions).
    """

    #: Default duration (s) used by the CLI and notebooks when none is given.
    duration: float | None = None
    name: str = "motion"

    def position(self, t: npt.ArrayLike) -> FloatArray:
        """Position ``r_n`` (m)."""
        raise NotImplementedError

    def velocity(self, t: npt.ArrayLike) -> FloatArray:
        """Velocity ``v_n = ṙ_n`` (m/s)."""
        raise NotImplementedError

    def acceleration(self, t: npt.ArrayLike) -> FloatArray:
        """Kinematic acceleration ``a_n = r̈_n`` (m/s²)."""
        raise NotImplementedError

    def attitude(self, t: npt.ArrayLike) -> FloatArray:
        """Attitude quaternion ``q_nb`` (scalar first, unit norm)."""
        raise NotImplementedError

    def angular_rate(self, t: npt.ArrayLike) -> FloatArray:
        """Body angular rate ``ω_b`` (rad/s): vector part of ``2 q* ⊗ q̇``."""
        raise NotImplementedError

    def specific_force(self, t: npt.ArrayLike, g: float = G0) -> FloatArray:
        """Specific force ``f_b = C_bn (a_n − g_n)`` (m/s²), ``g_n = [0, 0, +g]``."""
        t = _times(t)
        g = check_gravity(g)
        a = self.acceleration(t)
        a = a - np.array([0.0, 0.0, g])
        q = self.attitude(t)
        conj = q * np.array([1.0, -1.0, -1.0, -1.0])
        return _rotate(conj, a)

    def euler(self, t: npt.ArrayLike) -> FloatArray:
        """``[yaw, pitch, roll]`` (rad) of :meth:`attitude`."""
        from imunav.rotations import quat_to_euler

        return quat_to_euler(self.attitude(t))

    def dcm(self, t: npt.ArrayLike) -> FloatArray:
        """``C_nb`` at times ``t``; shape ``t.shape + (3, 3)``."""
        return _dcm(self.attitude(t))


def _times(t: npt.ArrayLike) -> FloatArray:
    return as_float_array(t, "t")


class Motion(BaseMotion):
    """A motion from analytic laws (SymPy expressions or strings in ``t``).

    Parameters
    ----------
    x, y, z : str, number or sympy.Expr
        Position laws (m) in the NED navigation frame. Missing laws are 0.
    yaw, pitch, roll : str, number or sympy.Expr
        Attitude laws (rad), intrinsic Z-Y-X: ``q_nb = q_z(yaw) ⊗ q_y(pitch) ⊗ q_x(roll)``.
    duration : float, optional
        Default duration (s) for simulation.
    name : str, optional

    Notes
    -----
    The body rate follows from the Euler-angle rates exactly:
    ``ω_b = [φ̇ − ψ̇ sin θ,  θ̇ cos φ + ψ̇ cos θ sin φ,  ψ̇ cos θ cos φ − θ̇ sin φ]``
    (the vector part of ``2 q* ⊗ q̇`` for ``q = q_z(ψ) q_y(θ) q_x(φ)``; the test suite checks
    it against a SymPy derivative of the quaternion itself).

    Examples
    --------
    >>> m = Motion(x="t**2", y="t*sin(t)**2", z="2*t", yaw="0.3*sin(t)", roll="0.2*t")
    >>> m.angular_rate([0.0, 1.0]).shape
    (2, 3)
    """

    def __init__(self, x=0, y=0, z=0, yaw=0, pitch=0, roll=0, *, duration: float | None = None,
                 name: str = "motion"):
        self.laws = {k: parse_law(v, k) for k, v in
                     zip(POSITION_KEYS + ATTITUDE_KEYS, (x, y, z, yaw, pitch, roll), strict=True)}
        if duration is not None:
            duration = check_positive(duration, "duration")
        self.duration = duration
        self.name = name
        L = self.laws
        pos = [L[k] for k in POSITION_KEYS]
        vel = [sp.diff(e, T) for e in pos]
        acc = [sp.diff(e, T) for e in vel]
        psi, theta, phi = (L[k] for k in ATTITUDE_KEYS)
        dpsi, dtheta, dphi = (sp.diff(e, T) for e in (psi, theta, phi))
        omega = [
            dphi - dpsi * sp.sin(theta),
            dtheta * sp.cos(phi) + dpsi * sp.cos(theta) * sp.sin(phi),
            dpsi * sp.cos(theta) * sp.cos(phi) - dtheta * sp.sin(phi),
        ]
        for key, exprs in (("velocity", vel), ("acceleration", acc), ("angular rate", omega)):
            if any(e.has(sp.I) for e in exprs):
                raise ImunavError(f"the {key} of this motion is complex-valued; laws must be real")
        #: SymPy expressions of every derived quantity (for inspection and notebooks).
        self.expressions = {"position": pos, "velocity": vel, "acceleration": acc,
                            "euler": [psi, theta, phi], "angular_rate": omega}
        src = {k: repr(str(v)) for k, v in zip(POSITION_KEYS + ATTITUDE_KEYS,
                                                 (x, y, z, yaw, pitch, roll), strict=True)}
        what = {"position": [f"position law {k} = {src[k]}" for k in POSITION_KEYS],
                "velocity": [f"velocity (d/dt of law {k} = {src[k]})" for k in POSITION_KEYS],
                "acceleration": [f"acceleration (d²/dt² of law {k} = {src[k]})"
                                 for k in POSITION_KEYS],
                "euler": [f"attitude law {k} = {src[k]}" for k in ATTITUDE_KEYS],
                "angular_rate": [f"angular rate ω_{c} (from the attitude laws)" for c in "xyz"]}
        self._f = {k: [(lambdify(e), w) for e, w in zip(v, what[k], strict=True)]
                   for k, v in self.expressions.items()}

    @classmethod
    def from_dict(cls, spec: Mapping, *, name: str = "motion") -> Motion:
        """Build from ``{"duration": …, "position": {"x": …}, "attitude": {"yaw": …}}``.

        This is the structure of ``MOTION.toml``; unknown keys are errors.
        """
        if not isinstance(spec, Mapping):
            raise ImunavError("motion specification must be a table/mapping")
        allowed = {"duration", "g", "position", "attitude", "name"}
        unknown = sorted(set(spec) - allowed)
        if unknown:
            raise ImunavError(
                f"unknown key(s) in motion: {', '.join(unknown)}; expected {sorted(allowed)}"
            )
        laws: dict = {}
        for table, keys in (("position", POSITION_KEYS), ("attitude", ATTITUDE_KEYS)):
            sub = spec.get(table, {})
            if not isinstance(sub, Mapping):
                raise ImunavError(f"[{table}] must be a table of {', '.join(keys)}")
            bad = sorted(set(sub) - set(keys))
            if bad:
                raise ImunavError(
                    f"unknown key(s) in [{table}]: {', '.join(bad)}; expected {', '.join(keys)}"
                )
            laws.update(sub)
        return cls(**laws, duration=spec.get("duration"), name=spec.get("name", name))

    def _eval(self, key: str, t: npt.ArrayLike) -> FloatArray:
        t = _times(t)
        return np.stack([evaluate(f, t, what) for f, what in self._f[key]], axis=-1)

    def position(self, t):
        return self._eval("position", t)

    def velocity(self, t):
        return self._eval("velocity", t)

    def acceleration(self, t):
        return self._eval("acceleration", t)

    def euler(self, t):
        """``[yaw, pitch, roll]`` (rad) straight from the laws (no wrapping)."""
        return self._eval("euler", t)

    def attitude(self, t):
        return euler_to_quat(self._eval("euler", t))

    def angular_rate(self, t):
        return self._eval("angular_rate", t)

    def __repr__(self) -> str:
        laws = ", ".join(f"{k}={str(v)!r}" for k, v in self.laws.items() if v != 0)
        return f"Motion({laws}, duration={self.duration})"
