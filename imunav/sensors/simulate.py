"""Ideal IMU simulation: body rates and specific force, as samples or as exact increments.

Two output kinds:

``rates``
    ``ω_b(t_k)`` and ``f_b(t_k)`` at ``t_k = t0 + k/rate``, ``k = 0..N``.
``increments``
    ``Δθ_k = ∫ ω_b dt`` and ``Δv_k = ∫ f_b dt`` over ``(t_{k−1}, t_k]``, ``k = 1..N``, stamped
    with the interval end ``t_k``; computed by adaptive composite Gauss–Legendre quadrature
    converged to ~1e-13 relative (checked against ``scipy.integrate.quad`` in the tests).

``N = round(duration × rate)``.

Every simulation is produced in chunks of :data:`CHUNK` samples (:func:`ideal_chunks`,
:func:`measured_chunks`), so the command line streams any duration to a file; the in-memory
:func:`simulate_imu` collects the same chunks.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors.signals``,
``imunav.sensors.models``.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.resources import check_memory
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import (
    ImunavError,
    as_float_array,
    check_gravity,
    check_int,
    check_positive,
)
from imunav.motion.base import BaseMotion
from imunav.sensors.models import MeasureStream
from imunav.sensors.signals import KINDS, ImuSignals

__all__ = ["ideal_chunks", "integrate_intervals", "interval_count", "measured_chunks",
           "sample_times", "simulate_imu", "truth_states"]


def interval_count(rate: float, duration: float) -> int:
    """``N = round(duration × rate)`` sample intervals (N ≥ 1), or an ImunavError."""
    rate = check_positive(rate, "rate")
    duration = check_positive(duration, "duration")
    n = round(duration * rate)
    if n < 1:
        raise ImunavError(f"duration × rate must give at least one sample interval, got "
                          f"{duration:g} s × {rate:g} Hz")
    return int(n)


def sample_times(rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """``t_k = t0 + k/rate`` for ``k = 0..N``, ``N = round(duration × rate)`` (N ≥ 1)."""
    n = interval_count(rate, duration)
    return float(t0) + np.arange(n + 1) / check_positive(rate, "rate")


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


#: Samples per chunk of the simulation (the working set of one chunk stays small).
CHUNK = 1 << 16

#: Most samples one simulation may compute (at the sensor's internal rate): about three hours
#: at a microsecond per sample. Beyond it a run is refused before it starts.
MAX_SAMPLES = 10_000_000_000


def check_work(n: int, rate: float, what: str = "this simulation") -> None:
    """Refuse a simulation of more than :data:`MAX_SAMPLES` samples, with the estimate."""
    if n > MAX_SAMPLES:
        raise ImunavError(f"{what} would compute {n:.3g} samples at {rate:g} Hz (hours to days); "
                          f"the limit is {MAX_SAMPLES:.0e}: lower the rate or the duration")


def _duration(motion: BaseMotion, duration) -> float:
    if duration is None:
        duration = motion.duration
        if duration is None:
            raise ImunavError("duration must be given (the motion has no default duration)")
    return check_positive(duration, "duration")


def ideal_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 output: str = "rates", g: float = G0, t0: float = 0.0, chunk: int = CHUNK
                 ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """The ideal signals of :func:`simulate_imu` as consecutive ``(t, gyro, accel)`` chunks of at
    most ``chunk`` samples (bounded memory for any duration)."""
    if output not in KINDS:
        raise ImunavError(f"output must be one of {KINDS}, got {output!r}")
    duration = _duration(motion, duration)
    rate = check_positive(rate, "rate")
    g = check_gravity(g)
    t0 = float(as_float_array(t0, "t0", ndim=0))
    n = interval_count(rate, duration)
    check_work(n, rate)
    first, last = (0, n + 1) if output == "rates" else (1, n + 1)      # sample indices k
    for lo in range(first, last, chunk):
        k = np.arange(lo, min(last, lo + chunk))
        t = t0 + k / rate
        if output == "rates":
            yield t, motion.angular_rate(t), motion.specific_force(t, g)
        else:
            a = t0 + (k - 1) / rate
            yield (t, integrate_intervals(motion.angular_rate, a, t),
                   integrate_intervals(lambda s: motion.specific_force(s, g), a, t))


def measured_chunks(motion: BaseMotion, model, rate: float, duration: float | None = None, *,
                    output: str = "rates", g: float = G0, t0: float = 0.0, seed: int = 0,
                    chunk: int = CHUNK, on_clip=None
                    ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """``(t, gyro, accel)`` chunks of what ``model`` (an :class:`~imunav.sensors.models.ImuModel`)
    outputs on ``motion`` at ``rate``: the ideal signals at the sensor's internal rate, then its
    errors (run 0 of the Monte Carlo streams of ``seed``: ``SeedSequence(seed).spawn(1)[0]``).
    ``on_clip(count)`` is called with the number of clipped output samples of each chunk."""
    seed = check_int(seed, "seed")
    k = model.decimation(rate)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    stream = MeasureStream(model, output, rate * k, rng, k)
    size = max(k, chunk // k * k)
    for t, gyro, accel in ideal_chunks(motion, rate * k, duration, output=output, g=g, t0=t0,
                                       chunk=size):
        gm, am, flags = stream.process(gyro, accel)
        if on_clip is not None and flags.any():
            on_clip(int(flags.sum()))
        yield (t[::k] if output == "rates" else t[k - 1::k][: gm.shape[0]]), gm, am


def simulate_imu(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 output: str = "rates", g: float = G0, t0: float = 0.0, imu=None,
                 seed: int = 0) -> ImuSignals:
    """IMU output for ``motion``: ideal, or with the errors of ``imu``.

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
    imu : ImuModel, optional
        Sensor errors to add (a preset via ``ImuModel.load("BMI088")``); ideal if None.
    seed : int
        Random seed for ``imu`` (the same stream as run 0 of a Monte Carlo with this seed).

    Returns
    -------
    ImuSignals

    Raises
    ------
    ImunavError
        Also when the arrays would not fit in memory (the command line streams to a file
        instead, for any duration).
    """
    duration = _duration(motion, duration)
    n = interval_count(rate, duration)
    k = 1 if imu is None else imu.decimation(rate)
    check_memory(8 * 7 * (n + 1) * (1 + k) + 64e6, f"simulating {n:,} samples",
                 "the command line (imunav simulate) streams any length to a file")
    if imu is None:
        chunks = ideal_chunks(motion, rate, duration, output=output, g=g, t0=t0)
    else:
        chunks = measured_chunks(motion, imu, rate, duration, output=output, g=g, t0=t0,
                                 seed=seed)
    parts = list(chunks)
    t, gyro, accel = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return ImuSignals(t, gyro, accel, output, float(rate), g,
                      meta={"motion": getattr(motion, "name", "motion"), "t0": float(t0)})
