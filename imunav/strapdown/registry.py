"""The algorithm registry and the one entry point that navigates: :func:`navigate` (one run, an
:class:`~imunav.sensors.signals.ImuSignals`) and :func:`navigate_batch` (many runs at once,
as Monte Carlo uses it).

Every algorithm is a row of :data:`ALGORITHMS` with its signal kind, its order (the measured
global convergence order of the attitude, velocity and position errors on smooth motion — see
``tests/strapdown/test_algorithms.py``), its source and whether it is causal. :data:`DEFAULT_ALGORITHM`
names the most accurate one per kind; every caller that does not choose goes through it.

All navigation goes through one driver, :class:`StreamNavigator`: it integrates chunks of
intervals in turn, each with the samples around it that the algorithm needs as context (its
``context``: two-sample corrections look one sample back, polynomial stencils a few both
ways), carrying the state from chunk to chunk. So a recording of any length is navigated in
bounded memory (the command line feeds it from the CSV as it reads), and the in-memory
:func:`navigate` is the same code with all samples fed at once.

The table is :mod:`~imunav.strapdown.algorithms` and the driver :mod:`~imunav.strapdown.stream`;
their names are re-exported here, the one place callers import them from.

May import: ``imunav.core``, ``imunav.sensors.signals``, ``imunav.strapdown`` modules below.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray, quat_normalize
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array, check_gravity
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.algorithms import ALGORITHMS, DEFAULT_ALGORITHM, Algorithm, resolve
from imunav.strapdown.stream import (
    CHUNK,
    EARTH_CHUNK_SECONDS,
    EARTHS,
    StreamNavigator,
    collect,
)

__all__ = ["ALGORITHMS", "Algorithm", "CHUNK", "DEFAULT_ALGORITHM", "EARTH_CHUNK_SECONDS",
           "EARTHS", "StreamNavigator", "navigate", "navigate_batch", "navigate_chunks",
           "resolve"]


def navigate(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike = (0.0, 0.0, 0.0),
             p0: npt.ArrayLike = (0.0, 0.0, 0.0), *, algorithm: str | None = None,
             g: float | None = None, earth: str = "flat", hold=None) -> States:
    """Integrate IMU signals from an initial state.

    Parameters
    ----------
    signals : ImuSignals
        Rates (``t_k``, k = 0..N) or increments (interval ends ``t_k``, k = 1..N).
    q0 : array_like, shape (4,)
        Initial attitude ``q_nb`` at the start time ``signals.t0`` (on the Earth: relative to
        the local NED frame).
    v0, p0 : array_like, shape (3,)
        Initial velocity (m/s) and position (m), NED; on the Earth (``earth="wgs84"``) the
        velocity relative to the Earth in local NED and ``p0 = [lat, lon, h]`` (rad, rad, m).
    algorithm : str, optional
        A name from ``ALGORITHMS[signals.kind]``; default the most accurate for the kind.
    g : float, optional
        Gravity magnitude (m/s²) of the flat frame; default ``signals.g``. Not with
        ``earth="wgs84"`` (gravity comes from the normal gravity model).
    earth : {"flat", "wgs84"}
        The navigation frame: flat and non-rotating, or the rotating WGS-84 Earth
        (:mod:`imunav.strapdown.rotating`: Earth rate, transport rate, Coriolis, normal gravity).
    hold : callable, optional
        On the Earth: ``hold(t) → (h, v_d)``, the heights (m) and down velocities (m/s) at the
        state times ``t`` to hold the vertical channel at (a perfect height aid); default free.

    Returns
    -------
    States
        States at ``signals.state_times()`` (the first row is the initial state), with the
        algorithm's name (and ``frame="wgs84"`` on the Earth: positions ``[lat, lon, h]``).

    Raises
    ------
    ImunavError
        If ``signals`` is not :class:`~imunav.sensors.signals.ImuSignals`; ``q0``, ``v0`` or
        ``p0`` has the wrong shape or is not finite (``q0`` also if it is zero); ``g`` is
        given with ``earth="wgs84"`` or is not a valid gravity; ``algorithm`` or ``earth`` is
        unknown; ``hold`` is given on the flat frame; the signals have fewer samples than the
        algorithm needs; or the navigation becomes non-finite (signals far too large).

    Examples
    --------
    1 m/s² north, level, for 1 s from rest: 1 m/s and 0.5 m north.

    >>> import numpy as np
    >>> from imunav.sensors.signals import ImuSignals
    >>> sig = ImuSignals(t=np.arange(11) / 10, gyro=np.zeros((11, 3)),
    ...                  accel=np.tile([1.0, 0.0, -9.80665], (11, 1)), kind="rates", rate=10)
    >>> s = navigate(sig, [1.0, 0.0, 0.0, 0.0])
    >>> s.algorithm, round(float(s.velocity[-1, 0]), 12), round(float(s.position[-1, 0]), 12)
    ('magnus6', 1.0, 0.5)
    """
    if not isinstance(signals, ImuSignals):
        raise ImunavError(f"signals must be ImuSignals, got {type(signals).__name__}")
    q0 = quat_normalize(as_float_array(q0, "q0", ndim=1, last=4), "q0")
    v0 = as_float_array(v0, "v0", ndim=1, last=3)
    p0 = as_float_array(p0, "p0", ndim=1, last=3)
    if earth == "wgs84" and g is not None:
        raise ImunavError("g belongs to the flat frame: on the WGS-84 Earth gravity comes from "
                          "the normal gravity model", argument="g")
    g = signals.g if g is None else check_gravity(g)
    algo = resolve(signals.kind, algorithm)
    if len(signals) < algo.min_samples:
        raise ImunavError(f"{signals.kind} signals need at least {algo.min_samples} samples, "
                          f"got {len(signals)}")
    nav = StreamNavigator(signals.kind, signals.rate, q0, v0, p0, g, algorithm=algo.name,
                          t0=signals.t0, earth=earth, hold=hold)
    q, v, p = collect(nav, signals.gyro, signals.accel, q0, v0, p0)
    return States(signals.state_times(), p, v, q, algo.name, frame=earth)


def navigate_batch(kind: str, gyro: FloatArray, accel: FloatArray, rate: float,
                   q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike, g: float = G0, *,
                   algorithm: str | None = None, earth: str = "flat", t0: float = 0.0,
                   hold=None) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Integrate R runs at once (as Monte Carlo does), as :func:`navigate` does one.

    Parameters
    ----------
    kind : {"rates", "increments"}
        The signal kind.
    gyro : ndarray, shape (N, R, 3)
        ω_b (rad/s) or Δθ (rad) of every run.
    accel : ndarray, shape (N, R, 3)
        f_b (m/s²) or Δv (m/s) of every run.
    rate : float
        Sample rate (Hz), > 0.
    q0 : array_like, shape (4,) or (R, 4)
        Initial attitude ``q_nb``, the same for every run or one per run.
    v0, p0 : array_like, shape (3,) or (R, 3)
        Initial velocity (m/s) and position (m), NED (on the Earth: Earth-relative local-NED
        velocity and ``[lat, lon, h]`` in rad, rad, m).
    g : float, default G0
        Gravity magnitude (m/s²) of the flat frame.
    algorithm : str, optional
        A name from ``ALGORITHMS[kind]``; default the most accurate.
    earth : {"flat", "wgs84"}, default "flat"
        The navigation frame.
    t0 : float, default 0.0
        Start time (s).
    hold : callable, optional
        On the Earth only: the vertical-channel hold of :func:`navigate`.

    Returns
    -------
    q : ndarray, shape (N + 1 or N, R, 4)
        ``q_nb`` at the state times (N + 1 for increments, N for rates), from the initial one.
    v : ndarray, shape (N + 1 or N, R, 3)
        Velocity (m/s).
    p : ndarray, shape (N + 1 or N, R, 3)
        Position (m, or ``[lat, lon, h]`` on the Earth).

    Raises
    ------
    ImunavError
        If ``kind`` or ``algorithm`` is unknown; ``gyro`` or ``accel`` is not a finite
        (N, R, 3) array or their shapes differ; there are fewer samples than the algorithm
        needs; an initial state has the wrong shape; ``rate``, ``g``, ``earth`` or ``hold`` is
        refused as by :class:`StreamNavigator`; or the navigation becomes non-finite.

    Examples
    --------
    >>> import numpy as np
    >>> dv = np.tile([0.1, 0.0, -0.980665], (10, 2, 1))       # 2 runs, 1 m/s² north, 1 s
    >>> q, v, p = navigate_batch("increments", np.zeros((10, 2, 3)), dv, 10,
    ...                          [1.0, 0, 0, 0], [0.0, 0, 0], [0.0, 0, 0])
    >>> q.shape, p[-1, :, 0].round(12)
    ((11, 2, 4), array([0.5, 0.5]))
    """
    algo = resolve(kind, algorithm)
    gyro = as_float_array(gyro, "gyro", ndim=3, last=3)
    accel = as_float_array(accel, "accel", ndim=3, last=3)
    if accel.shape != gyro.shape:
        raise ImunavError(f"accel must have the shape of gyro {gyro.shape}, got {accel.shape}")
    if gyro.shape[0] < algo.min_samples:
        raise ImunavError(f"{kind} signals need at least {algo.min_samples} samples")
    R = gyro.shape[1]
    q0 = np.ascontiguousarray(np.broadcast_to(quat_normalize(as_float_array(q0, "q0", last=4), "q0"),
                                              (R, 4)))
    v0 = np.ascontiguousarray(np.broadcast_to(as_float_array(v0, "v0", last=3), (R, 3)))
    p0 = np.ascontiguousarray(np.broadcast_to(as_float_array(p0, "p0", last=3), (R, 3)))
    nav = StreamNavigator(kind, rate, q0, v0, p0, g, algorithm=algo.name, runs=R, earth=earth,
                          t0=t0, hold=hold)
    return collect(nav, gyro, accel, q0, v0, p0)


