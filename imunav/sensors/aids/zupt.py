"""Zero-velocity updates during stance, the stance found by the truth or by the SHOE detector
on the IMU data (Skog et al. 2010, as OpenShoe).

``[zupt]`` of ``AIDING.toml``: ``sigma`` (m/s), ``detector = "truth" | "shoe"``, and the SHOE
detector's ``window`` (samples, default 3). With ``truth`` the stance intervals are read from
``zupt.csv`` (``t0,t1``); with ``shoe`` no file is needed. The filter applies the update
``v = 0`` at every IMU node inside a stance interval.

**The SHOE detector's one parameter set** (the defaults; nothing chosen against a truth): the
statistic's noise levels follow from what a zero-velocity update of σ_z = ``sigma`` allows —
σ_a = σ_z/(W h) (a specific force that changes the velocity by σ_z over the window of W
samples) and σ_g = σ_z/r with r = ``lever`` (0.1 m: a foot rolling about its ground contact
moves the IMU at ω r) —, stance where W·T lies below the χ² quantile of ``probability`` (0.99)
with 6W − 2 degrees of freedom (the statistic at rest when the foot moves no more than the update
assumes); and, with ``stride`` (1.2 s: the longest stride of a walk), the sample whose
statistic is the smallest of its centred stride window is stance too — a walking or running
foot stands still once in every stride, even where it rolls faster than the χ² threshold
allows. An explicit ``threshold`` instead gives the classic detector of Skog et al. (2010) with
OpenShoe's noise levels (σ_a 0.01 m/s², σ_g 0.1 °/s) and no stride rule.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.ndimage import minimum_filter1d
from scipy.stats import chi2

from imunav.core.constants import DEG, G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DV
from imunav.core.validation import ImunavError
from imunav.sensors.aids.base import AidSpec, Key, Measurement, Readings, TableConfig, register

__all__ = ["SHOE_SIGMA_A", "SHOE_SIGMA_G", "STANCE_SPEED", "Zupt", "ZuptConfig", "intervals_of",
           "nodes_within", "shoe_intervals", "shoe_statistic", "stance_flags", "true_stance"]

#: The SHOE detector's noise levels (OpenShoe's defaults, Skog et al. 2010): accelerometer
#: 0.01 m/s², gyro 0.1 °/s.
SHOE_SIGMA_A = 0.01
SHOE_SIGMA_G = 0.1 * DEG

#: Speed (m/s) below which the true motion counts as standing still.
STANCE_SPEED = 1e-9


@dataclass(frozen=True)
class ZuptConfig(TableConfig):
    """Zero-velocity updates during stance.

    Attributes
    ----------
    sigma : float
        Velocity noise of the update (m/s, per axis).
    detector : {"truth", "shoe"}
        The stance intervals of the motion (``zupt.csv``), or the SHOE detector on the IMU data.
    window : int
        SHOE window (samples).
    threshold : float or None
        The classic SHOE threshold (OpenShoe's noise levels); None: the χ² rule below.
    lever : float
        The foot's rolling lever (m): σ_g = sigma / lever.
    probability : float
        The χ² threshold's probability.
    stride : float
        The longest stride (s): one stance per stride window (0: none).
    """

    sigma: float
    detector: str = "truth"
    window: int = 3
    threshold: float | None = None
    lever: float = 0.1
    probability: float = 0.99
    stride: float = 1.2

    TABLE = "zupt"
    FIELDS = (Key("sigma", "m/s", "zero-velocity σ", required=True, hi=10.0),
              Key("detector", "", "stance detector", kind="choice", default="truth",
                  choices=("truth", "shoe")),
              Key("window", "samples", "SHOE window", kind="integer", default=3, hi=10000),
              Key("threshold", "", "SHOE threshold (the classic detector)", hi=1e15),
              Key("lever", "m", "foot contact lever", default=0.1, hi=2.0),
              Key("probability", "", "stance probability of the χ² threshold", default=0.99,
                  hi=1.0 - 1e-12),
              Key("stride", "s", "longest stride (0: no stride rule)", default=1.2,
                  positive=False, hi=10.0))


class Zupt(Measurement):
    """A zero-velocity update.

    Parameters
    ----------
    sigma : float
        m/s.
    """

    name, columns, batched = "zupt", ("vx", "vy", "vz"), True
    gated = False                    # the detector decided: a stance is applied, never gated

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``v``.
        return np.array(nav.v, dtype=float)

    def jacobian(self, nav):
        # ``δv``.
        H = self.zeros_H(nav)
        H[..., :, DV] = np.eye(3)
        return H

    def noise(self):
        # ``σ² I₃``.
        return self.sigma ** 2 * np.eye(3)


def intervals_of(flags: np.ndarray, t: FloatArray) -> FloatArray:
    """The runs of True in ``flags`` as ``[t_first, t_last]`` intervals.

    Parameters
    ----------
    flags : ndarray of bool, shape (n,)
    t : ndarray, shape (n,)
        The times of the flags.

    Returns
    -------
    ndarray, shape (k, 2)
    """
    f = np.concatenate([[False], np.asarray(flags, dtype=bool), [False]])
    d = np.diff(f.astype(int))
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1
    return np.stack([t[starts], t[ends]], axis=1) if starts.size else np.zeros((0, 2))


def nodes_within(intervals: FloatArray, t_nodes: FloatArray) -> FloatArray:
    """The node times inside stance intervals (ends included).

    Parameters
    ----------
    intervals : ndarray, shape (k, 2)
    t_nodes : ndarray, shape (n,)

    Returns
    -------
    ndarray
    """
    keep = np.zeros(t_nodes.size, dtype=bool)
    for a, b in np.asarray(intervals, dtype=float).reshape(-1, 2):
        keep |= (t_nodes >= a - 1e-12) & (t_nodes <= b + 1e-12)
    return t_nodes[keep]


def true_stance(motion, rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """The intervals where the motion stands still (zero velocity), sampled at ``rate``.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Hz.
    duration : float
        s.
    t0 : float
        Start time (s).

    Returns
    -------
    ndarray, shape (k, 2)
        ``[t0, t1]`` of each run of samples with ``|v| ≤`` :data:`STANCE_SPEED`.
    """
    n = int(round(duration * rate))
    t = t0 + np.arange(n + 1) / rate
    still = np.linalg.norm(motion.velocity(t), axis=1) <= STANCE_SPEED
    return intervals_of(still, t)


def shoe_statistic(gyro: FloatArray, accel: FloatArray, *, g: float = G0, window: int = 3,
                   sigma_a: float = SHOE_SIGMA_A, sigma_g: float = SHOE_SIGMA_G) -> FloatArray:
    """The SHOE (stance hypothesis optimal estimation) test statistic of Skog et al. (2010).

    ``T_k = (1/W) Σ_{l ∈ W_k} ( |a_l − g ā/|ā||² / σ_a² + |ω_l|² / σ_g² )`` over a centred
    window of ``W`` samples (ā its mean specific force); stance where ``T_k`` is below the
    threshold.

    Parameters
    ----------
    gyro, accel : ndarray, shape (n, 3)
        Rate samples: ``ω_b`` (rad/s) and ``f_b`` (m/s²).
    g : float
        Gravity (m/s²).
    window : int
        ``W`` (samples).
    sigma_a, sigma_g : float
        The noise levels the statistic is normalised by.

    Returns
    -------
    ndarray, shape (n,)
        ``T`` at each sample (the window's ends padded with the edge values).
    """
    n = gyro.shape[0]
    W = max(1, min(int(window), n))
    aw = sliding_window_view(np.asarray(accel, float), W, axis=0)     # (m, 3, W)
    ww = sliding_window_view(np.asarray(gyro, float), W, axis=0)
    am = aw.mean(axis=2)
    u = am / np.linalg.norm(am, axis=1, keepdims=True)
    acc_term = ((aw - g * u[:, :, None]) ** 2).sum(axis=(1, 2)) / W
    T = acc_term / sigma_a**2 + (ww ** 2).sum(axis=(1, 2)) / W / sigma_g**2
    m = T.size
    lo = (W - 1) // 2
    out = np.empty(n)
    out[lo:lo + m] = T
    out[:lo] = T[0]
    out[lo + m:] = T[-1]
    return out


def stance_flags(gyro: FloatArray, accel: FloatArray, rate: float, *, sigma: float,
                 g: float = G0, window: int = 3, lever: float = 0.1, probability: float = 0.99,
                 stride: float = 1.2) -> np.ndarray:
    """Stance at each sample by the SHOE statistic with the noise levels a zero-velocity update
    of σ = ``sigma`` allows and its χ² threshold, plus one stance per stride (see the module
    docstring).

    Parameters
    ----------
    gyro, accel : ndarray, shape (n, 3)
        Rate samples (rad/s, m/s²).
    rate : float
        Hz.
    sigma : float
        The update's σ (m/s).
    g : float
    window : int
    lever, probability, stride : float

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    W = max(1, int(window))
    T = shoe_statistic(gyro, accel, g=g, window=W, sigma_a=sigma * rate / W,
                       sigma_g=sigma / lever)
    flags = T < chi2.ppf(probability, 6 * W - 2) / W
    n = int(round(stride * rate))
    if n >= 3:
        smallest = T <= minimum_filter1d(T, n, mode="nearest")
        near = smallest.copy()
        for k in (1, 2):                       # ± 2 samples around the stride's quietest one
            near[k:] |= smallest[:-k]
            near[:-k] |= smallest[k:]
        flags |= near
    return flags


def shoe_intervals(t: FloatArray, gyro: FloatArray, accel: FloatArray, *, g: float = G0,
                   window: int = 3, threshold: float = 3e4) -> FloatArray:
    """Stance intervals by the classic SHOE detector (OpenShoe's noise levels).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times (s).
    gyro, accel : ndarray, shape (n, 3)
        Rate samples (rad/s, m/s²).
    g : float
        Gravity (m/s²).
    window : int
        Samples.
    threshold : float
        Stance where the statistic is below it.

    Returns
    -------
    ndarray, shape (k, 2)
    """
    T = shoe_statistic(gyro, accel, g=g, window=window)
    return intervals_of(T < threshold, t)


class ZuptSpec(AidSpec):
    """The zero-velocity aid (see the module docstring)."""

    name = "zupt"
    summary = "zero-velocity updates during stance"
    config = ZuptConfig
    file = "zupt.csv"
    headers = {"flat": (("t0", "t1"),), "wgs84": (("t0", "t1"),)}
    intervals = True
    stream = 4

    def units(self, config):
        return ("m/s",) * 3

    def measurement(self, config, *, truth=False):
        return Zupt(config.sigma)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        if config.detector != "truth":
            return None
        return true_stance(motion, imu_rate or 100.0, duration, t0)

    def file_needed(self, config):
        return config.detector == "truth"

    def rate(self, config):
        return None

    def stance(self, config, data, signals) -> FloatArray:
        """The stance intervals the filter uses: the SHOE detector's on the IMU data, or the
        given ones.

        Parameters
        ----------
        config : ZuptConfig
        data : AidingData
        signals : ImuSignals

        Returns
        -------
        ndarray, shape (k, 2)

        Raises
        ------
        ImunavError
            For the truth detector without its intervals.
        """
        if config.detector == "shoe":
            h = 1.0 / signals.rate
            inc = signals.kind == "increments"
            w = signals.gyro / h if inc else signals.gyro
            a = signals.accel / h if inc else signals.accel
            ts = signals.t - (h / 2 if inc else 0.0)
            if config.threshold is not None:
                return shoe_intervals(ts, w, a, g=signals.g, window=config.window,
                                      threshold=config.threshold)
            return intervals_of(stance_flags(w, a, signals.rate, sigma=config.sigma,
                                             g=signals.g, window=config.window,
                                             lever=config.lever, probability=config.probability,
                                             stride=config.stride), ts)
        intervals = data.get(self.name)
        if intervals is None:
            raise ImunavError("[zupt] detector = \"truth\" needs the stance intervals "
                              "(zupt.csv)", argument="data")
        return intervals

    def readings(self, config, data, signals):
        tz = nodes_within(self.stance(config, data, signals), signals.state_times())
        return Readings(tz, np.zeros((tz.size, 3)))

    def times(self, config, motion, rate, duration):
        n = int(round(duration * rate))
        return nodes_within(true_stance(motion, rate, duration), np.arange(n + 1) / rate)

    def analysis_warnings(self, config) -> list[str]:
        """What the covariance analysis cannot model of this aid.

        Parameters
        ----------
        config : ZuptConfig

        Returns
        -------
        list of str
        """
        if config.detector == "shoe":
            return ["the covariance analysis applies zero-velocity updates over the true "
                    "stance phases: the SHOE detector's misses and false stances are in the "
                    "Monte Carlo only (--runs)"]
        return []


register(ZuptSpec())
