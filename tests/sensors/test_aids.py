"""The aiding sensors (issue 28): AIDING.toml parsing (every key, the defaults, the refusals),
the simulation of each sensor against the exact motion (its noise level, correlation and
lever arm measured on the readings), and the SHOE zero-velocity detector."""

from pathlib import Path

import numpy as np
import pytest

from imunav import Motion, WaypointMotion
from imunav.core.constants import DEG
from imunav.core.kernels import quat_rotate, quat_to_dcm
from imunav.core.validation import ImunavError
from imunav.sensors.aids import (
    AidingConfig,
    intervals_of,
    shoe_intervals,
    shoe_statistic,
    simulate_aiding,
    true_stance,
    wrap_angle,
)

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "aiding.toml"


def test_example_lists_every_key():
    """examples/aiding.toml has every key of every table (the commented [zupt] too)."""
    from imunav.sensors.aids import SECTIONS

    text = EXAMPLE.read_text()
    for section, cls in SECTIONS.items():
        assert f"[{section}]" in text, section
        for key in cls.KEYS:
            assert f"{key} =" in text, (section, key)
    cfg = AidingConfig.from_toml(EXAMPLE)
    assert cfg.sensors == ["gnss", "baro", "heading", "nhc"]
    assert cfg.heading.sigma == pytest.approx(2 * DEG, rel=1e-15)
    assert cfg.gnss.outages == ((20.0, 35.0),)


def test_defaults():
    cfg = AidingConfig.from_dict({"gnss": {"rate": 2, "position_sigma": 3},
                                  "baro": {"rate": 1, "sigma": 1}, "nhc": {"sigma": 0.1},
                                  "zupt": {"sigma": 0.01}})
    g = cfg.gnss
    assert (g.velocity_sigma, g.correlated_sigma, g.correlation_time, g.lever_arm,
            g.outages) == (None, 0.0, None, (0.0, 0.0, 0.0), ())
    assert cfg.baro.bias_drift == 0.0
    assert cfg.nhc.rate == 10.0
    z = cfg.zupt
    assert (z.detector, z.window, z.threshold, z.lever, z.probability, z.stride) == (
        "truth", 3, None, 0.1, 0.99, 1.2)
    assert (cfg.initial.position_sigma, cfg.initial.velocity_sigma,
            cfg.initial.attitude_sigma) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("d, fragment", [
    ({"gps": {}}, "unknown table(s) in AIDING file: gps"),
    ({"gnss": {"rate": 1, "position_sigma": 1, "sigma": 2}}, "unknown key(s) in [gnss]: sigma"),
    ({"gnss": {"rate": 1}}, "[gnss] position_sigma (m) is required"),
    ({"gnss": {"position_sigma": 1}}, "[gnss] rate (Hz) is required"),
    ({"gnss": {"rate": 1, "position_sigma": 0}}, "[gnss] position_sigma must be a positive"),
    ({"gnss": {"rate": 1, "position_sigma": -1}}, "[gnss] position_sigma must be a positive"),
    ({"gnss": {"rate": 1, "position_sigma": 1, "velocity_sigma": 0}},
     "[gnss] velocity_sigma must be a positive"),
    ({"gnss": {"rate": 1, "position_sigma": 1, "correlated_sigma": 1}},
     "correlated_sigma needs correlation_time"),
    ({"gnss": {"rate": 1, "position_sigma": 1, "lever_arm": [1, 2]}}, "lever_arm must be 3"),
    ({"gnss": {"rate": 1, "position_sigma": 1, "outages": [[5, 3]]}}, "outages[0] must be"),
    ({"gnss": {"rate": 1, "position_sigma": "1"}}, "position_sigma must be a finite number"),
    ({"baro": {"rate": 1, "sigma": 0}}, "[baro] sigma must be a positive"),
    ({"baro": {"rate": 1, "sigma": 1, "bias_drift": -1}},
     "[baro] bias_drift must be a non-negative number (m/√s), got -1"),
    ({"heading": {"rate": 1, "sigma": "2 m"}}, "[heading] sigma = '2 m': unit 'm' is not an angle unit"),
    ({"nhc": {"sigma": -0.1}}, "[nhc] sigma must be a positive"),
    ({"zupt": {"sigma": 0.1, "detector": "glrt"}}, "detector must be \"truth\" or \"shoe\""),
    ({"zupt": {"sigma": 0.1, "window": 0}}, "window must be a whole number"),
    ({"initial": {"position_sigma": -1}},
     "[initial] position_sigma must be a non-negative number (m), got -1"),
    ({"gnss": [1, 2]}, "[gnss] must be a table"),
])
def test_refusals_name_table_and_key(d, fragment):
    with pytest.raises(ImunavError) as e:
        AidingConfig.from_dict(d)
    assert fragment in str(e.value)