def navigate_chunks(kind: str, rate: float, chunks: Iterable[tuple[FloatArray, FloatArray, FloatArray]],
                    q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike, g: float = G0, *,
                    algorithm: str | None = None, t0: float = 0.0, earth: str = "flat"
                    ) -> Iterator[States]:
    """Navigate signals that arrive in pieces, in bounded memory: what ``imunav navigate``
    streams from a CSV of any length.

    Parameters
    ----------
    kind : {"rates", "increments"}
    rate : float
        Sample rate (Hz).
    chunks : iterable of (t, gyro, accel)
        Consecutive pieces of the signals (``t`` (n,), ``gyro``/``accel`` (n, 3)), as
        :meth:`imunav.io.files.SignalFile.chunks` reads them.
    q0 : array_like, shape (4,)
        Initial attitude ``q_nb`` at ``t0`` (normalised).
    v0, p0 : array_like, shape (3,)
        Initial velocity (m/s) and position (m).
    g : float
        Gravity magnitude (m/s²).
    algorithm : str, optional
        A name from ``ALGORITHMS[kind]``; default the most accurate.
    t0 : float
        Start time (s): the first sample for rates, the start of the first interval for
        increments.
    earth : {"flat", "wgs84"}
        The navigation frame (as :func:`navigate`; on the Earth ``p0 = [lat, lon, h]`` and
        ``g`` is not used).

    Yields
    ------
    States
        First the initial state at ``t0``, then the navigated states in order as they complete,
        each with its time.

    Raises
    ------
    ImunavError
        For an unknown kind or algorithm, too few samples, or a navigation that turns
        non-finite.
    """
    algo = resolve(kind, algorithm)
    q0, v0, p0 = (np.asarray(a, dtype=float) for a in (q0, v0, p0))
    nav = StreamNavigator(kind, rate, q0, v0, p0, g, algorithm=algo.name, t0=t0, earth=earth)
    yield States(np.array([float(t0)]), p0[None], v0[None], (q0 / np.linalg.norm(q0))[None],
                 algo.name, frame=earth)
    times: deque[float] = deque()                    # times of the nodes still to come out
    skip = 1 if kind == "rates" else 0               # a rate signal's first sample is node 0
    fed = 0

    def out(parts):
        """The completed nodes as States, each with its time."""
        for q, v, p in parts:
            t = np.array([times.popleft() for _ in range(len(q))])
            yield States(t, p, v, q, algo.name, frame=earth)

    for t, gyro, accel in chunks:
        times.extend(np.asarray(t)[skip:].tolist())
        skip = 0
        fed += len(t)
        yield from out(nav.feed(gyro, accel))
    if fed < algo.min_samples:
        raise ImunavError(f"{kind} signals need at least {algo.min_samples} samples, got {fed}")
    yield from out(nav.finish())
