"""The levelled initial attitude (``alignment="level"``): the levelling Jacobian against the
levelling itself, the window statistics against quadrature, the bias/tilt equivalence at rest
(closed form), the covariance analysis against Monte Carlo runs that each level from their own
accelerometer, and the command line's --alignment."""

import json

import numpy as np
import pytest
from scipy.integrate import quad

from imunav import Motion
from imunav.analysis.assessment import assess, assess_covariance, format_verdict
from imunav.analysis.covariance import covariance, covariance_summary
from imunav.analysis.design import design
from imunav.analysis.montecarlo import monte_carlo
from imunav.cli import main
from imunav.core.constants import G0
from imunav.core.kernels import quat_to_dcm
from imunav.core.rotations import euler_to_quat, quat_to_euler
from imunav.core.validation import ImunavError
from imunav.estimation.alignment import levelling_jacobian, window_statistics
from imunav.motion.catalog import figure_eight
from imunav.sensors.models import ImuModel, TriadModel
from imunav.sensors.terms import SensorErrorStates
from imunav.strapdown.initial import level_attitude

STILL = Motion(duration=20.0, name="still")


def _tilt(q_est, q_true):
    """φ with ``Ĉ = (I − [φ×]) C`` (small angles), from two attitudes."""
    E = quat_to_dcm(q_est) @ quat_to_dcm(q_true).T          # ≈ I − [φ×]
    return 0.5 * np.array([E[1, 2] - E[2, 1], E[2, 0] - E[0, 2], E[0, 1] - E[1, 0]])


@pytest.mark.parametrize("ypr_deg", [(0, 0, 0), (40, 0, 0), (0, 25, 0), (0, 0, -35),
                                     (120, -30, 20), (-75, 60, 170)])
def test_levelling_jacobian_is_the_derivative_of_the_levelling(ypr_deg):
    """J against central differences of :func:`level_attitude` itself (heading held)."""
    q0 = euler_to_quat(np.radians(ypr_deg))
    yaw = quat_to_euler(q0)[0]
    f = quat_to_dcm(q0).T @ np.array([0.0, 0.0, -G0])
    assert np.abs(_tilt(level_attitude(f, yaw=yaw), q0)).max() < 1e-12   # exact at rest
    eps = 1e-5
    fd = np.column_stack([(_tilt(level_attitude(f + eps * e, yaw=yaw), q0)
                           - _tilt(level_attitude(f - eps * e, yaw=yaw), q0)) / (2 * eps)
                          for e in np.eye(3)])
    np.testing.assert_allclose(levelling_jacobian(q0), fd, atol=1e-9)


def test_levelling_jacobian_level_is_the_textbook_tilt():
    """Level: a bias b gives the tilt (b_y, −b_x, 0)/g, which makes the gravity it leaks
    cancel the bias (Titterton & Weston §10.3: the levelling error is b/g)."""
    J = levelling_jacobian(np.array([1.0, 0, 0, 0]))
    np.testing.assert_allclose(J, [[0, 1 / G0, 0], [-1 / G0, 0, 0], [0, 0, 0]], atol=1e-15)


@pytest.mark.parametrize("d, q, p0", [(-1 / 0.3, 0.7, 2.0), (-1 / 40.0, 1.3, 0.5),
                                      (0.0, 0.9, 0.0), (0.0, 0.0, 3.0), (-1e-4, 2.0, 1.0)])
def test_window_statistics_against_quadrature(d, q, p0):
    """The joint covariance of x(W) and ∫₀ᵂ x, for ẋ = d x + w (PSD q), x(0) ~ N(0, p0),
    from the defining integrals evaluated by scipy's quad."""
    W = 10.0
    st = SensorErrorStates("accel.x", "accel", np.array([d]), np.array([[p0]]), np.array([q]))
    Pxx, Pzx, Pzz = (float(x[0, 0]) for x in window_statistics(st, W))

    def resp(s):           # the response of ∫ x at W to a unit impulse of w at s
        return quad(lambda t: np.exp(d * (t - s)), s, W, epsabs=0, epsrel=1e-13)[0]

    a, z0 = np.exp(d * W), quad(lambda t: np.exp(d * t), 0, W, epsrel=1e-13)[0]
    kw = {"epsabs": 0, "epsrel": 1e-11, "limit": 200}
    assert Pxx == pytest.approx(a * a * p0 + q * quad(lambda s: np.exp(2 * d * (W - s)), 0, W,
                                                      **kw)[0], rel=1e-9)
    assert Pzx == pytest.approx(z0 * a * p0 + q * quad(lambda s: resp(s) * np.exp(d * (W - s)),
                                                       0, W, **kw)[0], rel=1e-9)
    assert Pzz == pytest.approx(z0 * z0 * p0 + q * quad(lambda s: resp(s) ** 2, 0, W,
                                                        **kw)[0], rel=1e-9)


