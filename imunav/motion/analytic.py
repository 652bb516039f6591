"""Motions from analytic laws: position ``x(t), y(t), z(t)`` (m, NED) and attitude
``yaw(t), pitch(t), roll(t)`` (rad, intrinsic Z-Y-X).

Laws are strings or SymPy expressions in ``t``, parsed by the whitelist of
:mod:`imunav.motion.laws`. Derivatives are exact (SymPy ``diff``, then ``lambdify``), never
finite differences.

May import: ``imunav.core``, ``imunav.motion.base``, ``imunav.motion.laws``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import numpy.typing as npt
import sympy as sp

from imunav.core.rotations import euler_to_quat
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion, times
from imunav.motion.laws import T, evaluate, lambdify, parse_law

POSITION_KEYS = ("x", "y", "z")
ATTITUDE_KEYS = ("yaw", "pitch", "roll")


class LawMotion(BaseMotion):
    """Base of motions compiled from laws: position ``x(t), y(t), z(t)`` and derived quantities.

    Subclasses call :meth:`_compile` with their attitude quantities; position, velocity and
    acceleration come from the three position laws. :attr:`expressions` keeps every SymPy
    expression (for inspection and notebooks).
    """

    def _compile(self, position_laws, extra: dict[str, list[tuple[sp.Expr, str]]]) -> None:
        """Parse the position laws, differentiate twice, and compile every group of ``(expression,
        description)`` pairs; the description names the law in error messages."""
        pos = [parse_law(v, k) for k, v in zip(POSITION_KEYS, position_laws, strict=True)]
        vel = [sp.diff(e, T) for e in pos]
        acc = [sp.diff(e, T) for e in vel]
        src = {k: repr(str(v)) for k, v in zip(POSITION_KEYS, position_laws, strict=True)}
        groups = {
            "position": [(e, f"position law {k} = {src[k]}")
                         for e, k in zip(pos, POSITION_KEYS, strict=True)],
            "velocity": [(e, f"velocity (d/dt of law {k} = {src[k]})")
                         for e, k in zip(vel, POSITION_KEYS, strict=True)],
            "acceleration": [(e, f"acceleration (d²/dt² of law {k} = {src[k]})")
                             for e, k in zip(acc, POSITION_KEYS, strict=True)],
            **extra,
        }
        for key, pairs in groups.items():
            if any(e.has(sp.I) for e, _ in pairs):
                raise ImunavError(f"the {key} of this motion is complex-valued; laws must be real")
        #: SymPy expressions of every quantity, by name.
        self.expressions = {k: [e for e, _ in v] for k, v in groups.items()}
        self._f = {k: [(lambdify(e), w) for e, w in v] for k, v in groups.items()}

    def _eval(self, key: str, t: npt.ArrayLike) -> np.ndarray:
        t = times(t)
        return np.stack([evaluate(f, t, what) for f, what in self._f[key]], axis=-1)

    def position(self, t):
        return self._eval("position", t)

    def velocity(self, t):
        return self._eval("velocity", t)

    def acceleration(self, t):
        return self._eval("acceleration", t)


class Motion(LawMotion):
    """A motion from analytic laws (SymPy expressions or strings in ``t``).

    Parameters
    ----------
    x, y, z : str, number or sympy.Expr
        Position laws (m) in the NED navigation frame. Missing laws are 0.
    yaw, pitch, roll : str, number or sympy.Expr
        Attitude laws (rad), intrinsic Z-Y-X: ``q_nb = q_z(yaw) ⊗ q_y(pitch) ⊗ q_x(roll)``.
    duration : float, optional
        Default duration (s) for simulation (None: every run must give one).
    name : str, default "motion"
        A name for reports and plots.

    Attributes
    ----------
    laws : dict of str to sympy.Expr
        The six parsed laws, by key (``x y z yaw pitch roll``).
    expressions : dict of str to list of sympy.Expr
        Every compiled quantity (position, velocity, acceleration, euler, angular_rate) as
        SymPy expressions, for inspection and notebooks.

    Raises
    ------
    ImunavError
        If a law is outside the whitelist of :mod:`imunav.motion.laws` (the message names the
        law and the offending token), a derived quantity is complex-valued, ``duration`` is not
        a finite number > 0, or ``name`` is not a string. A law that is finite where parsed but
        not at some time (``log(t - 1)``) raises when it is evaluated there, naming the law and
        the time.

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
        if not isinstance(name, str):
            raise ImunavError(f"name must be a string, got {name!r}")
        self.duration = duration
        self.name = name
        psi, theta, phi = (self.laws[k] for k in ATTITUDE_KEYS)
        dpsi, dtheta, dphi = (sp.diff(e, T) for e in (psi, theta, phi))
        omega = [
            dphi - dpsi * sp.sin(theta),
            dtheta * sp.cos(phi) + dpsi * sp.cos(theta) * sp.sin(phi),
            dpsi * sp.cos(theta) * sp.cos(phi) - dtheta * sp.sin(phi),
        ]
        src = {k: repr(str(v)) for k, v in zip(ATTITUDE_KEYS, (yaw, pitch, roll), strict=True)}
        self._compile((x, y, z), {
            "euler": [(self.laws[k], f"attitude law {k} = {src[k]}") for k in ATTITUDE_KEYS],
            "angular_rate": [(e, f"angular rate ω_{c} (from the attitude laws)")
                             for e, c in zip(omega, "xyz", strict=True)],
        })

    @classmethod
    def from_dict(cls, spec: Mapping, *, name: str = "motion") -> Motion:
        """Build from ``{"duration": …, "position": {"x": …}, "attitude": {"yaw": …}}``.

        This is the structure of ``MOTION.toml`` (:func:`imunav.io.files.load_motion_toml`
        reads the file); unknown keys are errors.

        Parameters
        ----------
        spec : mapping
            Top-level keys ``duration`` (s), ``name``, ``g`` (accepted for the file's sake: the
            gravity belongs to the simulation, not to the motion, and is not read here), and
            the tables ``position`` (keys ``x y z``, laws in m) and ``attitude`` (keys
            ``yaw pitch roll``, laws in rad). Missing laws are 0.
        name : str, default "motion"
            The name when ``spec`` has none.

        Returns
        -------
        Motion

        Raises
        ------
        ImunavError
            If ``spec`` or one of its tables is not a mapping, a key is unknown (the message
            lists the allowed ones), or the constructor refuses a law, the duration or the name.

        Examples
        --------
        >>> m = Motion.from_dict({"duration": 10, "position": {"x": "t**2"},
        ...                       "attitude": {"yaw": "0.1*t"}})
        >>> m.velocity([1.0])
        array([[2., 0., 0.]])
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

    def euler(self, t):
        """``[yaw, pitch, roll]`` (rad) straight from the laws (not wrapped to ±π).

        Parameters
        ----------
        t : array_like
            Times (s), any shape.

        Returns
        -------
        ndarray, shape ``t.shape + (3,)``
            The attitude laws evaluated at ``t`` (rad).

        Raises
        ------
        ImunavError
            If ``t`` is not a finite numeric array, or a law is not finite (or is complex) at
            one of the times.
        """
        return self._eval("euler", t)

    def attitude(self, t):
        return euler_to_quat(self._eval("euler", t))

    def angular_rate(self, t):
        return self._eval("angular_rate", t)

    def __repr__(self) -> str:
        laws = ", ".join(f"{k}={str(v)!r}" for k, v in self.laws.items() if v != 0)
        return f"Motion({laws}, duration={self.duration})"
