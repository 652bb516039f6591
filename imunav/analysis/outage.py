"""Can it bridge the outage? The aided assessment and design, by covariance and by Monte Carlo of
the real filter.

:func:`assess_aided` answers "with these aids, does this IMU keep the tolerance through every
GNSS outage of the motion?" by the covariance analysis of the aided filter linearised along the
true motion (:class:`~imunav.estimation.performance.AlongTruth`: the filter's gains, and the
*true* error covariance those gains leave when the filter's model differs from the simulation's —
a correlated GNSS error treated as white), and with ``runs`` by a Monte Carlo of the real EKF
(:func:`aided_monte_carlo`: :func:`~imunav.estimation.filters.run_filter_batch`, many runs at
once). :func:`find_outage` answers "how long an outage can it bridge?": the longest GNSS outage
(placed where it hurts most, or at a given start) whose 95th-percentile position error stays
within the tolerance — one covariance pass evaluates many outage placements side by side
(scenarios of the same gains' pass differ only in which fixes they use). :func:`outage_budget`
splits the error at the outage's end by its sources (the true covariance is linear in them).
:func:`bridgeable_outages` tabulates the answer for every IMU preset (notebook 10).

The outage of a scenario is ``[start, end]``, fixes at ``start ≤ t ≤ end`` left out (the
convention of ``[gnss] outages``); its ``position_p95_max_m`` is the largest 95th percentile of
the position-error norm at the covariance epochs from ``start`` until the first fix used after
``end`` (excluded: the error grows until that fix), and ``position_p95_end_m`` the value at the
last of them (``t_end_s``, one covariance step before that fix).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``, ``imunav.analysis``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from imunav.analysis.covariance import ENVELOPE_POINTS, envelope_index
from imunav.analysis.gaussnorm import eigenvalues, norm_cdf, norm_quantile, tabulated_quantile_bounds
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, check_int, check_positive
from imunav.estimation.error_model import DP, PHI
from imunav.estimation.filters import run_filter_batch
from imunav.estimation.performance import AlongTruth
from imunav.motion.base import BaseMotion
from imunav.sensors.aiding import AidingConfig, simulate_aiding
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.presets import PRESETS
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import interval_count, simulate_imu
from imunav.sensors.terms import TERMS, printed

__all__ = ["AidedMonteCarlo", "aided_covariance", "aided_monte_carlo", "assess_aided",
           "bridgeable_outages", "common_scale", "design_aided", "find_outage",
           "format_aided_verdict", "format_outage_design", "outage_budget", "outage_p95",
           "rank_presets", "term_limits"]

#: The percentile of the verdicts.
P95 = 0.95

#: p95 attitude error (rad) beyond which the linearised filter is flagged. A coarse flag: a
#: yaw not yet observed before the first accelerations reaches 0.4 rad with a BMI088 on the
#: example drive while the covariance still matches the EKF's Monte Carlo; with an MPU-6050's
#: 20 °/s turn-on bias it reaches 2.6 rad and the real filter diverges.
ATTITUDE_VALID = 0.5

#: Runs filtered at once by :func:`aided_monte_carlo` (fixed: the chunks, and so the numbers,
#: are the same on a Dask cluster and locally).
MC_CHUNK = 20


def _span(motion: BaseMotion, rate: float, duration: float | None) -> float:
    if duration is None:
        duration = getattr(motion, "duration", None)
        if duration is None:
            raise ImunavError("this motion has no duration of its own: give duration",
                              argument="duration")
    duration = check_positive(duration, "duration")
    return interval_count(rate, duration) / rate


def _file_outages(aiding: AidingConfig) -> list[tuple[float, float]]:
    return list(aiding.gnss.outages) if aiding.gnss is not None else []


def aided_covariance(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                     duration: float | None = None, *, kind: str = "increments",
                     covariance_step: float = 0.1, algorithm: str | None = None,
                     g: float = G0, terms: bool = False) -> AlongTruth:
    """The aided filter linearised along the true motion (built once; passes are cheap).

    Parameters
    ----------
    motion, imu, aiding, rate
        The truth, the IMU (simulated and assumed), the aids, the IMU rate (Hz).
    duration : float, optional
        Seconds (default the motion's own).
    kind, covariance_step, algorithm, g, terms
        As :class:`~imunav.estimation.performance.AlongTruth`.

    Returns
    -------
    AlongTruth
    """
    duration = _span(motion, rate, duration)
    at = AlongTruth(motion, imu, aiding, rate, duration, kind=kind,
                    covariance_step=covariance_step, algorithm=algorithm, g=g, terms=terms)
    at.warnings += imu.missing_term_warnings()        # issue 38: no bias instability, say so
    return at


def _gnss_times(at: AlongTruth) -> FloatArray:
    return np.array([r.t for rs in at.readings for r in rs if r.sensor == "gnss"])


def _check_start(tg: FloatArray, start: float, end: float, dt: float) -> None:
    """Refuse an outage start outside ``[0, end)``, or one that leaves no room for an outage of
    one GNSS interval before the record's ``end`` and a fix after it (the search would report
    0 s as "the rest of the motion")."""
    if not 0 <= start < end:
        raise ImunavError(f"outage_start must be in [0, {end:g}) s, got {start:g}",
                          argument="outage_start")
    if start > end - dt + 1e-9 or not np.any(tg > start + 1e-9):
        raise ImunavError(f"outage_start = {start:g} s leaves no GNSS fix after it to end an "
                          f"outage of one GNSS interval ({dt:g} s); expected a start at most "
                          f"{end - dt:g} s (the record ends at {end:g} s)",
                          argument="outage_start")


def _no_fix_warnings(at: AlongTruth, outages: list[tuple[float, float]]) -> list[str]:
    """A warning when the GNSS outages leave no fix in the record (an aided answer that is
    then the other aids' alone, which a reader of "GNSS outage 0–20 s" would not guess).

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)

    Returns
    -------
    list of str
        Empty, or the one warning.
    """
    tg = _gnss_times(at)
    if tg.size and not _active(at, [outages])[0].any():
        return ["the GNSS outages cover every fix of the record: GNSS helps nowhere, the "
                "answer is that of the other aids alone"]
    return []


def _active(at: AlongTruth, outages: list[list[tuple[float, float]]]) -> np.ndarray:
    """Per scenario (a list of outages), which GNSS fixes are used."""
    tg = _gnss_times(at)
    act = np.ones((len(outages), tg.size), dtype=bool)
    for b, outs in enumerate(outages):
        for t0, t1 in outs:
            act[b] &= ~((tg >= t0 - 1e-9) & (tg <= t1 + 1e-9))
    return act


def outage_p95(at: AlongTruth, outages: list[tuple[float, float]], *, imu_scale: float = 1.0
               ) -> tuple[FloatArray, FloatArray, FloatArray, list[dict]]:
    """One covariance pass with these outages: the p95 position error at every epoch, the
    filter's own p95 beside it, and each outage's largest p95.

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)
        GNSS outages (s), replacing the aiding file's.
    imu_scale : float
        Every IMU term times this.

    Returns
    -------
    t : ndarray, shape (E + 1,)
    truth_p95, filter_p95 : ndarray, shape (E + 1,)
        95th percentile of the position-error norm (m): the true error and the filter's belief
        (after each epoch's readings).
    per_outage : list of dict
        ``{"start", "end", "position_p95_max_m", "position_p95_end_m"}``.
    """
    return _outage_pass(at, outages, imu_scale)[:4]


def _outage_pass(at: AlongTruth, outages, imu_scale: float = 1.0):
    """:func:`outage_p95` and the true attitude error's p95 at every epoch."""
    wf, wt, _ = at.weights(imu_scale)
    act = _active(at, [outages])
    res = at.propagate(wf, wt, act)
    truth = norm_quantile(res.truth_post[0, 0][:, DP, DP], P95)
    filt = norm_quantile(res.filter_post[0][:, DP, DP], P95)
    att = norm_quantile(res.truth_post[0, 0][:, PHI, PHI], P95)
    return res.t, truth, filt, _per_outage(res.t, truth, outages,
                                           _windows(at, outages, act[0])), att


def _windows(at: AlongTruth, outages, active: np.ndarray) -> list[np.ndarray]:
    """Per outage, its epochs: from its start until the next fix used (that one excluded —
    the error grows until the fix after the outage, not only until the outage's end), or the
    end of the motion."""
    tg = _gnss_times(at)
    used = tg[active]
    t = at.t
    out = []
    for t0, t1 in outages:
        nxt = used[used > t1 + 1e-9]
        stop = nxt[0] - 1e-9 if nxt.size else t[-1] + 1e-9
        out.append((t >= t0 - 1e-9) & (t < stop))
    return out


def _per_outage(t: FloatArray, p95: FloatArray, outages, windows) -> list[dict]:
    out = []
    for (t0, t1), inside in zip(outages, windows, strict=True):
        if not inside.any():
            continue
        end = int(np.nonzero(inside)[0][-1])
        out.append({"start": float(t0), "end": float(t1),
                    "position_p95_max_m": float(p95[inside].max()),
                    "position_p95_end_m": float(p95[end]), "t_end_s": float(t[end])})
    return out


# ----------------------------------------------------------------------------- Monte Carlo

@dataclass
class AidedMonteCarlo:
    """Position errors of a Monte Carlo of the aided filter.

    Attributes
    ----------
    t : ndarray, shape (K,)
        The times evaluated (IMU nodes, s).
    position_error : ndarray, shape (runs, K, 3)
        Estimate − truth (m, NED).
    rejected : dict
        ``{sensor: readings the χ² gate rejected, all runs}``.
    """

    t: FloatArray
    position_error: FloatArray
    rejected: dict

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


@dataclass
class _McTask:
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


def _mc_chunk(task: _McTask, runs: list[int], seeds: list) -> tuple[FloatArray, dict]:
    """Filter the runs ``runs`` (their IMU streams ``seeds``) at once: position errors at the
    task's nodes."""
    k = task.imu.decimation(task.rate)
    m = task.motion
    sigs, datas = [], []
    for r, s in zip(runs, seeds, strict=True):
        gm, am, _ = measure(task.imu, task.gyro, task.accel, "increments", task.rate * k,
                            np.random.default_rng(s), k)
        sigs.append(ImuSignals(task.t_ideal[k - 1::k][:gm.shape[0]], gm, am, "increments",
                               task.rate, task.g))
        datas.append(simulate_aiding(m, task.aiding, task.duration, seed=task.seed, run=r,
                                     imu_rate=task.rate))
    st0 = m.states(np.array([0.0]))
    res = run_filter_batch(sigs, st0.quaternion[0], st0.velocity[0], st0.position[0],
                           task.aiding, datas, imu=task.imu, algorithm=task.algorithm,
                           covariance_step=task.covariance_step)
    tn = res.t[task.nodes]
    err = res.position[task.nodes] - m.position(tn)[:, None, :]           # (K, R, 3)
    rej = {k2: int(v.sum()) for k2, v in res.rejected.items()}
    return np.swapaxes(err, 0, 1), rej


def aided_monte_carlo(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                      duration: float | None = None, runs: int = 100, *, seed: int = 0,
                      times: FloatArray | None = None, algorithm: str | None = None,
                      covariance_step: float = 0.1, scheduler: str | None = None,
                      progress: bool = True, g: float = G0) -> AidedMonteCarlo:
    """``runs`` simulations of the IMU and the aids on ``motion``, each filtered by the real EKF
    (:func:`~imunav.estimation.filters.run_filter_batch`, :data:`MC_CHUNK` runs at once).

    Run ``r`` draws its IMU errors from ``SeedSequence(seed).spawn(runs)[r]`` and its aids from
    :func:`~imunav.sensors.aiding.aiding_streams` ``(seed, r)`` — the streams of
    :func:`~imunav.analysis.aided.filter_monte_carlo` — so the result is the same bit for bit
    locally and on a Dask cluster (``scheduler``: the chunks are fixed).

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
    progress : bool
        A progress bar on long runs.
    g : float

    Returns
    -------
    AidedMonteCarlo
    """
    if motion.frame != "flat":
        raise ImunavError("the aided Monte Carlo works in the flat frame so far",
                          argument="earth")
    rate = check_positive(rate, "rate")
    runs = check_int(runs, "runs", 1)
    seed = check_int(seed, "seed", 0)
    duration = _span(motion, rate, duration)
    N = interval_count(rate, duration)
    if times is None:
        times = np.arange(0.0, duration + 1e-9, 0.1)
    nodes = np.clip(np.rint(np.asarray(times, float) * rate).astype(int), 0, N)
    k = imu.decimation(rate)
    ideal = simulate_imu(motion, rate * k, duration, output="increments", g=g)
    task = _McTask(motion, imu, aiding, rate, duration, seed, algorithm, covariance_step,
                   ideal.gyro, ideal.accel, ideal.t, g, nodes)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    parts = [list(range(i, min(runs, i + MC_CHUNK))) for i in range(0, runs, MC_CHUNK)]
    if scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ImunavError("scheduler needs the dask extra: pip install 'imunav[dask]'",
                              argument="scheduler") from None
        with Client(scheduler) as client:
            futs = [client.submit(_mc_chunk, task, p, [seeds[i] for i in p], pure=False)
                    for p in parts]
            results = client.gather(futs)
    else:
        bar = None
        if progress and len(parts) > 1:
            from tqdm.auto import tqdm
            bar = tqdm(total=runs, desc="filter Monte Carlo", unit="run")
        results = []
        for p in parts:
            results.append(_mc_chunk(task, p, [seeds[i] for i in p]))
            if bar is not None:
                bar.update(len(p))
        if bar is not None:
            bar.close()
    err = np.concatenate([r[0] for r in results])
    rej: dict[str, int] = {}
    for _, d in results:
        for key, v in d.items():
            rej[key] = rej.get(key, 0) + v
    return AidedMonteCarlo(nodes / rate, err, rej)


# ----------------------------------------------------------------------------- the budget

def outage_budget(at: AlongTruth, outages: list[tuple[float, float]], at_time: float,
                  *, imu_scale: float = 1.0) -> dict[str, float]:
    """Which source eats the tolerance: the p95 position error at ``at_time`` of each source of
    the true error alone (an IMU term, an aid's noise or states, the initial uncertainty),
    the filter's gains those of all of them (the true covariance is their sum).

    Parameters
    ----------
    at : AlongTruth
        Built with ``terms=True`` for one row per IMU term (else one ``"imu"`` row).
    outages : list of (float, float)
    at_time : float
        Seconds (the epoch at or before it).
    imu_scale : float

    Returns
    -------
    dict
        ``{source: p95 (m)}``, largest first (sources that contribute nothing left out).
    """
    e = int(np.searchsorted(at.t, at_time + 1e-9)) - 1
    e = max(0, min(e, at.t.size - 1))
    wf, wt, names = at.weights(imu_scale, split=True)
    res = at.propagate(wf, wt, _active(at, [outages]), stop=e, keep=False)
    P = res.final[0, 1:, :, :]
    q = norm_quantile(P[:, DP, DP], P95)
    out = {nm: float(v) for nm, v in zip(names, q, strict=True) if v > 0}
    return dict(sorted(out.items(), key=lambda kv: -kv[1]))


# ----------------------------------------------------------------------------- assess

def assess_aided(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                 tolerance: float, duration: float | None = None, *, runs: int | None = None,
                 seed: int = 0, scheduler: str | None = None, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None,
                 budget: bool = True, progress: bool = True, g: float = G0) -> dict:
    """The aided verdict: does the tolerance hold through every GNSS outage of ``aiding``?

    By the covariance analysis of the filter along the true motion (the true error covariance,
    the model mismatch included); with ``runs`` by a Monte Carlo of the real filter too (its
    numbers then make the verdict, the covariance's stand beside them).

    Parameters
    ----------
    motion, imu, aiding, rate
    tolerance : float
        Position (m), 95th percentile of the error norm.
    duration : float, optional
    runs : int, optional
        Monte Carlo runs of the EKF.
    seed, scheduler
        Of the Monte Carlo.
    kind, covariance_step, algorithm, g
        As :class:`~imunav.estimation.performance.AlongTruth`.
    budget : bool
        The error budget per source at the worst outage's end.
    progress : bool

    Returns
    -------
    dict
        The JSON of ``imunav assess --aiding``: ``method``, ``suitable``,
        ``max_p95_position_m``, ``final_p95_position_m``, ``envelope`` (``t``,
        ``position_p95_m``, ``filter_position_p95_m``), ``outages`` (``start``, ``end``,
        ``position_p95_max_m``, with a Monte Carlo ``covariance_p95_max_m`` and the end values),
        ``error_budget``, ``warnings``.
    """
    tolerance = check_positive(tolerance, "tolerance")
    duration = _span(motion, rate, duration)
    if aiding.gnss is not None:
        aiding.gnss.check_within(0.0, duration)
    at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                          covariance_step=covariance_step, algorithm=algorithm, g=g,
                          terms=budget)
    outs = _file_outages(aiding)
    t, truth, filt, per, att = _outage_pass(at, outs)
    warnings = list(at.warnings) + _no_fix_warnings(at, outs)
    if att.max() > ATTITUDE_VALID:
        i = int(np.argmax(att))
        warnings.append(f"the attitude error reaches a p95 of {att[i]:.3g} rad at t = "
                        f"{t[i]:.4g} s: beyond the filter's linearisation (the real EKF may "
                        "diverge where the covariance does not); check with --runs")
    r: dict = {"motion": motion.name, "imu": imu.name, "rate_hz": float(rate),
               "tolerance_m": tolerance, "aiding": list(aiding.sensors),
               "method": "covariance", "runs": None, "seed": None,
               "max_p95_attitude_rad": float(att.max())}
    p95 = truth
    if runs is not None:
        mc = aided_monte_carlo(motion, imu, aiding, rate, duration, runs, seed=seed, times=t,
                               algorithm=algorithm, covariance_step=covariance_step,
                               scheduler=scheduler, progress=progress, g=g)
        p95 = mc.p95()
        mper = _per_outage(t, p95, outs, _windows(at, outs, _active(at, [outs])[0]))
        for o, c in zip(mper, per, strict=True):
            o["covariance_p95_max_m"] = c["position_p95_max_m"]
            o["covariance_p95_end_m"] = c["position_p95_end_m"]
        per = mper
        r.update(method="montecarlo", runs=int(runs), seed=int(seed),
                 rejected_readings=mc.rejected)
    for o in per:
        o["within_tolerance"] = bool(o["position_p95_max_m"] <= tolerance)
    over = np.nonzero(p95 > tolerance)[0]
    worst = int(np.argmax(p95))
    r.update({
        "suitable": bool(over.size == 0),
        "outages_within_tolerance": bool(all(o["within_tolerance"] for o in per)),
        "time_p95_exceeds_s": float(t[over[0]]) if over.size else None,
        "max_p95_position_m": float(p95[worst]), "time_max_p95_s": float(t[worst]),
        "final_p95_position_m": float(p95[-1]),
        "outages": per,
    })
    if budget:
        # at the end of the worst outage (else at the worst time)
        when = max(per, key=lambda o: o["position_p95_max_m"])["t_end_s"] if per else t[worst]
        r["error_budget_at_s"] = float(when)
        r["error_budget"] = outage_budget(at, outs, when)
    idx = envelope_index(t.size, ENVELOPE_POINTS)
    r["envelope"] = {"t": t[idx].tolist(), "position_p95_m": p95[idx].tolist(),
                     "filter_position_p95_m": filt[idx].tolist()}
    if runs is not None:
        r["envelope"]["covariance_position_p95_m"] = truth[idx].tolist()
    if np.any(filt < 0.8 * truth):
        i = int(np.argmax(truth / np.maximum(filt, 1e-300)))
        warnings.append(f"the filter believes its position better than it is (p95 "
                        f"{filt[i]:.3g} m believed, {truth[i]:.3g} m true at t = {t[i]:.4g} s): "
                        "its model differs from the sensors'")
    r["warnings"] = warnings
    return r


