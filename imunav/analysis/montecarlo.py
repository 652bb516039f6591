"""Monte Carlo of simulate → navigate with sensor errors.

The ideal signals are simulated once (at the sensor's internal rate if it has one); every run
adds its own errors from its own random stream (``SeedSequence(seed).spawn(runs)[r]``) and all
runs of a chunk are navigated together, vectorised across runs, through the algorithm registry
(:func:`imunav.strapdown.registry.navigate_batch`; the default algorithm for the signal kind
unless one is named). Chunks are independent tasks: locally they run in turn with a progress
bar; with ``scheduler=ADDRESS`` they are sent to a Dask cluster (``imunav[dask]``). Each chunk
runs with one BLAS thread unless the caller chose otherwise (:mod:`imunav.core.threads`; on a
Dask worker, its own ``IMUNAV_BLAS_THREADS`` or ``set_blas_threads``).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.strapdown``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.constants import G0
from imunav.core.resources import check_memory
from imunav.core.rotations import FloatArray
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, check_int, check_positive
from imunav.earth import ned_difference
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.simulate import interval_count, simulate_imu
from imunav.strapdown.registry import navigate_batch


@dataclass
class MonteCarloResult:
    """Per-run error histories at the output times ``t`` (runs × samples)."""

    t: FloatArray
    position: FloatArray     # |Δr| (m)
    velocity: FloatArray     # |Δv| (m/s)
    attitude: FloatArray     # angle (rad)
    saturated: np.ndarray    # clipped output samples per run
    model: str
    rate: float
    kind: str
    horizontal: FloatArray | None = None   # on the Earth: |Δr| north–east (m)

    @property
    def runs(self) -> int:
        return self.position.shape[0]

    def envelope(self, key: str = "position", q=(50, 68, 95)) -> dict[int, FloatArray]:
        """Percentile envelopes vs time (median, 68 %, 95 % by default)."""
        a = getattr(self, key)
        return {p: np.percentile(a, p, axis=0) for p in q}


@dataclass
class MonteCarloTask:
    """What every chunk of runs shares (sent once per chunk to a Dask worker).

    Attributes
    ----------
    gyro, accel : ndarray, shape (M, 3)
        The ideal signals at the sensor's internal rate.
    kind : {"rates", "increments"}
    sim_rate : float
        The internal rate (Hz) of ``gyro``/``accel``.
    decimate : int
        Internal samples per output sample.
    model : ImuModel
    rate : float
        Output rate (Hz).
    g : float
        Gravity magnitude (m/s²).
    truth_q, truth_v, truth_p : ndarray
        The true attitude (N, 4), velocity and position (N, 3) at the output states' times; the
        first rows are every run's initial state.
    algorithm : str or None
        The strapdown algorithm (None: the registry's default).
    earth : {"flat", "wgs84"}
        The navigation frame (the motion's): on the Earth positions are ``[lat, lon, h]`` and
        the position error is the distance in metres.
    vertical : {"free", "hold"}
        On the Earth: the vertical channel free, or held at the true height and vertical
        velocity (a perfect height aid).
    """

    gyro: FloatArray
    accel: FloatArray
    kind: str
    sim_rate: float
    decimate: int
    model: ImuModel
    rate: float
    g: float
    truth_q: FloatArray
    truth_v: FloatArray
    truth_p: FloatArray
    algorithm: str | None = None
    earth: str = "flat"
    vertical: str = "free"

    def hold(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The true heights and down velocities at the state times ``t`` (the perfect height
        aid of ``vertical="hold"``), from the truth at the output times."""
        k = np.rint(t * self.rate).astype(int)               # the states are at k / rate
        return self.truth_p[k, 2], self.truth_v[k, 2]


@limit_blas
def _mc_chunk(task: MonteCarloTask, seeds) -> tuple:
    """One chunk of runs (module-level and picklable: a Dask task)."""
    G, A, S = [], [], []
    for ss in seeds:
        gm, am, flags = measure(task.model, task.gyro, task.accel, task.kind, task.sim_rate,
                                np.random.default_rng(ss), task.decimate)
        G.append(gm)
        A.append(am)
        S.append(int(flags.sum()))
    # (N, R, 3) views of run-contiguous stacks: one contiguous copy per run instead of a
    # strided one (the navigation copies its stencil windows contiguous anyway)
    G = np.stack(G).transpose(1, 0, 2)
    A = np.stack(A).transpose(1, 0, 2)
    q, v, p = navigate_batch(task.kind, G, A, task.rate, task.truth_q[0], task.truth_v[0],
                             task.truth_p[0], task.g, algorithm=task.algorithm, earth=task.earth,
                             hold=task.hold if task.vertical == "hold" else None)
    truth_p, hor = task.truth_p, None
    if task.earth == "wgs84":            # [lat, lon, h] → metres from the truth, in local NED
        p = ned_difference(p, np.broadcast_to(truth_p[:, None], p.shape))
        truth_p = np.zeros_like(truth_p)
        hor = np.hypot(p[..., 0], p[..., 1]).T
    pos, vel, att = _run_errors(q, v, p, task.truth_q, task.truth_v, truth_p)
    return pos, vel, att, np.array(S), hor


#: Time rows per block of :func:`_run_errors` (its temporaries stay in the cache).
_ERR_ROWS = 64


def _run_errors(q, v, p, truth_q, truth_v, truth_p):
    """``|Δr|``, ``|Δv|`` and the attitude angle of every run (R, N+1) from states (N+1, R, ·)
    and the truth (N+1, ·): the arithmetic of ``np.linalg.norm(p − p_true, axis=−1)`` and
    ``_angle(q, q_true)`` written out per component (the same roundings, bit for bit), a block
    of rows at a time."""
    n, R = p.shape[:2]
    pos, vel, att = (np.empty((R, n)) for _ in range(3))
    for lo in range(0, n, _ERR_ROWS):
        hi = min(n, lo + _ERR_ROWS)
        for out, x, ref in ((pos, p, truth_p), (vel, v, truth_v)):
            d = x[lo:hi] - ref[lo:hi, None]                         # (rows, R, 3)
            s = d[..., 0] * d[..., 0]
            s += d[..., 1] * d[..., 1]
            s += d[..., 2] * d[..., 2]
            out[:, lo:hi] = np.sqrt(s).T
        a, b = q[lo:hi], truth_q[lo:hi, None]                       # d = a* ⊗ b
        aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
        bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
        dw = aw * bw + ax * bx + ay * by + az * bz
        dx = aw * bx - ax * bw - ay * bz + az * by
        dy = aw * by + ax * bz - ay * bw - az * bx
        dz = aw * bz - ax * by + ay * bx - az * bw
        nv = dx * dx
        nv += dy * dy
        nv += dz * dz
        np.sqrt(nv, out=nv)
        att[:, lo:hi] = (2 * np.arctan2(nv, np.abs(dw))).T
    return pos, vel, att


def monte_carlo(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
                runs: int = 100, seed: int = 0, output: str = "increments", g: float = G0,
                chunk: int | None = None, progress: bool = True,
                scheduler: str | None = None, algorithm: str | None = None,
                vertical: str = "free") -> MonteCarloResult:
    """``runs`` simulations of ``model`` on ``motion`` at ``rate`` Hz, each navigated back with
    ``algorithm`` (default: the registry's default for ``output``).

    Reproducible bit for bit for a given ``seed`` (whatever ``chunk`` or ``scheduler``). On the
    Earth (an :class:`~imunav.motion.geodetic.EarthMotion`) ``vertical="hold"`` holds each run's
    vertical channel at the true height (a perfect height aid).
    """
    if vertical not in ("free", "hold"):
        raise ImunavError(f"vertical must be 'free' or 'hold', got {vertical!r}",
                          argument="vertical")
    if vertical == "hold" and motion.frame != "wgs84":
        raise ImunavError("vertical='hold' applies to a motion on the WGS-84 Earth only",
                          argument="vertical")
    rate = check_positive(rate, "rate")
    runs = check_int(runs, "runs", 1)
    seed = check_int(seed, "seed", 0)
    duration = span(motion, rate, duration)
    k = model.decimation(rate)
    n = interval_count(rate, duration)
    chunk = chunk or max(1, min(runs, int(2e6 // max(n, 1))))
    # ideal signals at the internal rate, the per-run histories, one chunk's working set
    need = 8 * (6 * (n * k + 1) + 3 * runs * (n + 1) + 40 * chunk * (n + 1) * min(k, 4))
    check_memory(need, f"{runs:,} Monte Carlo runs of {n:,} samples (internal rate "
                       f"{rate * k:g} Hz)")
    sim = simulate_imu(motion, rate * k, duration, output=output, g=g)
    n_out = len(sim) // k if output == "increments" else (len(sim) - 1) // k + 1
    t = np.arange(n_out + (1 if output == "increments" else 0)) / rate
    truth_q, truth_v, truth_p = motion.attitude(t), motion.velocity(t), motion.position(t)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    parts = [seeds[i:i + chunk] for i in range(0, runs, chunk)]
    task = MonteCarloTask(sim.gyro, sim.accel, output, rate * k, k, model, rate, g, truth_q,
                          truth_v, truth_p, algorithm, motion.frame, vertical)
    if scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ImunavError("scheduler needs the dask extra: pip install 'imunav[dask]'",
                              argument="scheduler") from None
        with Client(scheduler) as client:
            futs = [client.submit(_mc_chunk, task, part, pure=False) for part in parts]
            results = client.gather(futs)
    else:
        results = []
        bar = _progress(len(parts), runs * n_out, progress)
        for part in parts:
            results.append(_mc_chunk(task, part))
            if bar is not None:
                bar.update(1)
        if bar is not None:
            bar.close()
    pos, vel, att, sat = (np.concatenate([r[i] for r in results]) for i in range(4))
    hor = None if results[0][4] is None else np.concatenate([r[4] for r in results])
    return MonteCarloResult(t, pos, vel, att, sat, model.name, rate, output, hor)


#: Samples above which a Monte Carlo always shows its bar; below, on a terminal, the bar
#: appears once the run has taken :data:`PROGRESS_DELAY` seconds (a shared machine can make
#: 1e6 samples take tens of seconds).
PROGRESS_WORK = 5e6
PROGRESS_DELAY = 2.0


def _interactive() -> bool:
    import sys

    return bool(getattr(sys.stderr, "isatty", lambda: False)())


def _progress(n_chunks: int, work: int, enabled: bool):
    """A tqdm bar (terminal or notebook) for long runs; on a terminal, for any run that
    lasts more than :data:`PROGRESS_DELAY` seconds."""
    if not enabled or n_chunks < 2:
        return None
    if work >= PROGRESS_WORK:
        from tqdm.auto import tqdm

        return tqdm(total=n_chunks, desc="Monte Carlo", unit="chunk")
    if not _interactive():
        return None
    from tqdm import tqdm

    return tqdm(total=n_chunks, desc="Monte Carlo", unit="chunk", delay=PROGRESS_DELAY)


