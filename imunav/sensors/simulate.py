"""Ideal IMU simulation: body rates and specific force, as samples or as exact increments.

Two output kinds:

``rates``
    ``ω_b(t_k)`` and ``f_b(t_k)`` at ``t_k = t0 + k/rate``, ``k = 0..N``.
``increments``
    ``Δθ_k = ∫ ω_b dt`` and ``Δv_k = ∫ f_b dt`` over ``(t_{k−1}, t_k]``, ``k = 1..N``, stamped
    with the interval end ``t_k``; computed from Chebyshev interpolants over blocks of 64
    intervals (:mod:`imunav.sensors.quadrature`: about a third of a motion evaluation per
    increment), within 1e-13 of the increment's norm against high-precision mpmath quadrature.

``N = round(duration × rate)``.

Every simulation is produced in chunks of :data:`CHUNK` samples (:func:`ideal_chunks`,
:func:`measured_chunks`), so the command line streams any duration to a file; the in-memory
:func:`simulate_imu` collects the same chunks.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors.signals``,
``imunav.sensors.models``, ``imunav.sensors.quadrature``.
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
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import MeasureStream
from imunav.sensors.quadrature import integrate_consecutive, integrate_piecewise
from imunav.sensors.signals import KINDS, ImuSignals

__all__ = ["ideal_chunks", "interval_count", "measured_chunks", "sample_times", "signal_chunks",
           "simulate_imu", "truth_chunks", "truth_states"]


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


def _duration(motion: BaseMotion, duration, rate: float) -> float:
    return span(motion, rate, duration)


def ideal_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 output: str = "rates", g: float = G0, t0: float = 0.0, chunk: int = CHUNK
                 ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """The ideal signals of :func:`simulate_imu` as consecutive ``(t, gyro, accel)`` chunks of at
    most ``chunk`` samples (bounded memory for any duration)."""
    if output not in KINDS:
        raise ImunavError(f"output must be one of {KINDS}, got {output!r}")
    duration = _duration(motion, duration, rate)
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
            bp = motion.breakpoints
            if bp is not None and len(bp):        # a spline: integrate piece by piece
                inc = integrate_piecewise(lambda s: _imu(motion, s, g), t0, 1.0 / rate,
                                          int(k[0]) - 1, int(k[-1]), bp)
            else:
                inc = integrate_consecutive(lambda s: _imu(motion, s, g), t0, 1.0 / rate,
                                            int(k[0]) - 1, int(k[-1]), groups=2)
            yield t, inc[:, :3], inc[:, 3:]


def _imu(motion: BaseMotion, t: FloatArray, g: float) -> FloatArray:
    """ω_b and f_b side by side: shape t.shape + (6,)."""
    return np.concatenate([motion.angular_rate(t), motion.specific_force(t, g)], axis=-1)


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
    duration = span(motion, rate, duration)          # whole output intervals (data motions)
    for t, gyro, accel in ideal_chunks(motion, rate * k, duration, output=output, g=g, t0=t0,
                                       chunk=size):
        gm, am, flags = stream.process(gyro, accel)
        if on_clip is not None and flags.any():
            on_clip(int(flags.sum()))
        yield (t[::k] if output == "rates" else t[k - 1::k][: gm.shape[0]]), gm, am


def signal_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                  output: str = "rates", g: float = G0, t0: float = 0.0, imu=None, seed: int = 0,
                  chunk: int = CHUNK, on_clip=None
                  ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """The signals of :func:`simulate_imu` as ``(t, gyro, accel)`` chunks: ideal
    (:func:`ideal_chunks`) without ``imu``, else with its errors (:func:`measured_chunks`).

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    output : {"rates", "increments"}
    g : float
        Gravity magnitude (m/s²).
    t0 : float
        Start time (s).
    imu : ImuModel, optional
        Sensor errors; ideal if None.
    seed : int
        Random seed for ``imu``.
    chunk : int
        Samples per chunk (at most).
    on_clip : callable, optional
        ``on_clip(count)``, called with the clipped output samples of each chunk.

    Yields
    ------
    tuple of ndarray
        ``(t, gyro, accel)``, shapes (n,), (n, 3), (n, 3).
    """
    if imu is None:
        return ideal_chunks(motion, rate, duration, output=output, g=g, t0=t0, chunk=chunk)
    return measured_chunks(motion, imu, rate, duration, output=output, g=g, t0=t0, seed=seed,
                           chunk=chunk, on_clip=on_clip)


def truth_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 chunk: int = CHUNK) -> Iterator[States]:
    """The true states at ``t_k = k/rate``, k = 0..N, ``N = round(duration × rate)``, in chunks
    of at most ``chunk`` rows (what ``imunav simulate --truth`` writes, in bounded memory).

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    chunk : int

    Yields
    ------
    States

    Raises
    ------
    ImunavError
        For a non-positive rate or duration.
    """
    n = interval_count(rate, motion.duration if duration is None else duration)
    for lo in range(0, n + 1, chunk):
        yield motion.states(np.arange(lo, min(n + 1, lo + chunk)) / rate)


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
    duration = _duration(motion, duration, rate)
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
                      meta={"motion": motion.name, "t0": float(t0)})
