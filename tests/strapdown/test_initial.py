"""The initial state from what a log gives (issue 36): static alignment and the GNSS heading, on
motions simulated by imunav (ideal signals from the analytic laws) with errors the test adds
itself, so that the truth — attitude, bias, velocity — is known exactly."""

from __future__ import annotations

import doctest
import warnings

import numpy as np
import pytest

from imunav import Motion, simulate_imu
from imunav.core.kernels import quat_conj, quat_mul, quat_rotate
from imunav.core.rotations import quat_angle, quat_to_euler
from imunav.core.validation import ImunavError
from imunav.sensors.signals import ImuSignals
from imunav.strapdown import initial as I

RATE = 100.0
BIAS = np.array([0.01, -0.02, 0.005])            # rad/s (0.6, −1.1, 0.3 °/s)
SG, SA = 0.002, 0.02                              # noise per sample: rad/s, m/s²


def _noisy(sig: ImuSignals, seed: int, bias=BIAS) -> ImuSignals:
    rng = np.random.default_rng(seed)
    scale = 1.0 / sig.rate if sig.kind == "increments" else 1.0
    gyro = sig.gyro + (bias + rng.normal(0, SG, sig.gyro.shape)) * scale
    accel = sig.accel + rng.normal(0, SA, sig.accel.shape) * scale
    return ImuSignals(sig.t, gyro, accel, sig.kind, sig.rate, sig.g)


