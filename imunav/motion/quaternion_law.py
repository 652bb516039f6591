"""Motions whose attitude is a closed-form quaternion law.

- :class:`QuaternionLawMotion` — any unit-quaternion law ``q_nb(t)`` given as SymPy expressions;
  ``ω_b = vec(2 q* ⊗ q̇)`` is derived symbolically, so the truth is exact to rounding.
- :class:`FourRotationMotion` — four simultaneous turns ``Λ = q₃(φ) ∘ q₂(ψ) ∘ q₁(ϑ) ∘ q₂(χ)``
  about body axes, the reference model of Plaksiy & Homozkova (general enough for any
  precession-like motion; the paper module :mod:`imunav.papers.plaksiy` adds its drift study).

May import: ``imunav.core``, ``imunav.motion.base``, ``imunav.motion.laws``,
``imunav.motion.analytic``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import sympy as sp

from imunav.core.kernels import axis_quat, quat_mul
from imunav.core.rotations import FloatArray
from imunav.core.validation import ImunavError, as_float_array, check_positive
from imunav.motion.analytic import LawMotion
from imunav.motion.base import BaseMotion, times
from imunav.motion.laws import T, evaluate, lambdify, parse_law

#: Plaksiy & Homozkova's Fig. 1–3 frequencies (rad/s): φ = k₁t, ψ = k₂t, ϑ = k₃t, χ = k₄t.
PAPER_K = (0.15, 1.55, 0.35, -1.55)


class QuaternionLawMotion(LawMotion):
    """A motion whose attitude is a closed-form quaternion ``q_nb(t)`` (SymPy, scalar first).

    The body rate ``ω_b = vec(2 q* ⊗ q̇)`` is differentiated symbolically, so the truth is
    exact to rounding; position, velocity and acceleration come from the position laws.

    Parameters
    ----------
    q : sequence of 4 str, number or sympy.Expr
        The attitude law ``[w, x, y, z]`` of ``q_nb`` in ``t`` (:data:`imunav.motion.T`), each
        passing the whitelist of :mod:`imunav.motion.laws`. It must be a unit quaternion for
        every t: checked at 17 times evenly spread over ``[0, duration]`` (``[0, 1]`` s without
        a duration) to 1e-12.
    x, y, z : str, number or sympy.Expr, default 0
        Position laws (m, NED), as for :class:`~imunav.motion.analytic.Motion`.
    duration : float, optional
        Default duration (s) for simulation.
    name : str, default "motion"
        A name for reports, plots and error messages.

    Raises
    ------
    ImunavError
        If a law is outside the whitelist, a derived quantity is complex-valued, ``duration``
        is not a finite number > 0, or ``|q| = 1`` fails by more than 1e-12 at a checked time.

    Examples
    --------
    A steady turn about the vertical at 0.5 rad/s:

    >>> m = QuaternionLawMotion(["cos(t/4)", 0, 0, "sin(t/4)"], duration=10)
    >>> m.angular_rate([1.0])
    array([[0. , 0. , 0.5]])
    """

    def __init__(self, q, x=0, y=0, z=0, *, duration: float | None = None, name: str = "motion"):
        q = [parse_law(c, f"q{i}") for i, c in enumerate(q)]
        qd = [sp.diff(c, T) for c in q]
        Q = sp.algebras.Quaternion
        w = 2 * Q(q[0], -q[1], -q[2], -q[3]) * Q(*qd)
        self.duration = None if duration is None else check_positive(duration, "duration")
        self.name = name
        self._compile((x, y, z), {
            "quaternion": [(c, f"quaternion law q{i} of {name}") for i, c in enumerate(q)],
            "angular_rate": [(c, f"angular rate ω_{i} of {name}")
                             for c, i in zip((w.b, w.c, w.d), "xyz", strict=True)],
        })
        tt = np.linspace(0, duration or 1.0, 17)
        n = np.linalg.norm(self._eval("quaternion", tt), axis=-1)
        if np.max(np.abs(n - 1)) > 1e-12:
            raise ImunavError("q must be a unit quaternion law (|q| = 1 at every t)")

    def attitude(self, t):
        return self._eval("quaternion", t)

    def angular_rate(self, t):
        return self._eval("angular_rate", t)


class FourRotationMotion(BaseMotion):
    """Rigid-body rotation by four simultaneous turns; the body stays at the origin.

    Parameters
    ----------
    phi, psi, vartheta, chi : str, number or sympy.Expr, optional
        Angle laws (rad) in ``t``. Defaults: linear laws ``k₁t, k₂t, k₃t, k₄t``.
    k : sequence of 4 float, default PAPER_K
        Frequencies (rad/s) of the default linear laws, in the order φ, ψ, ϑ, χ (the paper's
        Fig. 1–3 values ``(0.15, 1.55, 0.35, −1.55)`` by default). Ignored for a law given.
    duration : float, default 1000.0
        Default duration (s) for simulation.
    name : str, default "four_rotation"
        A name for reports and plots.

    Raises
    ------
    ImunavError
        If ``k`` is not 4 finite numbers, a law is outside the whitelist of
        :mod:`imunav.motion.laws`, or ``duration`` is not a finite number > 0.

    Notes
    -----
    Orientation: Plaksiy & Homozkova eq. (3) as corrected, ``Λ = q₃(φ) ∘ q₂(ψ) ∘ q₁(ϑ) ∘ q₂(χ)``.
    Angular velocity: their eq. (5), verified symbolically to equal ``2 Λ̃ ∘ Λ̇``
    (:mod:`imunav.symbolic.plaksiy`)::

        ω₁ = −sin χ (φ̇ cos ψ cos ϑ − ψ̇ sin ϑ) + cos χ (ϑ̇ − φ̇ sin ψ)
        ω₂ = χ̇ + φ̇ sin ϑ cos ψ + ψ̇ cos ϑ
        ω₃ =  sin χ (ϑ̇ − φ̇ sin ψ) + cos χ (φ̇ cos ψ cos ϑ − ψ̇ sin ϑ)
    """

    def __init__(self, phi=None, psi=None, vartheta=None, chi=None, *,
                 k: tuple[float, float, float, float] = PAPER_K, duration: float = 1000.0,
                 name: str = "four_rotation"):
        k = as_float_array(k, "k", ndim=1, last=4)
        laws = [phi, psi, vartheta, chi]
        names = ("phi", "psi", "vartheta", "chi")
        self.k = tuple(float(x) for x in k)
        self.laws = [parse_law(sp.Float(float(ki)) * T if law is None else law, n)
                     for law, ki, n in zip(laws, k, names, strict=True)]
        self._ang = [(lambdify(e), f"angle law {n}") for e, n in zip(self.laws, names, strict=True)]
        self._rate = [(lambdify(sp.diff(e, T)), f"rate of angle law {n}")
                      for e, n in zip(self.laws, names, strict=True)]
        self.duration = check_positive(duration, "duration")
        self.name = name

    def angles(self, t: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The four angle laws and their exact time derivatives.

        Parameters
        ----------
        t : array_like
            Times (s), any shape.

        Returns
        -------
        angles : ndarray, shape ``t.shape + (4,)``
            ``(φ, ψ, ϑ, χ)`` (rad).
        rates : ndarray, shape ``t.shape + (4,)``
            ``(φ̇, ψ̇, ϑ̇, χ̇)`` (rad/s).

        Raises
        ------
        ImunavError
            If ``t`` is not a finite numeric array, or a law or its rate is not finite at one
            of the times.

        Examples
        --------
        >>> angles, rates = FourRotationMotion().angles([2.0])
        >>> rates                                   # the default linear laws: the paper's k
        array([[ 0.15,  1.55,  0.35, -1.55]])
        """
        t = times(t)
        a = np.stack([evaluate(f, t, what) for f, what in self._ang], -1)
        r = np.stack([evaluate(f, t, what) for f, what in self._rate], -1)
        return a, r

    def attitude(self, t):
        a, _ = self.angles(t)
        return quat_mul(quat_mul(quat_mul(axis_quat(a[..., 0], 3), axis_quat(a[..., 1], 2)),
                                 axis_quat(a[..., 2], 1)), axis_quat(a[..., 3], 2))

    def angular_rate(self, t):
        a, r = self.angles(t)
        ph, ps, th, ch = np.moveaxis(a, -1, 0)
        dph, dps, dth, dch = np.moveaxis(r, -1, 0)
        u = dth - dph * np.sin(ps)
        v = dph * np.cos(ps) * np.cos(th) - dps * np.sin(th)
        return np.stack([
            -np.sin(ch) * v + np.cos(ch) * u,                    # eq. (5), ω₁
            dch + dph * np.sin(th) * np.cos(ps) + dps * np.cos(th),  # eq. (5), ω₂
            np.sin(ch) * u + np.cos(ch) * v,                     # eq. (5), ω₃
        ], -1)

    def position(self, t):
        t = times(t)
        return np.zeros(t.shape + (3,))

    velocity = position
    acceleration = position