def format_aided_verdict(r: dict) -> str:
    """The aided verdict as text (what ``imunav assess --aiding`` prints).

    Parameters
    ----------
    r : dict
        :func:`assess_aided`'s result.

    Returns
    -------
    str
    """
    how = ("covariance analysis of the filter" if r["method"] == "covariance" else
           f"Monte Carlo of the filter, {r['runs']} runs")
    lines = [f"Aided verdict for motion {r['motion']}, IMU {r['imu']} at {r['rate_hz']:g} Hz "
             f"with {', '.join(r['aiding'])} ({how}), tolerance {r['tolerance_m']:g} m "
             "(95th percentile of the position error):",
             f"  {'SUITABLE' if r['suitable'] else 'NOT SUITABLE'}: largest p95 "
             f"{r['max_p95_position_m']:.3g} m at t = {r['time_max_p95_s']:.4g} s, final "
             f"{r['final_p95_position_m']:.3g} m."]
    for o in r["outages"]:
        extra = (f" (covariance {o['covariance_p95_max_m']:.3g} m)"
                 if "covariance_p95_max_m" in o else "")
        lines.append(f"  GNSS outage {o['start']:g}–{o['end']:g} s: p95 up to "
                     f"{o['position_p95_max_m']:.3g} m{extra} — "
                     + ("within" if o["within_tolerance"] else "BEYOND") + " the tolerance")
    if r.get("error_budget"):
        lines.append(f"  Error budget at t = {r['error_budget_at_s']:.4g} s (p95 of each "
                     "source alone):")
        for k, v in list(r["error_budget"].items())[:8]:
            lines.append(f"    {k:28s} {v:10.3g} m")
    for w in r["warnings"]:
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- design

