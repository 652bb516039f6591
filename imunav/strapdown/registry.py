"""The algorithm registry and the one entry point that navigates: :func:`navigate` (one run, an
:class:`~imunav.sensors.signals.ImuSignals`) and :func:`navigate_batch` (many runs at once,
as Monte Carlo uses it).

Every algorithm is a row of :data:`ALGORITHMS` with its signal kind, its order (the measured
global convergence order of the attitude, velocity and position errors on smooth motion — see
``tests/test_strapdown.py``), its source and whether it is causal. :data:`DEFAULT_ALGORITHM`
names the most accurate one per kind; every caller that does not choose goes through it.

All navigation goes through one driver, :class:`StreamNavigator`: it integrates chunks of
intervals in turn, each with the samples around it that the algorithm needs as context (its
``context``: two-sample corrections look one sample back, polynomial stencils a few both
ways), carrying the state from chunk to chunk. So a recording of any length is navigated in
bounded memory (the command line feeds it from the CSV as it reads), and the in-memory
:func:`navigate` is the same code with all samples fed at once.

May import: ``imunav.core``, ``imunav.sensors.signals``, ``imunav.strapdown`` modules below.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray, quat_normalize
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array, check_gravity, check_positive
from imunav.sensors.signals import KINDS, ImuSignals
from imunav.strapdown import classic
from imunav.strapdown.highorder import navigate_poly
from imunav.strapdown.rotating import EarthIntegrator

__all__ = ["ALGORITHMS", "Algorithm", "DEFAULT_ALGORITHM", "EARTH_CHUNK_SECONDS", "EARTHS",
           "StreamNavigator", "navigate", "navigate_batch", "navigate_chunks", "resolve"]

#: The navigation frames: the flat, non-rotating NED frame, or the rotating WGS-84 Earth
#: (:mod:`imunav.strapdown.rotating`).
EARTHS = ("flat", "wgs84")
#: On the Earth the body-frame algorithm runs on pieces of at most this many seconds, with the
#: gravitation at the piece's start as a constant gravity (``StreamNavigator._gravity``): its
#: thrust sums then grow only with the change of gravity, ~0.4 m/s² over 10 minutes as the
#: Earth turns, not like g·t, so that their rounding stays near 1e-13 m/s (the vertical
#: channel amplifies velocity errors ~1.6e5 s over an hour). Measured, an hour at rest at
#: 100 Hz: the same errors, to 1 %, with pieces of 64 to 512 s (with g = 0 in the sums 64 s
#: pieces were needed and still gave twice the height error). 640 s: 20 of the integrator's
#: 32 s blocks.
EARTH_CHUNK_SECONDS = 640.0


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
        measured in ``tests/test_strapdown.py``).
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


#: Intervals × runs per chunk of the driver (the working set of one chunk stays small).
CHUNK = 1 << 16


class StreamNavigator:
    """Navigate samples fed in pieces of any size; states come out chunk by chunk.

    :meth:`feed` takes the next samples and returns the states completed so far;
    :meth:`finish` integrates what is left. The initial state (node 0) is not returned.
    Memory: the samples of about two chunks.

    Parameters
    ----------
    kind : {"rates", "increments"}
        The signal kind.
    rate : float
        Sample rate (Hz), > 0.
    q0 : array_like, shape (4,) or (R, 4)
        Initial attitude ``q_nb`` (normalised; on the Earth relative to local NED).
    v0, p0 : array_like, shape (3,) or (R, 3)
        Initial velocity (m/s) and position (m), NED; on the Earth the velocity relative to
        the Earth in local NED and ``p0 = [lat, lon, h]`` (rad, rad, m).
    g : float, default G0
        Gravity magnitude (m/s²) of the flat frame (not used on the Earth).
    algorithm : str, optional
        A name from ``ALGORITHMS[kind]``; default the most accurate.
    runs : int, optional
        R, the runs fed at once (sizes the chunks); default 1.
    chunk : int, default CHUNK
        Intervals × runs per chunk.
    t0 : float, default 0.0
        Start time (s).
    earth : {"flat", "wgs84"}, default "flat"
        The navigation frame (see :func:`navigate`).
    hold : callable, optional
        On the Earth only: ``hold(t) → (h, v_d)`` to hold the vertical channel (see
        :func:`navigate`).

    Raises
    ------
    ImunavError
        If ``kind`` or ``algorithm`` is unknown, ``rate`` is not a finite number > 0, ``earth``
        is not in :data:`EARTHS`, ``hold`` is given on the flat frame, or ``g`` is not a
        valid gravity; later, from :meth:`feed` or :meth:`finish`, if the navigation becomes
        non-finite (signals far too large: wrong units).

    Examples
    --------
    >>> import numpy as np
    >>> nav = StreamNavigator("increments", 10, [1.0, 0, 0, 0], np.zeros(3), np.zeros(3))
    >>> dv = np.tile([0.1, 0.0, -0.980665], (10, 1))          # 1 m/s² north for 1 s
    >>> nav.feed(np.zeros((10, 3)), dv)                       # too little for a chunk yet
    []
    >>> (q, v, p), = nav.finish()
    >>> q.shape, round(float(p[-1, 0]), 12)
    ((10, 4), 0.5)
    """

    def __init__(self, kind: str, rate: float, q0, v0, p0, g: float = G0, *,
                 algorithm: str | None = None, runs: int | None = None, chunk: int = CHUNK,
                 t0: float = 0.0, earth: str = "flat", hold=None):
        self.algo = resolve(kind, algorithm)
        self.t0 = float(t0)
        self.h = 1.0 / check_positive(rate, "rate")
        if earth not in EARTHS:
            raise ImunavError(f"earth must be one of {EARTHS}, got {earth!r}", argument="earth")
        self.own = 1 if kind == "rates" else 0           # an interval's own samples beyond k
        before, after = self.algo.context
        self.before, self.after = before, after
        per = max(1, chunk // max(1, runs or 1))
        if earth == "wgs84":
            # the body-frame algorithm in the inertial frame, without gravity (EarthIntegrator)
            self.earth = EarthIntegrator(self.h, self.t0, q0, v0, p0, hold=hold)
            zero = np.zeros(np.shape(v0))
            self.state, self.g = (self.earth.q_ib, zero, zero), 0.0
            per = min(per, max(1, int(EARTH_CHUNK_SECONDS * rate)))
        else:
            if hold is not None:
                raise ImunavError("hold applies to earth='wgs84' only (the flat frame has no "
                                  "vertical instability)", argument="hold")
            self.earth = None
            self.g = check_gravity(g)
            self.state = (q0, v0, p0)
        self.chunk = max(self.algo.align, per // self.algo.align * self.algo.align)
        self.buf_g: list[np.ndarray] = []
        self.buf_a: list[np.ndarray] = []
        self.buf_start = 0          # global index of the first buffered sample
        self.buf_len = 0
        self.next = 0               # next interval to integrate
        self.total = 0              # samples fed so far

    def _gravity(self):
        """The gravity the body-frame algorithm runs with over the next chunk: the flat frame's
        ``g``; on the Earth the inertial gravitation at the current position, held constant:
        the algorithm's thrust sums then stay near the change of gravity over the chunk instead
        of growing like g·t, and :meth:`EarthIntegrator.advance` takes it out exactly."""
        return self.g if self.earth is None else self.earth.hist[-1].copy()

    def _window(self, w0: int, w1: int) -> tuple[np.ndarray, np.ndarray]:
        g = np.concatenate(self.buf_g) if len(self.buf_g) > 1 else self.buf_g[0]
        a = np.concatenate(self.buf_a) if len(self.buf_a) > 1 else self.buf_a[0]
        self.buf_g, self.buf_a = [g], [a]
        return g[w0 - self.buf_start: w1 - self.buf_start], a[w0 - self.buf_start: w1 - self.buf_start]

    def _step(self, lo: int, hi: int, end: int):
        w0 = max(0, lo - self.before)
        w1 = min(end, hi + self.own + self.after)
        g, a = self._window(w0, w1)
        gravity = self._gravity()
        with np.errstate(all="ignore"):                           # checked just below
            try:
                q, v, p = self.algo.func(g, a, self.h, *self.state, gravity, lo - w0, hi - lo)
            except ImunavError as exc:          # an internal array's check ("phi contains NaN")
                if "NaN or inf" not in str(exc):
                    raise
                big = float(max(np.abs(g).max(), np.abs(a).max()))
                raise ImunavError(
                    f"navigation became non-finite between t = {self.t0 + lo * self.h:.9g} and "
                    f"{self.t0 + hi * self.h:.9g} s: the signals are too large to integrate "
                    f"(up to {big:.3g} in SI units); check their units") from None
        # a NaN or inf propagates through every recursion to the chunk's last state
        if not (np.isfinite(q[-1]).all() and np.isfinite(v[-1]).all() and np.isfinite(p[-1]).all()):
            ok = (np.isfinite(q).all(axis=-1) & np.isfinite(v).all(axis=-1)
                  & np.isfinite(p).all(axis=-1))
            k = lo + int(np.argmin(ok.reshape(len(ok), -1).all(axis=1)))
            big = float(max(np.abs(g).max(), np.abs(a).max()))
            raise ImunavError(
                f"navigation became non-finite at t = {self.t0 + k * self.h:.9g} s: the signals "
                f"are too large to integrate (up to {big:.3g} in SI units); check their units")
        if self.earth is not None:
            zero = np.zeros_like(v[-1])
            self.state = (q[-1], zero, zero)
            out = self.earth.advance(q, v, p, gravity)
        else:
            self.state = (q[-1], v[-1], p[-1])
            out = q[1:], v[1:], p[1:]
        self.next = hi
        keep = max(self.buf_start, hi - self.before)               # drop what is not context
        if keep > self.buf_start:
            cut = keep - self.buf_start
            self.buf_g, self.buf_a = [self.buf_g[0][cut:]], [self.buf_a[0][cut:]]
            self.buf_start, self.buf_len = keep, self.buf_len - cut
        return out

    def feed(self, gyro: np.ndarray, accel: np.ndarray) -> list[tuple]:
        """Take the next samples; integrate every chunk they complete.

        Parameters
        ----------
        gyro : ndarray, shape (n, 3) or (n, R, 3)
            The next ω_b (rad/s) or Δθ (rad) samples, as the navigator's kind.
        accel : ndarray, shape (n, 3) or (n, R, 3)
            The next f_b (m/s²) or Δv (m/s) samples.

        Returns
        -------
        list of tuple
            ``(q, v, p)`` per chunk completed (possibly none): the states after the last ones
            returned, shapes (m, 4) and (m, 3) (or (m, R, …)); flat: ``q_nb``, velocity (m/s)
            and position (m) NED; on the Earth local-NED ``q_nb``, Earth-relative velocity and
            ``[lat, lon, h]`` (rad, rad, m).

        Raises
        ------
        ImunavError
            If the navigation becomes non-finite (signals far too large: wrong units).
        """
        self.buf_g.append(np.asarray(gyro, float))
        self.buf_a.append(np.asarray(accel, float))
        self.buf_len += len(gyro)
        self.total += len(gyro)
        out = []
        while self.next + self.chunk + self.own + self.after <= self.total:
            out.append(self._step(self.next, self.next + self.chunk, self.total))
        return out

    def finish(self) -> list[tuple]:
        """Integrate the samples left over after the last :meth:`feed`.

        Returns
        -------
        list of tuple
            ``(q, v, p)`` per chunk, as :meth:`feed` returns them, up to the last state.

        Raises
        ------
        ImunavError
            If the navigation becomes non-finite (signals far too large: wrong units).
        """
        out = []
        n_int = self.total - self.own
        while self.next < n_int:
            out.append(self._step(self.next, min(n_int, self.next + self.chunk), self.total))
        return out


def _collect(nav: StreamNavigator, gyro, accel, q0, v0, p0) -> tuple[FloatArray, ...]:
    """All samples at once through the driver, into preallocated arrays."""
    n_nodes = gyro.shape[0] + 1 - nav.own
    q = np.empty((n_nodes,) + np.shape(q0))
    v = np.empty((n_nodes,) + np.shape(v0))
    p = np.empty_like(v)
    q[0], v[0], p[0] = quat_normalize(q0, "q0"), v0, p0
    k = 1

    def store(parts):
        nonlocal k
        for qc, vc, pc in parts:
            m = qc.shape[0]
            q[k:k + m], v[k:k + m], p[k:k + m] = qc, vc, pc
            k += m

    for lo in range(0, gyro.shape[0], nav.chunk):        # a chunk at a time: bounded memory
        store(nav.feed(gyro[lo:lo + nav.chunk], accel[lo:lo + nav.chunk]))
    store(nav.finish())
    return q, v, p


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
    q, v, p = _collect(nav, signals.gyro, signals.accel, q0, v0, p0)
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
    return _collect(nav, gyro, accel, q0, v0, p0)


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
