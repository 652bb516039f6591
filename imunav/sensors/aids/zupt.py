"""Zero-velocity updates during stance, the stance found by the truth or by the SHOE detector
on the IMU data (Skog et al. 2010, as OpenShoe).

``[zupt]`` of ``AIDING.toml``: ``sigma`` (m/s), ``detector = "truth" | "shoe"``, ``window``
(samples, default 3) and ``threshold`` (default 3e4) of the SHOE detector. With ``truth`` the
stance intervals are read from ``zupt.csv`` (``t0,t1``); with ``shoe`` no file is needed. The
filter applies the update ``v = 0`` at every IMU node inside a stance interval.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from imunav.core.constants import DEG, G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DV
from imunav.core.validation import ImunavError
from imunav.sensors.aids.base import AidSpec, Key, Measurement, Readings, TableConfig, register

__all__ = ["SHOE_SIGMA_A", "SHOE_SIGMA_G", "STANCE_SPEED", "Zupt", "ZuptConfig", "intervals_of",
           "nodes_within", "shoe_intervals", "shoe_statistic", "true_stance"]

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
    threshold : float
        SHOE threshold: stance where the statistic is below it.
    """

    sigma: float
    detector: str = "truth"
    window: int = 3
    threshold: float = 3e4

    TABLE = "zupt"
    FIELDS = (Key("sigma", "m/s", "zero-velocity σ", required=True, hi=10.0),
              Key("detector", "", "stance detector", kind="choice", default="truth",
                  choices=("truth", "shoe")),
              Key("window", "samples", "SHOE window", kind="integer", default=3, hi=10000),
              Key("threshold", "", "SHOE threshold", default=3e4, hi=1e15))


class Zupt(Measurement):
    """A zero-velocity update.

    Parameters
    ----------
    sigma : float
        m/s.
    """

    name, columns, batched = "zupt", ("vx", "vy", "vz"), True

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


def shoe_intervals(t: FloatArray, gyro: FloatArray, accel: FloatArray, *, g: float = G0,
                   window: int = 3, threshold: float = 3e4) -> FloatArray:
    """Stance intervals by the SHOE detector.

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
            return shoe_intervals(ts, w, a, g=signals.g, window=config.window,
                                  threshold=config.threshold)
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
