"""Filtering a real log: what a recording needs before the filter can use it, and the pipeline
that does it — :func:`filter_log` (what ``imunav filter`` runs on a log without a truth file).

A real log differs from a simulation in what it does not give and in what it gets wrong:

- **the IMU's axes are not the vehicle's**: ``[mounting] rpy_deg`` turns the samples into the
  vehicle's forward-right-down axes (:func:`mounted`), so that the non-holonomic constraint,
  the odometer and a GNSS heading hold along the body x axis;
- **its clock is not the aids'**: ``[mounting] time_offset`` (or ``time_offset="auto"``:
  :func:`imu_time_offset`, the lag that best lines up the IMU's yaw rate with the GNSS course
  rate) moves the IMU's time stamps; a receiver's velocity may lag its own positions
  (:func:`velocity_lag`, from the positions' differences);
- **its noise is not the datasheet's**: in a vehicle the engine's vibration and in a shoe the
  foot's own motion are noise the datasheet leaves out. ``noise="rest"`` measures the white
  noise on the still start (:func:`rest_noise`: the Allan deviation at τ = 1 s) and raises the
  IMU model's densities to it;
- **there is no truth to start from**: ``align="static"`` levels the still start (heading 0,
  position 0: the frame of a foot-mounted walk), ``align="gnss"`` levels it and takes the
  heading from the GNSS velocity once moving (:mod:`imunav.strapdown.initial`);
- **the IMU may be unknown**: :func:`unknown_imu` is the stated default model.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.strapdown``, ``imunav.estimation``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from imunav.core.constants import DEG
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError
from imunav.estimation.filters import run_filter
from imunav.estimation.results import FilterResult
from imunav.sensors.aids import AIDS, AidingConfig, AidingData, InitialConfig, Readings
from imunav.sensors.allan import allan_deviation
from imunav.sensors.models import ImuModel
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.initial import InitialState, gnss_alignment, static_alignment

__all__ = ["FOOT_NOISE", "MIN_BIAS_SECONDS", "STILL_MARGIN", "STILL_SPEED", "UNKNOWN_IMU",
           "LogResult", "filter_log", "imu_time_offset", "mounted", "rest_noise", "unknown_imu"]

#: The stated model of an IMU nobody named (``imunav filter`` without ``--imu``): white noise of
#: a consumer MEMS part at rest in a vehicle (0.05 °/s/√Hz, 700 µg/√Hz — what an engine's
#: vibration makes of a datasheet's 0.004 °/s/√Hz and 70 µg/√Hz), turn-on biases of 0.2 °/s
#: and 20 mg with random walks of 4e-5 °/s/√s and 7 µg/√s (the orders of a consumer part's
#: datasheet: BMI088, ICM-42688).
UNKNOWN_IMU = {"name": "unknown IMU (imunav's stated default)",
               "gyro": {"noise_density": "0.05 deg/s/sqrt(Hz)", "bias": "0.2 deg/s",
                        "random_walk": "4e-5 deg/s/sqrt(s)"},
               "accel": {"noise_density": "700 ug/sqrt(Hz)", "bias": "20 mg",
                         "random_walk": "7 ug/sqrt(s)"}}

#: A foot's IMU when only zero-velocity updates aid it: white noise that covers the foot's own
#: dynamics — the process noise of the PyShoe and OpenShoe filters (0.5 m/s² and 0.5 °/s per
#: sample at 200 Hz: 0.035 m/s²/√Hz and 0.035 °/s/√Hz; Wagstaff, Peretroukhin & Kelly 2017),
#: and no bias states (a walk of a minute does not observe them between stances).
FOOT_NOISE = {"name": "foot-mounted IMU (ZUPT process noise of PyShoe/OpenShoe)",
              "gyro": {"noise_density": "0.0354 deg/s/sqrt(Hz)"},
              "accel": {"noise_density": "0.0354 m/s^2/sqrt(Hz)"}}


#: The shortest still start whose gyro mean is taken as the gyro's bias and removed (s).
MIN_BIAS_SECONDS = 5.0
#: A vehicle has moved once its GNSS speed exceeds this (m/s: a few times a receiver's velocity
#: noise) …
STILL_SPEED = 0.1
#: … and was still until this long before (s: the creep before a move).
STILL_MARGIN = 2.0


def unknown_imu(aiding: AidingConfig | None = None) -> ImuModel:
    """The stated model of an IMU nobody named: :data:`FOOT_NOISE` when zero-velocity updates
    are the only aid (a foot), else :data:`UNKNOWN_IMU`.

    Parameters
    ----------
    aiding : AidingConfig, optional

    Returns
    -------
    ImuModel
    """
    foot = aiding is not None and aiding.sensors == ["zupt"]
    return ImuModel.from_dict(FOOT_NOISE if foot else UNKNOWN_IMU)


def mounted(signals: ImuSignals, rotation: FloatArray | None = None, time_offset: float = 0.0
            ) -> ImuSignals:
    """The samples in the vehicle's axes and on the aids' clock.

    Parameters
    ----------
    signals : ImuSignals
        In the IMU's axes.
    rotation : ndarray, shape (3, 3), optional
        ``C``: IMU axes → vehicle axes (:attr:`~imunav.sensors.aids.MountingConfig.rotation`).
    time_offset : float
        Seconds added to the time stamps.

    Returns
    -------
    ImuSignals
    """
    C = np.eye(3) if rotation is None else np.asarray(rotation, float)
    return ImuSignals(signals.t + float(time_offset), signals.gyro @ C.T, signals.accel @ C.T,
                      signals.kind, signals.rate, signals.g, dict(signals.meta))


def _rates(signals: ImuSignals) -> tuple[FloatArray, FloatArray]:
    if signals.kind == "rates":
        return signals.gyro, signals.accel
    return signals.gyro * signals.rate, signals.accel * signals.rate


def rest_noise(signals: ImuSignals, seconds: float, tau: float = 1.0) -> tuple[float, float]:
    """The white noise of the still start: the Allan deviation at ``tau`` times ``√tau``, the
    largest axis — a white noise's density (at τ = 1 s a random walk or an instability has not
    yet risen).

    Parameters
    ----------
    signals : ImuSignals
    seconds : float
        The still start (s): at least ``3 tau``.
    tau : float

    Returns
    -------
    gyro, accel : float
        Noise densities (rad/s/√Hz, m/s²/√Hz).

    Raises
    ------
    ImunavError
        If the still start is shorter than ``3 tau``.
    """
    n = int(round(seconds * signals.rate))
    if n < 3 * tau * signals.rate:
        raise ImunavError(f"the still start of {seconds:g} s is too short to measure the noise at "
                          f"τ = {tau:g} s (at least {3 * tau:g} s)", argument="still_seconds")
    w, f = _rates(signals)
    out = []
    for x in (w[:n], f[:n]):
        taus, ad = allan_deviation(x, signals.rate, taus=[tau])
        out.append(float(np.max(ad[0]) * np.sqrt(taus[0])))
    return out[0], out[1]


def _with_noise(imu: ImuModel, gyro: float, accel: float) -> ImuModel:
    """``imu`` with its white-noise densities raised to at least these."""
    g = imu.gyro.replace(noise_density=max(float(imu.gyro.noise_density or 0.0), gyro))
    a = imu.accel.replace(noise_density=max(float(imu.accel.noise_density or 0.0), accel))
    return ImuModel(gyro=g, accel=a, name=f"{imu.name} (noise measured at rest)")


def imu_time_offset(signals: ImuSignals, t_gnss: FloatArray, velocity: FloatArray, *,
                    max_offset: float = 1.0, min_speed: float = 3.0) -> float:
    """The time offset to add to the IMU's stamps so that its yaw rate lines up with the GNSS
    course rate: the maximum of their cross-correlation over ±``max_offset`` (a grid of one IMU
    interval). The IMU's yaw rate is its rate about the vertical of the still start, averaged
    over the GNSS epochs' central-difference windows; the course rate is the central difference
    of ``atan2(v_E, v_N)`` at speeds above ``min_speed`` (its noise grows as the speed falls).

    Parameters
    ----------
    signals : ImuSignals
        In vehicle axes.
    t_gnss : ndarray, shape (n,)
        GNSS epochs on the IMU's clock to be (s).
    velocity : ndarray, shape (n, 3)
        NED velocity (m/s).
    max_offset : float
    min_speed : float

    Returns
    -------
    float
        Seconds.

    Raises
    ------
    ImunavError
        When the vehicle hardly turns (no correlation to find).
    """
    w, f = _rates(signals)
    n0 = max(3, int(signals.rate))
    down = -f[:n0].mean(axis=0)
    down /= np.linalg.norm(down)
    yaw_rate = w @ down
    cum = np.concatenate([[0.0], np.cumsum(yaw_rate) / signals.rate])
    ts = np.concatenate([[signals.t[0] - 1.0 / signals.rate], signals.t])
    t = np.asarray(t_gnss, float)
    course = np.unwrap(np.arctan2(velocity[:, 1], velocity[:, 0]))
    speed = np.hypot(velocity[:, 0], velocity[:, 1])
    a, b = t[:-2], t[2:]
    rate_g = (course[2:] - course[:-2]) / (b - a)
    ok = (speed[:-2] > min_speed) & (speed[2:] > min_speed) & (speed[1:-1] > min_speed)
    if ok.sum() < 10 or np.std(rate_g[ok]) < 0.02:
        raise ImunavError("the vehicle hardly turns at speed: no yaw rate to line the IMU's "
                          "clock up with; give the time offset", argument="time_offset")
    offsets = np.arange(-max_offset, max_offset + 0.5 / signals.rate, 1.0 / signals.rate)
    best, best_c = 0.0, -np.inf
    for L in offsets:
        # IMU stamps + L = true time: the IMU's mean rate over [a, b] in true time
        ia = np.interp(a - L, ts, cum)
        ib = np.interp(b - L, ts, cum)
        inside = ok & (a - L >= ts[0]) & (b - L <= ts[-1])
        r = (ib - ia)[inside] / (b - a)[inside]
        c = np.corrcoef(r, rate_g[inside])[0, 1]
        if c > best_c:
            best, best_c = float(L), float(c)
    return best


@dataclass
class LogResult:
    """What :func:`filter_log` did and found.

    Attributes
    ----------
    result : FilterResult
        The filter's (its ``smoothed`` with ``smooth``).
    initial : InitialState
        Where the filter started.
    imu : ImuModel
        The IMU model the filter assumed.
    time_offset : float
        Seconds added to the IMU's stamps.
    notes : list of str
        What was measured or assumed (printed by ``imunav filter``).
    """

    result: FilterResult
    initial: InitialState
    imu: ImuModel
    time_offset: float
    notes: list = field(default_factory=list)


def filter_log(signals: ImuSignals, aiding: AidingConfig, data: AidingData | None = None, *,
               imu: ImuModel | None = None, align: str = "static",
               still_seconds: float | str = "auto",
               noise: str = "model", time_offset: float | str | None = None,
               align_speed: float = 1.0, heading_seconds: float = 1.0, smooth: bool = False,
               gate: float | None = 0.9999, recover: int | None = 5,
               covariance_step: float = 0.1, algorithm: str | None = None) -> LogResult:
    """A real log through the aided filter, from what the log gives (flat frame).

    Parameters
    ----------
    signals : ImuSignals
        The IMU's samples in its own axes, on its own clock.
    aiding : AidingConfig
        The aids, the set-up (``[mounting]``) and the initial uncertainty (``[initial]``: a
        default follows from the alignment when it is absent).
    data : AidingData, optional
        The aids' readings (GNSS in NED metres from an origin, on the aids' clock); none when no
        aid needs a file (zero-velocity updates found by the SHOE detector).
    imu : ImuModel, optional
        The IMU model (default :func:`unknown_imu`).
    align : {"static", "gnss"}
        Level the still start (heading 0, position 0), or level it and take the heading from
        the GNSS velocity once the speed exceeds ``align_speed`` (the filter then starts there).
    still_seconds : float or "auto"
        The still start (s). ``"auto"``: with ``align="gnss"`` until :data:`STILL_MARGIN` s
        before the first GNSS epoch faster than :data:`STILL_SPEED` (the vehicle's first
        move), else 1 s.
    noise : {"model", "rest"}
        The model's white noise, or at least what the still start shows (:func:`rest_noise`).
    time_offset : float or "auto", optional
        Seconds added to the IMU's stamps (default ``[mounting] time_offset``); ``"auto"``:
        :func:`imu_time_offset` against the GNSS course (after ``[mounting] time_offset``).
    align_speed, heading_seconds : float
        Of ``align="gnss"`` (:func:`~imunav.strapdown.initial.gnss_alignment`).
    smooth, gate, recover, covariance_step, algorithm
        As :func:`~imunav.estimation.filters.run_filter`.

    Returns
    -------
    LogResult

    Raises
    ------
    ImunavError
        For another ``align`` or ``noise``, ``align="gnss"`` without GNSS velocity readings,
        and the reasons of the alignment and the filter.
    """
    if align not in ("static", "gnss"):
        raise ImunavError(f"align must be 'static' or 'gnss', got {align!r}", argument="align")
    if noise not in ("model", "rest"):
        raise ImunavError(f"noise must be 'model' or 'rest', got {noise!r}", argument="noise")
    data = data if data is not None else AidingData()
    notes: list[str] = []
    mnt = aiding.mounting
    offset = mnt.time_offset
    sig = mounted(signals, mnt.rotation, offset)
    gnss = data.get("gnss")
    if time_offset == "auto":
        if gnss is None or gnss.values.shape[1] < 6:
            raise ImunavError("time_offset='auto' needs GNSS velocity readings",
                              argument="time_offset")
        extra = imu_time_offset(sig, gnss.t, gnss.values[:, 3:6])
        sig = mounted(sig, None, extra)
        offset += extra
        notes.append(f"IMU clock: {extra:+.3f} s from the GNSS course (time offset "
                     f"{offset:+.3f} s in all)")
    elif time_offset is not None:
        sig = mounted(sig, None, float(time_offset) - offset)
        offset = float(time_offset)
    model = imu if imu is not None else unknown_imu(aiding)
    if imu is None:
        notes.append(f"no IMU model given: {model.name}")
    if still_seconds == "auto":
        still_seconds = 1.0
        if align == "gnss" and gnss is not None and gnss.values.shape[1] >= 6:
            fast = np.hypot(gnss.values[:, 3], gnss.values[:, 4]) > STILL_SPEED
            if fast.any():
                still_seconds = max(1.0, float(gnss.t[int(np.argmax(fast))] - STILL_MARGIN
                                               - sig.t[0]))
        elif aiding.zupt is not None:                # a foot: its first stance
            stance = AIDS["zupt"].stance(aiding.zupt, data, sig)
            if len(stance) and stance[0, 0] <= sig.t[0] + 1.5 / sig.rate:
                still_seconds = float(np.clip(stance[0, 1] - sig.t[0], 0.1, 2.0))
            else:
                still_seconds = 0.1
        notes.append(f"still start: {still_seconds:.3g} s")
    if noise == "rest":
        g_n, a_n = rest_noise(sig, still_seconds)
        model = _with_noise(model, g_n, a_n)
        notes.append(f"white noise at rest: gyro {g_n / DEG:.3g} °/s/√Hz, accel "
                     f"{a_n * 1e6 / 9.80665:.3g} µg/√Hz (the model's raised to it)")
    initial = aiding.initial
    # the gyro bias of the still start, when it is long enough to measure it (a foot's second
    # is not: the bias states or the noise carry it)
    remove_bias = still_seconds >= MIN_BIAS_SECONDS
    if align == "static":
        with warnings.catch_warnings():             # its warnings go into the result's
            warnings.simplefilter("ignore")
            start = static_alignment(sig, still_seconds, gyro_bias=remove_bias)
        if initial == InitialConfig():
            initial = InitialConfig(attitude_sigma=float(np.radians(1.0)))
    else:
        if gnss is None or gnss.values.shape[1] < 6:
            raise ImunavError("align='gnss' needs GNSS velocity readings (vn, ve, vd)",
                              argument="align")
        lever = aiding.gnss.lever_arm if aiding.gnss is not None else (0.0, 0.0, 0.0)
        inside = (gnss.t > sig.t[0]) & (gnss.t < sig.t[-1])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            start = gnss_alignment(sig, gnss.t[inside], gnss.values[inside, :3],
                                   gnss.values[inside, 3:6], still_seconds=still_seconds,
                                   speed=align_speed, heading_seconds=heading_seconds,
                                   lever_arm=lever, gyro_bias=remove_bias)
        if initial == InitialConfig():
            initial = InitialConfig(position_sigma=float(aiding.gnss.position_sigma or 1.0),
                                    velocity_sigma=0.1, attitude_sigma=float(np.radians(2.0)))
    k = start.index
    if start.gyro_bias is not None:
        notes.append("gyro bias of the still start removed: "
                     + ", ".join(f"{b / DEG:.3g}" for b in start.gyro_bias) + " °/s")
    gyro = sig.gyro - (0.0 if start.gyro_bias is None else
                       (start.gyro_bias if sig.kind == "rates" else start.gyro_bias / sig.rate))
    # from the start node on (node k is sample k of rates, the start of increment k)
    run = ImuSignals(sig.t[k:], gyro[k:], sig.accel[k:], sig.kind, sig.rate, sig.g)
    t0 = float(run.state_times()[0])
    kept = AidingData()
    for name, r in data.items():
        if isinstance(r, Readings):
            w = (r.t > t0 + 1e-9) & (r.t <= float(run.state_times()[-1]) + 1e-9)
            setattr(kept, name, Readings(r.t[w], r.values[w],
                                         None if r.sigma is None else r.sigma[w]))
        else:
            setattr(kept, name, r)
    res = run_filter(run, start.q0, start.v0, start.p0, aiding, kept, imu=model,
                     initial=initial, smooth=smooth, gate=gate, recover=recover,
                     covariance_step=covariance_step, algorithm=algorithm)
    res.warnings = list(start.warnings) + res.warnings
    return LogResult(res, start, model, offset, notes)
