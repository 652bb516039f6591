"""Monte Carlo of the aided filter with known truth: the one driver of every aided Monte Carlo —
the error through an outage (:func:`aided_monte_carlo`) and the filter's consistency
(:func:`filter_monte_carlo`, the NEES).

Each run simulates the IMU's errors (its own stream, ``SeedSequence(seed).spawn(runs)[r]``, as
:func:`imunav.analysis.montecarlo.monte_carlo`) on the exact increments of the motion, the
aiding sensors' readings (their own streams, :func:`imunav.sensors.aids.aid_stream`) — and a
user's own measurements (:class:`~imunav.sensors.aids.Aid`: their readings drawn as the
model's prediction from the truth plus white noise of the model's ``R``) — and the real EKF
filters them from the true initial state (:func:`~imunav.estimation.filters.run_filter_batch`:
:data:`MC_CHUNK` runs at once, each with its own linearisation and gate). The chunks are fixed,
so the numbers are the same bit for bit locally and on a Dask cluster (``scheduler``).

At every covariance epoch the normalised estimation error squared (NEES) of position, velocity
and attitude is ``eᵀ P⁻¹ e`` with ``e`` the error against the exact motion (attitude: ``φ`` with
``C_est = (I − [φ×]) C``); for a consistent filter its average over ``R`` runs is
``χ²(3R)/R``. On the rotating Earth (``motion.frame == "wgs84"``) the position error is the
estimate's NED offset from the truth (metres, :func:`imunav.earth.ned_difference`) and the
covariances those of local NED the filter reports.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.estimation``, ``imunav.analysis.montecarlo``.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import chi2

from imunav.analysis.montecarlo import run_chunks
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray, quat_conj, quat_log, quat_mul
from imunav.core.layout import DP, DV, PHI
from imunav.core.validation import ImunavError, check_int, check_positive
from imunav.earth import ned_difference
from imunav.estimation.filters import FilterResult, run_filter_batch
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import Aid, AidingConfig, NavPoint, simulate_aiding
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import interval_count, simulate_imu

__all__ = ["BLOCKS", "MC_CHUNK", "AidedMonteCarlo", "FilterMonteCarlo", "aided_monte_carlo",
           "filter_monte_carlo", "nees", "nees_band", "simulate_readings"]

#: The NEES blocks and their rows of the navigation error.
BLOCKS = {"position": DP, "velocity": DV, "attitude": PHI}

#: Runs filtered at once (fixed: the chunks, and so the numbers, are the same on a Dask cluster,
#: on ``workers`` processes and locally). Measured (issue 39, the BMI088 on the 300 s example
#: drive with its GNSS outages and NHC, a busy 2-core Xeon with 2 MB of L2 per core): 1.25,
#: 0.83, 0.55, 0.76 s a run in chunks of 25, 50, 100, 200 — each epoch's Python work shared by
#: more runs, until a chunk's covariances (R·n² doubles: 1.4 MB at n = 42 for 100 runs) no
#: longer fit in a core's cache; 1000 runs are 10 chunks, five for each of two processes.
MC_CHUNK = 100

#: The random streams of a user's measurements, beside the registered aids' (their stream
#: numbers stay below it).
USER_STREAM = 100


def nees(result: FilterResult, motion: BaseMotion, skip: float = 0.0) -> dict[str, FloatArray]:
    """NEES of position, velocity and attitude at the covariance epochs after ``skip`` s.

    Parameters
    ----------
    result : FilterResult
        A filter's (or smoother's) result.
    motion : BaseMotion
        The truth.
    skip : float
        Seconds after the start left out (where the covariance starts near zero).

    Returns
    -------
    dict
        ``{"position" | "velocity" | "attitude": (E,) NEES}``, and ``"t"`` the epochs' times.
    """
    keep = result.t[result.epochs] >= result.t[0] + skip
    ep = result.epochs[keep]
    st = result.states
    out = _nees(st.quaternion[ep], st.velocity[ep], st.position[ep], result.P_nav[keep],
                motion, result.t[ep])
    out["t"] = result.t[ep]
    return out


def _nees(q, v, p, P, motion: BaseMotion, t: FloatArray) -> dict[str, FloatArray]:
    """NEES of states (E, [R,] ·) with covariances (E, [R,] 9, 9) against the truth at ``t``."""
    tr = motion.states(t)
    extra = (slice(None),) + (None,) * (q.ndim - 2)
    dp = (ned_difference(p, tr.position[extra]) if tr.frame == "wgs84"
          else p - tr.position[extra])
    err = {"position": dp, "velocity": v - tr.velocity[extra],
           "attitude": -quat_log(quat_mul(q, quat_conj(tr.quaternion[extra])))}
    return {k: np.einsum("...i,...i->...", e, np.linalg.solve(P[..., BLOCKS[k], BLOCKS[k]],
                                                               e[..., None])[..., 0])
            for k, e in err.items()}


def nees_band(runs: int, dof: int = 3, level: float = 0.95) -> tuple[float, float]:
    """The two-sided ``level`` band of the run-average NEES: ``χ²(dof·runs)/runs``.

    Parameters
    ----------
    runs : int
    dof : int
    level : float

    Returns
    -------
    tuple of float
    """
    a = (1 - level) / 2
    lo, hi = chi2.ppf([a, 1 - a], dof * runs) / runs
    return float(lo), float(hi)


def simulate_readings(aid: Aid, motion: BaseMotion, rng: np.random.Generator, g: float = G0
                      ) -> Aid:
    """A user's measurement read along the true motion: the model's prediction from the exact
    state at each of the aid's reading times, plus white noise of the model's ``R``.

    Parameters
    ----------
    aid : Aid
        The measurement model and its reading times (its values are not used).
    motion : BaseMotion
        The truth (flat frame).
    rng : numpy.random.Generator
    g : float

    Returns
    -------
    Aid
        The same model and times, the simulated readings.
    """
    m, t = aid.measurement, aid.t
    n = 9 + sum(s.size for s in m.states)
    st = motion.states(t)
    w = motion.angular_rate(t)
    pred = []
    for i in range(t.size):
        nav = NavPoint(st.quaternion[i], st.velocity[i], st.position[i], w[i], 0.0,
                       np.zeros(n), np.zeros((3, n)))
        if m.batched:
            nav = NavPoint(*(np.asarray(x)[None] for x in (nav.q, nav.v, nav.p, nav.omega)),
                           0.0, nav.estimates[None], nav.gyro_input[None])
            pred.append(np.asarray(m.predict(nav), float).reshape(m.size))
        else:
            pred.append(np.asarray(m.predict(nav), float).reshape(m.size))
    L = np.linalg.cholesky(np.asarray(m.noise(), float))
    noise = rng.standard_normal((t.size, m.size)) @ L.T
    return Aid(m, t, np.array(pred).reshape(t.size, m.size) + noise)


@dataclass
class AidedMonteCarlo:
    """What a Monte Carlo of the aided filter measured.

    Attributes
    ----------
    t : ndarray, shape (K,)
        The times the errors are kept at (IMU nodes, s).
    position_error : ndarray, shape (runs, K, 3)
        Estimate − truth (m, NED; on the Earth the NED offset from the truth).
    rejected : dict
        ``{aid: readings the χ² gate rejected, all runs}``.
    nees_t : ndarray, shape (E,)
        The epochs of the NEES (with ``nees``).
    filter, smoother : dict
        ``{block: (runs, E) NEES}`` of the filter (and the smoother).
    innovations : list of dict
        Per run, ``{aid: Innovations}`` (with ``innovations``).
    results : list of FilterResult
        The first ``keep`` runs' whole results.
    """

    t: FloatArray
    position_error: FloatArray
    rejected: dict
    nees_t: FloatArray = field(default_factory=lambda: np.zeros(0))
    filter: dict = field(default_factory=dict)
    smoother: dict = field(default_factory=dict)
    innovations: list = field(default_factory=list)
    results: list = field(default_factory=list)

    @property
    def runs(self) -> int:
        """Number of runs.

        Returns
        -------
        int
        """
        return int(self.position_error.shape[0])

    def p95(self) -> FloatArray:
        """The 95th percentile over runs of the position-error norm at each time (m).

        Returns
        -------
        ndarray, shape (K,)
        """
        return np.percentile(np.linalg.norm(self.position_error, axis=-1), 95, axis=0)


class _SharedTruth:
    """A motion whose values at given times are computed once and shared by every run of a
    chunk (each run's aids read the same truth at the same times, only their errors differ):
    ``attitude``, ``position``, ``velocity``, ``angular_rate`` and ``states`` remembered by
    their times (a copy returned each call: a caller may change it); anything else is the
    motion's own.

    Parameters
    ----------
    motion : BaseMotion
    """

    _MEMO = ("attitude", "position", "velocity", "angular_rate", "states")

    def __init__(self, motion: BaseMotion):
        self.motion = motion
        self._memo: dict = {}

    def __getattr__(self, name):
        attr = getattr(self.motion, name)
        if name not in self._MEMO:
            return attr

        def remembered(t, *args, **kw):
            ta = np.asarray(t, dtype=float)
            key = (name, ta.shape, ta.tobytes(), args, tuple(sorted(kw.items())))
            hit = self._memo.get(key)
            if hit is None:
                hit = self._memo[key] = attr(t, *args, **kw)
            return copy.deepcopy(hit)

        return remembered


@dataclass
class _Task:
    motion: BaseMotion
    imu: ImuModel
    aiding: AidingConfig
    rate: float
    duration: float
    seed: int
    algorithm: str | None
    covariance_step: float
    gyro: FloatArray
    accel: FloatArray
    t_ideal: FloatArray
    g: float
    nodes: np.ndarray
    measurements: list
    smooth: bool
    nees: bool
    skip: float
    innovations: bool
    keep: int


def _chunk(task: _Task, runs: list[int], seeds: list) -> dict:
    """Filter the runs ``runs`` (their IMU streams ``seeds``) at once."""
    k = task.imu.decimation(task.rate)
    m = task.motion
    shared = _SharedTruth(m)
    sigs, datas, users = [], [], []
    for r, s in zip(runs, seeds, strict=True):
        gm, am, _ = measure(task.imu, task.gyro, task.accel, "increments", task.rate * k,
                            np.random.default_rng(s), k)
        sigs.append(ImuSignals(task.t_ideal[k - 1::k][:gm.shape[0]], gm, am, "increments",
                               task.rate, task.g))
        datas.append(simulate_aiding(shared, task.aiding, task.duration, seed=task.seed, run=r,
                                     imu_rate=task.rate))
        users.append([simulate_readings(a, shared, np.random.default_rng(np.random.SeedSequence(
            task.seed, spawn_key=(0xA1D, r, USER_STREAM + i))), task.g)
            for i, a in enumerate(task.measurements)])
    st0 = m.states(np.array([0.0]))
    res = run_filter_batch(sigs, st0.quaternion[0], st0.velocity[0], st0.position[0],
                           task.aiding, datas, measurements=users, imu=task.imu,
                           algorithm=task.algorithm, covariance_step=task.covariance_step,
                           smooth=task.smooth and task.nees, earth=m.frame,
                           innovations=task.innovations,
                           keep=max(0, min(task.keep - runs[0], len(runs))))
    tn = res.t[task.nodes]
    truth = m.position(tn)[:, None, :]
    p = res.position[task.nodes]
    err = ned_difference(p, truth) if m.frame == "wgs84" else p - truth       # (K, R, 3)
    out = {"error": np.swapaxes(err, 0, 1),
           "rejected": {k2: int(v.sum()) for k2, v in res.rejected.items()},
           "innovations": res.innovations, "results": res.results}
    if task.nees:
        keep = res.t[res.epochs] >= res.t[0] + task.skip
        ep = res.epochs[keep]
        out["nees_t"] = res.t[ep]
        out["filter"] = {b: v.T for b, v in _nees(res.quaternion[ep], res.velocity[ep],
                                                    res.position[ep], res.P_nav[keep], m,
                                                    res.t[ep]).items()}
        if task.smooth:
            sm = res.smoothed
            out["smoother"] = {b: v.T for b, v in _nees(sm["quaternion"][ep], sm["velocity"][ep],
                                                        sm["position"][ep], sm["P_nav"][keep], m,
                                                        res.t[ep]).items()}
    return out


def aided_monte_carlo(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig | None,
                      rate: float, duration: float | None = None, runs: int = 100, *,
                      seed: int = 0, times: FloatArray | None = None,
                      algorithm: str | None = None, covariance_step: float = 0.1,
                      scheduler: str | None = None, workers: int | None = None,
                      progress: bool = True, g: float = G0,
                      measurements: list[Aid] | None = None, smooth: bool = False,
                      nees: bool = False, skip: float = 5.0, innovations: bool = False,
                      keep: int = 0) -> AidedMonteCarlo:
    """``runs`` simulations of the IMU and the aids on ``motion``, each filtered by the real EKF
    (:func:`~imunav.estimation.filters.run_filter_batch`, :data:`MC_CHUNK` runs at once).

    Run ``r`` draws its IMU errors from ``SeedSequence(seed).spawn(runs)[r]``, its aids from
    :func:`~imunav.sensors.aids.aid_stream` ``(seed, r, stream)``, a user's measurement ``i``
    from stream ``USER_STREAM + i`` — so the result is the same bit for bit locally and on a
    Dask cluster (``scheduler``: the chunks are fixed).

    Parameters
    ----------
    motion, imu, aiding, rate
        The truth, the IMU, the aids (simulated and assumed), the IMU rate (Hz).
    duration : float, optional
        Seconds (default the motion's own).
    runs : int
    seed : int
    times : ndarray, optional
        Where to keep the errors (rounded to IMU nodes; default every 0.1 s).
    algorithm : str, optional
    covariance_step : float
    scheduler : str, optional
        A Dask scheduler's address (``imunav[dask]``).
    workers : int, optional
        Local worker processes (a Dask ``LocalCluster``, ``imunav[dask]``): the chunks spread
        over them, the numbers the same bit for bit as here. Their start costs seconds (5–7 s
        measured on two processes), worth it for chunks that take longer; a script that uses
        it runs its top level under ``if __name__ == "__main__":`` (the processes are
        spawned and import it).
    progress : bool
        A progress bar on long runs.
    g : float
    measurements : list of Aid, optional
        A user's own measurements (their models and reading times; the readings are simulated).
    smooth : bool
        Also the smoother's NEES (with ``nees``).
    nees : bool
        The NEES of every run at the covariance epochs after ``skip`` s.
    skip : float
    innovations : bool
        Keep every run's innovations.
    keep : int
        Keep the whole results of the first ``keep`` runs.

    Returns
    -------
    AidedMonteCarlo

    Raises
    ------
    ImunavError
        For a non-positive rate or duration, a motion without a duration of its own, runs or
        seed out of range, NEES asked for runs whose epochs differ, or the reasons of the
        filter.
    """
    rate = check_positive(rate, "rate")
    runs = check_int(runs, "runs", 1)
    if workers is not None:
        workers = check_int(workers, "workers", 1)
    seed = check_int(seed, "seed", 0)
    aiding = aiding if aiding is not None else AidingConfig()
    if duration is None:
        duration = getattr(motion, "duration", None)
        if duration is None:
            raise ImunavError("this motion has no duration of its own: give duration",
                              argument="duration")
    N = interval_count(rate, check_positive(duration, "duration"))
    duration = N / rate
    if times is None:
        times = np.arange(0.0, duration + 1e-9, 0.1)
    nodes = np.clip(np.rint(np.asarray(times, float) * rate).astype(int), 0, N)
    k = imu.decimation(rate)
    ideal = simulate_imu(motion, rate * k, duration, kind="increments", g=g)
    task = _Task(motion, imu, aiding, rate, duration, seed, algorithm, covariance_step,
                 ideal.gyro, ideal.accel, ideal.t, g, nodes, list(measurements or []), smooth,
                 nees, skip, innovations, keep)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    shoe = aiding.zupt is not None and aiding.zupt.detector == "shoe"
    size = 1 if shoe else MC_CHUNK            # the SHOE detector's stances differ run by run
    parts = [list(range(i, min(runs, i + size))) for i in range(0, runs, size)]
    results = run_chunks(_chunk, task, [(p, [seeds[i] for i in p]) for p in parts],
                         scheduler=scheduler, workers=workers, progress=progress, total=runs,
                         desc="filter Monte Carlo", unit="run")
    out = AidedMonteCarlo(nodes / rate, np.concatenate([r["error"] for r in results]), {})
    for r in results:
        for key, v in r["rejected"].items():
            out.rejected[key] = out.rejected.get(key, 0) + v
        out.innovations += r["innovations"]
        out.results += r["results"]
    if nees:
        if any(r["nees_t"].shape != results[0]["nees_t"].shape for r in results):
            raise ImunavError("the runs' covariance epochs differ (a SHOE detector's stances): "
                              "their NEES cannot be averaged epoch by epoch", argument="nees")
        out.nees_t = results[0]["nees_t"]
        out.filter = {b: np.concatenate([r["filter"][b] for r in results]) for b in BLOCKS}
        if smooth:
            out.smoother = {b: np.concatenate([r["smoother"][b] for r in results])
                            for b in BLOCKS}
    return out


@dataclass
class FilterMonteCarlo:
    """NEES per run and the innovations of a Monte Carlo of the aided filter.

    Attributes
    ----------
    t : ndarray, shape (E,)
        Epoch times of the NEES (s).
    filter : dict
        ``{block: (runs, E) NEES}`` of the filter.
    smoother : dict
        The same for the smoother (empty without smoothing).
    innovations : list of dict
        Per run, ``{aid: Innovations}``.
    results : list of FilterResult
        The runs kept (``keep``).
    """

    t: FloatArray
    filter: dict
    smoother: dict = field(default_factory=dict)
    innovations: list = field(default_factory=list)
    results: list = field(default_factory=list)

    @property
    def runs(self) -> int:
        """Number of runs.

        Returns
        -------
        int
        """
        return int(next(iter(self.filter.values())).shape[0])

    def summary(self, level: float = 0.95) -> dict:
        """Time-averaged run-average NEES per block, the band and the fraction of epochs in it.

        Parameters
        ----------
        level : float

        Returns
        -------
        dict
            ``{"band": (lo, hi), "filter": {block: {"mean", "inside"}}, "smoother": …}``.
        """
        lo, hi = nees_band(self.runs, 3, level)
        out: dict = {"band": (lo, hi), "runs": self.runs}
        for name, d in (("filter", self.filter), ("smoother", self.smoother)):
            if d:
                out[name] = {}
                for k, a in d.items():
                    avg = a.mean(axis=0)
                    out[name][k] = {"mean": float(avg.mean()),
                                    "inside": float(np.mean((avg >= lo) & (avg <= hi)))}
        return out


def filter_monte_carlo(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig | None,
                       rate: float, duration: float, runs: int, *, seed: int = 0,
                       smooth: bool = False, algorithm: str | None = None, skip: float = 5.0,
                       keep: int = 1, covariance_step: float = 0.1,
                       measurements: list[Aid] | None = None, scheduler: str | None = None,
                       workers: int | None = None, progress: bool = False) -> FilterMonteCarlo:
    """Run the aided filter ``runs`` times on simulated data with known truth: its NEES
    (:func:`aided_monte_carlo` with ``nees``).

    Parameters
    ----------
    motion : BaseMotion
    imu : ImuModel
        The IMU simulated and assumed by the filter.
    aiding : AidingConfig
        The aids simulated and assumed.
    rate : float
        IMU rate (Hz).
    duration : float
        Seconds.
    runs : int
    seed : int
    smooth : bool
        Also the smoother's NEES.
    algorithm : str, optional
        Strapdown algorithm.
    skip : float
        Seconds at the start left out of the NEES.
    keep : int
        How many runs' full results to keep.
    covariance_step : float
        The filter's covariance step (s).
    measurements : list of Aid, optional
        A user's own measurements (simulated as in :func:`aided_monte_carlo`).
    scheduler : str, optional
        A Dask scheduler's address.
    workers : int, optional
        Local worker processes (as :func:`aided_monte_carlo`).
    progress : bool

    Returns
    -------
    FilterMonteCarlo
    """
    mc = aided_monte_carlo(motion, imu, aiding, rate, duration, runs, seed=seed,
                           algorithm=algorithm, covariance_step=covariance_step,
                           scheduler=scheduler, workers=workers, progress=progress,
                           g=getattr(motion, "g", G0),
                           measurements=measurements, smooth=smooth, nees=True, skip=skip,
                           innovations=True, keep=keep)
    return FilterMonteCarlo(mc.nees_t, mc.filter, mc.smoother, mc.innovations, mc.results)
