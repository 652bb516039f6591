"""The one navigation driver, :class:`StreamNavigator`: it integrates chunks of intervals in
turn, each with the samples around it that the algorithm needs as context (its ``context``:
two-sample corrections look one sample back, polynomial stencils a few both ways), carrying the
state from chunk to chunk — flat, or on the rotating Earth through
:class:`~imunav.strapdown.rotating.EarthIntegrator`. So a recording of any length is navigated
in bounded memory; :mod:`imunav.strapdown.registry` feeds it all samples at once
(:func:`~imunav.strapdown.registry.navigate`), many runs (``navigate_batch``) or pieces as they
arrive (``navigate_chunks``).

May import: ``imunav.core``, ``imunav.strapdown.algorithms``, ``imunav.strapdown.rotating``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray, quat_normalize
from imunav.core.validation import ImunavError, check_gravity, check_positive
from imunav.strapdown.algorithms import resolve
from imunav.strapdown.rotating import EarthIntegrator

__all__ = ["CHUNK", "EARTH_CHUNK_SECONDS", "EARTHS", "StreamNavigator", "collect"]

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
    chunk : int, optional
        Intervals × runs per chunk; default :data:`CHUNK` (read when the navigator is made).
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
                 algorithm: str | None = None, runs: int | None = None, chunk: int | None = None,
                 t0: float = 0.0, earth: str = "flat", hold=None):
        self.algo = resolve(kind, algorithm)
        self.t0 = float(t0)
        self.h = 1.0 / check_positive(rate, "rate")
        if earth not in EARTHS:
            raise ImunavError(f"earth must be one of {EARTHS}, got {earth!r}", argument="earth")
        self.own = 1 if kind == "rates" else 0           # an interval's own samples beyond k
        before, after = self.algo.context
        self.before, self.after = before, after
        per = max(1, (CHUNK if chunk is None else chunk) // max(1, runs or 1))
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


def collect(nav: StreamNavigator, gyro, accel, q0, v0, p0) -> tuple[FloatArray, ...]:
    """All samples at once through the driver, a chunk at a time, into preallocated arrays.

    Parameters
    ----------
    nav : StreamNavigator
        A fresh navigator.
    gyro, accel : ndarray, shape (N, 3) or (N, R, 3)
        The samples.
    q0, v0, p0 : ndarray
        The initial state the navigator started from (the first row of the output).

    Returns
    -------
    q, v, p : ndarray
        The states at every node from the initial one.
    """
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
