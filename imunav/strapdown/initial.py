"""The initial state from what a log gives: levelled at rest, and heading from GNSS once moving.

General strapdown practice first, the coarse levelling at rest: roll and pitch from gravity
(:func:`level_attitude`, :func:`gravity_reading`) and the static bias removal
(:func:`remove_static_biases`) — Dickson & Rae 2021 use both steps in their processing chain
(:mod:`imunav.papers.dickson_rae2021` calls these), and so do the readers of real recordings
when no initial state is given. (These were ``imunav.strapdown.alignment`` until 0.3, a name
that :mod:`imunav.estimation.alignment` also had; the old path still imports, with a warning.)

A real log comes without a truth file. What it does give:

- **a still start** (a foot before the first step, a car before it drives off): the mean
  specific force of those seconds is gravity, so roll and pitch follow
  (:func:`level_attitude`); the gyro's mean over them is its bias
  (plus the Earth's rate, ≤ 15 °/h, which the flat frame does not model anyway). The heading
  is unobservable at rest without a magnetometer: 0, and the position 0 — the frame of a
  foot-mounted walk (:func:`static_alignment`);
- **GNSS velocity once moving**: a vehicle travels along its body x axis (no sideslip, the
  mounting applied), so the course ``atan2(v_E, v_N)`` is its heading. The attitude levelled
  at rest is carried forward by the gyro to the epochs where the horizontal speed exceeds a
  threshold, and turned about the vertical so that its yaw matches the course there
  (:func:`gnss_alignment`). imunav's choice for ``--align gnss``: heading from velocity, not a
  filter started with a wide heading σ (whose linearised error model would have to absorb a
  heading error of up to 180°).

Both check what they assume and say so (``warnings.warn``, one line) when a log disagrees:
a start that is not still, GNSS headings that scatter.

May import: ``imunav.core``, ``imunav.sensors.signals``, ``imunav.strapdown.scan``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from imunav.core.constants import DEG, G0
from imunav.core.kernels import FloatArray, axis_quat, cross, quat_conj, quat_mul, quat_rotate
from imunav.core.rotations import euler_to_quat, quat_to_euler
from imunav.core.validation import ImunavError, as_float_array, check_gravity, check_positive
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.scan import exp_product

__all__ = ["STILL_GRAVITY", "STILL_RATE", "STILL_TILT", "InitialState", "gnss_alignment",
           "gravity_reading", "level_attitude", "remove_static_biases", "static_alignment"]


def level_attitude(accel: npt.ArrayLike, g: float = G0, tol: float = 0.05,
                   yaw: float = 0.0) -> FloatArray:
    """``q_nb`` from the mean resting specific force (m/s²): roll and pitch from gravity, yaw given.

    Level at rest the accelerometer reads ``[0, 0, −g]``, so θ = atan2(f_x, √(f_y² + f_z²)) and
    φ = atan2(−f_y, −f_z). Raises if |f| differs from g by more than ``tol`` (relative): the
    accelerometer is then not measuring gravity alone (the body is not at rest).
    """
    f = as_float_array(accel, "accel", last=3)
    g = check_gravity(g)
    f = f.reshape(-1, 3).mean(axis=0)
    n = float(np.linalg.norm(f))
    if abs(n - g) > tol * g:
        raise ImunavError(f"accel at rest has |a| = {n:.4g} m/s², not ≈ g = {g:.4g} "
                          f"(tolerance {tol:.0%}): cannot take the initial orientation from it")
    theta = np.arctan2(f[0], np.hypot(f[1], f[2]))
    phi = np.arctan2(-f[1], -f[2])
    return euler_to_quat([yaw, theta, phi])


def gravity_reading(q: npt.ArrayLike, g: float = G0) -> FloatArray:
    """What an ideal accelerometer at rest reads at attitude ``q_nb``: ``C_bn (−g_n)``."""
    q = as_float_array(q, "q", last=4)
    return quat_rotate(quat_conj(q), np.array([0.0, 0.0, -g]))


def remove_static_biases(gyro: FloatArray, accel: FloatArray, window: slice, q0: FloatArray,
                         g: float = G0) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Subtract the offsets measured over a stationary ``window`` at attitude ``q0``: the gyro's
    mean, and the accelerometer's mean minus the gravity reading :func:`gravity_reading`.
    Returns ``(gyro, accel, gyro_bias, accel_bias)``."""
    bg = gyro[window].mean(axis=0)
    ba = accel[window].mean(axis=0) - gravity_reading(q0, g)
    return gyro - bg, accel - ba, bg, ba


