"""Monte Carlo plumbing (issue 19, found by the mutation run): an ideal IMU's runs are exactly
the round trip of the chosen algorithm, with the chosen gravity and duration; argument checks;
when the progress bar appears. The truth errors are computed here with scipy and the laws."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from imunav import ImunavError, Motion, navigate, simulate_imu
from imunav.analysis.montecarlo import _progress, monte_carlo
from imunav.sensors.models import ImuModel

M = Motion(x="2*sin(0.7*t)", y="0.5*t**2", yaw="0.5*sin(0.9*t)", roll="0.2*sin(1.3*t)",
           duration=2.0, name="m")


def test_ideal_runs_are_the_round_trip_of_the_chosen_algorithm_and_gravity():
    g = 9.7
    mc = monte_carlo(M, ImuModel.load("ideal"), 50.0, duration=1.5, runs=2, kind="rates",
                     g=g, algorithm="first_order", progress=False)
    sig = simulate_imu(M, 50.0, 1.5, kind="rates", g=g)
    t0 = np.array([0.0])
    nav = navigate(sig, M.attitude(t0)[0], M.velocity(t0)[0], M.position(t0)[0],
                   algorithm="first_order", g=g)
    np.testing.assert_allclose(mc.t, nav.t, atol=1e-15)
    assert mc.t[-1] == pytest.approx(1.5)
    pos = np.linalg.norm(nav.position - M.position(nav.t), axis=-1)
    vel = np.linalg.norm(nav.velocity - M.velocity(nav.t), axis=-1)
    att = (Rotation.from_quat(M.attitude(nav.t), scalar_first=True).inv()
           * Rotation.from_quat(nav.quaternion, scalar_first=True)).magnitude()
    for run in range(2):
        np.testing.assert_allclose(mc.position[run], pos, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(mc.velocity[run], vel, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(mc.attitude[run], att, rtol=1e-7, atol=1e-12)
    assert vel.max() > 1e-3 and att.max() > 1e-4          # first order: visibly non-zero


def test_defaults_and_argument_checks():
    model = ImuModel.load("BMI088")
    a = monte_carlo(M, model, 20.0, progress=False)
    b = monte_carlo(M, model, 20.0, runs=100, seed=0, progress=False)
    assert a.runs == 100
    np.testing.assert_array_equal(a.position, b.position)
    with pytest.raises(ImunavError, match="^runs must be an integer ≥ 1"):
        monte_carlo(M, model, 20.0, runs=0)
    with pytest.raises(ImunavError, match="^rate must be"):
        monte_carlo(M, model, -20.0)
    with pytest.raises(ImunavError, match="^seed must be an integer ≥ 0"):
        monte_carlo(M, model, 20.0, seed=-1)


def test_progress_bar_only_for_long_runs(monkeypatch):
    # a recorder instead of tqdm: a real bar starts tqdm's monitor thread, and a thread alive at
    # a fork (mutmut forks a process per mutant) can leave a lock held in the child
    import tqdm.auto

    made = []
    monkeypatch.setattr(tqdm.auto, "tqdm", lambda **kw: made.append(kw) or kw)
    assert _progress(3, 10**7, False) is None
    assert _progress(1, 10**7, True) is None                 # one chunk: nothing to show
    assert _progress(3, 4_999_999, True) is None             # short: no bar
    assert made == []
    bar = _progress(2, 5_000_000, True)                      # the smallest run with a bar
    assert made == [bar] == [{"total": 2, "desc": "Monte Carlo", "unit": "chunk"}]
