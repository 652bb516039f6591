"""The aided filter on the rotating WGS-84 Earth (issue 28): its measurement Jacobians against
finite differences of the full nonlinear prediction, and its consistency by Monte Carlo with
known truth (an exact EarthMotion): NEES of position, velocity and attitude inside the 95 % χ²
band, white innovations, the smoother consistent too."""

from __future__ import annotations

import numpy as np
import pytest

from imunav.analysis.aided_montecarlo import filter_monte_carlo
from imunav.estimation.inertial import EarthSide
from imunav.estimation.measurements import Baro, GnssFix, Heading, Nhc, Zupt
from imunav.motion.geodetic import EarthMotion
from imunav.sensors.aids import AidingConfig, build_measurements
from tests.estimation.test_filters import IMU_TERMS, assert_consistent, assert_white, drive

ORIGIN = (np.radians(50.0), np.radians(30.0), 200.0)


def _nav_state():
    """A moving, turned state at 50° N an hour into the record (the inertial frame has turned
    by 15° from ECEF), its inertial form."""
    m = EarthMotion(drive(100.0), ORIGIN)
    st = m.states(np.array([40.0]))
    E = EarthSide(0.01, -3600.0, st.quaternion[0], st.velocity[0], st.position[0])
    return E, E.state()                         # the inertial state


@pytest.mark.parametrize("meas", [
    GnssFix(1.0, 0.1, lever_arm=(1.0, 0.2, -1.5)), Baro(0.5), Heading(0.01), Nhc(0.05),
    Zupt(0.01)], ids=lambda m: m.name)
def test_earth_jacobians_match_finite_differences(meas):
    """``predicted − reading`` at a state with a small inertial error ``e`` minus the same at
    the state itself equals ``H e`` to second order: the local prediction (GNSS fixes as NED
    offsets of the estimate, heights above the ellipsoid, the Earth-relative body rate) and
    the map onto the inertial error state together. Errors of 1e-4 rad, 0.01 m/s and 1 m:
    the second-order remainder is ~1e-4 of the first-order term (checked at two sizes)."""
    E, inertial = _nav_state()
    t = 0.0                                      # an hour after the inertial frame was ECEF
    meas.bind({})
    omega = np.array([0.01, -0.02, 0.3])
    est = np.zeros(9)
    Mg = np.zeros((3, 9))
    values = {"gnss": np.array([ORIGIN[0] + 1e-6, ORIGIN[1] - 2e-6, 190.0, 1.0, 2.0, 0.1]),
              "baro": np.array([190.0]), "heading": np.array([0.3]), "nhc": np.zeros(2),
              "zupt": np.zeros(3)}[meas.name]
    if meas.name == "gnss":                            # near the state (linearity)
        loc = E.local(t, *inertial)
        values[:3] = loc[2] + np.array([3e-7, -2e-7, 2.0])

    def z(x):
        nav, lla, M = E.reading(t, inertial, x, omega, 0.0, est, Mg)
        vals = meas.localise(values, lla)
        return meas.residual(meas.predict(nav), vals), meas.jacobian(nav), M

    rng = np.random.default_rng(2)
    e = np.concatenate([rng.normal(0, 1e-4, 3), rng.normal(0, 1e-2, 3), rng.normal(0, 1.0, 3)])
    z0, Hl, M = z(np.zeros(9))
    H = Hl @ M
    for scale in (1.0, 0.1):
        # the estimate with error e is the state corrected by −e
        dz = z(-scale * e)[0] - z0
        np.testing.assert_allclose(dz, scale * H @ e, rtol=2e-3 * scale + 1e-6,
                                   atol=1e-9 * scale)