def _lost_from(at: AlongTruth, starts: FloatArray, tolerance: float, *,
               imu_scale: float = 1.0, chunk: float = 10.0) -> list[tuple[FloatArray, FloatArray]]:
    """Per start (ascending): the epochs' times and true position covariances of the scenario
    "GNSS lost for good at that start", until the p95 passes ``tolerance`` (or the end). Up to
    the fix after it, an outage ``[s, s + L]`` is exactly this scenario (the covariance is
    causal), so it answers every length at once. Before its start a scenario is the baseline
    (every fix), so the baseline is walked once and each scenario started from it, and stopped
    ``chunk`` seconds after it passes the tolerance at the latest."""
    wf, wt, _ = at.weights(imu_scale)
    E = at.t.size - 1
    base_act = _active(at, [[]])
    out = []
    e0, P = 0, None
    step = max(1, int(round(chunk / max(np.diff(at.t).mean(), 1e-9))))
    for s0 in starts:
        e_b = max(0, int(np.searchsorted(at.t, s0 - 1e-9)) - 1)   # the last epoch before s0
        if P is None:                                            # from the initial covariance
            P = at.propagate(wf, wt, base_act, stop=e_b, keep=False).final
        elif e_b > e0:
            P = at.propagate(wf, wt, base_act, start=e0, stop=e_b, P_start=P, keep=False).final
        e0 = e_b
        act = _active(at, [[(float(s0), float(at.t[-1]) + 1.0)]])
        ts, Ps, Pc, e = [], [], P, e_b
        while e < E:
            stop = min(E, e + step)
            res = at.propagate(wf, wt, act, start=e, stop=stop, P_start=Pc)
            Pp = res.truth_post[0, 0][1:][:, DP, DP]
            ts.append(res.t[1:])
            Ps.append(Pp)
            Pc, e = res.final, stop
            if _over(Pp, tolerance).any():
                break
        out.append((np.concatenate(ts) if ts else np.zeros(0),
                    np.concatenate(Ps) if Ps else np.zeros((0, 3, 3))))
    return out


