"""Monte Carlo of simulate → navigate with sensor errors.

The ideal signals are simulated once (at the sensor's internal rate if it has one); every run
adds its own errors from its own random stream (``SeedSequence(seed).spawn(runs)[r]``) and all
runs of a chunk are navigated together, vectorised across runs, through the algorithm registry
(:func:`imunav.strapdown.registry.navigate_batch`; the default algorithm for the signal kind
unless one is named). Chunks are independent tasks: locally they run in turn with a progress
bar; with ``scheduler=ADDRESS`` they are sent to a Dask cluster (``imunav[dask]``). Each chunk
runs with one BLAS thread unless the caller chose otherwise (:mod:`imunav.core.threads`; on a
Dask worker, its own ``IMUNAV_BLAS_THREADS`` or ``set_blas_threads``).

With ``alignment="level"`` every run starts from its own levelled attitude: the IMU rests at
the motion's initial attitude for ``align_window`` seconds before ``t = 0`` (the ideal signals
of rest are prepended, so each run's errors run on from the window into the motion), and roll and
pitch come from that run's mean measured specific force over the window
(:func:`imunav.strapdown.initial.level_attitude`, the heading given) — what
:mod:`imunav.estimation.alignment` models in the covariance analysis.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.strapdown``, ``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import beta

from imunav.core.constants import G0
from imunav.core.deprecation import renamed
from imunav.core.resources import check_memory
from imunav.core.rotations import FloatArray, quat_to_dcm, quat_to_euler
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, check_int, check_positive
from imunav.earth import ned_difference
from imunav.estimation.alignment import WINDOW, check_alignment, window_samples
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.simulate import interval_count, simulate_imu
from imunav.strapdown.initial import level_attitude
from imunav.strapdown.registry import navigate_batch


@dataclass
class MonteCarloResult:
    """Per-run error histories at the output times ``t`` (runs × samples): what
    :func:`monte_carlo` returns.

    Attributes
    ----------
    t : ndarray, shape (N,)
        The output state times (s), from the initial state.
    position : ndarray, shape (R, N)
        Each run's position error norm ``|Δr|`` (m; on the WGS-84 Earth the distance in local
        NED).
    velocity : ndarray, shape (R, N)
        Each run's velocity error norm ``|Δv|`` (m/s).
    attitude : ndarray, shape (R, N)
        Each run's attitude error angle (rad).
    saturated : ndarray of int, shape (R,)
        Output samples clipped at the sensor's range in each run.
    model : str
        The IMU model's name.
    rate : float
        Output rate (Hz).
    kind : {"rates", "increments"}
        The signal kind.
    horizontal : ndarray, shape (R, N), optional
        On the WGS-84 Earth: the north–east position error norm (m); None on the flat frame.
    """

    t: FloatArray
    position: FloatArray     # |Δr| (m)
    velocity: FloatArray     # |Δv| (m/s)
    attitude: FloatArray     # angle (rad)
    saturated: np.ndarray    # clipped output samples per run
    model: str
    rate: float
    kind: str
    horizontal: FloatArray | None = None   # on the Earth: |Δr| north–east (m)
    alignment: str = "truth"

    @property
    def runs(self) -> int:
        """The number of runs R."""
        return self.position.shape[0]

    def envelope(self, key: str = "position", q=(50, 68, 95)) -> dict[int, FloatArray]:
        """Percentile envelopes of an error over the runs, vs time.

        Parameters
        ----------
        key : {"position", "velocity", "attitude", "horizontal"}, default "position"
            The error (``"horizontal"`` on the WGS-84 Earth only).
        q : sequence of float, default (50, 68, 95)
            Percentiles (0–100).

        Returns
        -------
        dict
            Percentile → ndarray of shape (N,) (the error's unit: m, m/s or rad).
        """
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
    align : int
        Output samples of rest before the motion that each run levels from (0: every run
        starts from the true attitude); ``gyro``/``accel`` then begin with their ideal signals.
    yaw0 : float
        The heading the levelling is given (rad).
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
    align: int = 0
    yaw0: float = 0.0

    def hold(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The true heights and down velocities at the state times ``t`` (the perfect height
        aid of ``vertical="hold"``), from the truth at the output times."""
        k = np.rint(t * self.rate).astype(int)               # the states are at k / rate
        return self.truth_p[k, 2], self.truth_v[k, 2]


@limit_blas
def _mc_chunk(task: MonteCarloTask, seeds) -> tuple:
    """One chunk of runs (module-level and picklable: a Dask task)."""
    G, A, S, Q0 = [], [], [], []
    n = task.align
    for ss in seeds:
        gm, am, flags = measure(task.model, task.gyro, task.accel, task.kind, task.sim_rate,
                                np.random.default_rng(ss), task.decimate)
        if n:                   # level from this run's window, then navigate what follows
            f = am[:n].mean(axis=0) * (task.rate if task.kind == "increments" else 1.0)
            Q0.append(level_attitude(f, task.g, tol=0.5, yaw=task.yaw0))
            gm, am = gm[n:], am[n:]
        G.append(gm)
        A.append(am)
        S.append(int(flags.sum()))
    # (N, R, 3) views of run-contiguous stacks: one contiguous copy per run instead of a
    # strided one (the navigation copies its stencil windows contiguous anyway)
    G = np.stack(G).transpose(1, 0, 2)
    A = np.stack(A).transpose(1, 0, 2)
    q0 = np.array(Q0) if n else task.truth_q[0]
    q, v, p = navigate_batch(task.kind, G, A, task.rate, q0, task.truth_v[0],
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


@renamed(model="imu", output="kind")
def monte_carlo(motion: BaseMotion, imu: ImuModel, rate: float, duration: float | None = None,
                runs: int = 100, seed: int = 0, kind: str = "increments", g: float = G0,
                chunk: int | None = None, progress: bool = True,
                scheduler: str | None = None, algorithm: str | None = None,
                vertical: str = "free", *, alignment: str = "truth",
                align_window: float = WINDOW) -> MonteCarloResult:
    """Simulate a sensor on a motion many times with independent errors and navigate each run
    back from the true initial state.

    Reproducible bit for bit for a given ``seed`` (whatever ``chunk`` or ``scheduler``); run 0
    is what :func:`~imunav.sensors.simulate.simulate_imu` gives for the same seed.

    Parameters
    ----------
    motion : BaseMotion
        The truth (flat, or an :class:`~imunav.motion.geodetic.EarthMotion` on WGS-84).
    imu : ImuModel
        The sensor's errors.
    rate : float
        Output sample rate (Hz), > 0.
    duration : float, optional
        Seconds; default the motion's own.
    runs : int, default 100
        Number of runs, ≥ 1.
    seed : int, default 0
        Random seed, ≥ 0 (run r draws from ``SeedSequence(seed).spawn(runs)[r]``).
    kind : {"increments", "rates"}, default "increments"
        The signal kind.
    g : float, default G0
        Gravity magnitude (m/s²) of the flat frame.
    chunk : int, optional
        Runs navigated together; default sized to about 2e6 samples.
    progress : bool, default True
        Show a progress bar on long runs.
    scheduler : str, optional
        The address of a Dask scheduler to send the chunks to (needs ``imunav[dask]``).
    algorithm : str, optional
        The strapdown algorithm; default the registry's most accurate for ``kind``.
    vertical : {"free", "hold"}, default "free"
        On the WGS-84 Earth: hold each run's vertical channel at the true height (a perfect
        height aid).
    alignment : {"truth", "level"}, default "truth"
        The initial attitude of each run: the truth, or levelled from the run's own
        accelerometer output at rest over ``align_window`` seconds before the motion
        (:mod:`imunav.estimation.alignment`; flat frame only; the heading is given).
    align_window : float, default WINDOW
        The levelling window (s), > 0.

    Returns
    -------
    MonteCarloResult

    Raises
    ------
    ImunavError
        If ``vertical`` is unknown, or ``"hold"`` for a flat motion; ``rate`` or the duration
        is not a finite number > 0; ``runs`` is not an integer ≥ 1 or ``seed`` not one ≥ 0;
        the runs would not fit in memory; ``scheduler`` is given without dask installed; or
        for the reasons of the simulation and the navigation (an unknown ``kind`` or
        ``algorithm``, …).
        Also if ``alignment`` is not ``"truth"`` or ``"level"``, ``align_window`` is not
        a finite number > 0, or ``"level"`` is asked on the WGS-84 Earth.

    Examples
    --------
    An accelerometer bias of σ = 0.01 m/s² per axis, at rest for 10 s: the final position
    error is 0.5 m × a χ₃ variable, whose median is 0.5 m × 1.538:

    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> mc = monte_carlo(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)), rate=10,
    ...                  runs=400, progress=False)
    >>> mc.runs, mc.position.shape
    (400, (400, 101))
    >>> bool(abs(mc.envelope(q=(50,))[50][-1] / (0.5 * 1.5382) - 1) < 0.05)
    True
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
    alignment, align_window = check_alignment(alignment, align_window, motion.frame)
    duration = span(motion, rate, duration)
    k = imu.decimation(rate)
    n = interval_count(rate, duration)
    n_align = window_samples(rate, align_window) if alignment == "level" else 0
    chunk = chunk or max(1, min(runs, int(2e6 // max(n, 1))))
    # ideal signals at the internal rate, the per-run histories, one chunk's working set
    need = 8 * (6 * ((n + n_align) * k + 1) + 3 * runs * (n + 1)
                + 40 * chunk * (n + n_align + 1) * min(k, 4))
    check_memory(need, f"{runs:,} Monte Carlo runs of {n:,} samples (internal rate "
                       f"{rate * k:g} Hz)")
    sim = simulate_imu(motion, rate * k, duration, kind=kind, g=g)
    n_out = len(sim) // k if kind == "increments" else (len(sim) - 1) // k + 1
    t = np.arange(n_out + (1 if kind == "increments" else 0)) / rate
    truth_q, truth_v, truth_p = motion.attitude(t), motion.velocity(t), motion.position(t)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    parts = [seeds[i:i + chunk] for i in range(0, runs, chunk)]
    gyro, accel, yaw0 = sim.gyro, sim.accel, 0.0
    if n_align:                 # the ideal signals of rest at the initial attitude come first
        rest = quat_to_dcm(truth_q[0]).T @ np.array([0.0, 0.0, -g])
        if kind == "increments":
            rest = rest / (rate * k)
        gyro = np.concatenate([np.zeros((n_align * k, 3)), gyro])
        accel = np.concatenate([np.tile(rest, (n_align * k, 1)), accel])
        yaw0 = float(quat_to_euler(truth_q[0])[0])
    task = MonteCarloTask(gyro, accel, kind, rate * k, k, imu, rate, g, truth_q,
                          truth_v, truth_p, algorithm, motion.frame, vertical, n_align, yaw0)
    results = run_chunks(_mc_chunk, task, [(part,) for part in parts], scheduler=scheduler,
                         bar=_progress(len(parts), runs * n_out, progress))
    pos, vel, att, sat = (np.concatenate([r[i] for r in results]) for i in range(4))
    hor = None if results[0][4] is None else np.concatenate([r[4] for r in results])
    return MonteCarloResult(t, pos, vel, att, sat, imu.name, rate, kind, hor, alignment)


#: Samples above which a Monte Carlo always shows its bar; below, on a terminal, the bar
#: appears once the run has taken :data:`PROGRESS_DELAY` seconds (a shared machine can make
#: 1e6 samples take tens of seconds).
PROGRESS_WORK = 5e6
PROGRESS_DELAY = 2.0


def run_chunks(func, task, parts: list[tuple], *, scheduler: str | None = None,
               workers: int | None = None, bar=None, progress: bool = False,
               total: int | None = None, desc: str = "Monte Carlo", unit: str = "run") -> list:
    """``func(task, *part)`` for every part, in order — here, on a Dask cluster at
    ``scheduler``, or on ``workers`` local processes (a Dask ``LocalCluster``): the one
    dispatcher of imunav's Monte Carlo runs. The parts are fixed by the caller, so the results
    are the same wherever they run.

    Parameters
    ----------
    func : callable
        A module-level function (it is sent to other processes).
    task : object
        What every part shares (picklable).
    parts : list of tuple
        The other arguments of each call.
    scheduler : str, optional
        A Dask scheduler's address.
    workers : int, optional
        Local worker processes (a ``LocalCluster``; ``imunav[dask]``).
    bar : tqdm, optional
        Updated by one per part (local runs).
    progress : bool
        Without ``bar``: a bar of ``total`` items (each part's first argument's length).
    total : int, optional
    desc, unit : str
        The bar's words.

    Returns
    -------
    list
        The results of the parts, in order.

    Raises
    ------
    ImunavError
        For ``scheduler`` or ``workers`` without dask installed, or both given.
    """
    if scheduler and workers:
        raise ImunavError("give scheduler or workers, not both", argument="workers")
    if scheduler or (workers and workers > 1):
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise ImunavError("scheduler and workers need the dask extra: pip install "
                              "'imunav[dask]'", argument="scheduler" if scheduler else
                              "workers") from None
        if scheduler:
            with Client(scheduler) as client:
                return client.gather([client.submit(func, task, *p, pure=False)
                                      for p in parts])
        import dask

        # Dask's nanny starts its workers with MALLOC_TRIM_THRESHOLD_=65536, which also fixes
        # glibc's mmap threshold at 128 kB: every temporary of a chunk (a 100-run covariance
        # is 1.4 MB) is then mapped, zeroed and unmapped anew — measured 1.7× slower per
        # chunk (44 s against 26 s for 100 filter runs). Our workers keep glibc's defaults.
        with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_":
                              None}), \
                LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                             dashboard_address=None) as cluster, Client(cluster) as client:
            fut = client.scatter(task, broadcast=True)
            return client.gather([client.submit(func, fut, *p, pure=False) for p in parts])
    own = None
    if bar is None and progress and len(parts) > 1:
        from tqdm.auto import tqdm
        own = tqdm(total=total or len(parts), desc=desc, unit=unit)
    results = []
    for p in parts:
        results.append(func(task, *p))
        if bar is not None:
            bar.update(1)
        if own is not None:
            own.update(len(p[0]) if total else 1)
    for b in (bar, own):
        if b is not None:
            b.close()
    return results


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


# ------------------------------------------------------- intervals of Monte Carlo answers

#: Runs of the Monte Carlo that ``method="auto"`` falls back to (when no ``runs`` is given).
AUTO_RUNS = 200

#: The confidence of the interval on a Monte Carlo fraction (:func:`runs_interval`).
CONFIDENCE = 0.95


def runs_interval(inside: int, runs: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The Clopper–Pearson interval of a fraction of runs: exact (conservative) for ``inside``
    successes in ``runs`` Bernoulli trials.

    Parameters
    ----------
    inside, runs : int
        Runs within the tolerance, and all runs (≥ 1).
    confidence : float
        Two-sided.

    Returns
    -------
    lo, hi : float
    """
    a = (1 - confidence) / 2
    lo = 0.0 if inside == 0 else float(beta.ppf(a, inside, runs - inside + 1))
    hi = 1.0 if inside == runs else float(beta.ppf(1 - a, inside + 1, runs - inside))
    return lo, hi
