"""The sensor error terms drawn once per run and constant along it: the turn-on bias
(:class:`TurnOnBias`), the scale factor (:class:`ScaleFactor`), the misalignment
(:class:`Misalignment`) and the gyro's g-sensitivity (:class:`GSensitivity`). Registered in
:data:`imunav.sensors.terms.TERMS`.

May import: ``imunav.core``, ``imunav.sensors.term_base``.
"""

from __future__ import annotations

import numpy as np

from imunav.core import units as U
from imunav.core.kernels import FloatArray
from imunav.sensors.term_base import (
    SensorErrorStates,
    Term,
    both_triads,
    identity_input,
    main_parameter,
    per_triad,
)

__all__ = ["OFF_DIAGONAL", "GSensitivity", "Misalignment", "ScaleFactor", "TurnOnBias"]


class TurnOnBias(Term):
    """A constant offset per run, 1σ per axis."""

    name, stage = "bias", "offset"
    parameters_ = (main_parameter("bias", per_triad(U.RATE, U.ACCEL), both_triads("turn-on bias (1σ)")),)
    display = {"gyro": ("deg/h", "°/h", "rad/s"), "accel": ("mg", "mg", "m/s²")}

    def start(self, model, stream, rng):
        """The run's bias vector (3,)."""
        return rng.normal(0.0, model.bias, 3)

    def offset(self, model, state) -> FloatArray:
        """The term's part of the constant offset (rate units)."""
        return state

    def linearise(self, model, ctx):
        """Three random constants of variance σ²."""
        if not self.present(model):
            return []
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  model.bias ** 2 * np.eye(3), np.zeros(3), identity_input)]


class ScaleFactor(Term):
    """``y = (I + diag(s)) x``, s drawn once per run."""

    name, stage = "scale_factor", "gain"
    parameters_ = (main_parameter("scale_factor", per_triad(U.FRACTION, U.FRACTION),
                         both_triads("scale-factor error (1σ)")),)
    display = {"gyro": ("ppm", "ppm", "1"), "accel": ("ppm", "ppm", "1")}

    def start(self, model, stream, rng):
        """The run's gain error, a diagonal 3×3 matrix."""
        return np.diag(rng.normal(0.0, model.scale_factor, 3))

    def gain(self, model, state) -> FloatArray:
        """The term's part of ``M − I``."""
        return state

    def linearise(self, model, ctx):
        """3 random constants: ``δu = diag(u) s``."""
        if not self.present(model):
            return []

        def diag_u(u, f):
            """``diag(u)`` at each step."""
            M = np.zeros((u.shape[0], 3, 3))
            M[:, [0, 1, 2], [0, 1, 2]] = u
            return M

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  model.scale_factor ** 2 * np.eye(3), np.zeros(3), diag_u)]


#: The six off-diagonal (row, column) pairs of a 3×3 matrix, in row order.
OFF_DIAGONAL = [(i, j) for i in range(3) for j in range(3) if i != j]


class Misalignment(Term):
    """Cross-axis coupling: 6 off-diagonal entries of ``M``, drawn once per run."""

    name, stage = "misalignment", "gain"
    parameters_ = (main_parameter("misalignment", per_triad(U.ANGLE, U.ANGLE),
                         both_triads("misalignment / cross-axis coupling (1σ)")),)
    display = {"gyro": ("mrad", "mrad", "rad"), "accel": ("mrad", "mrad", "rad")}

    def start(self, model, stream, rng):
        """The run's cross-axis matrix (zero diagonal)."""
        off = rng.normal(0.0, model.misalignment, (3, 3))
        np.fill_diagonal(off, 0.0)
        return off

    def gain(self, model, state) -> FloatArray:
        """The term's part of ``M − I``."""
        return state

    def linearise(self, model, ctx):
        """6 random constants: ``δu_i = Σ_{j≠i} m_ij u_j``."""
        if not self.present(model):
            return []

        def cross_axis(u, f):
            """The other axes' ``u`` in each off-diagonal column."""
            M = np.zeros((u.shape[0], 3, 6))
            for c, (i, j) in enumerate(OFF_DIAGONAL):
                M[:, i, c] = u[:, j]
            return M

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(6),
                                  model.misalignment ** 2 * np.eye(6), np.zeros(6), cross_axis)]


class GSensitivity(Term):
    """The gyro's response to specific force: ``ω += G f_b``."""

    name, stage, triads = "g_sensitivity", "coupling", ("gyro",)
    parameters_ = (main_parameter("g_sensitivity", {"gyro": U.GSENS}, {"gyro": "g-sensitivity (1σ)"}),)
    display = {"gyro": ("deg/h/g", "°/h/g", "rad/s/(m/s²)")}

    def start(self, model, stream, rng):
        """The run's 3×3 g-sensitivity matrix."""
        return rng.normal(0.0, model.g_sensitivity, (3, 3))

    def couple(self, model, state, stream, y: FloatArray, other: FloatArray | None
               ) -> FloatArray:
        """``y + G f`` with ``f`` the ideal specific force of the same samples."""
        if other is None:
            return y
        f = other / stream.dt if stream.kind == "increments" else other
        y += f @ state.T
        return y

    def linearise(self, model, ctx):
        """9 random constants: ``δω_i = Σ_j G_ij f_j``."""
        if ctx.triad != "gyro" or not self.present(model):
            return []

        def by_force(u, f):
            """``f`` in the row block of each gyro axis."""
            M = np.zeros((u.shape[0], 3, 9))
            for i in range(3):
                M[:, i, 3 * i: 3 * i + 3] = f
            return M

        return [SensorErrorStates(f"gyro.{self.name}", "gyro", np.zeros(9),
                                  model.g_sensitivity ** 2 * np.eye(9), np.zeros(9), by_force)]