def _over(P: FloatArray, tolerance: float) -> np.ndarray:
    """Where the p95 of ``|x|``, ``x ~ N(0, P)``, exceeds ``tolerance``: the tabulated bounds
    decide most, the exact probability the rest."""
    lo, hi = tabulated_quantile_bounds(eigenvalues(P), P95)
    over = lo > tolerance
    open_ = ~over & (hi > tolerance)
    if open_.any():
        over[open_] = norm_cdf(P[open_], tolerance) < P95
    return over


def find_outage(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                tolerance: float, duration: float | None = None, *,
                start: float | None = None, at: AlongTruth | None = None,
                starts: int = 24, settle: float = 30.0, budget: bool = True,
                kind: str = "increments", covariance_step: float = 0.1,
                algorithm: str | None = None, g: float = G0) -> dict:
    """The longest GNSS outage the IMU bridges with these aids: its p95 position error stays
    within ``tolerance`` from the outage's start until the first fix after it.

    The aiding file's own outages are replaced by the one searched. Placed at ``start`` or, by
    default, where it hurts most: of ``starts`` placements from ``settle`` s (the filter's
    convergence) to the end, the one that bridges the shortest outage. One covariance pass
    answers every length and placement: until the fix after it, an outage is the scenario
    "GNSS lost for good at its start". Lengths are whole GNSS intervals. An outage that could
    outlast the motion is cut at its end (``limited_by_motion``: the IMU bridges at least the
    rest of the motion).

    Parameters
    ----------
    motion, imu, aiding, rate, tolerance, duration
    start : float, optional
        The outage's start (s).
    at : AlongTruth, optional
        Reuse a built analysis (its IMU and aids).
    starts : int
        Placements compared.
    settle : float
        Earliest start (s; at most a quarter of the motion).
    budget : bool
        Error budget per source at the outage's end.
    kind, covariance_step, algorithm, g

    Returns
    -------
    dict
        ``max_outage_s``, ``outage_start_s``, ``position_p95_end_m`` (the p95 just before the
        fix after it), ``limited_by_motion``, ``gnss_interval_s``, ``error_budget``,
        ``warnings``.
    """
    tolerance = check_positive(tolerance, "tolerance")
    if aiding.gnss is None:
        raise ImunavError("finding the longest outage needs [gnss] in the aiding file",
                          argument="aiding")
    duration = _span(motion, rate, duration)
    if at is None:
        at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                              covariance_step=covariance_step, algorithm=algorithm, g=g,
                              terms=budget)
    T = float(at.t[-1])
    dt = 1.0 / aiding.gnss.rate
    tg = _gnss_times(at)
    if start is not None:
        _check_start(tg, start, T, dt)
        cand = np.array([float(start)])
    else:
        lo_s = min(settle, T / 4)
        grid = tg[(tg >= lo_s - 1e-9) & (tg < T - dt)]
        if grid.size == 0:
            raise ImunavError("the motion is too short to place an outage after the filter "
                              "settles", argument="duration")
        cand = grid[np.unique(np.linspace(0, grid.size - 1, min(starts, grid.size)).round()
                              .astype(int))]
    scen = _lost_from(at, cand, tolerance)
    warnings = list(at.warnings)
    # per start: the longest L (whole GNSS intervals) with p95 ≤ tol on [s, s + L + dt)
    best_L = np.zeros(cand.size)
    limited = np.zeros(cand.size, dtype=bool)
    for b, s0 in enumerate(cand):
        t, Pb = scen[b]
        after = np.nonzero(t >= s0 - 1e-9)[0]
        over = after[_over(Pb[after], tolerance)]
        if over.size == 0:
            # the whole rest of the motion (the last fix at or before the end)
            best_L[b] = (np.floor((T - s0) / dt + 1e-9)) * dt
            limited[b] = True
            continue
        t_over = t[over[0]]
        # the fix after the outage must come at or before the first epoch over the tolerance
        n = int(np.floor((t_over - s0) / dt + 1e-9)) - 1
        best_L[b] = max(n, -1) * dt
    # where it hurts most: the shortest bridgeable outage among the placements that the end of
    # the motion does not cut short (those only give lower bounds)
    b = (int(np.argmin(np.where(limited, np.inf, best_L))) if not limited.all()
         else int(np.argmax(best_L)))
    L, s_best = float(best_L[b]), float(cand[b])
    if L < 0:
        warnings.append(f"at {s_best:g} s the p95 position error exceeds the tolerance within "
                        "one GNSS interval even with every fix")
        L = 0.0
    t, Pb = scen[b]
    win = np.nonzero((t >= s_best - 1e-9) & (t < s_best + L + dt - 1e-9))[0]
    e_end = win[-1] if win.size else 0
    end_p95 = float(norm_quantile(Pb[e_end], P95))
    r = {"max_outage_s": L, "outage_start_s": s_best, "position_p95_end_m": end_p95,
         "limited_by_motion": bool(limited[b]), "gnss_interval_s": dt,
         "starts_compared": int(cand.size)}
    if budget and L > 0:
        when = float(t[e_end])
        r["error_budget_at_s"] = when
        r["error_budget"] = outage_budget(at, [(s_best, s_best + L)], when)
    else:
        r["error_budget"] = {}
    r["warnings"] = warnings
    return r


