"""Analyses of real recordings: the device's quaternion convention checked against the gyro,
gyro-only attitude against the device's, stationary segments, drift from rest, and bias
calibration judged out of sample; and the errors of a filtered log against its truth (a car's
withheld GNSS fixes in simulated outages, a foot's motion-capture track).

The readers are :mod:`imunav.io.realdata`; for one import in a notebook the shipped recordings'
readers are re-exported here (``read_ximu3``, ``read_ximu``, ``read_generic``, ``data_path``,
``Recording``).

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.strapdown``, ``imunav.io``.
"""

from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from imunav.core.kernels import FloatArray, quat_angle, quat_conj, quat_mul, quat_rotate
from imunav.core.validation import ImunavError
from imunav.io.realdata import READERS, Recording, data_path, read_generic, read_ximu, read_ximu3
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.initial import level_attitude, remove_static_biases
from imunav.strapdown.registry import navigate

__all__ = ["CHI2_2_95", "READERS", "Recording", "aligned_track", "antenna_track", "armse2d", "data_path",
           "device_as_q_nb", "outage_errors", "outage_schedule",
           "device_quaternion_convention", "drift_from_rest", "gyro_attitude", "gyro_vs_device",
           "holdout_bias", "read_generic", "read_ximu", "read_ximu3", "static_segments"]


def gyro_attitude(sig: ImuSignals, q0: FloatArray, i0: int = 0, i1: int | None = None,
                  algorithm: str = "magnus6") -> FloatArray:
    """Gyro-only attitude from sample ``i0`` (attitude ``q0``) to ``i1``: (i1 − i0, 4)."""
    i1 = len(sig) if i1 is None else i1
    sub = ImuSignals(sig.t[i0:i1], sig.gyro[i0:i1], sig.accel[i0:i1], "rates", sig.rate, sig.g)
    return navigate(sub, q0, algorithm=algorithm).quaternion


def _device_at(rec: Recording, layout: str) -> FloatArray:
    q = rec.device_q
    if layout == "wxyz":
        out = q
    elif layout == "xyzw":
        out = q[:, [3, 0, 1, 2]]
    else:
        raise ImunavError(f"layout must be 'wxyz' or 'xyzw', got {layout!r}")
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def device_quaternion_convention(rec: Recording, window: float = 2.0) -> dict:
    """Which reading of the device quaternion agrees with the gyro?

    For each candidate (element order ``wxyz``/``xyzw``; the quaternion as sensor→earth
    ``q_nb`` or as earth→sensor ``q_bn = q_nb*``) compare the relative rotation the device
    reports over consecutive windows with the gyro's (frame-free: body-frame relative
    rotations do not depend on the earth frame's axes). Returns the median disagreement (deg)
    per candidate.
    """
    sig = rec.signals
    n = int(window * sig.rate)
    out = {}
    idx = np.arange(0, len(sig) - n, n)
    ti = np.searchsorted(rec.device_t, sig.t[idx])
    tj = np.searchsorted(rec.device_t, sig.t[idx + n])
    ok = (ti < len(rec.device_t)) & (tj < len(rec.device_t))
    for layout in ("wxyz", "xyzw"):
        qd = _device_at(rec, layout)
        for meaning in ("q_nb", "q_bn"):
            errs = []
            for a, b, i in zip(ti[ok], tj[ok], idx[ok], strict=True):
                qa, qb = qd[a], qd[b]
                if meaning == "q_bn":
                    qa, qb = quat_conj(qa), quat_conj(qb)
                rel_dev = quat_mul(quat_conj(qa), qb)
                g = gyro_attitude(sig, [1.0, 0, 0, 0], i, i + n + 1)[-1]
                errs.append(np.degrees(quat_angle(rel_dev, g)))
            out[f"{layout}/{meaning}"] = float(np.median(errs))
    return out


