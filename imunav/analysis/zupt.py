"""The foot-mounted walk with zero-velocity updates: how far does it drift, and does the stance
detector find the stances?

:func:`zupt_walk` simulates an IMU on a walk (:func:`imunav.motion.foot.foot_walk`), finds the
stances (the motion's true stance phases, ``detector="truth"``, or the SHOE detector on the IMU
data, ``"shoe"``, :func:`imunav.sensors.aids.shoe_intervals`) and runs the error-state filter
(:func:`imunav.estimation.filters.run_filter`) with a zero-velocity update at the filter's nodes
inside each stance, thinned to ``zupt_rate`` (each stance's first and last node always kept):
the filter's cost is one strapdown segment per update, and updates every 0.2 s carry almost all
a stance's information (its velocity drift over the stance). :func:`match_stances` counts the
detector's misses (true stances it found no part of) and false stances (detections outside
every true stance). The drift is the horizontal position error against the exact motion, as a
fraction of the distance walked.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, check_positive
from imunav.estimation.filters import FilterResult, run_filter
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig, AidingData, shoe_intervals, shoe_statistic
from imunav.sensors.models import ImuModel, MeasureStream
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import CHUNK, interval_count, simulate_imu

__all__ = ["StanceMatch", "WalkRun", "detect_stances", "match_stances", "thin_stances",
           "walk_table", "zupt_walk"]


@dataclass(frozen=True)
class StanceMatch:
    """A stance detector's intervals against the true stance phases.

    Attributes
    ----------
    true : int
        True stance phases.
    detected : int
        Detected intervals.
    missed : int
        True stances that no detected interval overlaps.
    false : int
        Detected intervals that overlap no true stance.
    coverage : float
        Fraction of the true stance time detected.
    outside : float
        Seconds detected outside every true stance.
    """

    true: int
    detected: int
    missed: int
    false: int
    coverage: float
    outside: float


def _length(iv: FloatArray) -> float:
    return float(np.sum(iv[:, 1] - iv[:, 0])) if iv.size else 0.0


def _intersection(a: FloatArray, b: FloatArray) -> float:
    """Seconds in both sets of disjoint intervals."""
    if not a.size or not b.size:
        return 0.0
    lo = np.maximum(a[:, None, 0], b[None, :, 0])
    hi = np.minimum(a[:, None, 1], b[None, :, 1])
    return float(np.clip(hi - lo, 0.0, None).sum())


def match_stances(true: FloatArray, detected: FloatArray) -> StanceMatch:
    """Count a detector's misses and false stances against the true stance phases.

    Parameters
    ----------
    true, detected : ndarray, shape (k, 2)
        Disjoint ``[t0, t1]`` intervals (s).

    Returns
    -------
    StanceMatch
    """
    true = np.asarray(true, dtype=float).reshape(-1, 2)
    detected = np.asarray(detected, dtype=float).reshape(-1, 2)
    if true.size and detected.size:
        over = (true[:, None, 0] <= detected[None, :, 1]) & (detected[None, :, 0] <= true[:, None, 1])
    else:
        over = np.zeros((true.shape[0], detected.shape[0]), dtype=bool)
    both = _intersection(true, detected)
    total = _length(true)
    return StanceMatch(int(true.shape[0]), int(detected.shape[0]), int((~over.any(1)).sum()),
                       int((~over.any(0)).sum()), both / total if total > 0 else float("nan"),
                       _length(detected) - both)


def thin_stances(intervals: FloatArray, t_nodes: FloatArray, rate: float | None) -> FloatArray:
    """The filter's nodes inside each stance interval, thinned to ``rate``, as point intervals
    ``[t, t]`` (what ``run_filter`` takes as ``data.zupt``).

    Parameters
    ----------
    intervals : ndarray, shape (k, 2)
        Stance intervals (s).
    t_nodes : ndarray, shape (N,)
        The filter's node times (``signals.state_times()``).
    rate : float or None
        Updates per second within a stance (None: every node); each stance's first and last
        node are always kept.

    Returns
    -------
    ndarray, shape (m, 2)
    """
    t_nodes = np.asarray(t_nodes, dtype=float)
    h = float(np.median(np.diff(t_nodes))) if t_nodes.size > 1 else 1.0
    step = 1 if rate is None else max(1, int(round(1.0 / (check_positive(rate, "zupt_rate") * h))))
    keep = []
    for a, b in np.asarray(intervals, dtype=float).reshape(-1, 2):
        idx = np.nonzero((t_nodes >= a - 1e-12) & (t_nodes <= b + 1e-12))[0]
        if idx.size:
            sel = idx[::step]
            keep.append(sel if sel[-1] == idx[-1] else np.append(sel, idx[-1]))
    t = t_nodes[np.concatenate(keep)] if keep else np.zeros(0)
    return np.stack([t, t], axis=1)


@dataclass
class WalkRun:
    """One ZUPT-aided walk.

    Attributes
    ----------
    result : FilterResult
    detector : str
    stances : FloatArray
        The stance intervals the filter used (before thinning).
    match : StanceMatch
        Those against the true stances.
    distance : float
        Metres walked (the path of the true positions).
    drift : float
        Horizontal position error at the end (m).
    drift_max : float
        Largest horizontal position error over the walk (m).
    stride_t : FloatArray
        The middle of each true stance (s).
    stride_error : FloatArray
        The horizontal position error there (m).
    statistic : FloatArray
        The SHOE statistic at the IMU samples (for the detector's timeline).
    t : FloatArray
        The IMU sample times of ``statistic``.
    shoe : StanceMatch
        The SHOE detector's intervals on these samples against the true stances, whichever
        detector the filter used (:func:`detect_stances` without simulating again).
    """

    result: FilterResult
    detector: str
    stances: FloatArray
    match: StanceMatch
    distance: float
    drift: float
    drift_max: float
    stride_t: FloatArray
    stride_error: FloatArray
    statistic: FloatArray
    t: FloatArray
    shoe: StanceMatch

    @property
    def drift_percent(self) -> float:
        """Final horizontal error as a percentage of the distance walked.

        Returns
        -------
        float
        """
        return 100.0 * self.drift / self.distance

    @property
    def drift_per_stride(self) -> float:
        """The horizontal error's growth per stride (m): its least-squares slope against the
        stride count.

        Returns
        -------
        float
        """
        k = np.arange(self.stride_error.size)
        return float(np.polyfit(k, self.stride_error, 1)[0]) if k.size > 1 else float("nan")


def zupt_walk(motion: BaseMotion, imu: ImuModel | str, rate: float = 100.0, *,
              detector: str = "truth", sigma: float = 0.01, zupt_rate: float | None = 5.0,
              threshold: float = 3e4, window: int = 3, seed: int = 0,
              algorithm: str | None = None, smooth: bool = False,
              ideal: ImuSignals | None = None) -> WalkRun:
    """Simulate ``imu`` on a walk and navigate it with zero-velocity updates.

    Parameters
    ----------
    motion : BaseMotion
        A walk with ``stance_intervals()`` (:class:`imunav.motion.foot.FootWalk`).
    imu : ImuModel or str
        The IMU simulated and assumed by the filter (a preset name or a model).
    rate : float
        IMU rate (Hz).
    detector : {"truth", "shoe"}
        The true stance phases, or the SHOE detector on the IMU data.
    sigma : float
        ZUPT velocity noise (m/s).
    zupt_rate : float or None
        Updates per second within a stance (None: at every IMU node).
    threshold, window : float, int
        The SHOE detector's (:func:`imunav.sensors.aids.shoe_intervals`).
    seed : int
        The IMU's random seed.
    algorithm : str, optional
        Strapdown algorithm of the filter (default the most accurate, ``poly8_m6``: a foot's
        swing is violent — at 100 Hz a second-order algorithm such as ``ignagni2`` alone drifts
        0.2 % of the distance with an ideal IMU, ``poly8_m6`` 0.0003 %).
    smooth : bool
        Also the RTS smoother.
    ideal : ImuSignals, optional
        The ideal increments of ``motion`` at the IMU's internal rate (``simulate_imu(motion,
        rate · imu.decimation(rate), kind="increments")``): most of a simulation's cost, the
        same for every preset and detector, so a table of runs simulates them once. The result
        is the same as without (the IMU's errors are applied to them exactly as
        :func:`~imunav.sensors.simulate.simulate_imu` does).

    Returns
    -------
    WalkRun

    Raises
    ------
    ImunavError
        For an unknown ``detector``, a motion without stance intervals, or an ``ideal`` record
        that is not that of ``motion`` at the internal rate.
    """
    if detector not in ("truth", "shoe"):
        raise ImunavError(f"detector must be \"truth\" or \"shoe\", got {detector!r}")
    if not hasattr(motion, "stance_intervals"):
        raise ImunavError("motion must be a walk with stance_intervals() (foot_walk)")
    model = ImuModel.load(imu) if isinstance(imu, str) else imu
    sig, found, stat, ts = _detect(motion, model, rate, seed, threshold, window, ideal)
    true = motion.stance_intervals()
    used = true if detector == "truth" else found
    t_nodes = sig.state_times()
    cfg = AidingConfig.from_dict({"zupt": {"sigma": sigma, "detector": "truth"}})
    data = AidingData(zupt=thin_stances(used, t_nodes, zupt_rate))
    st = motion.states(t_nodes[:1])
    res = run_filter(sig, st.quaternion[0], st.velocity[0], st.position[0], cfg, data,
                     imu=model, algorithm=algorithm, smooth=smooth)
    truth = motion.position(res.t)
    err = np.linalg.norm(res.states.position[:, :2] - truth[:, :2], axis=1)
    distance = float(np.linalg.norm(np.diff(truth[:, :2], axis=0), axis=1).sum())
    mid = true.mean(axis=1)
    stride_err = np.interp(mid, res.t, err)
    return WalkRun(res, detector, used, match_stances(true, used), distance, float(err[-1]),
                   float(err.max()), mid, stride_err, stat, ts, match_stances(true, found))


def _measured(motion, imu: ImuModel, rate: float, seed: int, ideal) -> ImuSignals:
    """What ``simulate_imu(motion, rate, kind="increments", imu=imu, seed=seed)`` returns,
    from the ideal increments at the internal rate: the same random streams, the same chunks
    (``tests/motion/test_foot.py`` checks it bit for bit)."""
    k = imu.decimation(rate)
    n = k * interval_count(rate, float(motion.duration))
    if not isinstance(ideal, ImuSignals) or ideal.kind != "increments" or len(ideal) != n \
            or not np.isclose(ideal.rate, rate * k, rtol=1e-12, atol=0.0):
        got = (f"{ideal.kind} at {ideal.rate:g} Hz, {len(ideal)} samples"
               if isinstance(ideal, ImuSignals) else type(ideal).__name__)
        raise ImunavError(f"ideal must be the ideal increments of the motion at the IMU's "
                          f"internal rate ({rate * k:g} Hz, {n} samples), got {got}",
                          argument="ideal")
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    stream = MeasureStream(imu, "increments", rate * k, rng, k)
    size = max(k, CHUNK // k * k)
    parts = []
    for lo in range(0, n, size):
        gm, am, _ = stream.process(ideal.gyro[lo:lo + size], ideal.accel[lo:lo + size])
        parts.append((ideal.t[lo:lo + size][k - 1::k][: gm.shape[0]], gm, am))
    t, gyro, accel = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return ImuSignals(t, gyro, accel, "increments", float(rate), ideal.g, meta=dict(ideal.meta))


def _detect(motion, imu, rate, seed, threshold, window, ideal=None):
    """The IMU record of the walk and the SHOE detector on it: the mean rates of each
    increment at the interval's middle, as the filter's own ``"shoe"`` path."""
    if ideal is None:
        sig = simulate_imu(motion, rate, float(motion.duration), kind="increments",
                           imu=imu, seed=seed)
    else:
        sig = _measured(motion, imu, rate, seed, ideal)
    h = 1.0 / rate
    w, a, ts = sig.gyro / h, sig.accel / h, sig.t - h / 2
    stat = shoe_statistic(w, a, g=sig.g, window=window)
    found = shoe_intervals(ts, w, a, g=sig.g, window=window, threshold=threshold)
    return sig, found, stat, ts


def detect_stances(motion: BaseMotion, imu: ImuModel | str, rate: float = 100.0, *,
                   threshold: float = 3e4, window: int = 3, seed: int = 0,
                   ideal: ImuSignals | None = None) -> StanceMatch:
    """The SHOE detector on the IMU record of :func:`zupt_walk` (same seed, same samples),
    against the true stances — without running the filter.

    Parameters
    ----------
    motion : BaseMotion
        A walk with ``stance_intervals()``.
    imu : ImuModel or str
    rate : float
        IMU rate (Hz).
    threshold, window : float, int
        The SHOE detector's.
    seed : int
    ideal : ImuSignals, optional
        As :func:`zupt_walk`.

    Returns
    -------
    StanceMatch
    """
    model = ImuModel.load(imu) if isinstance(imu, str) else imu
    found = _detect(motion, model, rate, seed, threshold, window, ideal)[1]
    return match_stances(motion.stance_intervals(), found)


def walk_table(motion: BaseMotion, presets: list[str], rate: float = 100.0, *,
               detectors: tuple[str, ...] = ("truth", "shoe"), **kw) -> list[dict]:
    """:func:`zupt_walk` for every preset and detector: one row each (the ideal record
    simulated once for all).

    Parameters
    ----------
    motion : BaseMotion
    presets : list of str
    rate : float
    detectors : tuple of str
    **kw
        Passed to :func:`zupt_walk`.

    Returns
    -------
    list of dict
        ``preset, detector, distance_m, drift_m, drift_percent, drift_max_percent,
        drift_per_stride_m, true, detected, missed, false``.
    """
    rows = []
    ideal: dict[float, ImuSignals] = {}                 # simulated once per internal rate
    for p in presets:
        model = ImuModel.load(p)
        r = rate * model.decimation(rate)
        if r not in ideal:
            ideal[r] = simulate_imu(motion, r, float(motion.duration), kind="increments")
        for d in detectors:
            w = zupt_walk(motion, model, rate, detector=d, ideal=ideal[r], **kw)
            rows.append({"preset": p, "detector": d, "distance_m": w.distance, "drift_m": w.drift,
                         "drift_percent": w.drift_percent,
                         "drift_max_percent": 100 * w.drift_max / w.distance,
                         "drift_per_stride_m": w.drift_per_stride, "true": w.match.true,
                         "detected": w.match.detected, "missed": w.match.missed,
                         "false": w.match.false})
    return rows