def bridgeable_outages(motion: BaseMotion, aiding: AidingConfig, rate: float, tolerance: float,
                       duration: float | None = None, *, presets: list[str] | None = None,
                       start: float | None = None, **kw) -> list[dict]:
    """:func:`find_outage` for every IMU preset (the table of notebook 10).

    Parameters
    ----------
    motion, aiding, rate, tolerance, duration, start
        As :func:`find_outage`.
    presets : list of str, optional
        Default every preset but ``ideal``.
    **kw
        Passed to :func:`find_outage`.

    Returns
    -------
    list of dict
        ``{"imu", "max_outage_s", "outage_start_s", "position_p95_end_m",
        "limited_by_motion", "warnings"}``, longest first.
    """
    names = presets or [p for p in PRESETS if p != "ideal"]
    rows = []
    for name in names:
        f = find_outage(motion, ImuModel.load(name), aiding, rate, tolerance, duration,
                        start=start, budget=False, **kw)
        rows.append({"imu": name, **{k: f[k] for k in ("max_outage_s", "outage_start_s",
                                                      "position_p95_end_m",
                                                      "limited_by_motion", "warnings")}})
    rows.sort(key=lambda d: -d["max_outage_s"])
    return rows


def common_scale(at: AlongTruth, tolerance: float, outages, *, rtol: float = 0.01,
                 iters: int = 8) -> float:
    """The largest factor on every IMU term for which the p95 position error stays within
    ``tolerance`` over the whole motion with these outages. The filter's gains change with the
    IMU, so each trial is one pass; the largest p95 grows smoothly and nearly as a power of the
    factor, so a secant on its logarithms lands within ``rtol`` of the tolerance in a few
    passes (the answer is the largest factor tried that passes).

    Parameters
    ----------
    at : AlongTruth
    tolerance : float
    outages : list of (float, float)
    rtol : float
        Stop when the p95 is this close to the tolerance (relative).
    iters : int
        At most this many secant steps.

    Returns
    -------
    float
        0 when even the smallest factor tried exceeds the tolerance (the aids' own errors do).
    """
    def worst(k):
        return float(outage_p95(at, outages, imu_scale=k)[1].max())

    tried = [(1.0, worst(1.0))]
    k1 = tolerance / tried[0][1] if tried[0][1] > 0 else 1e3
    tried.append((k1, worst(k1)))
    for _ in range(iters):
        (k0, p0), (k1, p1) = tried[-2], tried[-1]
        if p1 <= 0 or 0 <= 1 - p1 / tolerance < rtol:         # just within: done
            break
        slope = (np.log(p1) - np.log(p0)) / (np.log(k1) - np.log(k0)) if k1 != k0 else 1.0
        slope = float(np.clip(slope, 0.05, 2.0))
        k2 = k1 * (tolerance / p1) ** (1 / slope) * (1 - rtol / 2)
        tried.append((k2, worst(k2)))
    ok = [k for k, p in tried if p <= tolerance]
    return float(max(ok)) if ok else 0.0


#: Per-term limits are searched between this fraction and this multiple of the base value.
TERM_RANGE = (1e-3, 1e4)

#: A gain error (misalignment in rad, scale factor) whose 1σ limit passes this is flagged: the
#: error model is linear in it (small angles), and the filter estimating it may hide that.
GAIN_VALID = 0.05