@pytest.mark.parametrize("kind", ["rates", "increments"])
def test_static_alignment_against_the_truth(kind):
    """At rest at yaw 1, pitch 0.1, roll −0.2: roll and pitch from 1 s of noisy samples within
    5× the averaging error σ_a/(g√N) = 2e-4 rad; yaw 0; the gyro bias within 5 σ_g/√N."""
    m = Motion(yaw=1.0, pitch=0.1, roll=-0.2, duration=3.0)
    sig = _noisy(simulate_imu(m, RATE, kind=kind), seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = I.static_alignment(sig, 1.0)
    yaw, pitch, roll = a.euler
    assert abs(yaw) < 1e-12
    assert abs(pitch - 0.1) < 5 * SA / (9.80665 * 10) and abs(roll + 0.2) < 5 * SA / (9.80665 * 10)
    np.testing.assert_allclose(a.gyro_bias, BIAS, atol=5 * SG / 10)
    assert a.index == 0 and a.t0 == sig.state_times()[0] and a.still_seconds == 1.0
    np.testing.assert_array_equal(a.v0, 0.0)
    np.testing.assert_array_equal(a.p0, 0.0)
    assert a.warnings == []
    assert I.static_alignment(sig, 1.0, gyro_bias=False).gyro_bias is None


@pytest.mark.parametrize("laws, what", [
    (dict(pitch="0.2*sin(2*t)"), "level attitude of its quarters differs"),
    (dict(x="0.05*sin(6*t)"), "level attitude of its quarters differs"),     # 1.8 m/s² shaking
    (dict(x="2*t**2"), "mean specific force is .* from g"),                  # 4 m/s² forward
    (dict(yaw="0.3*t**2"), "gyro's mean changes"),                           # a starting turn
])
def test_static_alignment_says_when_the_start_is_not_still(laws, what):
    sig = simulate_imu(Motion(duration=3.0, **laws), RATE)
    with pytest.warns(UserWarning, match=what):
        a = I.static_alignment(sig, 1.0)
    assert any("may not be still" in w for w in a.warnings)


@pytest.mark.parametrize("kw, msg", [
    (dict(still_seconds=0.02), "holds 2 samples"),
    (dict(still_seconds=10.0), "longer than the record"),
    (dict(still_seconds=-1.0), "still_seconds must be a positive"),
])
def test_static_alignment_refusals(kw, msg):
    sig = simulate_imu(Motion(duration=3.0), RATE)
    with pytest.raises(ImunavError, match=msg):
        I.static_alignment(sig, **kw)
    with pytest.raises(ImunavError, match="signals must be ImuSignals"):
        I.static_alignment(np.zeros((10, 6)))
    upside_down_g = simulate_imu(Motion(duration=3.0), RATE)
    upside_down_g.accel[:] *= 0.5                         # half of g: not gravity at all
    with pytest.raises(ImunavError, match="not ≈ g"):
        I.static_alignment(upside_down_g)


PSI_A, PSI_0, PITCH, ROLL = 0.3, 2.0, 0.02, -0.03
LEVER = np.array([0.5, 0.1, -1.0])


def _drive(kind="rates"):
    """At rest 2 s (yaw 0.3), a turn in place to yaw 2.0 over 2 s, then off along the body x
    axis (s = 0.5 τ³: 6 m/s after 2 s). Three analytic pieces, continuous in ω and f."""
    a = Motion(yaw=PSI_A, pitch=PITCH, roll=ROLL)
    tau = "((t - 2)/2)"
    b = Motion(yaw=f"{PSI_A} + {PSI_0 - PSI_A}*(3*{tau}**2 - 2*{tau}**3)", pitch=PITCH,
               roll=ROLL)
    u = np.array([np.cos(PSI_0) * np.cos(PITCH), np.sin(PSI_0) * np.cos(PITCH), -np.sin(PITCH)])
    s = "0.5*(t - 4)**3"
    c = Motion(x=f"{u[0]}*{s}", y=f"{u[1]}*{s}", z=f"{u[2]}*{s}", yaw=PSI_0, pitch=PITCH,
               roll=ROLL)
    parts = [simulate_imu(m, RATE, 2.0 if i < 2 else 6.0, t0=t0, kind=kind)
             for i, (m, t0) in enumerate([(a, 0.0), (b, 2.0), (c, 4.0)])]
    skip = 1 if kind == "rates" else 0                    # rates repeat the joint sample
    t = np.concatenate([parts[0].t] + [p.t[skip:] for p in parts[1:]])
    g = np.concatenate([parts[0].gyro] + [p.gyro[skip:] for p in parts[1:]])
    f = np.concatenate([parts[0].accel] + [p.accel[skip:] for p in parts[1:]])
    return ImuSignals(t, g, f, kind, RATE), c


def _gnss(c: Motion, seed: int, sigma_v=0.05):
    """4 Hz fixes at the antenna from 4 s on (before: at rest at the origin)."""
    rng = np.random.default_rng(seed)
    t = np.arange(1, 41) / 4.0
    moving = t >= 4.0
    q = c.attitude(np.maximum(t, 4.0))
    p = np.where(moving[:, None], c.position(np.maximum(t, 4.0)), 0.0) + quat_rotate(
        q, np.broadcast_to(LEVER, (t.size, 3)))
    v = np.where(moving[:, None], c.velocity(np.maximum(t, 4.0)), 0.0)
    return t, p + rng.normal(0, 0.01, p.shape), v + rng.normal(0, sigma_v, v.shape)


@pytest.mark.parametrize("kind", ["rates", "increments"])
def test_gnss_alignment_against_the_truth(kind):
    sig, c = _drive(kind)
    sig = _noisy(sig, seed=2)
    t, p, v = _gnss(c, seed=3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = I.gnss_alignment(sig, t, p, v, still_seconds=1.5, speed=5.0, heading_seconds=1.0,
                             lever_arm=LEVER)
    # the speed reaches 5 m/s at τ = 1.83 s: epochs 6.0 … 7.0 s; the state at the last one
    assert a.t0 == pytest.approx(7.0) and a.index == 700
    q_true = c.attitude(np.array([a.t0]))[0]
    err = quat_mul(a.q0, quat_conj(q_true))
    # yaw from 5 courses at 6–8 m/s with σ_v = 5 cm/s (≈ 0.4° each, 0.003 rad averaged), the
    # gyro carrying 7 s with its bias known to ~3e-5 rad/s: measured 2e-4 rad; the tilt from
    # the levelling (σ_a/(g√N) = 1.6e-4 rad) carried through the turn: measured 8.6e-4 rad
    assert abs(quat_to_euler(err)[0]) < 3e-3
    assert quat_angle(a.q0, q_true) < 3e-3
    ypr = a.euler
    assert abs(ypr[1] - PITCH) < 3e-3 and abs(ypr[2] - ROLL) < 3e-3
    # the epoch's own velocity and position (σ 5 cm/s, 1 cm), carried from the antenna
    # (1.1 m away) to the IMU
    np.testing.assert_allclose(a.v0, c.velocity(np.array([a.t0]))[0], atol=0.05)
    np.testing.assert_allclose(a.p0, c.position(np.array([a.t0]))[0], atol=0.03)


def test_gnss_alignment_refusals_and_warnings():
    sig, c = _drive()
    t, p, v = _gnss(c, seed=4)
    with pytest.raises(ImunavError, match="reaches speed = 100 m/s .* fastest: "):
        I.gnss_alignment(sig, t, p, v, speed=100.0)
    with pytest.raises(ImunavError, match="one row per epoch"):
        I.gnss_alignment(sig, t[:-1], p, v)
    with pytest.raises(ImunavError, match="speed must be a positive"):
        I.gnss_alignment(sig, t, p, v, speed=0)
    t2, p2, v2 = _gnss(c, seed=5, sigma_v=1.5)             # ±1.5 m/s at 5–8 m/s: ~15° apart
    with pytest.warns(UserWarning, match="GNSS headings scatter by"):
        a = I.gnss_alignment(sig, t2, p2, v2, heading_seconds=2.0)
    assert any("scatter" in w for w in a.warnings)


def test_module_examples():
    result = doctest.testmod(I)
    assert result.attempted >= 4 and result.failed == 0


def test_gnss_alignment_weights_fast_epochs():
    """Slow epochs whose courses are 20° off (creeping, sideslip) and fast ones that are right:
    weighting by speed² keeps the heading within 1.5° (0.1° expected; the unweighted mean of
    these 11 epochs, 3 of them slow, would be 5.5° off)."""
    sig, c = _drive()
    t, p, v = _gnss(c, seed=6, sigma_v=0.0)
    sp = np.hypot(v[:, 0], v[:, 1])
    slow = (sp > 0.3) & (sp < 1.5)
    turn = np.array([[np.cos(0.35), -np.sin(0.35)], [np.sin(0.35), np.cos(0.35)]])
    v[slow, :2] = v[slow, :2] @ turn.T                     # 20° off
    a = I.gnss_alignment(sig, t, p, v, still_seconds=1.5, speed=0.3, heading_seconds=2.5,
                         lever_arm=LEVER)
    yaw_err = quat_to_euler(quat_mul(a.q0, quat_conj(c.attitude(np.array([a.t0]))[0])))[0]
    assert abs(yaw_err) < np.radians(1.5)
    assert slow.sum() >= 2 and (sp >= 1.5).sum() >= 2
