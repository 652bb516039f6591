"""The filter open to aids it has never seen (issue 35): a measurement written here, in the test
file only, runs through the filter, the smoother, the aided covariance analysis and the aided
Monte Carlo with no change to imunav; and imunav's own new aid, the odometer, shortens the
along-track drift of a GNSS outage."""

from pathlib import Path

import numpy as np
import pytest

from imunav.analysis.aided_assessment import aided_covariance, assess_aided
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.core.kernels import skew
from imunav.core.layout import DV, PHI
from imunav.estimation import Aid, Measurement, run_filter, run_smoother
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig, reading_times, simulate_aiding
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import simulate_imu

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


class WheelSpeed(Measurement):
    """A user's wheel-speed sensor: the body-frame velocity is [speed, 0, 0] (the wheels' speed
    and a car that neither slides nor jumps) — written against the contract alone."""

    name, columns = "wheels", ("vx", "vy", "vz")

    def __init__(self, sigma):
        super().__init__()
        self.sigma = sigma

    def predict(self, nav):
        return nav.C.T @ nav.v

    def jacobian(self, nav):
        H = np.zeros((3, nav.estimates.size))
        H[:, PHI] = -nav.C.T @ skew(nav.v)
        H[:, DV] = nav.C.T
        return H

    def noise(self):
        return self.sigma ** 2 * np.eye(3)


@pytest.fixture(scope="module")
def drive():
    m, dur, _ = load_motion(EXAMPLES / "drive.toml")
    return m


def _wheels(m, t, sigma, rng):
    """The wheel-speed readings along the truth, with white noise."""
    from imunav.core.kernels import quat_conj, quat_rotate
    vb = quat_rotate(quat_conj(m.attitude(t)), m.velocity(t))
    vb[:, 1:] = 0.0
    return Aid(WheelSpeed(sigma), t, np.column_stack([vb[:, 0], vb[:, 1:]])
               + rng.normal(0.0, sigma, (t.size, 3)))


def test_a_users_wheel_speed_alone_halves_the_velocity_error(drive):
    """issue 35: BMI088 on a 120 s drive, the user's wheel speed alone (no GNSS): the final
    velocity error less than half the unaided run's."""
    imu = ImuModel.load("BMI088")
    rate, dur = 100.0, 120.0
    sig = simulate_imu(drive, rate, dur, kind="increments", imu=imu, seed=7)
    st = drive.states(np.array([0.0]))
    x0 = (st.quaternion[0], st.velocity[0], st.position[0])
    t = reading_times(10.0, dur)
    aided = run_filter(sig, *x0, measurements=[_wheels(drive, t, 0.05,
                                                       np.random.default_rng(1))], imu=imu)
    free = run_filter(sig, *x0, measurements=[], imu=imu)
    v_true = drive.velocity(np.array([dur]))[0]
    e_aided = np.linalg.norm(aided.states.velocity[-1] - v_true)
    e_free = np.linalg.norm(free.states.velocity[-1] - v_true)
    assert e_aided < 0.5 * e_free, (e_aided, e_free)
    assert "wheels" in aided.innovations and aided.innovations["wheels"].t.size == t.size


def test_a_users_measurement_runs_through_smoother_covariance_and_monte_carlo(drive):
    imu = ImuModel.load("BMI088")
    rate, dur = 50.0, 60.0
    gnss = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                            "outages": [[30, 45]]}})
    t = reading_times(5.0, dur)
    aid = _wheels(drive, t, 0.05, np.random.default_rng(2))
    sig = simulate_imu(drive, rate, dur, kind="increments", imu=imu, seed=3)
    data = simulate_aiding(drive, gnss, dur, seed=3, imu_rate=rate)
    st = drive.states(np.array([0.0]))
    x0 = (st.quaternion[0], st.velocity[0], st.position[0])
    sm = run_smoother(sig, *x0, gnss, data, measurements=[aid], imu=imu)
    assert np.all(np.isfinite(sm.states.position)) and "wheels" in sm.innovations
    # the covariance analysis along the truth: the user's aid shrinks the outage's error
    with_ = assess_aided(drive, imu, gnss, rate, 5.0, dur, measurements=[aid], budget=False,
                         progress=False)
    without = assess_aided(drive, imu, gnss, rate, 5.0, dur, budget=False, progress=False)
    assert with_["outages"][0]["position_p95_max_m"] < without["outages"][0]["position_p95_max_m"]
    # the aided Monte Carlo simulates its readings from the model and filters them
    mc = aided_monte_carlo(drive, imu, gnss, rate, dur, 6, seed=1, measurements=[aid],
                           progress=False)
    assert mc.runs == 6 and np.all(np.isfinite(mc.position_error))


def test_the_odometer_shortens_the_along_track_drift_of_an_outage(drive):
    """imunav's own odometer (wheel speed along the body x axis with a scale-factor state) on
    the example drive's 60 s outage: the along-track σ at the outage's end, from the covariance
    analysis along the truth, falls by more than half; and one filtered run ends its outage
    with a smaller along-track error."""
    imu = ImuModel.load("BMI088")
    rate = 50.0
    base = AidingConfig.from_toml(EXAMPLES / "drive_aiding.toml")
    odo = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                           "velocity_sigma": 0.1,
                                           "outages": [[60, 90], [160, 220]]},
                                  "nhc": {"sigma": 0.1},
                                  "odometer": {"rate": 10, "sigma": 0.05,
                                               "scale_factor_sigma": 0.01}})
    e_end = 219.0

    def along(cfg):
        at = aided_covariance(drive, imu, cfg, rate)
        k = int(np.searchsorted(at.t, e_end))
        wf, wt, _ = at.weights()
        P = at.propagate(wf, wt).truth_post[0, 0][k][6:9, 6:9]
        u = drive.velocity(np.array([at.t[k]]))[0]
        u /= np.linalg.norm(u)
        return float(np.sqrt(u @ P @ u))

    assert along(odo) < 0.5 * along(base)
    sig = simulate_imu(drive, rate, 300.0, kind="increments", imu=imu, seed=5)
    st = drive.states(np.array([0.0]))
    errs = []
    for cfg in (base, odo):
        data = simulate_aiding(drive, cfg, 300.0, seed=5, imu_rate=rate)
        r = run_filter(sig, st.quaternion[0], st.velocity[0], st.position[0], cfg, data, imu=imu)
        k = int(np.searchsorted(r.t, e_end))
        u = drive.velocity(r.t[k:k + 1])[0]
        errs.append(abs((r.states.position[k] - drive.position(r.t[k:k + 1])[0]) @ u)
                    / np.linalg.norm(u))
    assert errs[1] < errs[0], errs
