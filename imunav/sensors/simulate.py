"""Ideal IMU simulation: body rates and specific force, as samples or as exact increments.

Two output kinds:

``rates``
    ``ω_b(t_k)`` and ``f_b(t_k)`` at ``t_k = t0 + k/rate``, ``k = 0..N``.
``increments``
    ``Δθ_k = ∫ ω_b dt`` and ``Δv_k = ∫ f_b dt`` over ``(t_{k−1}, t_k]``, ``k = 1..N``, stamped
    with the interval end ``t_k``; computed by adaptive composite Gauss–Legendre quadrature
    converged to ~1e-13 relative (checked against ``scipy.integrate.quad`` in the tests).

``N = round(duration × rate)``.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors.signals``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array, check_gravity, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.signals import KINDS, ImuSignals

__all__ = ["integrate_intervals", "sample_times", "simulate_imu", "truth_states"]


def sample_times(rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """``t_k = t0 + k/rate`` for ``k = 0..N``, ``N = round(duration × rate)`` (N ≥ 1)."""
    rate = check_positive(rate, "rate")
    duration = check_positive(duration, "duration")
    n = int(round(duration * rate))
    if n < 1:
        raise ImunavError(
            f"duration × rate must give at least one sample interval, got {duration} s × {rate} Hz"
        )
    return t0 + np.arange(n + 1) / rate


def truth_states(motion: BaseMotion, t: npt.ArrayLike) -> States:
    """True position, velocity and attitude of ``motion`` at times ``t`` (``motion.states``)."""
    return motion.states(t)


_GL_CACHE: dict[int, tuple[FloatArray, FloatArray]] = {}


def _gauss_legendre(n: int) -> tuple[FloatArray, FloatArray]:
    if n not in _GL_CACHE:
        x, w = np.polynomial.legendre.leggauss(n)
        _GL_CACHE[n] = ((x + 1) / 2, w / 2)  # nodes and weights on [0, 1]
    return _GL_CACHE[n]


def _composite(f, a: FloatArray, b: FloatArray, panels: int, nodes: int) -> FloatArray:
    x, w = _gauss_legendre(nodes)
    h = (b - a) / panels
    # nodes of every panel of every interval: shape (M, panels*nodes)
    s = (np.arange(panels)[:, None] + x[None, :]).ravel()
    tt = a[:, None] + h[:, None] * s[None, :]
    vals = f(tt)  # (M, panels*nodes, 3)
    ww = np.tile(w, panels)
    return h[:, None] * np.einsum("mkc,k->mc", vals, ww)


def integrate_intervals(f, a: npt.ArrayLike, b: npt.ArrayLike, *, rtol: float = 1e-13,
                        atol: float = 1e-15, nodes: int = 8, max_panels: int = 1024,
                        budget: int = 2_000_000) -> FloatArray:
    """``∫_a^b f(t) dt`` for many intervals at once (vector-valued ``f``: ``t → (..., 3)``).

    Composite Gauss–Legendre with ``nodes`` points per panel; for each interval the number of
    panels is doubled until two successive estimates agree to ``atol + rtol·|I|`` in every
    component (the finer estimate is returned), only unconverged intervals being refined.
    Far from t = 0 the integrand itself carries rounding (``ω t`` loses digits), so an
    interval whose difference has stopped shrinking (less than 4× per doubling — a converging
    8-node rule gains ~2¹⁶) and is below ``1e-10`` of its scale is accepted at that floor.
    Raises if ``max_panels`` is reached otherwise. At most ``budget`` integrand points are
    evaluated per call of ``f`` (bounded memory).
    """
    a = as_float_array(a, "a", ndim=1)
    b = as_float_array(b, "b", ndim=1)
    out = np.empty((a.shape[0], 3))
    chunk = max(1, budget // (2 * nodes))
    for s in range(0, a.shape[0], chunk):
        idx = np.arange(s, min(a.shape[0], s + chunk))
        prev = _composite(f, a[idx], b[idx], 1, nodes)
        last = np.full(idx.shape, np.inf)
        panels = 1
        while idx.size:
            panels *= 2
            if panels > max_panels:
                raise ImunavError(
                    "increment quadrature did not converge: the motion is not smooth enough "
                    "at this sample rate (try a higher rate)"
                )
            step = max(1, budget // (panels * nodes))
            cur = np.concatenate([_composite(f, a[idx[i:i + step]], b[idx[i:i + step]], panels,
                                             nodes) for i in range(0, idx.size, step)])
            diff = np.abs(cur - prev).max(axis=1)
            scale = np.abs(cur).max(axis=1)
            ok = np.all(np.abs(cur - prev) <= atol + rtol * np.abs(cur), axis=1)
            ok |= (diff > last / 4) & (diff <= 1e-10 * scale + atol)
            out[idx[ok]] = cur[ok]
            idx, prev, last = idx[~ok], cur[~ok], diff[~ok]
    return out


def simulate_imu(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 output: str = "rates", g: float = G0, t0: float = 0.0) -> ImuSignals:
    """Ideal (error-free) IMU output for ``motion``.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output sample rate (Hz), > 0.
    duration : float, optional
        Seconds to simulate; defaults to ``motion.duration``.
    output : {"rates", "increments"}
        ``rates``: ``ω_b``, ``f_b`` at ``t_k``, k = 0..N. ``increments``: ``Δθ``, ``Δv`` over
        ``(t_{k−1}, t_k]``, k = 1..N, stamped with ``t_k``.
    g : float
        Gravity magnitude (m/s²), ``g_n = [0, 0, +g]``.
    t0 : float
        Start time (s).

    Returns
    -------
    ImuSignals
    """
    if output not in KINDS:
        raise ImunavError(f"output must be one of {KINDS}, got {output!r}")
    if duration is None:
        duration = motion.duration
        if duration is None:
            raise ImunavError("duration must be given (the motion has no default duration)")
    g = check_gravity(g)
    t = sample_times(rate, duration, float(t0))
    if output == "rates":
        gyro = motion.angular_rate(t)
        accel = motion.specific_force(t, g)
        ts = t
    else:
        a, b = t[:-1], t[1:]
        gyro = integrate_intervals(motion.angular_rate, a, b)
        accel = integrate_intervals(lambda s: motion.specific_force(s, g), a, b)
        ts = b
    return ImuSignals(ts, gyro, accel, output, float(rate), g,
                      meta={"motion": getattr(motion, "name", "motion"), "t0": float(t0)})