#: A still start: the level attitude of each quarter of the window within this of the whole
#: window's (rad; 1°)…
STILL_TILT = 1.0 * DEG
#: … the gyro's mean over each quarter within this of the whole window's (rad/s; 1 °/s)…
STILL_RATE = 1.0 * DEG
#: … and the mean specific force's magnitude within this fraction of g (a 5 % accelerometer
#: scale or bias error, or an acceleration).
STILL_GRAVITY = 0.05
#: GNSS headings (course minus the gyro-carried yaw) that scatter by more than this (rad, 5°)
#: are worth a warning: sideslip, or a body x axis that is not the direction of travel.
HEADING_SCATTER = 5.0 * DEG


@dataclass
class InitialState:
    """A navigation state to start a filter or a navigation from, and how it was found.

    Attributes
    ----------
    t0 : float
        The time of the state (s): a node of the signals (:meth:`ImuSignals.state_times`).
    index : int
        That node's index.
    q0 : ndarray, shape (4,)
        Attitude ``q_nb``.
    v0, p0 : ndarray, shape (3,)
        Velocity (m/s) and position (m), NED.
    gyro_bias : ndarray, shape (3,) or None
        The gyro bias measured over the still start (rad/s), None if not estimated.
    still_seconds : float
        The length of the still window used (s).
    warnings : list of str
        What the checks found doubtful (also issued with ``warnings.warn``).
    """

    t0: float
    index: int
    q0: FloatArray
    v0: FloatArray
    p0: FloatArray
    gyro_bias: FloatArray | None
    still_seconds: float
    warnings: list[str] = field(default_factory=list)

    @property
    def euler(self) -> FloatArray:
        """Yaw, pitch, roll of ``q0`` (rad).

        Returns
        -------
        ndarray, shape (3,)
        """
        return quat_to_euler(self.q0)


def _rates(signals: ImuSignals) -> tuple[FloatArray, FloatArray]:
    """Gyro and accelerometer in rate units (increments divided by the interval)."""
    if signals.kind == "increments":
        return signals.gyro * signals.rate, signals.accel * signals.rate
    return signals.gyro, signals.accel


def _warn(found: list[str], message: str) -> None:
    found.append(message)
    warnings.warn(message, stacklevel=3)


def _window(signals: ImuSignals, still_seconds, name: str = "still_seconds") -> int:
    s = check_positive(still_seconds, name)
    n = int(round(s * signals.rate))
    if n < 4:
        raise ImunavError(f"{name} = {s:g} s holds {n} samples at {signals.rate:g} Hz; give at "
                          "least 4 samples' worth", argument=name)
    if n > len(signals):
        raise ImunavError(f"{name} = {s:g} s is longer than the record ({len(signals)} samples, "
                          f"{len(signals) / signals.rate:g} s)", argument=name)
    return n