@pytest.mark.parametrize("motion", [STILL, Motion(yaw="0.7", pitch="0.4", roll="-0.3",
                                                  duration=20.0, name="still, tilted")])
def test_levelling_absorbs_the_horizontal_bias_at_rest(motion):
    """At rest the levelled tilt cancels the horizontal accelerometer bias exactly (any
    attitude); the vertical part still integrates to ½ b t²."""
    sigma = 0.02                                                  # m/s², 1σ per axis
    m = ImuModel(accel=TriadModel(bias=sigma))
    truth = covariance(motion, m, 50.0, alignment="truth").total[-1, 6:9, 6:9]
    level = covariance(motion, m, 50.0, alignment="level").total[-1, 6:9, 6:9]
    half = (0.5 * sigma * 20.0 ** 2) ** 2                         # (½ σ t²)²
    np.testing.assert_allclose(np.diag(truth), half, rtol=1e-9)
    assert np.abs(level[:2]).max() < 1e-9 * half                 # north, east: absorbed
    assert level[2, 2] == pytest.approx(half, rel=1e-9)          # down: not


def test_levelled_noise_and_random_walk_of_the_window():
    """The window's mean white noise becomes a constant tilt, φ ~ N/√W / g per level axis,
    whose leaked gravity grows as ½ g φ t²; a random walk has grown over the window."""
    N, W, T = 1e-3, 10.0, 20.0
    cov = covariance(STILL, ImuModel(accel=TriadModel(noise_density=N)), 50.0,
                     alignment="level", align_window=W, kind="rates")
    P0 = cov.total[0]
    np.testing.assert_allclose(np.diag(P0)[:2], N * N / W / G0 ** 2, rtol=1e-12)
    assert P0[2, 2] == 0.0
    truth = covariance(STILL, ImuModel(accel=TriadModel(noise_density=N)), 50.0, kind="rates")
    extra = (0.5 * G0 * T * T) ** 2 * N * N / W / G0 ** 2        # the tilt's ½ g φ t²
    np.testing.assert_allclose(cov.total[-1, 6, 6] - truth.total[-1, 6, 6], extra, rtol=1e-9)
    K = 1e-3
    rw = covariance(STILL, ImuModel(gyro=TriadModel(random_walk=K)), 50.0, alignment="level",
                    align_window=W)
    rw_truth = covariance(STILL, ImuModel(gyro=TriadModel(random_walk=K)), 50.0)
    # a rate random walk switched on W earlier: b(0) ~ N(0, K² W), and φ(t) = t b(0) + ∫₀ᵗ
    # (b − b(0)): K² (t² W + t³/3), against K² t³/3 from a start at t = 0
    t = T
    assert rw.total[-1, 0, 0] == pytest.approx(K * K * (t * t * W + t ** 3 / 3), rel=1e-9)
    assert rw_truth.total[-1, 0, 0] == pytest.approx(K * K * t ** 3 / 3, rel=1e-9)


RUNS = 500


def _quantile_interval(samples, p=0.95, alpha=1e-3):
    """Distribution-free (1 − α) interval of the p-quantile (order statistics)."""
    from scipy import stats

    n = samples.shape[0]
    s = np.sort(samples, axis=0)
    lo = int(stats.binom.ppf(alpha / 2, n, p))
    hi = int(stats.binom.ppf(1 - alpha / 2, n, p)) + 1
    return s[max(lo - 1, 0)], s[min(hi - 1, n - 1)]


#: Besides sampling: the simulation's discrete noise against the PSD, linearisation, and the
#: window's sampled mean against its integral (O(h/τ) for the fastest flicker state).
MODEL = 0.02

RICH = ImuModel(TriadModel(noise_density=2e-5, bias=5e-6, random_walk=1e-5),
                TriadModel(noise_density=5e-4, bias=0.01, bias_instability=2e-4,
                           misalignment=1e-3, scale_factor=3e-4, random_walk=2e-4,
                           resolution=1e-3), "rich")


