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
from imunav.core.deprecation import renamed
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
    """The number of sample intervals ``N = round(duration × rate)``.

    Parameters
    ----------
    rate : float
        Sample rate (Hz), > 0.
    duration : float
        Duration (s), > 0.

    Returns
    -------
    int
        N ≥ 1.

    Raises
    ------
    ImunavError
        If ``rate`` or ``duration`` is not a finite number > 0, or their product rounds to 0.

    Examples
    --------
    >>> interval_count(100, 2.004)
    200
    """
    rate = check_positive(rate, "rate")
    duration = check_positive(duration, "duration")
    n = round(duration * rate)
    if n < 1:
        raise ImunavError(f"duration × rate must give at least one sample interval, got "
                          f"{duration:g} s × {rate:g} Hz")
    return int(n)


def sample_times(rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """The sample times ``t_k = t0 + k/rate``, k = 0..N, with ``N = round(duration × rate)``.

    Parameters
    ----------
    rate : float
        Sample rate (Hz), > 0.
    duration : float
        Duration (s), > 0.
    t0 : float, default 0.0
        Start time (s).

    Returns
    -------
    ndarray, shape (N + 1,)
        Times (s); each is ``t0 + k/rate`` computed afresh (no accumulated rounding).

    Raises
    ------
    ImunavError
        If ``rate`` or ``duration`` is not a finite number > 0, or N would be 0.

    Examples
    --------
    >>> sample_times(4, 1.0)
    array([0.  , 0.25, 0.5 , 0.75, 1.  ])
    """
    n = interval_count(rate, duration)
    return float(t0) + np.arange(n + 1) / check_positive(rate, "rate")


def truth_states(motion: BaseMotion, t: npt.ArrayLike) -> States:
    """True position, velocity and attitude of ``motion`` at times ``t``.

    The same as ``motion.states(t)``: the truth a navigation run is compared with.

    Parameters
    ----------
    motion : BaseMotion
        The motion.
    t : array_like, shape (N,)
        Times (s), e.g. :func:`sample_times` or ``ImuSignals.state_times()``.

    Returns
    -------
    States
        Position (m, NED), velocity (m/s, NED) and ``q_nb`` at ``t``; on the WGS-84 Earth
        (an :class:`~imunav.motion.geodetic.EarthMotion`) latitude, longitude, height and
        ``frame="wgs84"``.

    Raises
    ------
    ImunavError
        If ``t`` is not a 1-D finite array (or, for a motion from data, reaches outside it).

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> truth_states(Motion(x="2*t"), [0.0, 1.0]).position
    array([[0., 0., 0.],
           [2., 0., 0.]])
    """
    return motion.states(t)


#: Samples per chunk of the simulation (the working set of one chunk stays small).
CHUNK = 1 << 16

#: Most samples one simulation may compute (at the sensor's internal rate): about three hours
#: at a microsecond per sample. Beyond it a run is refused before it starts.
MAX_SAMPLES = 10_000_000_000


def check_work(n: int, rate: float, what: str = "this simulation") -> None:
    """Refuse a simulation of more than :data:`MAX_SAMPLES` samples, with the estimate.

    Parameters
    ----------
    n : int
        Samples the simulation would compute (at the sensor's internal rate).
    rate : float
        That rate (Hz), for the message.
    what : str, default "this simulation"
        What is refused, for the message.

    Raises
    ------
    ImunavError
        If ``n > MAX_SAMPLES`` (hours to days of work): lower the rate or the duration.
    """
    if n > MAX_SAMPLES:
        raise ImunavError(f"{what} would compute {n:.3g} samples at {rate:g} Hz (hours to days); "
                          f"the limit is {MAX_SAMPLES:.0e}: lower the rate or the duration")


def _duration(motion: BaseMotion, duration, rate: float) -> float:
    return span(motion, rate, duration)


@renamed(output="kind")
def ideal_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 kind: str = "rates", g: float = G0, t0: float = 0.0, chunk: int = CHUNK
                 ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """The ideal signals of :func:`simulate_imu` as consecutive ``(t, gyro, accel)`` chunks.

    Bounded memory for any duration: each chunk holds at most ``chunk`` samples. Rates are
    ``ω_b(t_k)``, ``f_b(t_k)``; increments are integrated exactly over each interval
    (piece by piece between a spline motion's ``breakpoints``).

    Parameters
    ----------
    motion : BaseMotion
        The motion.
    rate : float
        Sample rate (Hz), > 0.
    duration : float, optional
        Seconds; default the motion's own (a motion from data stops at its last whole sample).
    kind : {"rates", "increments"}, default "rates"
        What to produce (see :func:`simulate_imu`).
    g : float, default G0
        Gravity magnitude (m/s²), ``g_n = [0, 0, +g]``.
    t0 : float, default 0.0
        Start time (s).
    chunk : int, default CHUNK
        Samples per chunk (at most).

    Yields
    ------
    t : ndarray, shape (n,)
        Sample times (s), interval ends for increments.
    gyro : ndarray, shape (n, 3)
        ``ω_b`` (rad/s) or ``Δθ`` (rad).
    accel : ndarray, shape (n, 3)
        ``f_b`` (m/s²) or ``Δv`` (m/s).

    Raises
    ------
    ImunavError
        On the first ``next``: if ``kind`` is unknown, ``rate``, the duration or ``g`` is not
        a finite number > 0, ``t0`` is not a finite number, or the run exceeds
        :data:`MAX_SAMPLES`; later, if the motion is not finite at a sample.
    """
    if kind not in KINDS:
        raise ImunavError(f"kind must be one of {KINDS}, got {kind!r}")
    duration = _duration(motion, duration, rate)
    rate = check_positive(rate, "rate")
    g = check_gravity(g)
    t0 = float(as_float_array(t0, "t0", ndim=0))
    n = interval_count(rate, duration)
    check_work(n, rate)
    first, last = (0, n + 1) if kind == "rates" else (1, n + 1)      # sample indices k
    for lo in range(first, last, chunk):
        k = np.arange(lo, min(last, lo + chunk))
        t = t0 + k / rate
        if kind == "rates":
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


@renamed(model="imu", output="kind")
def measured_chunks(motion: BaseMotion, imu, rate: float, duration: float | None = None, *,
                    kind: str = "rates", g: float = G0, t0: float = 0.0, seed: int = 0,
                    chunk: int = CHUNK, on_clip=None
                    ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
    """``(t, gyro, accel)`` chunks of what ``imu`` outputs on ``motion`` at ``rate``.

    The ideal signals are simulated at the sensor's internal rate (``rate ×
    imu.decimation(rate)``), then its errors are applied and the output decimated
    (:class:`~imunav.sensors.models.MeasureStream`). The random errors are run 0 of the Monte
    Carlo streams of ``seed`` (``SeedSequence(seed).spawn(1)[0]``), so a Monte Carlo's first run
    and this simulation agree.

    Parameters
    ----------
    motion : BaseMotion
        The motion.
    imu : ImuModel
        The sensor's errors (:class:`~imunav.sensors.models.ImuModel`).
    rate : float
        Output rate (Hz), > 0.
    duration : float, optional
        Seconds; default the motion's own.
    kind : {"rates", "increments"}, default "rates"
        What to produce (see :func:`simulate_imu`).
    g : float, default G0
        Gravity magnitude (m/s²).
    t0 : float, default 0.0
        Start time (s).
    seed : int, default 0
        Random seed (an integer ≥ 0).
    chunk : int, default CHUNK
        Samples per chunk at the internal rate (rounded down to whole output samples).
    on_clip : callable, optional
        ``on_clip(count)``, called with the number of output samples clipped at the sensor's
        range in each chunk where there are some.

    Yields
    ------
    t : ndarray, shape (n,)
        Output sample times (s), interval ends for increments.
    gyro : ndarray, shape (n, 3)
        Measured ``ω_b`` (rad/s) or ``Δθ`` (rad).
    accel : ndarray, shape (n, 3)
        Measured ``f_b`` (m/s²) or ``Δv`` (m/s).

    Raises
    ------
    ImunavError
        On the first ``next``: if ``seed`` is not an integer ≥ 0, or for the reasons of
        :func:`ideal_chunks` (at the internal rate).
    """
    seed = check_int(seed, "seed")
    k = imu.decimation(rate)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    stream = MeasureStream(imu, kind, rate * k, rng, k)
    size = max(k, chunk // k * k)
    duration = span(motion, rate, duration)          # whole output intervals (data motions)
    for t, gyro, accel in ideal_chunks(motion, rate * k, duration, kind=kind, g=g, t0=t0,
                                       chunk=size):
        gm, am, flags = stream.process(gyro, accel)
        if on_clip is not None and flags.any():
            on_clip(int(flags.sum()))
        yield (t[::k] if kind == "rates" else t[k - 1::k][: gm.shape[0]]), gm, am


@renamed(output="kind")
def signal_chunks(motion: BaseMotion, rate: float, duration: float | None = None, *,
                  kind: str = "rates", g: float = G0, t0: float = 0.0, imu=None, seed: int = 0,
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
    kind : {"rates", "increments"}
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
        return ideal_chunks(motion, rate, duration, kind=kind, g=g, t0=t0, chunk=chunk)
    return measured_chunks(motion, imu, rate, duration, kind=kind, g=g, t0=t0, seed=seed,
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


@renamed(output="kind")
def simulate_imu(motion: BaseMotion, rate: float, duration: float | None = None, *,
                 kind: str = "rates", g: float = G0, t0: float = 0.0, imu=None,
                 seed: int = 0) -> ImuSignals:
    """IMU output for ``motion``: ideal, or with the errors of ``imu``.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Output sample rate (Hz), > 0.
    duration : float, optional
        Seconds to simulate; defaults to ``motion.duration``.
    kind : {"rates", "increments"}
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
        If ``kind`` is unknown; ``rate``, the duration (given or the motion's) or ``g`` is
        not a finite number > 0; ``seed`` is not an integer ≥ 0; the motion is not finite at
        a sample; the run (at the sensor's internal rate) would exceed
        :data:`MAX_SAMPLES`; or the arrays would not fit in memory (the command line streams
        to a file instead, for any duration).

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> sig = simulate_imu(Motion(yaw="0.5*t", duration=1.0), rate=10, kind="increments")
    >>> sig.t.shape, sig.dtheta[0]                   # 0.5 rad/s for 0.1 s about z
    ((10,), array([0.  , 0.  , 0.05]))
    """
    duration = _duration(motion, duration, rate)
    n = interval_count(rate, duration)
    k = 1 if imu is None else imu.decimation(rate)
    check_memory(8 * 7 * (n + 1) * (1 + k) + 64e6, f"simulating {n:,} samples",
                 "the command line (imunav simulate) streams any length to a file")
    if imu is None:
        chunks = ideal_chunks(motion, rate, duration, kind=kind, g=g, t0=t0)
    else:
        chunks = measured_chunks(motion, imu, rate, duration, kind=kind, g=g, t0=t0,
                                 seed=seed)
    parts = list(chunks)
    t, gyro, accel = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return ImuSignals(t, gyro, accel, kind, float(rate), g,
                      meta={"motion": motion.name, "t0": float(t0)})