def test_file_errors_name_the_file(tmp_path):
    p = tmp_path / "a.toml"
    p.write_text("[gnss]\nrate = 1\nposition_sigma = 1\nfoo = 2\n")
    with pytest.raises(ImunavError, match=r"a\.toml: unknown key\(s\) in \[gnss\]: foo"):
        AidingConfig.from_toml(p)


def _drive():
    return Motion(x="10*t + 5*sin(0.2*t)", y="30*sin(0.05*t)", z="-2*sin(0.1*t)",
                  yaw="0.4*sin(0.05*t)", pitch="0.05*sin(0.1*t)", roll="0.1*sin(0.3*t)",
                  duration=400)


def test_gnss_readings_have_their_noise_lever_arm_and_outages():
    """Position minus the exact antenna position: mean 0, σ as configured; velocity minus the
    antenna's exact velocity (``v + C (ω × l)``) likewise; no fix inside an outage."""
    m = _drive()
    lever = np.array([1.0, -0.5, -2.0])
    cfg = AidingConfig.from_dict({"gnss": {"rate": 10, "position_sigma": 2.0,
                                           "velocity_sigma": 0.2, "lever_arm": lever.tolist(),
                                           "outages": [[100, 160]]}})
    d = simulate_aiding(m, cfg, 400.0, seed=1)
    t = d.gnss.t
    assert t.size == 4000 - 601 and not np.any((t >= 100) & (t <= 160))
    q = m.attitude(t)
    ant = m.position(t) + quat_rotate(q, np.broadcast_to(lever, (t.size, 3)))
    e = d.gnss.values[:, :3] - ant
    assert np.abs(e.mean(axis=0)).max() < 4 * 2.0 / np.sqrt(t.size)
    np.testing.assert_allclose(e.std(axis=0), 2.0, rtol=0.05)
    vel = m.velocity(t) + quat_rotate(q, np.cross(m.angular_rate(t), lever))
    ev = d.gnss.values[:, 3:] - vel
    np.testing.assert_allclose(ev.std(axis=0), 0.2, rtol=0.05)
    assert np.abs(ev.mean(axis=0)).max() < 4 * 0.2 / np.sqrt(t.size)


def test_gnss_gauss_markov_error_has_its_variance_and_correlation():
    """The correlated part: stationary σ and lag-τ autocorrelation e^{−1} (pooled over runs)."""
    m = _drive()
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1e-6,
                                           "correlated_sigma": 3.0, "correlation_time": 20.0}})
    es = []
    for run in range(40):
        d = simulate_aiding(m, cfg, 400.0, seed=2, run=run)
        es.append(d.gnss.values[:, :3] - m.position(d.gnss.t))
    e = np.array(es)                                       # (runs, n, 3)
    assert e.std() == pytest.approx(3.0, rel=0.05)
    lag = 20
    rho = (e[:, lag:] * e[:, :-lag]).mean() / (e * e).mean()
    assert rho == pytest.approx(np.exp(-1.0), abs=0.05)


def test_baro_and_heading_readings():
    """Baro: ``−z`` plus white noise and a random walk of density bias_drift (the variance of
    the error grows as σ² + drift²·t, pooled over runs); heading: the true yaw plus σ, wrapped."""
    m = _drive()
    cfg = AidingConfig.from_dict({"baro": {"rate": 2, "sigma": 0.3, "bias_drift": 0.05},
                                  "heading": {"rate": 1, "sigma": 0.02}})
    eb, eh = [], []
    for run in range(60):
        d = simulate_aiding(m, cfg, 400.0, seed=3, run=run)
        eb.append(d.baro.values[:, 0] + m.position(d.baro.t)[:, 2])
        C = quat_to_dcm(m.attitude(d.heading.t))
        eh.append(wrap_angle(d.heading.values[:, 0] - np.arctan2(C[:, 1, 0], C[:, 0, 0])))
    eb = np.array(eb)
    tb = d.baro.t
    want = 0.3 ** 2 + 0.05 ** 2 * tb
    np.testing.assert_allclose(eb[:, -200:].var(axis=0).mean(), want[-200:].mean(), rtol=0.15)
    assert np.array(eh).std() == pytest.approx(0.02, rel=0.05)
    assert np.all(np.abs(d.heading.values) <= np.pi)