def _term_weights(at: AlongTruth, j: int, k: float, retune: bool
                  ) -> tuple[FloatArray, FloatArray]:
    """The weights with ingredient ``j`` (an IMU term) times ``k``: in the truth, and with
    ``retune`` in the filter's model too."""
    wf, wt, _ = at.weights()
    wt = wt.copy()
    wt[:, j] *= k * k
    if retune:
        wf = wf.copy()
        wf[j] *= k * k
    return wf, wt


def _fixed_tuning_limit(P_rest: FloatArray, P_term: FloatArray, tolerance: float) -> float:
    """The largest ``k`` with ``max_t p95(P_rest + k² P_term) ≤ tolerance`` (the filter's gains
    fixed, the true covariance linear in each source's weight): bisection on ``log k`` (every
    epoch's p95 grows with ``k``), each trial decided by :func:`_over` (bounds first, the
    exact probability where they do not decide). 0 when the rest alone exceeds the tolerance,
    inf when the term cannot reach it within :data:`TERM_RANGE`."""
    def passes(k):
        return not _over(P_rest + k * k * P_term, tolerance).any()

    if not passes(0.0):
        return 0.0
    lo, hi = np.log(TERM_RANGE[0]), np.log(TERM_RANGE[1])
    if passes(np.exp(hi)):
        return float("inf")
    if not passes(np.exp(lo)):
        return 0.0
    while hi - lo > 1e-6:                       # 24 bisections of 16 decades
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if passes(np.exp(mid)) else (lo, mid)
    return float(np.exp(lo))


def _term_pass(at: AlongTruth, act: np.ndarray, j: int, k: float
               ) -> tuple[FloatArray, FloatArray]:
    """One pass with the filter tuned to IMU term ``j`` times ``k``: the true position
    covariance of that term (at ``k``) and of every other source, at every epoch."""
    wf, wt = _term_weights(at, j, k, True)
    rows = np.zeros((2, wt.shape[1]))
    rows[0, j] = wt[0, j]
    rows[1] = wt[0]
    rows[1, j] = 0.0
    res = at.propagate(wf, rows, act)
    P = res.truth_post[0][:, :, DP, DP]
    return P[0], P[1]


def _retuned_limit(at: AlongTruth, act: np.ndarray, j: int, k0: float, tolerance: float,
                   rtol: float, iters: int) -> tuple[float, float]:
    """The largest factor ``k`` on IMU term ``j`` with the largest p95 within ``tolerance``,
    the filter tuned to the term at ``k``: a fixed-point iteration from ``k0``. Each pass is
    tuned to the current ``k`` and split into the term and the rest; with those gains the
    true covariance is ``rest + (k'/k)² term`` exactly, so the next ``k'`` is the exact limit
    at those gains (:func:`_fixed_tuning_limit`). The gains of a filter tuned to the truth
    are (nearly: the models may differ) optimal, so the true covariance is stationary in them:
    the iteration converges in a few passes, usually from below. Stops when a tried ``k``
    passes within ``rtol`` below the tolerance; returns the largest passing ``k`` tried and
    its largest p95 (``(0, p)`` when the others
    alone exceed the tolerance even with the term at ``TERM_RANGE[0]``)."""
    lo_k, hi_k = TERM_RANGE
    k = float(np.clip(k0, lo_k, hi_k))
    best = (0.0, float("nan"))
    for _ in range(iters):
        P_term, P_rest = _term_pass(at, act, j, k)
        p = float(norm_quantile(P_rest + P_term, P95).max())
        if p <= tolerance and k > best[0]:
            best = (k, p)
            if 1 - p / tolerance < rtol or k >= hi_k:
                break
        # the exact limit with these gains, aimed a hair inside the tolerance
        r = _fixed_tuning_limit(P_rest, P_term / (k * k), tolerance * (1 - rtol / 4))
        if r == 0.0:
            if k <= lo_k:
                return (0.0, p) if best[0] == 0.0 else best
            r = lo_k
        k_new = float(np.clip(r, lo_k, hi_k))
        if k_new == k:
            break
        k = k_new
    return best


def term_limits(at: AlongTruth, tolerance: float, outages, *, retune: bool = True,
                rtol: float = 0.01, iters: int = 8) -> dict[str, dict]:
    """The largest value of each IMU error term, every other term at the IMU's own value, for
    which the p95 position error stays within ``tolerance`` over the whole motion with these
    GNSS outages (the aided counterpart of :func:`~imunav.analysis.design.design`'s limits).

    **The filter is retuned** to the term's value (``retune=True``, the default): the filter
    of ``imunav filter --imu`` is built from the IMU file, so an engineer who asks "how bad
    may this term be with this filter" fits the IMU they would buy and gives the filter its
    datasheet; the gains then change with the value, and a fixed-point iteration of passes
    tuned to the current value (:func:`_retuned_limit`; two or three per term) lands within
    ``rtol`` below the tolerance. The limit with the filter **kept at the IMU's own tuning** (the
    same gains, the real term worse than the filter believes) is exact from one pass split by
    source — the true covariance is then linear in each source's weight — and is reported
    beside it (``limit_base_tuning_si``); it also starts the retuned search.

    Parameters
    ----------
    at : AlongTruth
        Built with ``terms=True`` (one ingredient per IMU term).
    tolerance : float
    outages : list of (float, float)
    retune : bool
        The filter follows the term (default) or keeps the IMU's tuning.
    rtol : float
        Stop when the p95 at the limit is this close below the tolerance (relative).
    iters : int
        At most this many passes per term.

    Returns
    -------
    dict
        ``{term: {"limit_si", "limit", "base", "max_p95_at_limit_m", "limit_base_tuning_si",
        "limit_base_tuning", "note"}}`` for each IMU term with an effect, ``limit_si`` the
        term's value at the limit (SI; 0 when no value in ``TERM_RANGE`` × the IMU's meets the
        tolerance — the other sources alone exceed it —, None when even ``TERM_RANGE[1]`` ×
        it does); ``note`` says which, or that a gain error's limit passes
        :data:`GAIN_VALID`.
    """
    tolerance = check_positive(tolerance, "tolerance")
    act = _active(at, [outages])
    names = [i.name for i in at.ingredients]
    imu_j = [j for j, i in enumerate(at.ingredients) if i.kind == "imu" and "." in i.name]
    if not imu_j:
        return {}
    wf, wt_split, _ = at.weights(split=True)
    split = at.propagate(wf, wt_split, act).truth_post[0][:, :, DP, DP]     # (M, E + 1, 3, 3)
    total = split.sum(axis=0)
    out: dict[str, dict] = {}
    for j in imu_j:
        term = names[j]
        triad, _, name = term.partition(".")
        value = float(getattr(getattr(at.imu, triad), name))
        if not np.any(split[j]):
            continue
        k_fix = _fixed_tuning_limit(total - split[j], split[j], tolerance)
        note = None
        if not retune or not np.isfinite(k_fix):
            k = k_fix
            p = (float(norm_quantile(total - split[j] + k * k * split[j], P95).max())
                 if np.isfinite(k) else float("nan"))
        else:
            k, p = _retuned_limit(at, act, j, k_fix, tolerance, rtol, iters)
        if k == 0.0:
            note = "the other sources alone exceed the tolerance"
        elif not np.isfinite(k) or k >= TERM_RANGE[1]:
            note = f"within the tolerance up to {TERM_RANGE[1]:g} × this IMU's value"
            k = float("inf")
        elif name in ("misalignment", "scale_factor") and value * k > GAIN_VALID:
            note = (f"beyond the small-error model (1σ above {GAIN_VALID:g}): check with "
                    "Monte Carlo")
        lim = None if not np.isfinite(k) else value * k
        fix = None if not np.isfinite(k_fix) else value * k_fix
        out[term] = {"limit_si": lim,
                     "limit": "unbounded" if lim is None else _show(term, lim),
                     "base": _show(term, value),
                     "max_p95_at_limit_m": p if np.isfinite(p) else None,
                     "limit_base_tuning_si": fix,
                     "limit_base_tuning": "unbounded" if fix is None else _show(term, fix),
                     "note": note}
    return out