def device_as_q_nb(rec: Recording) -> FloatArray:
    """The device quaternion as ``q_nb`` (device body axes → device earth frame), using the
    convention :func:`device_quaternion_convention` establishes for each device:
    x-IMU3 ``[W, X, Y, Z]`` sensor→earth; x-IMU ``[w, x, y, z]`` earth→sensor (conjugated)."""
    q = _device_at(rec, "wxyz")
    if rec.meta.get("device") == "x-IMU":
        q = quat_conj(q)
    return q


def gyro_vs_device(rec: Recording, windows=(0.25, 0.5, 1.0, 2.0), algorithm: str = "magnus6",
                   gyro_bias: FloatArray | None = None, start: float = 0.0) -> dict[float, float]:
    """Median angle (deg) between gyro-only and device attitude at the end of windows of each
    length, each window started from the device attitude (start times from ``start`` on)."""
    sig = rec.signals
    if gyro_bias is not None:
        sig = ImuSignals(sig.t, sig.gyro - gyro_bias, sig.accel, "rates", sig.rate, sig.g)
    qd = device_as_q_nb(rec)
    out = {}
    for w in windows:
        n = int(round(w * sig.rate))
        errs = []
        for i in range(int(start * sig.rate), len(sig) - n - 1, max(n, 1)):
            a = int(np.searchsorted(rec.device_t, sig.t[i]))
            b = int(np.searchsorted(rec.device_t, sig.t[i + n]))
            if b >= len(rec.device_t):
                break
            q = gyro_attitude(ImuSignals(sig.t, sig.gyro, sig.accel, "rates", sig.rate, sig.g),
                              qd[a], i, i + n + 1, algorithm)[-1]
            errs.append(np.degrees(quat_angle(q, qd[b])))
        out[w] = float(np.median(errs))
    return out


def static_segments(sig: ImuSignals, window: float = 0.5, gyro_tol: float = np.radians(3.0),
                    accel_tol: float = 0.03) -> list[tuple[int, int]]:
    """Index ranges where, over sliding ``window`` s, each gyro axis spreads by less than
    ``gyro_tol`` (max − min: a biased gyro at rest still counts) and |f| stays within
    ``accel_tol`` (relative) of g: candidate stationary periods for bias estimation.

    Each range ``(i0, i1)`` is half-open: it starts at the first quiet window and ends with the
    last sample of the last quiet window (a window of ``n`` samples starting at ``j − 1`` ends
    at ``j + n − 2``, so ``i1 = j + n − 1``), so no sample after the motion resumes is in it."""
    n = max(2, int(window * sig.rate))
    gw = sliding_window_view(sig.gyro, n, axis=0)            # (N−n+1, 3, n)
    spread = (gw.max(axis=-1) - gw.min(axis=-1)).max(axis=-1)
    a = np.abs(np.linalg.norm(sig.accel, axis=1) / sig.g - 1)
    aw = sliding_window_view(a, n).max(axis=-1)
    ok = (spread < gyro_tol) & (aw < accel_tol)
    segs, i = [], 0
    while i < len(ok):
        if ok[i]:
            j = i
            while j < len(ok) and ok[j]:
                j += 1
            segs.append((i, j - 1 + n))      # the last quiet window starts at j − 1
            i = j
        else:
            i += 1
    return segs


def drift_from_rest(sig: ImuSignals, i0: int, i1: int, bias_window: int | None = None,
                    algorithm: str = "magnus6") -> dict:
    """Double-integrate the accelerometers over a stationary stretch ``[i0, i1)`` from rest,
    with the attitude from the resting accelerometer and the gyro. The true position stays 0,
    so |p(t)| is pure drift; it is fitted as ``c₂t² + c₃t³`` (accelerometer residual bias,
    and tilt from gyro bias feeding gravity into the horizontal).

    ``bias_window``: if given, gyro bias and accelerometer residual are first estimated over
    the first ``bias_window`` samples and subtracted (static-segment calibration)."""
    g, a = sig.gyro[i0:i1], sig.accel[i0:i1]
    nb = bias_window or min(len(g), int(0.5 * sig.rate))
    q0 = level_attitude(a[:nb], sig.g, tol=0.1)
    if bias_window:
        g, a, _, _ = remove_static_biases(g, a, slice(0, bias_window), q0, sig.g)
    sub = ImuSignals(sig.t[i0:i1] - sig.t[i0], g, a, "rates", sig.rate, sig.g)
    nav = navigate(sub, q0, algorithm=algorithm)
    t = nav.t
    d = np.linalg.norm(nav.position, axis=1)
    A = np.stack([t**2, t**3], 1)
    c, *_ = np.linalg.lstsq(A, d, rcond=None)
    return {"t": t, "drift": d, "c2": float(c[0]), "c3": float(c[1])}


