"""The algorithm table: every strapdown algorithm of imunav is a row of :data:`ALGORITHMS` with
its signal kind, its order (the measured global convergence order of the attitude, velocity and
position errors on smooth motion — see ``tests/strapdown/test_algorithms.py``), its source, whether it is
causal and the samples it needs around an interval; :data:`DEFAULT_ALGORITHM` names the most
accurate one per kind and :func:`resolve` is how every caller picks one. Navigating with them
is :mod:`imunav.strapdown.registry`.

May import: ``imunav.core``, ``imunav.sensors.signals``, ``imunav.strapdown.classic``,
``imunav.strapdown.highorder``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from imunav.core.validation import ImunavError
from imunav.sensors.signals import KINDS
from imunav.strapdown import classic
from imunav.strapdown.highorder import navigate_poly

__all__ = ["ALGORITHMS", "Algorithm", "DEFAULT_ALGORITHM", "resolve"]


@dataclass(frozen=True)
class Algorithm:
    """One strapdown algorithm: a row of :data:`ALGORITHMS`.

    Attributes
    ----------
    name : str
        The name users choose it by (``algorithm=`` of :func:`navigate`).
    kind : {"rates", "increments"}
        The signals it integrates.
    order : tuple of int
        The global convergence order ``(attitude, velocity, position)`` on smooth motion (as
        measured in ``tests/strapdown/test_algorithms.py``).
    summary : str
        What it does, in one line.
    source : str
        Where it comes from (papers, books).
    func : callable
        ``func(gyro, accel, h, q0, v0, p0, g, first, count) → (q, v, p)``: integrates ``count``
        intervals of a window of samples from interval ``first`` (``h`` in s, ``g`` in m/s²;
        see :mod:`imunav.strapdown.classic`), for one run ((M, 3) inputs) or R runs at once
        ((M, R, 3)); returns the ``count + 1`` states from the initial one.
    causal : bool, default True
        The state at ``t_k`` uses no sample after ``t_k`` (real-time capable; multi-sample
        algorithms update once per major interval).
    context : tuple of int, default (0, 0)
        Samples needed before and after an interval's own.
    align : int, default 1
        Chunks must start at multiples of it (multi-sample groups).

    Examples
    --------
    >>> ALGORITHMS["rates"]["magnus4"].order, ALGORITHMS["rates"]["magnus4"].causal
    ((4, 4, 4), False)
    """

    name: str
    kind: str
    order: tuple[int, int, int]
    summary: str
    source: str
    func: Callable
    causal: bool = True
    context: tuple[int, int] = (0, 0)
    align: int = 1

    @property
    def min_samples(self) -> int:
        """Fewest samples it integrates: two rate samples (one interval) or one increment."""
        return 2 if self.kind == "rates" else 1


def _poly(kind: str, m: int, order: int) -> Callable:
    """A high-order offline algorithm: local m-node fit + Magnus-``order`` (strapdown.highorder)."""
    def run(gyro, accel, h, q0, v0, p0, g, first, count):
        return navigate_poly(kind, gyro, accel, h, q0, v0, p0, g, first, count, m=m, order=order)

    return run


def _register(*algos: Algorithm) -> dict[str, dict[str, Algorithm]]:
    reg: dict[str, dict[str, Algorithm]] = {k: {} for k in KINDS}
    for a in algos:
        reg[a.kind][a.name] = a
    return reg


#: ``ALGORITHMS[kind][name]`` → :class:`Algorithm`.
ALGORITHMS = _register(
    Algorithm("first_order", "rates", (1, 1, 1),
              "q ← normalise(q + ½ q⊗ω_{k−1} h); trapezoidal velocity, position exact for "
              "linear a_n", "textbook Poisson/quaternion update, e.g. Marusenkova 2020 eq. (15); "
              "Madgwick's tutorial", classic.rates_first_order),
    Algorithm("exact_exponential", "rates", (2, 2, 2),
              "q ← q ⊗ exp(h (ω_{k−1}+ω_k)/2): exact for constant rate; trapezoidal velocity",
              "Dickson & Rae 2021 (rotation quaternion from rates); Savage 1998",
              classic.rates_exponential),
    Algorithm("magnus4", "rates", (4, 4, 4),
              "local cubic through 4 rate samples, one 2-node fourth-order Magnus step; "
              "velocity/position by 3-point Gauss quadrature of C_nb f_b",
              "Iserles & Nørsett 1999 (Magnus integrators); offline (uses the next sample)",
              _poly("rates", 4, 4), causal=False, context=(4, 4)),
    Algorithm("magnus6", "rates", (6, 6, 6),
              "local quintic through 6 rate samples, one 3-node sixth-order Magnus step; "
              "velocity/position by 3-point Gauss quadrature of C_nb f_b",
              "Blanes, Casas & Ros 2000 (sixth-order Magnus); offline (uses 3 later samples)",
              _poly("rates", 6, 6), causal=False, context=(6, 6)),
    Algorithm("first_order", "increments", (2, 2, 2),
              "q ← normalise(q ⊗ [1, Δθ/2]); Δv with rotation compensation, no sculling",
              "textbook small-angle quaternion, Marusenkova 2020 eq. (25)",
              classic.increments_first_order),
    Algorithm("exact_exponential", "increments", (2, 2, 2),
              "q ← q ⊗ exp(Δθ): exact for constant rate; no coning/sculling correction",
              "Marusenkova 2020 eq. (36); Savage 1998", classic.increments_exponential),
    Algorithm("coning2", "increments", (3, 2, 2),
              "rotation vector φ = Δθ_k + Δθ_{k−1}×Δθ_k/12 (1+1 'previous interval' coning), "
              "two-sample sculling and rotation compensation; trapezoidal position",
              "Savage 1998 (J. Guid. Control Dyn. 21(1)), Titterton & Weston ch. 11",
              classic.increments_coning2, context=(1, 0)),
    Algorithm("ignagni2", "increments", (3, 2, 2),
              "2-sample rotation vector: θ₁+θ₂ + ⅔ θ₁×θ₂ per major interval of 2 increments",
              "Ignagni 1990 (J. Guid. Control Dyn. 13(2)); causal", classic.multisample("ignagni2"),
              context=(1, 0), align=2),
    Algorithm("miller3", "increments", (3, 2, 2),
              "3-sample rotation vector, eq. (2) of Plaksiy & Homozkova with α=33/80, β=57/80",
              "Miller 1983 (J. Guid. Control Dyn. 6(4)); causal", classic.multisample("miller3"),
              context=(1, 0), align=3),
    Algorithm("ignagni3", "increments", (3, 2, 2),
              "3-sample rotation vector optimised for coning: α=9/20, β=27/40",
              "Ignagni 1990; causal", classic.multisample("ignagni3"),
              context=(1, 0), align=3),
    Algorithm("ignagni4", "increments", (3, 2, 2),
              "4-sample rotation vector optimised for coning (coefficients /945)",
              "Ignagni 1990; Savage 1998 table 1; causal", classic.multisample("ignagni4"),
              context=(1, 0), align=4),
    Algorithm("poly6_m4", "increments", (4, 4, 4),
              "6-node fit of cumulative increments, one fourth-order Magnus step per interval; "
              "Gauss quadrature of C_nb f_b for velocity/position",
              "this work (local polynomial + Magnus, Iserles & Nørsett 1999); offline",
              _poly("increments", 6, 4), causal=False, context=(6, 6)),
    Algorithm("poly8_m6", "increments", (6, 6, 6),
              "8-node fit of cumulative increments, one sixth-order Magnus step per interval; "
              "Gauss quadrature of C_nb f_b for velocity/position",
              "this work (local polynomial + Blanes–Casas–Ros sixth-order Magnus); offline",
              _poly("increments", 8, 6), causal=False, context=(8, 8)),
)

#: The most accurate algorithm for each signal kind (used when none is named).
DEFAULT_ALGORITHM = {"rates": "magnus6", "increments": "poly8_m6"}


def resolve(kind: str, algorithm: str | None = None) -> Algorithm:
    """The registry row for ``algorithm`` on ``kind`` signals.

    Parameters
    ----------
    kind : {"rates", "increments"}
        The signal kind.
    algorithm : str, optional
        A name from ``ALGORITHMS[kind]``; default :data:`DEFAULT_ALGORITHM` ``[kind]``.

    Returns
    -------
    Algorithm

    Raises
    ------
    ImunavError
        If ``kind`` is unknown, or ``algorithm`` is not registered for it (the message lists
        the choices).

    Examples
    --------
    >>> resolve("increments").name, resolve("rates", "first_order").order
    ('poly8_m6', (1, 1, 1))
    """
    if kind not in KINDS:
        raise ImunavError(f"kind must be one of {KINDS}, got {kind!r}")
    name = algorithm or DEFAULT_ALGORITHM[kind]
    table = ALGORITHMS[kind]
    if name not in table:
        raise ImunavError(
            f"unknown algorithm {name!r} for {kind}; choose one of {', '.join(sorted(table))}")
    return table[name]