@pytest.mark.parametrize("motion, model, output", [
    (figure_eight(), ImuModel.load("tactical"), "increments"),
    (Motion(x="3*t + sin(0.4*t)", yaw="0.8*sin(0.2*t)", pitch="0.2", duration=20.0,
            name="pitched drive"), RICH, "increments"),
    (Motion(x="3*t + sin(0.4*t)", yaw="0.8*sin(0.2*t)", pitch="0.2", duration=20.0,
            name="pitched drive"), RICH, "rates"),
])
def test_levelled_covariance_agrees_with_levelled_monte_carlo(motion, model, output):
    """Each Monte Carlo run levels from its own measured accelerometer over the window; the
    covariance analysis couples the tilt with the sensor states: the same 95th percentiles of
    the position and attitude errors (at the start and at ten times), in total and for the
    terms the levelling touches."""
    rate = 50.0
    cov = covariance(motion, model, rate, kind=output, alignment="level")
    assert not cov.warnings
    idx = np.linspace(0, cov.t.size - 1, 11).round().astype(int)
    for term in [None, "accel.bias", "accel.bias_instability", "accel.misalignment",
                 "accel.noise_density", "accel.random_walk"]:
        if term is not None and term not in cov.terms:
            continue
        m = model if term is None else model.only(term)
        mc = monte_carlo(motion, m, rate, runs=RUNS, seed=17, kind=output, progress=False,
                         alignment="level")
        for key, q in (("position", cov.position_quantile), ("attitude", cov.attitude_quantile)):
            c = q(index=idx, term=term)
            lo, hi = _quantile_interval(getattr(mc, key)[:, idx])
            ok = (hi < 1e-9) | ((c >= lo / (1 + MODEL)) & (c <= hi * (1 + MODEL)))
            assert ok.all(), (term, key, c, lo, hi)


def test_levelling_changes_the_verdict_and_the_budget():
    """On a vehicle drive with a tactical IMU: levelled, the accelerometer bias alone drops to
    its vertical share (the horizontal is absorbed while the heading holds), the verdict says
    how it started, and the design's limits stay the square-root scaling of the covariance."""
    car = Motion(x="10*t", duration=60.0, name="straight drive")
    tac = ImuModel.load("tactical")
    r_t = assess_covariance(car, tac, 50.0, tolerance=30.0, progress=False)
    r_l = assess_covariance(car, tac, 50.0, tolerance=30.0, progress=False, alignment="level")
    assert "alignment" not in r_t and r_l["alignment"] == {"method": "level", "window_s": 10.0}
    assert "levelled from the accelerometer" in format_verdict(r_l)
    assert "levelled" not in format_verdict(r_t)
    b_t, b_l = r_t["error_budget"]["accel.bias"], r_l["error_budget"]["accel.bias"]
    half = 0.5 * tac.accel.bias * 60.0 ** 2                      # ½ σ t², σ per axis
    assert b_l == pytest.approx(1.959964 * half, rel=1e-4)       # 1-D: the vertical alone
    assert b_t > 2.7 * half                                      # 3-D norm
    d = design(car, tac, 50.0, tolerance=30.0, progress=False, alignment="level")
    s = covariance_summary(car, tac, 50.0, p=0.95, maxima=True, alignment="level")
    worst = s.max_position_quantile(0.95, term="accel.bias")
    assert d["terms"]["accel.bias"]["limit_si"] == pytest.approx(tac.accel.bias * 30.0 / worst)
    assert d["alignment"]["method"] == "level"


def test_alignment_arguments_are_checked():
    with pytest.raises(ImunavError, match="alignment must be one of truth, level"):
        covariance(STILL, ImuModel.load("tactical"), 10.0, alignment="gyrocompass")
    with pytest.raises(ImunavError, match="align_window"):
        monte_carlo(STILL, ImuModel.load("tactical"), 10.0, runs=2, alignment="level",
                    align_window=0.0, progress=False)
    with pytest.raises(ImunavError, match="alignment"):
        assess(STILL, ImuModel.load("tactical"), 10.0, 2, 1.0, alignment="levelled",
               progress=False)


def test_command_line_alignment(tmp_path, capsys):
    (tmp_path / "m.toml").write_text('duration = 20.0\n[position]\nx = "5*t"\n')
    m, out = str(tmp_path / "m.toml"), tmp_path / "v.json"
    base = ["assess", m, "--imu", "tactical", "--rate", "20", "--tolerance", "5"]
    assert main(base) == 0
    plain = capsys.readouterr().out
    assert "levelled" not in plain
    assert main([*base, "--alignment", "level", "--align-window", "30", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "levelled from the accelerometer at rest over 30 s" in text
    assert json.loads(out.read_text())["alignment"] == {"method": "level", "window_s": 30.0}
    assert main([*base, "--align-window", "30"]) == 2
    assert "--align-window applies to --alignment level only" in capsys.readouterr().err
    assert main([*base, "--alignment", "level", "--align-window", "-1"]) == 2
    assert "--align-window" in capsys.readouterr().err
    assert main(["design", m, "--imu", "tactical", "--rate", "20", "--tolerance", "5",
                 "--alignment", "level"]) == 0
    assert "levelled from the accelerometer" in capsys.readouterr().out
    assert main([*base, "--alignment", "level", "--earth", "wgs84", "--origin", "45,10,100",
                 "--method", "montecarlo", "--runs", "2"]) == 2
    assert "--alignment level works on --earth flat only" in capsys.readouterr().err