def test_earth_gnss_fix_is_the_ned_offset():
    """A GNSS fix 10 m north, 5 m east and 2 m above the estimate (no lever arm) gives the
    innovation −[10, 5, −2] m in local NED, and its Jacobian on the inertial position error
    is ``C_ni`` (orthonormal, its down row the local down)."""
    E, inertial = _nav_state()
    t = 0.0                                      # an hour after the inertial frame was ECEF
    q, v, lla = E.local(t, *inertial)
    from imunav.earth import radii
    rn, re = radii(lla[0])
    fix = lla + np.array([10.0 / (rn + lla[2]), 5.0 / ((re + lla[2]) * np.cos(lla[0])), 2.0])
    g = GnssFix(1.0)
    g.bind({})
    nav, lla_est, M = E.reading(t, inertial, np.zeros(9), np.zeros(3), 0.0, np.zeros(9),
                                np.zeros((3, 9)))
    vals = g.localise(fix, lla_est)
    np.testing.assert_allclose(g.residual(g.predict(nav), vals), [-10.0, -5.0, 2.0], atol=2e-5)
    C = (g.jacobian(nav) @ M)[:, 6:9]
    np.testing.assert_allclose(C @ C.T, np.eye(3), atol=1e-12)


RUNS = 12


@pytest.fixture(scope="module")
def earth_gnss_drive():
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                           "velocity_sigma": 0.1,
                                           "lever_arm": [1.0, 0.2, -1.5]}})
    motion = EarthMotion(drive(100.0), ORIGIN)
    mc = filter_monte_carlo(motion, IMU_TERMS, cfg, 100.0, 100.0, RUNS, seed=3, smooth=True,
                            algorithm="coning2", skip=5.0)
    per_run = {name: [{k: v[r] for k, v in d.items()} for r in range(RUNS)]
               for name, d in (("filter", mc.filter), ("smoother", mc.smoother))}
    return {**per_run, "innovations": mc.innovations, "result": mc.results[0]}


def test_gnss_aided_earth_drive_is_consistent(earth_gnss_drive):
    """12 runs of 100 s at 50° N (the test MEMS IMU: biases, Gauss–Markov, random walk, scale
    factor, misalignment, g-sensitivity; GNSS position and velocity with a lever arm): the
    run-average NEES of each block inside the 95 % band of χ²(36)/12, filter and smoother."""
    assert_consistent(earth_gnss_drive["filter"], RUNS, "wgs84 filter")
    assert_consistent(earth_gnss_drive["smoother"], RUNS, "wgs84 smoother")


def test_earth_gnss_innovations_are_white(earth_gnss_drive):
    assert_white(earth_gnss_drive["innovations"], RUNS)


def test_earth_result_is_geodetic_and_the_smoother_more_certain(earth_gnss_drive):
    """The states are latitude, longitude, height (frame wgs84) near the origin; the
    smoothed σ nowhere above the filter's."""
    res = earth_gnss_drive["result"]
    assert res.states.frame == "wgs84" and res.smoothed.states.frame == "wgs84"
    assert abs(res.states.position[-1, 0] - ORIGIN[0]) < 1e-3
    assert np.all(res.smoothed.sd <= res.sd * (1 + 1e-9) + 1e-12)


def test_build_measurements_unchanged_on_earth():
    """The same aids and AIDING.toml keys on both frames."""
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.0},
                                  "baro": {"rate": 1, "sigma": 0.5}})
    assert set(build_measurements(cfg)) == {"gnss", "baro"}


def test_earth_fast_rows_are_the_models_transition():
    """Issue 39: the nav rows of Φ(s) the Earth filter's Gauss–Legendre nodes use (the flat
    rows plus the gravity-gradient terms, their φ₂…φ₄ remembered) equal the rows of
    ``EARTH.transition`` — the error model's own closed form — at every node."""
    from imunav.core.layout import NAV
    from imunav.estimation.error_model import EARTH, Trajectory
    from imunav.estimation.system import AidedSystem

    motion = EarthMotion(drive(20.0), (np.radians(50.0), np.radians(30.0), 200.0))
    traj = Trajectory.of(motion, 10.0, 2.0)
    assert traj.gradient is not None
    sysm = AidedSystem(IMU_TERMS, [Baro(0.5, 0.01)], h=0.01, model=EARTH)
    B = sysm.sensor_input(traj)
    rows = sysm._flat_rows(traj, B)
    for s in (0.0, 0.013, 0.1, 0.37):
        want = EARTH.transition(traj, B, sysm.D, s)[:, :NAV]
        np.testing.assert_allclose(rows(s), want, rtol=1e-14, atol=1e-15 * np.abs(want).max())
