"""The wgs84 aided filter side by side with pyins (python-ins 1.0.1, ``run_feedback_filter``):
the same simulated increments on the rotating Earth and the same GNSS positions through both
filters, each told the same IMU model (white noise and a turn-on bias per axis: 15 error
states in both), the same GNSS σ, the same initial uncertainty and a 0.1 s covariance step.

The truth is imunav's exact EarthMotion (independent of both filters); pyins integrates with
its own Earth and gravity models. ``benchmarks/bench.py`` times the same pair
(``pyins_filter_over_imunav``) through :func:`side_by_side`.
"""

from __future__ import annotations

import numpy as np
import pytest

from imunav.core.rotations import quat_to_euler
from imunav.earth import ned_difference
from imunav.estimation.filters import run_filter
from imunav.motion import Motion
from imunav.motion.geodetic import EarthMotion
from imunav.sensors.aids import AidingConfig, simulate_aiding
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import simulate_imu

pyins = pytest.importorskip("pyins")

XD, YD, ZD = "(12 + 3*cos(0.05*t))", "(2.48*cos(0.031*t) + 2.2*cos(0.11*t))", "(-0.06*cos(0.02*t))"
#: 50° N, 30° E, 200 m: where the drive runs.
ORIGIN = (np.radians(50.0), np.radians(30.0), 200.0)
#: A MEMS IMU both filters can model exactly: white noise and a turn-on bias.
IMU = ImuModel.from_dict({"gyro": {"noise_density": "0.3 deg/sqrt(h)", "bias": "20 deg/h"},
                          "accel": {"noise_density": "0.05 m/s/sqrt(h)", "bias": "2 mg"}},
                         "pyins comparison")
GNSS_SIGMA = 1.5
#: Initial uncertainty told to both (the filters start at the truth).
INITIAL = {"position_sigma": 1.0, "velocity_sigma": 0.1, "attitude_sigma": "0.1 deg"}


def drive(duration: float) -> Motion:
    """Turns and climbs at 12 m/s, body x along the velocity (as tests/estimation/test_filters)."""
    return Motion(x="12*t + 60*sin(0.05*t)", y="80*sin(0.031*t) + 20*sin(0.11*t)",
                  z="-3*sin(0.02*t)", yaw=f"atan2({YD}, {XD})",
                  pitch=f"atan2(-{ZD}, sqrt({XD}**2 + {YD}**2))", roll="0.05*sin(0.2*t)",
                  duration=duration)


def side_by_side(seconds: float, rate: float = 100.0, seed: int = 5, first: float | None = None):
    """The scenario and two callables running each filter on it.

    Parameters
    ----------
    seconds : float
        The record simulated.
    rate : float
        IMU rate (Hz).
    seed : int
    first : float, optional
        Run both filters on the first ``first`` seconds of that record only (the same
        increments and fixes; the bench's shorter record for pyins).

    Returns
    -------
    motion : EarthMotion
        The truth.
    run_imunav, run_pyins : callable
        ``() → (t, lla (rad, rad, m), sd_ned (m))`` at every IMU node (imunav) / every
        integrator row and covariance epoch (pyins: ``(t, lla, t_sd, sd_ned)``).
    """
    import pandas as pd
    from pyins import filters, inertial_sensor, measurements, util

    motion = EarthMotion(drive(seconds), ORIGIN)
    sig = simulate_imu(motion, rate, seconds, kind="increments", imu=IMU, seed=seed)
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": GNSS_SIGMA},
                                  "initial": INITIAL})
    data = simulate_aiding(motion, cfg, seconds, seed=seed)
    if first is not None and first < seconds:
        from imunav.sensors.aids import AidingData, Readings
        from imunav.sensors.signals import ImuSignals
        n = int(round(first * rate))
        sig = ImuSignals(sig.t[:n], sig.gyro[:n], sig.accel[:n], sig.kind, sig.rate, sig.g)
        k = data.gnss.t <= sig.t[-1] + 1e-9
        data = AidingData(gnss=Readings(data.gnss.t[k], data.gnss.values[k]))
    st0 = motion.states(np.array([0.0]))
    q0, v0, p0 = st0.quaternion[0], st0.velocity[0], st0.position[0]

    def run_imunav():
        res = run_filter(sig, q0, v0, p0, cfg, data, imu=IMU, earth="wgs84",
                         algorithm="coning2")
        return res.t, res.states.position, res.sd[:, :3]

    # pyins: the same increments (interval ends as the index), the initial PVA in degrees,
    # the GNSS fixes as lat/lon in degrees
    inc = pd.DataFrame(np.column_stack([np.full(len(sig.t), 1.0 / rate), sig.gyro, sig.accel]),
                       index=sig.t, columns=["dt"] + util.THETA_COLS + util.DV_COLS)
    ypr = np.degrees(quat_to_euler(q0))
    pva0 = pd.Series([np.degrees(p0[0]), np.degrees(p0[1]), p0[2], *v0, ypr[2], ypr[1],
                      ypr[0] % 360.0], index=util.TRAJECTORY_COLS, name=float(sig.t0))
    g = data.gnss.values
    fixes = pd.DataFrame(np.column_stack([np.degrees(g[:, 0]), np.degrees(g[:, 1]), g[:, 2]]),
                         index=data.gnss.t, columns=util.LLA_COLS)
    gyro = inertial_sensor.EstimationModel(bias_sd=IMU.gyro.bias, noise=IMU.gyro.noise_density)
    accel = inertial_sensor.EstimationModel(bias_sd=IMU.accel.bias,
                                            noise=IMU.accel.noise_density)
    att = np.degrees(cfg.initial.attitude_sigma)

    def run_pyins():
        out = filters.run_feedback_filter(
            pva0, INITIAL["position_sigma"], INITIAL["velocity_sigma"], att, att, inc, gyro,
            accel, measurements=[measurements.Position(fixes, GNSS_SIGMA)], time_step=0.1)
        tr, sd = out.trajectory, out.trajectory_sd
        lla = np.column_stack([np.radians(tr.lat), np.radians(tr.lon), tr.alt])
        return (tr.index.values, lla, sd.index.values,
                sd[["north", "east", "down"]].values)

    return motion, run_imunav, run_pyins