def static_alignment(signals: ImuSignals, still_seconds: float = 1.0, *,
                     gyro_bias: bool = True) -> InitialState:
    """Level at rest: roll and pitch from the mean specific force of the first still seconds,
    heading 0, zero velocity and position; the gyro bias from the same seconds.

    The start is checked for stillness (a warning if not): the level attitude of each quarter
    of the window within :data:`STILL_TILT` (1°) of the whole window's, the gyro's quarter
    means within :data:`STILL_RATE` (1 °/s) of its mean, and ``|f̄|`` within
    :data:`STILL_GRAVITY` (5 %) of g.

    Parameters
    ----------
    signals : ImuSignals
        The record (rates or increments); its first ``still_seconds`` at rest.
    still_seconds : float, default 1.0
        The still window (s), at least 4 samples.
    gyro_bias : bool, default True
        Estimate the gyro bias as the window's mean rate (it includes the Earth's rate as seen
        at that attitude).

    Returns
    -------
    InitialState
        At the first node (``signals.t0``, index 0): ``q0`` level with yaw 0, ``v0 = p0 = 0``.

    Raises
    ------
    ImunavError
        If ``signals`` is not :class:`~imunav.sensors.signals.ImuSignals`; ``still_seconds``
        is not a positive number, holds fewer than 4 samples or exceeds the record; or the
        mean specific force differs from g by more than 25 % (not gravity at all).

    Examples
    --------
    >>> import numpy as np
    >>> from imunav.sensors.signals import ImuSignals
    >>> f = np.tile([0.0, 9.80665 * np.sin(0.1), -9.80665 * np.cos(0.1)], (100, 1))
    >>> sig = ImuSignals(np.arange(100) / 100, np.tile([1e-3, 0, 0], (100, 1)), f, "rates", 100)
    >>> a = static_alignment(sig, 0.5)
    >>> a.euler.round(6).tolist(), a.gyro_bias.round(9).tolist(), a.t0
    ([0.0, 0.0, -0.1], [0.001, 0.0, 0.0], 0.0)
    """
    if not isinstance(signals, ImuSignals):
        raise ImunavError(f"signals must be ImuSignals, got {type(signals).__name__}",
                          argument="signals")
    n = _window(signals, still_seconds)
    gyro, accel = _rates(signals)
    f, w = accel[:n], gyro[:n]
    found: list[str] = []
    q0 = level_attitude(f, signals.g, tol=0.25)
    fbar = f.mean(axis=0)
    mag = float(np.linalg.norm(fbar))
    if abs(mag - signals.g) > STILL_GRAVITY * signals.g:
        _warn(found, f"the first {still_seconds:g} s may not be still: the mean specific force "
                     f"is {mag:.4g} m/s², {abs(mag / signals.g - 1):.1%} from g")
    quarters = np.array_split(np.arange(n), 4)
    e_all = quat_to_euler(q0)[1:]
    tilt = max(float(np.max(np.abs(quat_to_euler(level_attitude(f[i], signals.g, tol=0.5))[1:]
                                   - e_all))) for i in quarters)
    if tilt > STILL_TILT:
        _warn(found, f"the first {still_seconds:g} s may not be still: the level attitude of "
                     f"its quarters differs by up to {tilt / DEG:.2g}° (a tilt or an "
                     "acceleration)")
    wbar = w.mean(axis=0)
    turn = max(float(np.linalg.norm(w[i].mean(axis=0) - wbar)) for i in quarters)
    if turn > STILL_RATE:
        _warn(found, f"the first {still_seconds:g} s may not be still: the gyro's mean changes "
                     f"by up to {turn / DEG:.2g} °/s between its quarters (a rotation)")
    t0 = float(signals.state_times()[0])
    return InitialState(t0, 0, q0, np.zeros(3), np.zeros(3), wbar.copy() if gyro_bias else None,
                        n / signals.rate, found)


def _attitudes(signals: ImuSignals, q0: FloatArray, bias: FloatArray | None, upto: int
               ) -> FloatArray:
    """``q_nb`` at nodes 0 … ``upto`` carried by the gyro (bias removed): trapezoidal rate
    increments for rate samples, the increments themselves for increments."""
    b = np.zeros(3) if bias is None else bias
    h = 1.0 / signals.rate
    if signals.kind == "increments":
        phi = signals.gyro[:upto] - b * h
    else:
        w = signals.gyro[:upto + 1] - b
        phi = 0.5 * (w[:-1] + w[1:]) * h
    return exp_product(q0, phi) if upto else q0[None]