def _show(term: str, si: float) -> str:
    triad, _, name = term.partition(".")
    return TERMS[name].show(si, triad)


def rank_presets(motion: BaseMotion, aiding: AidingConfig, rate: float, tolerance: float,
                 duration: float | None = None, *, presets: list[str] | None = None,
                 find: str | None = None, start: float | None = None, **kw) -> list[dict]:
    """Every IMU preset with these aids, best first: the largest p95 position error through
    the file's GNSS outages (the whole motion), within the tolerance or not, and with
    ``find="outage"`` its longest bridgeable outage (:func:`find_outage`; the table of
    :func:`bridgeable_outages`).

    Parameters
    ----------
    motion, aiding, rate, tolerance, duration
    presets : list of str, optional
        Default every preset.
    find : {None, "outage"}
    start : float, optional
        With ``find="outage"``: the outage's start.
    **kw
        ``kind``, ``covariance_step``, ``algorithm``, ``g``.

    Returns
    -------
    list of dict
        ``{"name", "max_p95_position_m", "final_p95_position_m", "suitable", "warnings"}``
        (the keys of :func:`~imunav.analysis.design.design`'s presets, ``max_p95…`` added)
        and ``outside_linearisation`` (the attitude error's p95 beyond
        :data:`ATTITUDE_VALID`: the real EKF may diverge where the covariance does not), with
        ``find`` ``max_outage_s``, ``outage_start_s``, ``limited_by_motion``; sorted by the
        largest p95, those outside the linearisation last.
    """
    outs = _file_outages(aiding)
    rows = []
    for name in presets or list(PRESETS):
        imu = ImuModel.load(name)
        at = aided_covariance(motion, imu, aiding, rate, duration, **kw)
        t, truth, _, _, att = _outage_pass(at, outs)
        warnings = list(at.warnings)
        if att.max() > ATTITUDE_VALID:
            warnings.append(f"the attitude error reaches a p95 of {att.max():.3g} rad: beyond "
                            "the filter's linearisation")
        row = {"name": name, "max_p95_position_m": float(truth.max()),
               "final_p95_position_m": float(truth[-1]),
               "suitable": bool(truth.max() <= tolerance), "warnings": warnings,
               "outside_linearisation": bool(att.max() > ATTITUDE_VALID)}
        if find == "outage":
            f = find_outage(motion, imu, aiding, rate, tolerance, duration, start=start, at=at,
                            budget=False)
            row.update({k: f[k] for k in ("max_outage_s", "outage_start_s",
                                          "limited_by_motion")})
        rows.append(row)
    # a preset beyond the linearisation last: its small p95 is not to be trusted
    rows.sort(key=lambda r: (r["outside_linearisation"], r["max_p95_position_m"]))
    return rows