def test_streams_are_reproducible_and_independent():
    m = _drive()
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.0},
                                  "baro": {"rate": 1, "sigma": 1.0}})
    a = simulate_aiding(m, cfg, 50.0, seed=7)
    b = simulate_aiding(m, cfg, 50.0, seed=7)
    np.testing.assert_array_equal(a.gnss.values, b.gnss.values)
    # adding a sensor does not change another's draws
    only = simulate_aiding(m, AidingConfig.from_dict({"baro": {"rate": 1, "sigma": 1.0}}), 50.0,
                           seed=7)
    np.testing.assert_array_equal(only.baro.values, a.baro.values)
    c = simulate_aiding(m, cfg, 50.0, seed=7, run=1)
    assert not np.allclose(c.gnss.values, a.gnss.values)


def test_nhc_readings_are_the_slip_and_stance_is_the_still_motion():
    m = Motion(x="0", duration=10)                         # standing still
    cfg = AidingConfig.from_dict({"nhc": {"sigma": 0.1, "rate": 20}, "zupt": {"sigma": 0.01}})
    d = simulate_aiding(m, cfg, 10.0, seed=1, imu_rate=100)
    assert d.nhc.values.shape == (200, 2)
    assert d.nhc.values.std() == pytest.approx(0.1, rel=0.1)
    np.testing.assert_array_equal(d.zupt, [[0.0, 10.0]])
    route = WaypointMotion([0.0, 5.0, 10.0], [[0, 0, 0], [20, 5, 0], [30, 30, -1]])
    np.testing.assert_array_equal(true_stance(route, 100.0, 10.0), [[0, 0], [10, 10]])
    moving = Motion(x="t - sin(t)", duration=10)          # v = 1 − cos t: still only at t = 0
    np.testing.assert_array_equal(true_stance(moving, 1000.0, 10.0), [[0, 0]])


def test_intervals_of_runs():
    f = np.array([0, 1, 1, 0, 1, 0, 0, 1], dtype=bool)
    t = np.arange(8.0)
    np.testing.assert_array_equal(intervals_of(f, t), [[1, 2], [4, 4], [7, 7]])
    assert intervals_of(np.zeros(3, bool), t[:3]).shape == (0, 2)


def test_shoe_statistic_is_the_formula_and_detects_rest():
    """The statistic against a direct evaluation of its formula on a window; at rest with
    OpenShoe-level noise it is of order 1 (below the threshold), in motion far above."""
    rng = np.random.default_rng(4)
    g = 9.80665
    n = 400
    gyro = rng.normal(0, 0.1 * DEG, (n, 3))
    acc = np.array([0, 0, -g]) + rng.normal(0, 0.01, (n, 3))
    gyro[200:] += [0.5, -0.3, 1.0]                          # moving from sample 200
    acc[200:] += [2.0, 1.0, 0.5]
    T = shoe_statistic(gyro, acc, g=g, window=3)
    k = 100
    W = acc[k - 1:k + 2]
    u = W.mean(axis=0) / np.linalg.norm(W.mean(axis=0))
    want = (np.sum((W - g * u) ** 2) / 0.01 ** 2 + np.sum(gyro[k - 1:k + 2] ** 2)
            / (0.1 * DEG) ** 2) / 3
    assert T[k] == pytest.approx(want, rel=1e-12)
    assert np.median(T[:190]) < 20 and T[210:].min() > 1e5
    st = shoe_intervals(np.arange(n) / 100.0, gyro, acc, g=g)
    assert st[0, 0] == 0.0 and st[-1, 1] < 2.01


def test_outages_overlapping_or_outside_the_record_are_refused():
    """An overlap, or an outage wholly after the record, used to be accepted silently (an
    outage at 400-500 s on a 300 s drive left the verdict 'SUITABLE' and the report silent)."""
    import pytest as _pytest

    from imunav.core.validation import ImunavError
    from imunav.sensors.aids import AidingConfig

    with _pytest.raises(ImunavError, match=r"outages\[1\].*without overlaps"):
        AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.0,
                                         "outages": [[20, 35], [30, 40]]}})
    cfg = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.0,
                                           "outages": [[400, 500]]}})
    with _pytest.raises(ImunavError, match=r"outages\[0\] = \[400, 500\] s lies outside"):
        cfg.gnss.check_within(0.0, 300.0)
    AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.0,
                                     "outages": [[250, 400]]}}).gnss.check_within(0.0, 300.0)