def gnss_alignment(signals: ImuSignals, gnss_t: npt.ArrayLike, gnss_position: npt.ArrayLike,
                   gnss_velocity: npt.ArrayLike, *, still_seconds: float = 1.0,
                   speed: float = 5.0, heading_seconds: float = 1.0,
                   lever_arm: npt.ArrayLike = (0.0, 0.0, 0.0), gyro_bias: bool = True
                   ) -> InitialState:
    """Levelled at rest, then the heading from GNSS velocity once moving.

    :func:`static_alignment` over the first ``still_seconds`` (yaw 0); the gyro (its bias
    removed) carries that attitude forward; at the GNSS epochs of the first ``heading_seconds``
    after the horizontal speed first reaches ``speed``, the yaw is compared with the course
    ``atan2(v_E, v_N)`` — the body x axis is assumed to be the direction of travel — and the
    attitude turned about the vertical by their circular mean, each epoch weighted by its
    speed squared (a course's error is about ``σ_v / speed``: inverse-variance weights). The
    state is given at the IMU node nearest the last of those epochs: velocity and position from
    that epoch, carried from the antenna to the IMU (``v − C (ω × l)``, ``p + v Δt − C l``).

    Parameters
    ----------
    signals : ImuSignals
        The record, in vehicle axes (x forward); its first ``still_seconds`` at rest.
    gnss_t : array_like, shape (n,)
        GNSS epoch times, on the signals' clock (s).
    gnss_position : array_like, shape (n, 3)
        The antenna's position, NED (m).
    gnss_velocity : array_like, shape (n, 3)
        The antenna's velocity, NED (m/s).
    still_seconds : float, default 1.0
        The still window (s).
    speed : float, default 5.0
        Horizontal speed (m/s) from which the course is a heading: its error is about
        ``σ_v / speed`` (0.6° for 5 cm/s at 5 m/s; a vehicle that must start navigating soon
        after it drives off can take a lower speed, ~10 σ_v).
    heading_seconds : float, default 1.0
        Seconds of epochs averaged from that moment.
    lever_arm : array_like, shape (3,)
        The antenna in the body frame (m).
    gyro_bias : bool, default True
        Remove the gyro bias measured at rest before carrying the attitude.

    Returns
    -------
    InitialState
        At the node where the heading is known (``index > 0``).

    Raises
    ------
    ImunavError
        As :func:`static_alignment`; if the GNSS arrays do not match in length or are not
        finite; ``speed`` or ``heading_seconds`` is not a positive number; or no epoch inside
        the record after the still window reaches ``speed``.

    Examples
    --------
    >>> import numpy as np
    >>> from imunav.sensors.signals import ImuSignals
    >>> n = 301                                         # 3 s at 100 Hz, level and at rest
    >>> sig = ImuSignals(np.arange(n) / 100, np.zeros((n, 3)), np.tile([0, 0, -9.80665], (n, 1)),
    ...                  "rates", 100)
    >>> t = np.array([1.5, 2.0, 2.5])                   # then GNSS says: north-east at 6 m/s
    >>> v = np.tile([6 * np.cos(0.5), 6 * np.sin(0.5), 0.0], (3, 1))
    >>> a = gnss_alignment(sig, t, v * (t[:, None] - 1.5), v, still_seconds=1.0)
    >>> a.t0, a.euler.round(9).tolist()
    (2.5, [0.5, 0.0, 0.0])
    """
    st = static_alignment(signals, still_seconds, gyro_bias=gyro_bias)
    tg = as_float_array(gnss_t, "gnss_t", ndim=1)
    pos = as_float_array(gnss_position, "gnss_position", ndim=2, last=3)
    vel = as_float_array(gnss_velocity, "gnss_velocity", ndim=2, last=3)
    if not tg.size == pos.shape[0] == vel.shape[0]:
        raise ImunavError(f"gnss_t, gnss_position and gnss_velocity must have one row per epoch, "
                          f"got {tg.size}, {pos.shape[0]} and {vel.shape[0]}",
                          argument="gnss_velocity")
    speed = check_positive(speed, "speed")
    heading_seconds = check_positive(heading_seconds, "heading_seconds")
    lever = as_float_array(lever_arm, "lever_arm", ndim=1, last=3)
    nodes = signals.state_times()
    h = 1.0 / signals.rate
    start = nodes[0] + st.still_seconds
    horiz = np.hypot(vel[:, 0], vel[:, 1])
    inside = (tg >= start) & (tg <= nodes[-1])
    fast = np.nonzero(inside & (horiz >= speed))[0]
    if fast.size == 0:
        top = float(horiz[inside].max()) if inside.any() else 0.0
        raise ImunavError(f"no GNSS epoch inside the record after the still start reaches speed "
                          f"= {speed:g} m/s (the fastest: {top:.3g} m/s): the heading cannot be "
                          "taken from GNSS velocity", argument="speed")
    t_first = tg[fast[0]]
    use = fast[tg[fast] <= t_first + heading_seconds]
    k = np.clip(np.rint((tg[use] - nodes[0]) / h).astype(int), 0, nodes.size - 1)
    q_carried = _attitudes(signals, st.q0, st.gyro_bias, int(k.max()))
    yaw = quat_to_euler(q_carried[k])[:, 0]
    course = np.arctan2(vel[use, 1], vel[use, 0])
    d = np.exp(1j * (course - yaw))
    w = horiz[use] ** 2                        # a course's error is about σ_v / speed
    mean = (w * d).sum() / w.sum()
    dpsi = float(np.angle(mean))
    found = list(st.warnings)
    scatter = math.sqrt(max(0.0, -2.0 * math.log(max(abs(mean), 1e-300))))
    if scatter > HEADING_SCATTER:
        _warn(found, f"GNSS headings scatter by {scatter / DEG:.2g}° over {use.size} epochs "
                     f"from t = {t_first:.6g} s: sideslip, or the body x axis is not the "
                     "direction of travel (mounting?)")
    j, kj = use[-1], int(k[-1])
    q = quat_mul(axis_quat(np.array(dpsi), 3), q_carried[kj])
    gyro, _ = _rates(signals)
    i = min(kj, len(signals) - 1)
    omega = gyro[i] - (st.gyro_bias if st.gyro_bias is not None else 0.0)
    v_imu = vel[j] - quat_rotate(q, cross(omega, lever))
    p_imu = pos[j] + vel[j] * (nodes[kj] - tg[j]) - quat_rotate(q, lever)
    return InitialState(float(nodes[kj]), kj, q, v_imu, p_imu, st.gyro_bias, st.still_seconds,
                        found)