def holdout_bias(sig: ImuSignals, i0: int, i1: int, split: int,
                 algorithm: str = "magnus6") -> dict:
    """Bias calibration judged out of sample: gyro and accelerometer offsets estimated over
    ``[i0, split)`` of a static stretch, then the held-out ``[split, i1)`` navigated from rest
    (attitude from its own first samples) two ways — raw, and with the estimated offsets
    (out of sample: what a calibration delivers, judged on data it has not seen). Returns the
    drift histories and their final values (m)."""
    if not i0 < split < i1:
        raise ImunavError(f"split must lie inside ({i0}, {i1}), got {split}")
    g_all, a_all = sig.gyro, sig.accel
    est = slice(i0, split)
    q_est = level_attitude(a_all[est], sig.g, tol=0.1)
    _, _, bg, ba = remove_static_biases(g_all[est], a_all[est], slice(None), q_est, sig.g)
    test_g, test_a = g_all[split:i1], a_all[split:i1]
    q0 = level_attitude(test_a[: max(2, (i1 - split) // 4)], sig.g, tol=0.1)
    out = {"estimation_s": (split - i0) / sig.rate, "test_s": (i1 - split) / sig.rate,
           "gyro_bias_est": bg, "accel_bias_est": ba}
    for name, (dg, da) in (("raw", (0.0, 0.0)), ("out_of_sample", (bg, ba))):
        sub = ImuSignals(sig.t[split:i1] - sig.t[split], test_g - dg, test_a - da, "rates",
                         sig.rate, sig.g)
        nav = navigate(sub, q0, algorithm=algorithm)
        d = np.linalg.norm(nav.position, axis=1)
        out[name] = {"t": nav.t, "drift": d, "final": float(d[-1])}
    return out


# ----------------------------------------------------------------------------- logs with truth

def outage_schedule(t_gnss: FloatArray, length: float = 15.0, first: float = 40.0,
                    period: float = 45.0, end_margin: float = 30.0
                    ) -> list[tuple[float, float]]:
    """Simulated GNSS outages on a log (rtklibexplorer's evaluation of his drive): ``length`` s
    each, the first starting ``first`` s after the first epoch, then one every ``period`` s, the
    last ending before ``end_margin`` s from the last epoch.

    Parameters
    ----------
    t_gnss : ndarray
        The GNSS epochs (s).
    length, first, period, end_margin : float
        Seconds.

    Returns
    -------
    list of (float, float)
    """
    t_gnss = np.asarray(t_gnss, float)
    out, s = [], float(t_gnss[0]) + first
    while s + length <= float(t_gnss[-1]) - end_margin:
        out.append((s, s + length))
        s += period
    return out


def antenna_track(states, t: FloatArray, lever_arm) -> FloatArray:
    """An estimate's antenna position at times ``t``: the node before each carried by its
    velocity, plus the lever arm turned by its attitude.

    Parameters
    ----------
    states : States
        The estimate (flat frame).
    t : ndarray, shape (k,)
    lever_arm : array_like, shape (3,)
        The antenna in the body frame (m).

    Returns
    -------
    ndarray, shape (k, 3)
    """
    t = np.asarray(t, float)
    k = np.clip(np.searchsorted(states.t, t) - 1, 0, states.t.size - 1)
    return (states.position[k] + states.velocity[k] * (t - states.t[k])[:, None]
            + quat_rotate(states.quaternion[k],
                          np.broadcast_to(np.asarray(lever_arm, float), (t.size, 3))))


#: χ² with 2 degrees of freedom at 95 %: the filter's own horizontal 95 % ellipse.
CHI2_2_95 = 5.991464547107979


def outage_errors(result, t_fix: FloatArray, ned_fix: FloatArray, outages, lever_arm, *,
                  smoothed: bool = False) -> dict:
    """The horizontal error of an estimated antenna track against the GNSS fixes withheld in
    each outage, and how many of them lie inside the filter's own 95 % ellipse.

    Parameters
    ----------
    result : FilterResult
        The filter's (its horizontal covariance at the last covariance epoch before each fix).
    t_fix, ned_fix : ndarray
        The fixes: times (s) and NED positions (m).
    outages : list of (float, float)
    lever_arm : array_like, shape (3,)
    smoothed : bool
        The errors of ``result.smoothed`` (the ellipse stays the filter's).

    Returns
    -------
    dict
        ``per_outage`` (the largest horizontal error of each, m), ``median``, ``mean``,
        ``worst``, ``inside_95``; ``t``, ``error`` (k, 2) and ``sd`` (k, 2) of every withheld
        fix.
    """
    r = result.smoothed if smoothed else result
    ep_t = result.t[result.epochs]
    per, ts, errs, sds, inside = [], [], [], [], 0
    for a, b in outages:
        k = (t_fix >= a) & (t_fix <= b)
        e = (antenna_track(r.states, t_fix[k], lever_arm) - ned_fix[k])[:, :2]
        per.append(float(np.hypot(e[:, 0], e[:, 1]).max()))
        j = np.clip(np.searchsorted(ep_t, t_fix[k], side="right") - 1, 0, ep_t.size - 1)
        P = result.P_nav[j][:, 6:8, 6:8]
        inside += int((np.einsum("ni,nij,nj->n", e, np.linalg.inv(P), e) <= CHI2_2_95).sum())
        ts.append(t_fix[k])
        errs.append(e)
        sds.append(np.sqrt(np.diagonal(P, axis1=1, axis2=2)))
    per = np.array(per)
    n = sum(x.size for x in ts)
    return {"per_outage": per.tolist(), "median": float(np.median(per)),
            "mean": float(per.mean()), "worst": float(per.max()), "inside_95": inside / n,
            "t": np.concatenate(ts), "error": np.concatenate(errs), "sd": np.concatenate(sds)}


def aligned_track(estimate: FloatArray, truth: FloatArray, distance: float = 0.8
                  ) -> tuple[FloatArray, FloatArray]:
    """The PyShoe dataset's alignment of a foot-mounted track to its truth: both shifted to
    start at 0; the estimate turned about the vertical so that its horizontal position at the
    first sample at least ``distance`` of horizontal travel from its start (the last sample if
    it never gets that far) points the way the truth's does at that sample.

    Parameters
    ----------
    estimate, truth : ndarray, shape (n, ≥2)
        Positions at the same samples (m).
    distance : float

    Returns
    -------
    estimate, truth : ndarray, shape (n, 2)
        Horizontal, aligned.
    """
    e = np.asarray(estimate, float)[:, :2] - np.asarray(estimate, float)[0, :2]
    g = np.asarray(truth, float)[:, :2] - np.asarray(truth, float)[0, :2]
    r = np.hypot(e[:, 0], e[:, 1])
    k = int(np.argmax(r >= distance)) if (r >= distance).any() else len(r) - 1
    a = np.arctan2(g[k, 1], g[k, 0]) - np.arctan2(e[k, 1], e[k, 0])
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return e @ R.T, g


def armse2d(estimate: FloatArray, truth: FloatArray, distance: float = 0.8) -> float:
    """The PyShoe dataset's error of a foot-mounted track: the mean over samples of
    ``√((Δx² + Δy²)/2)`` after :func:`aligned_track`.

    Parameters
    ----------
    estimate, truth : ndarray, shape (n, ≥2)
        Positions at the same samples (m).
    distance : float

    Returns
    -------
    float
        Metres.
    """
    e, g = aligned_track(estimate, truth, distance)
    d = e - g
    return float(np.mean(np.sqrt((d ** 2).sum(axis=1) / 2)))