def design_aided(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                 tolerance: float, duration: float | None = None, *, find: str | None = None,
                 outage_start: float | None = None, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None,
                 g: float = G0, presets: bool = True, retune: bool = True) -> dict:
    """The numbers of ``imunav design --aiding`` (its JSON), the aided counterpart of
    :func:`~imunav.analysis.design.design`: the limit of each IMU error term with these aids
    (:func:`term_limits`: the others at the IMU's values, **the filter retuned to the term's
    value** — the limit with the filter kept at the IMU's own tuning beside it), the worst IMU
    that still passes (every IMU term scaled together, the filter retuned:
    :func:`common_scale`), every preset ranked (:func:`rank_presets`), all through the file's
    GNSS outages; the error budget at the worst time; and with ``find="outage"`` the longest
    bridgeable outage (:func:`find_outage`; top-level ``max_outage_s``, and each preset's).

    Parameters
    ----------
    motion, imu, aiding, rate, tolerance, duration
    find : {None, "outage"}
    outage_start : float, optional
        With ``find="outage"``: the outage's start (s).
    kind, covariance_step, algorithm, g
    presets : bool
        Rank every preset (one analysis each).
    retune : bool
        The term limits with the filter retuned (default) or kept at ``imu``'s tuning.

    Returns
    -------
    dict
        ``motion``, ``imu``, ``rate_hz``, ``tolerance_m``, ``aiding``, ``max_p95_position_m``,
        ``time_max_p95_s``, ``outages``; ``terms`` (as :func:`term_limits`: ``limit_si``,
        ``limit``, ``base`` — the keys of the unaided design's ``terms``); ``common_scale``;
        ``presets`` (``name``, ``max_p95_position_m``, ``final_p95_position_m``,
        ``suitable``, ``warnings``, with ``find`` ``max_outage_s``…), best first;
        ``error_budget_at_s``, ``error_budget``; with ``find``: ``max_outage_s``,
        ``outage_start_s``, ``position_p95_end_m``, ``limited_by_motion``,
        ``gnss_interval_s``, ``outage_error_budget``; ``warnings``.
    """
    tolerance = check_positive(tolerance, "tolerance")
    if find not in (None, "outage"):
        raise ImunavError(f"find must be 'outage', got {find!r}", argument="find")
    duration = _span(motion, rate, duration)
    if aiding.gnss is not None:
        aiding.gnss.check_within(0.0, duration)
    at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                          covariance_step=covariance_step, algorithm=algorithm, g=g,
                          terms=True)
    if find == "outage" and outage_start is not None and aiding.gnss is not None:
        # before the term limits' passes
        _check_start(_gnss_times(at), float(outage_start), float(at.t[-1]),
                     1.0 / aiding.gnss.rate)
    outs = _file_outages(aiding)
    t, truth, _, per = outage_p95(at, outs)
    for o in per:
        o["within_tolerance"] = bool(o["position_p95_max_m"] <= tolerance)
    worst = int(np.argmax(truth))
    r: dict = {"motion": motion.name, "imu": imu.name, "rate_hz": float(rate),
               "tolerance_m": tolerance, "aiding": list(aiding.sensors),
               "max_p95_position_m": float(truth[worst]), "time_max_p95_s": float(t[worst]),
               "outages": per,
               "terms": term_limits(at, tolerance, outs, retune=retune),
               "term_limits_filter": "retuned" if retune else "base",
               "common_scale": common_scale(at, tolerance, outs)}
    r["error_budget_at_s"] = float(t[worst])
    r["error_budget"] = outage_budget(at, outs, float(t[worst]))
    warnings = list(at.warnings) + _no_fix_warnings(at, outs)
    if find == "outage":
        f = find_outage(motion, imu, aiding, rate, tolerance, duration, start=outage_start,
                        at=at)
        r.update({k: f[k] for k in ("max_outage_s", "outage_start_s", "position_p95_end_m",
                                    "limited_by_motion", "gnss_interval_s")
                  if k in f})
        r["outage_error_budget"] = f["error_budget"]
        r["outage_error_budget_at_s"] = f.get("error_budget_at_s")
        warnings += [w for w in f["warnings"] if w not in warnings]
    if presets:
        r["presets"] = rank_presets(motion, aiding, rate, tolerance, duration, find=find,
                                    start=outage_start, kind=kind,
                                    covariance_step=covariance_step, algorithm=algorithm, g=g)
    r["warnings"] = warnings
    return r


def format_outage_design(r: dict) -> str:
    """The ``--find outage`` answer as text.

    Parameters
    ----------
    r : dict
        ``imunav design --aiding … --find outage``'s JSON.

    Returns
    -------
    str
    """
    lines = [f"Aided design for motion {r['motion']}, IMU {r['imu']} at {r['rate_hz']:g} Hz "
             f"with {', '.join(r['aiding'])}, tolerance {r['tolerance_m']:g} m (95th "
             "percentile of the position error):"]
    if "max_p95_position_m" in r:
        lines.append(f"  With the file's GNSS outages: largest p95 {r['max_p95_position_m']:.3g} "
                     f"m at t = {r['time_max_p95_s']:.4g} s.")
    if r.get("terms"):
        retuned = r.get("term_limits_filter", "retuned") == "retuned"
        lines.append("  Largest value of each IMU term, the others at this IMU's, within the "
                     "tolerance through the file's outages ("
                     + ("the filter retuned to each value; 'filter kept': the limit with the "
                        "filter at this IMU's tuning):" if retuned
                        else "the filter kept at this IMU's tuning):"))
        for k, v in sorted(r["terms"].items()):
            lim = printed(k, v["limit"])                  # "0 °/h": none of it is allowed
            extra = (f"; filter kept: {printed(k, v['limit_base_tuning'])}" if retuned and
                     v.get("limit_base_tuning_si") else "")
            note = f" — {v['note']}" if v.get("note") else ""
            lines.append(f"    {k:24s} {lim:>22s}   (this IMU: {printed(k, v['base'])}{extra})"
                         f"{note}")
    if r.get("common_scale") is not None:
        cs = r["common_scale"]
        if cs > 0:
            lines.append("  All IMU terms together: within the tolerance up to "
                         f"{cs:.3g} × this IMU's values"
                         + (" (it already meets it)." if cs >= 1 else
                            f" (its errors must shrink {1 / cs:.3g}-fold)."))
        else:
            lines.append("  No scale of this IMU's terms tried meets the tolerance with these "
                         "aids.")
    if r.get("error_budget") and "max_p95_position_m" in r:
        lines.append(f"  Error budget at t = {r['error_budget_at_s']:.4g} s (p95 of each "
                     "source alone):")
        for k, v in list(r["error_budget"].items())[:8]:
            lines.append(f"    {k:28s} {v:10.3g} m")
    if "max_outage_s" in r:
        L = r["max_outage_s"]
        lines.append(f"  Longest GNSS outage within the tolerance: max_outage_s = {L:g} s, "
                     f"starting at {r['outage_start_s']:g} s (p95 "
                     f"{r['position_p95_end_m']:.3g} m at its end)"
                     + (" — the whole rest of the motion: it bridges at least this"
                        if r["limited_by_motion"] else ""))
        budget = r.get("outage_error_budget", r.get("error_budget") if "outages" not in r
                       else None)
        if budget:
            lines.append("  Error budget at the outage's end (p95 of each source alone):")
            for k, v in list(budget.items())[:8]:
                lines.append(f"    {k:28s} {v:10.3g} m")
    if r.get("presets"):
        find = any("max_outage_s" in p for p in r["presets"])
        lines.append("  Presets, best first (largest 95th-percentile position error through the "
                     "file's outages" + ("; the longest outage each bridges" if find else "")
                     + "):")
        for p in r["presets"]:
            flag = "SUITABLE    " if p["suitable"] else "NOT SUITABLE"
            row = f"    {p['name']:10s} {flag} {p['max_p95_position_m']:10.3g} m"
            if find:
                row += (f"   max_outage_s {p['max_outage_s']:5g} s from "
                        f"{p['outage_start_s']:g} s"
                        + (" (the rest of the motion)" if p["limited_by_motion"] else ""))
            if p.get("outside_linearisation"):
                row += " (outside the linear model: check with Monte Carlo)"
            lines.append(row)
    for w in r["warnings"]:
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)


def _replace_outages(aiding: AidingConfig, outages) -> AidingConfig:
    """``aiding`` with other GNSS outages."""
    return dataclasses.replace(aiding, gnss=dataclasses.replace(aiding.gnss,
                                                                outages=tuple(outages)))