def rms(x):
    return np.sqrt(np.mean(np.asarray(x) ** 2, axis=0))


@pytest.fixture(scope="module")
def both():
    motion, run_imunav, run_pyins = side_by_side(60.0)
    t, lla, sd = run_imunav()
    tp, llap, tsd, sdp = run_pyins()
    keep, keepp, keeps = t >= 5.0, tp >= 5.0, tsd >= 5.0          # after the first fixes
    return {"imunav_err": ned_difference(lla, motion.states(t).position)[keep],
            "imunav_sd": sd[keep],
            "pyins_err": ned_difference(llap, motion.states(tp).position)[keepp],
            "pyins_sd": sdp[keeps]}


def test_imunav_position_rms_no_worse_than_pyins(both):
    """The 3-D position RMS against the exact truth: imunav's at most pyins' (measured, 60 s at
    100 Hz after the first 5 s: imunav [1.1759, 0.7345, 0.6029] m, 3-D 1.5118 m; pyins
    [1.1755, 0.7361, 0.6025] m, 3-D 1.5121 m — the same estimator on the same data to 0.3 %
    per axis, pyins' own Earth and gravity models and strapdown the difference; the margin is
    small, and the comparison deterministic: fixed seeds, no threads in either)."""
    e_i = float(np.sqrt(np.mean(np.sum(both["imunav_err"] ** 2, axis=1))))
    e_p = float(np.sqrt(np.mean(np.sum(both["pyins_err"] ** 2, axis=1))))
    assert e_i <= e_p, (e_i, e_p)
    # and the two are the same estimator: per axis within 10 % of each other
    np.testing.assert_allclose(rms(both["imunav_err"]), rms(both["pyins_err"]), rtol=0.1)


@pytest.mark.parametrize("who", ["imunav", "pyins"])
def test_position_errors_within_reported_sigma(both, who):
    """Each filter's position RMS per NED axis within twice the RMS of the σ it reports (a
    single run: the 95 % band of the RMS of ~55 strongly correlated epochs is wide; measured
    1.45, 0.91, 0.86 times σ for both), and imunav's horizontal errors beyond 3σ at under 5 % of
    the nodes."""
    err, sd = both[f"{who}_err"], both[f"{who}_sd"]
    assert np.all(rms(err) <= 2.0 * rms(sd)), (who, rms(err), rms(sd))
    if who == "imunav":                                  # σ at the same nodes as the errors
        assert np.mean(np.abs(err[:, :2]) > 3 * sd[:, :2]) < 0.05
