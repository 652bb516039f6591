"""Linear covariance analysis (issue 18): the closed forms of inertial error growth, the norm
percentiles against independent distributions, and agreement with Monte Carlo within its
sampling error."""

import numpy as np
import pytest
from scipy import stats
from scipy.integrate import quad

from imunav import Motion
from imunav.analysis.covariance import LINEAR_LIMIT, covariance
from imunav.analysis.gaussnorm import norm_cdf, norm_quantile
from imunav.analysis.montecarlo import monte_carlo
from imunav.core.constants import G0
from imunav.core.kernels import quat_angle
from imunav.motion.catalog import figure_eight
from imunav.sensors.models import ImuModel, TriadModel, measure
from imunav.sensors.simulate import simulate_imu
from imunav.sensors.terms import bias_instability_sigma
from imunav.strapdown.registry import navigate_batch

STILL = Motion(duration=20.0, name="still")


def _model(triad, **kw):
    return ImuModel(**{triad: TriadModel(**kw)})


def _diag(P):
    return np.diagonal(P, axis1=-2, axis2=-1)


# ----------------------------------------------------------------------------- closed forms
# Textbook error growth of a level, stationary strapdown solution (e.g. Titterton & Weston,
# Strapdown Inertial Navigation Technology, §12; Groves, Principles of GNSS, Inertial and
# Multisensor Navigation, §5.7, without Schuler feedback over 20 s): every formula is written
# here from those sources, not from the code.

T_END = 20.0


def _cov(model, motion=STILL, rate=100.0, kind="rates"):
    return covariance(motion, model, rate, kind=kind)


def test_gyro_white_noise_attitude_and_position():
    N = 3e-4
    r = _cov(_model("gyro", noise_density=N))
    t = r.t
    np.testing.assert_allclose(_diag(r.total[:, 0:3, 0:3]), (N * N * t)[:, None] * [1, 1, 1],
                               rtol=1e-12, atol=0)
    hor = G0 ** 2 * N ** 2 * t ** 5 / 20                     # σ² = g²N²t⁵/20
    np.testing.assert_allclose(_diag(r.total[1:, 6:8, 6:8]), np.stack([hor[1:]] * 2, -1),
                               rtol=1e-12)
    assert np.abs(r.total[:, 8, 8]).max() == 0.0             # vertical: no tilt coupling


def test_gyro_bias_position_cubic():
    b = 1e-4
    r = _cov(_model("gyro", bias=b))
    t = r.t
    np.testing.assert_allclose(np.sqrt(_diag(r.total[1:, 0:3, 0:3])),
                               np.stack([b * t[1:]] * 3, -1), rtol=1e-12)
    np.testing.assert_allclose(np.sqrt(_diag(r.total[1:, 6:8, 6:8])),
                               np.stack([G0 * b * t[1:] ** 3 / 6] * 2, -1), rtol=1e-12)


def test_accel_bias_and_white_noise():
    b, N = 2e-3, 1e-3
    r = _cov(_model("accel", bias=b))
    t = r.t[1:]
    np.testing.assert_allclose(np.sqrt(_diag(r.total[1:, 6:9, 6:9])),
                               np.stack([b * t * t / 2] * 3, -1), rtol=1e-12)
    r = _cov(_model("accel", noise_density=N))
    np.testing.assert_allclose(_diag(r.total[1:, 6:9, 6:9]),
                               np.stack([N * N * t ** 3 / 3] * 3, -1), rtol=1e-12)
    assert np.abs(r.total[:, 0:3, 0:3]).max() == 0.0         # accel errors never tilt


def test_random_walk_and_gauss_markov_attitude():
    K = 1e-5
    t = _cov(_model("gyro", random_walk=K)).t
    att = _diag(_cov(_model("gyro", random_walk=K)).total[:, 0:3, 0:3])
    np.testing.assert_allclose(att[1:], np.stack([K * K * t[1:] ** 3 / 3] * 3, -1), rtol=1e-12)
    # stationary Gauss–Markov bias (std s, correlation T): Var ∫₀ᵗ b = 2s²T²(t/T − 1 + e^{−t/T});
    # s is the σ whose Allan peak is B (pinned to the textbook 0.6174 s in tests/sensors/test_terms)
    B, T = 1e-4, 7.0
    s = bias_instability_sigma(B, T)
    att = _diag(_cov(_model("gyro", bias_instability=B, bias_correlation_time=T),
                     rate=10.0).total[:, 0:3, 0:3])
    t = np.arange(att.shape[0]) / 10.0
    want = 2 * s * s * T * T * (t / T - 1 + np.exp(-t / T))
    np.testing.assert_allclose(att[1:], np.stack([want[1:]] * 3, -1), rtol=1e-11)
    # a correlation time 20× shorter than the step (the bias decorrelates within one step:
    # the step is cut into sub-steps of at most half a decay time)
    T = 0.005
    s = bias_instability_sigma(B, T)
    att = _diag(_cov(_model("gyro", bias_instability=B, bias_correlation_time=T),
                     rate=10.0).total[:, 0:3, 0:3])
    want = 2 * s * s * T * T * (t / T - 1 + np.exp(-t / T))
    np.testing.assert_allclose(att[1:], np.stack([want[1:]] * 3, -1), rtol=1e-9)


def test_scale_factor_on_a_constant_turn():
    w, s = 0.5, 1e-3
    turn = Motion(yaw="0.5*t", duration=T_END)
    r = _cov(_model("gyro", scale_factor=s), motion=turn)
    np.testing.assert_allclose(np.sqrt(r.total[1:, 2, 2]), s * w * r.t[1:], rtol=1e-12)
    assert np.abs(r.total[:, 0:2, 0:2]).max() < 1e-30        # the error stays about z


def test_resolution_rates_white_increments_bounded():
    q, rate = 1e-3, 50.0
    r = _cov(_model("gyro", resolution=q), rate=rate, kind="rates")
    np.testing.assert_allclose(_diag(r.total[1:, 0:3, 0:3]),
                               np.stack([q * q / (12 * rate) * r.t[1:]] * 3, -1), rtol=1e-12)
    # increments carry the rounding residual: the angle error is the current residual, uniform
    # on ±q·h/2 per axis (variance (qh)²/12) at every time, however long the motion
    r = _cov(_model("gyro", resolution=q), rate=rate, kind="increments")
    np.testing.assert_allclose(_diag(r.total[1:, 0:3, 0:3]), (q / rate) ** 2 / 12, rtol=1e-12)
    # every term starts from the known initial state; the constant tilt then drives a
    # horizontal position error that grows at every step (g·φ·t²/2)
    assert np.all(r.total[0] == 0)
    assert np.all(np.diff(_diag(r.total[:, 6:8, 6:8]), axis=0) > 0)


# ----------------------------------------------------------------------------- the norm


@pytest.mark.parametrize("lam, dist", [
    ((1.0, 1.0, 1.0), stats.chi(3)),                 # isotropic: χ₃
    ((1.0, 1.0, 0.0), stats.chi(2)),                 # a disc: Rayleigh
    ((1.0, 0.0, 0.0), stats.halfnorm()),             # a line: |N(0, 1)|
])
def test_norm_quantile_special_cases(lam, dist):
    for p in (0.5, 0.68, 0.95, 0.999):
        assert norm_quantile(np.diag(lam), p) == pytest.approx(dist.ppf(p), rel=1e-10)


def _cdf_nested(lam, r):
    """P(λ₁z₁² + λ₂z₂² + λ₃z₃² ≤ r²) by nested adaptive quadrature of a different formula:
    condition on z₁, and the 2-D remainder in polar form, P(λ₂z₂² + λ₃z₃² ≤ s) =
    (2/π) ∫₀^{π/2} (1 − exp(−s / 2(λ₂cos²φ + λ₃sin²φ))) dφ (R² ~ χ²₂ is exponential)."""
    l1, l2, l3 = lam

    def g2(s):
        def f(ph):
            return -np.expm1(-s / (2 * (l2 * np.cos(ph) ** 2 + l3 * np.sin(ph) ** 2)))

        return quad(f, 0, np.pi / 2, epsabs=1e-15, epsrel=1e-13, limit=200)[0] * 2 / np.pi

    a = r / np.sqrt(l1)
    return 2 * quad(lambda z: stats.norm.pdf(z) * g2(r * r - l1 * z * z), 0, a,
                    epsabs=1e-15, epsrel=1e-13, limit=200)[0]


@pytest.mark.parametrize("lam", [(1.0, 0.3, 0.01), (1.0, 0.05, 0.002), (2.0, 1.0, 0.5)])
def test_norm_cdf_and_quantile_anisotropic_vs_quadrature(lam):
    # measured: the two agree to 1e-15; the graded rule's own error is below 3e-12
    rot = stats.special_ortho_group.rvs(3, random_state=5)
    P = rot @ np.diag(lam) @ rot.T
    for r in (0.1, 0.8, 2.0, 4.0):
        assert float(norm_cdf(P, r)) == pytest.approx(_cdf_nested(lam, r), abs=1e-11)
    r = float(norm_quantile(P, 0.95))
    assert _cdf_nested(lam, r) == pytest.approx(0.95, abs=1e-11)


def test_norm_cdf_against_sampling(rng):
    A = rng.normal(size=(3, 3))
    P = A @ A.T
    x = rng.multivariate_normal(np.zeros(3), P, size=400_000)
    n = np.linalg.norm(x, axis=1)
    for r in np.percentile(n, [10, 50, 95]):
        p = float(norm_cdf(P, r))
        assert np.mean(n <= r) == pytest.approx(p, abs=5 * np.sqrt(p * (1 - p) / n.size))


# ------------------------------------------------------------------- agreement with Monte Carlo

RUNS = 500
ALPHA = 1e-3      # per comparison: the true 95th percentile lies in [X(l), X(u)] w.p. ≥ 1 − α
#: allowance for what differs between the two besides sampling: the discrete-time noise of the
#: simulation vs the continuous PSD (O(h/t)), linearisation (φ ≤ 1e-3 rad here: O(φ))
MODEL = 0.02


def _order_interval(samples, p=0.95, alpha=ALPHA):
    """Distribution-free confidence interval of the p-quantile: order statistics l and u with
    P(X(l) ≤ Q ≤ X(u)) ≥ 1 − α (binomial counts of samples below Q)."""
    n = samples.shape[0]
    s = np.sort(samples, axis=0)
    lo = int(stats.binom.ppf(alpha / 2, n, p))                   # 1-based order statistics
    hi = int(stats.binom.ppf(1 - alpha / 2, n, p)) + 1
    return s[max(lo - 1, 0)], s[min(hi - 1, n - 1)]


def _agree(cov_q, mc, what):
    lo, hi = _order_interval(mc)
    small = hi < 1e-9                                            # both at rounding level
    ok = small | ((cov_q >= lo / (1 + MODEL)) & (cov_q <= hi * (1 + MODEL)))
    assert ok.all(), (what, cov_q, lo, hi)


@pytest.mark.parametrize("motion, preset", [
    (figure_eight(), "tactical"),          # GM bias instability, scale factors, turn-on biases
    (STILL, "ADIS16470"),                  # flicker bank, misalignment, a stationary IMU
])
def test_covariance_agrees_with_monte_carlo(motion, preset):
    model = ImuModel.load(preset)
    rate = 50.0
    cov = covariance(motion, model, rate)
    assert not cov.warnings
    idx = np.linspace(0, cov.t.size - 1, 11).round().astype(int)[1:]      # ten times
    for term in [None, *cov.terms]:
        m = model if term is None else model.only(term)
        mc = monte_carlo(motion, m, rate, runs=RUNS, seed=11, progress=False)
        _agree(cov.position_quantile(index=idx, term=term), mc.position[:, idx], (term, "pos"))
        _agree(cov.attitude_quantile(index=idx, term=term), mc.attitude[:, idx], (term, "att"))


def test_resolution_as_dithered_white_noise():
    """With noise present the rounding residuals are random: paired runs (same noise, with and
    without the quantiser) isolate the rounding's own error, which the covariance predicts."""
    motion, rate, runs, q = figure_eight(), 50.0, 300, 1e-3
    noisy = _model("gyro", noise_density=2e-4)
    quant = _model("gyro", noise_density=2e-4, resolution=q)
    sim = simulate_imu(motion, rate, motion.duration, kind="increments")
    t = sim.state_times()
    start = motion.attitude(t)[0], motion.velocity(t)[0], motion.position(t)[0]

    def runs_of(model):
        seeds = np.random.SeedSequence(7).spawn(runs)
        G, A = zip(*(measure(model, sim.gyro, sim.accel, "increments", rate,
                             np.random.default_rng(s))[:2] for s in seeds), strict=True)
        return navigate_batch("increments", np.stack(G, 1), np.stack(A, 1), rate, *start)

    qa, _, pa = runs_of(noisy)
    qb, _, pb = runs_of(quant)
    dp = np.linalg.norm(pb - pa, axis=-1).T
    da = quat_angle(qb, qa).T
    cov = covariance(motion, _model("gyro", resolution=q), rate)
    idx = np.linspace(0, t.size - 1, 11).round().astype(int)[1:]
    _agree(cov.position_quantile(index=idx), dp[:, idx], "resolution position")
    # the angle error is the current residual: uniform, not Gaussian, so compare its mean square
    # (exact for any distribution) with the trace of the covariance
    ms = np.mean(da[:, idx] ** 2, axis=0)
    tr = np.trace(cov.total[idx, 0:3, 0:3], axis1=1, axis2=2)
    se = np.std(da[:, idx] ** 2, axis=0) / np.sqrt(runs)
    assert np.all(np.abs(ms - tr) < 4 * se + 0.02 * tr), (ms, tr)


# ----------------------------------------------------------------------------- validity warnings


def test_warnings_outside_the_linear_model():
    # MPU-6050: 20 °/s turn-on gyro bias → attitude errors of radians: the model says so
    r = covariance(STILL, ImuModel.load("MPU-6050"), 50.0)
    assert r.attitude_quantile(index=-1) > LINEAR_LIMIT
    assert any("small-angle" in w for w in r.warnings)
    # a motion faster than the gyro range
    fast = Motion(roll="5*t", duration=2.0)
    r = covariance(fast, _model("gyro", noise_density=1e-4, range=1.0), 50.0)
    assert any("beyond the gyro range" in w for w in r.warnings)
    r = covariance(fast, _model("gyro", noise_density=1e-4, range=10.0), 50.0)
    assert not r.warnings


def test_within_summary_equals_the_brute_force_scan():
    """The verdict reads min_t P(|δp| ≤ tol) and the first time it drops below 95 % through
    eigenvalue bounds; the same from the CDF at every time."""
    for motion in (figure_eight(), STILL):
        for preset in ("tactical", "BMI088"):
            c = covariance(motion, ImuModel.load(preset), 50.0)
            for tol in (0.01, 0.5, 3.0, 10.0, 1e4):
                w = c.position_within(tol)
                over = np.nonzero(w < 0.95)[0]
                low, first = c.within_summary(tol, 0.95)
                assert low == w.min()
                assert first == (int(over[0]) if over.size else None)


def test_decimated_rate_samples_fold_the_noise():
    """Rate samples kept every k-th internal sample: sampling white noise of per-sample variance
    N²·f_i at the output rate r gives the density N·√(f_i/r) (without a filter, exactly); with
    the anti-alias filter the folded power is Σ|H(m·r)|², checked against Monte Carlo on a
    stationary IMU (no signal, so no filter lag)."""
    N, k = 1e-3, 50
    m = ImuModel(TriadModel(noise_density=N, internal_rate=20.0 * k))
    r = covariance(STILL, m, 20.0, kind="rates")
    np.testing.assert_allclose(_diag(r.total[1:, 0:3, 0:3]),
                               np.stack([k * N * N * r.t[1:]] * 3, -1), rtol=1e-12)
    m = ImuModel(TriadModel(noise_density=N, internal_rate=1000.0, bandwidth=100.0))
    cov = covariance(STILL, m, 20.0, kind="rates")
    mc = monte_carlo(STILL, m, 20.0, runs=RUNS, seed=5, kind="rates", progress=False)
    idx = np.linspace(0, cov.t.size - 1, 11).round().astype(int)[1:]
    _agree(cov.attitude_quantile(index=idx), mc.attitude[:, idx], "aliased attitude")
    _agree(cov.position_quantile(index=idx), mc.position[:, idx], "aliased position")
    # increments sum the internal samples: no folding, the plain density
    r = covariance(STILL, m, 20.0, kind="increments")
    np.testing.assert_allclose(r.total[-1, 0, 0], N * N * T_END, rtol=1e-12)


def test_filter_lag_is_measured_and_warned():
    from imunav.analysis.assessment import assess_covariance

    lagging = ImuModel(TriadModel(noise_density=1e-4, internal_rate=1000.0, bandwidth=8.0),
                       TriadModel(internal_rate=1000.0, bandwidth=8.0))
    r = assess_covariance(figure_eight(), lagging, 20.0, 1.0)
    assert r["deterministic_position_m"] > 1.0                  # measured 5.6 m
    assert any("without noise" in w for w in r["warnings"])
    r = assess_covariance(STILL, lagging, 20.0, 1.0)
    # no lag warning at rest; only the one every model without a bias instability carries
    assert r["deterministic_position_m"] < 1e-9
    assert r["warnings"] == lagging.missing_term_warnings()


def test_max_position_quantile_when_the_worst_time_is_a_line():
    """The worst time has a one-dimensional (line) covariance, another an isotropic one: the
    quantiles are 1.96·2 = 3.92 (|N(0, 4)|, scipy's half-normal) against 2.795 (χ₃): the line
    wins, although its middle eigenvalue is zero (a pruning bound built on the wrong eigenvalue
    would drop it)."""
    from imunav.analysis.covariance import CovarianceResult

    P = np.zeros((3, 9, 9))
    P[1, 6:9, 6:9] = np.eye(3)
    P[2, 6:9, 6:9] = np.diag([0.0, 4.0, 0.0])
    r = CovarianceResult(np.arange(3.0), {"x": P}, P, 1.0, "hand", 0.0, 0.0, [])
    want = 2 * stats.halfnorm.ppf(0.95)
    assert r.max_position_quantile(0.95) == pytest.approx(want, rel=1e-9)
    assert r.max_position_quantile(0.95, term="x") == pytest.approx(want, rel=1e-9)
    assert r.max_position_quantile(0.5) == pytest.approx(
        max(2 * stats.halfnorm.ppf(0.5), stats.chi(3).ppf(0.5)), rel=1e-9)


def test_chi3_cdf_against_scipy():
    from imunav.analysis.gaussnorm import chi3_cdf

    s = np.array([0.0, 0.3, 1.0, 1.5, stats.chi(3).ppf(0.95), 4.0, 7.0])
    np.testing.assert_allclose(chi3_cdf(s), stats.chi(3).cdf(s), rtol=1e-13, atol=1e-16)
    np.testing.assert_allclose(chi3_cdf([1, 2]), stats.chi(3).cdf([1.0, 2.0]), rtol=1e-13)
    assert chi3_cdf(np.inf) == 1.0 and chi3_cdf(np.array([np.inf, 0.0])).tolist() == [1.0, 0.0]


def test_norm_cdf_batches_and_non_positive_radius():
    P = np.stack([np.eye(3), np.diag([4.0, 1.0, 0.25])])
    got = norm_cdf(P, 1.5)                                   # one radius for the batch
    assert got.shape == (2,)
    assert got[0] == pytest.approx(stats.chi(3).cdf(1.5), rel=1e-9)
    np.testing.assert_array_equal(norm_cdf(P, 0.0), [0.0, 0.0])
    np.testing.assert_array_equal(norm_cdf(P, -1.0), [0.0, 0.0])
    np.testing.assert_allclose(norm_cdf(P, [1, 2]), [stats.chi(3).cdf(1.0), norm_cdf(P[1], 2.0)],
                               rtol=1e-12)


def test_aliasing_gain_cases():
    from scipy.signal import butter, freqz

    from imunav.sensors.models import TriadModel
    from imunav.sensors.terms import aliasing_gain

    plain, filt = TriadModel(noise_density=1e-3), TriadModel(noise_density=1e-3, bandwidth=30.0)
    assert aliasing_gain(filt, 100.0, 8, "increments") == 1.0     # increments integrate: no fold
    assert aliasing_gain(filt, 100.0, 1, "rates") == 1.0          # not decimated
    assert aliasing_gain(plain, 100.0, 8, "rates") == pytest.approx(np.sqrt(8), rel=1e-15)
    # a filter wider than the internal Nyquist frequency is no filter
    assert aliasing_gain(TriadModel(bandwidth=500.0), 100.0, 8, "rates") == pytest.approx(
        np.sqrt(8), rel=1e-15)
    # the 2nd-order Butterworth at the internal rate 800 Hz: |H|² at 0, 100, …, 700 Hz
    b, a = butter(2, 30.0, fs=800.0)
    h2 = np.abs(freqz(b, a, worN=np.arange(8) * 100.0, fs=800.0)[1]) ** 2
    assert aliasing_gain(filt, 100.0, 8, "rates") == pytest.approx(np.sqrt(h2.sum()), rel=1e-10)
    assert 1.0 < aliasing_gain(filt, 100.0, 8, "rates") < 1.1


def test_other_gravity_and_the_range_warnings():
    """g = 1.62 m/s² (the Moon): a level, still IMU reads f = −g, so a gyro bias b tilts the
    solution into a horizontal position error g·b·t³/6; a constant turn of 0.5 rad/s is the peak
    rate, exactly at a 0.5 rad/s range (no warning) and over a 0.49 rad/s one (warned)."""
    from imunav.sensors.models import ImuModel, TriadModel

    b, g = 1e-4, 1.62
    r = covariance(STILL, _model("gyro", bias=b), 100.0, g=g, kind="rates")
    t = r.t[1:]
    np.testing.assert_allclose(np.sqrt(_diag(r.total[1:, 6:8, 6:8])),
                               np.stack([g * b * t ** 3 / 6] * 2, -1), rtol=1e-12)
    assert r.max_force == pytest.approx(g, rel=1e-12) and r.max_rate == 0.0
    turn = Motion(yaw="0.5*t", duration=4.0, name="turn")
    at = covariance(turn, ImuModel(TriadModel(bias=b, range=0.5), TriadModel(range=20.0), "r"),
                    50.0)
    assert at.max_rate == pytest.approx(0.5, rel=1e-12) and at.warnings == [] and at.model == "r"
    over = covariance(turn, ImuModel(TriadModel(bias=b, range=0.49), TriadModel(range=9.0), "r"),
                      50.0)
    # in datasheet units (issue 25, point 11: "372 … (SI)" had no unit): 0.5 rad/s = 28.6 °/s,
    # 0.49 rad/s = 28.1 °/s; 9.81 m/s² = 1 g (of 9.80665), 9 m/s² = 0.918 g
    assert over.warnings == [
        "the motion's angular rate reaches 28.6 °/s, beyond the gyro range 28.1 °/s: clipping is "
        "not in the covariance; use Monte Carlo",
        "the motion's specific force reaches 1 g, beyond the accel range 0.918 g: clipping is not "
        "in the covariance; use Monte Carlo"]


@pytest.mark.parametrize("lam", [(1.0, 1.0, 1.0), (4.0, 1.0, 0.25), (2.0, 0.5, 0.0),
                                 (3.0, 0.0, 0.0), (0.0, 0.0, 0.0)])
def test_norm_density_is_the_derivative_of_the_cdf(lam):
    """The density that speeds up the quantile's Newton steps is d/dr of the CDF (a central
    difference of the CDF here; 0 for a zero covariance), and the CDF itself matches scipy
    where scipy has the distribution (rank 1: a half-normal)."""
    from imunav.analysis.gaussnorm import _cdf_pdf, _eig

    l1, l2, l3 = _eig(np.diag(lam)[None].repeat(4, 0))
    r = np.array([0.3, 1.0, 2.0, 3.5])
    P, D = _cdf_pdf(l1, l2, l3, r, density=True)
    eps = 1e-5
    num = (_cdf_pdf(l1, l2, l3, r + eps) - _cdf_pdf(l1, l2, l3, r - eps)) / (2 * eps)
    np.testing.assert_allclose(D, num, rtol=1e-6, atol=1e-9)
    if lam[1] == 0 and lam[0] > 0:
        np.testing.assert_allclose(P, stats.halfnorm(scale=np.sqrt(lam[0])).cdf(r), rtol=1e-12)
    if lam[0] == 0:
        np.testing.assert_array_equal(P, 1.0)
        np.testing.assert_array_equal(D, 0.0)


def test_norm_quantile_converges_in_a_few_newton_steps(monkeypatch):
    """The moment-matched start and the exact density make Newton converge in at most 6 CDF
    evaluations (measured: 1 for isotropic or line covariances, 3–5 otherwise); the result
    solves CDF(q) = p to 1e-12 and sits between the bracket's ends."""
    import imunav.analysis.gaussnorm as G

    calls = []
    real = G._cdf_pdf
    monkeypatch.setattr(G, "_cdf_pdf", lambda *a, **k: calls.append(1) or real(*a, **k))
    cov = np.stack([np.diag(d) for d in ((1.0, 1, 1), (4, 1, 0.25), (2, 0.5, 0), (3, 0, 0),
                                          (1e-6, 1e-7, 0), (100, 99, 1))])
    for p in (0.5, 0.95, 0.999):
        calls.clear()
        q = G.norm_quantile(cov, p)
        assert len(calls) <= 6, (p, len(calls))
        calls.clear()
        np.testing.assert_allclose(G.norm_cdf(cov, q), p, rtol=0, atol=1e-12)
        top = np.sqrt(cov[:, 0, 0])
        assert np.all(q >= top * stats.halfnorm.ppf(p) * (1 - 1e-12))
        assert np.all(q <= top * stats.chi(3).ppf(p) * (1 + 1e-12))
    assert G.norm_quantile(np.zeros((3, 3)), 0.95) == 0.0


# ------------------------------------------------------------ streamed analysis (issue 25)


@pytest.mark.parametrize("motion", [figure_eight(), STILL], ids=["figure_eight", "still"])
def test_streamed_summary_is_the_full_analysis_to_the_bit(motion):
    """The streamed analysis (what `assess` and `design` run) keeps the grid and the extrema of
    the full-history one, with the same bits: the verdict and the design numbers are the same
    dictionaries, whatever the piece size."""
    from imunav.analysis.assessment import verdict_covariance
    from imunav.analysis.covariance import covariance_summary, envelope_index

    for preset, output in (("ADIS16470", "increments"), ("MPU-6050", "rates")):
        model = ImuModel.load(preset)
        full = covariance(motion, model, 50.0, kind=output)
        for tol in (0.05, 2.0, 1e4):
            for chunk in (1000, 77):
                s = covariance_summary(motion, model, 50.0, kind=output, tolerance=tol,
                                       level=0.95, maxima=True, chunk=chunk)
                idx = envelope_index(full.t.size)
                np.testing.assert_array_equal(s.t, full.t[idx])
                np.testing.assert_array_equal(s.total, full.total[idx])
                for k in full.terms:
                    np.testing.assert_array_equal(s.terms[k], full.terms[k][idx])
                    assert s.max_position_quantile(0.95, k) == full.max_position_quantile(0.95, k)
                assert s.max_position_quantile() == full.max_position_quantile()
                assert s.within_summary(tol, 0.95) == full.within_summary(tol, 0.95)
                assert s.warnings == full.warnings
                assert verdict_covariance(s, tol, None) == verdict_covariance(full, tol, None)


def test_streamed_minimum_and_crossing_are_the_brute_force_ones():
    """The pruned minimum and first crossing against the CDF evaluated at every output time,
    on a record long enough for many pieces, where the bounds decide most steps."""
    from imunav.analysis.covariance import covariance_summary

    motion, model = figure_eight(), ImuModel.load("ADIS16470")
    full = covariance(motion, model, 100.0)
    for tol in (0.02, 0.3, 5.0, 50.0):
        w = full.position_within(tol)
        over = np.nonzero(w < 0.95)[0]
        s = covariance_summary(motion, model, 100.0, tolerance=tol, level=0.95, chunk=100)
        assert s.within == (w.min(), int(over[0]) if over.size else None)
        if w.min() < 1 - 1e-9:                 # (within 1e-9 of 1 a short record is scanned)
            assert s.exact_evaluations < 0.05 * full.t.size      # the bounds did most of it


def _peak_memory(fn):
    import tracemalloc

    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_covariance_assessment_memory_does_not_grow_with_the_record():
    """Issue 25: the covariance assessment kept ~100 kB per sample (`still_2h --rate 50` took
    more than 16 GB). Now a record 10× longer needs about the same memory."""
    from imunav.analysis.assessment import assess_covariance

    model = ImuModel.load("tactical")
    short = _peak_memory(lambda: assess_covariance(Motion(duration=60.0), model, 50.0, 5.0,
                                                   progress=False))
    long = _peak_memory(lambda: assess_covariance(Motion(duration=600.0), model, 50.0, 5.0,
                                                  progress=False))
    assert long < 1.3 * short + 2e6, (short, long)


def test_streamed_analysis_refuses_what_cannot_fit(monkeypatch):
    import imunav.core.resources as res
    from imunav.analysis.covariance import covariance_summary
    from imunav.core.validation import ImunavError

    monkeypatch.setattr(res, "available_memory", lambda: 20_000_000)
    with pytest.raises(ImunavError, match="covariance analysis of 1,000 steps .* would need "
                                          "about .* of memory; 20 MB is available"):
        covariance_summary(STILL, ImuModel.load("ADIS16470"), 50.0)


def test_long_streamed_analysis_shows_progress(monkeypatch, capsys):
    import importlib

    C = importlib.import_module("imunav.analysis.covariance")

    monkeypatch.setattr(C, "PROGRESS_WORK", 1e4)
    C.covariance_summary(STILL, ImuModel.load("tactical"), 50.0, progress=True, chunk=100)
    assert "covariance" in capsys.readouterr().err
    C.covariance_summary(STILL, ImuModel.load("tactical"), 50.0, progress=False, chunk=100)
    assert capsys.readouterr().err == ""


def test_streamed_summary_on_the_earth_is_the_local_covariance():
    """On the rotating Earth the streamed analysis propagates the inertial error state step by
    step (its transition is not unipotent) and keeps the local NED errors' covariance on the
    grid: the same as the whole history mapped by EarthErrorModel.local."""
    from imunav.analysis.covariance import covariance_summary, envelope_index
    from imunav.estimation import EARTH, Trajectory, linearise, propagate
    from imunav.motion import EarthMotion

    m = EarthMotion(Motion(x="30*sin(0.1*t)", yaw="0.2*t", duration=60.0), (0.7, 0.2, 100.0))
    model = ImuModel.load("BMI088")
    traj = Trajectory.of(m, 5.0, 60.0)
    sources, _ = linearise(model, traj, "increments")
    full = EARTH.local(traj, sum(propagate(sources, traj, EARTH)))
    s = covariance_summary(m, model, 5.0, 60.0, tolerance=50.0, level=0.95, chunk=64)
    idx = envelope_index(traj.t.size)
    np.testing.assert_allclose(s.total, full[idx], rtol=1e-12, atol=1e-12 * np.abs(full).max())
    w = norm_cdf(full[:, 6:9, 6:9], 50.0)
    assert s.within[0] == pytest.approx(w.min(), rel=1e-12)


def test_the_norm_probability_is_right_at_any_tolerance_however_large():
    """7. The quadrature is validated to r ≤ 8√λ₁: a 300 s still IMU with a 1e-4 m/s² accel
    bias was SUITABLE for 1000 m and "NOT SUITABLE 82.6 %" for 1e6 m (its early covariances are
    1e-13 m², the tolerance 1e12 σ away). Now the probability is kept within its closed-form
    bounds: 1 to 1e-13 there, never above 1, monotone in r."""
    from imunav.analysis.assessment import assess_covariance

    still = Motion(duration=300.0, name="still")
    model = _model("accel", bias=1e-4)
    for tol in (1e3, 1e6, 1e12):
        r = assess_covariance(still, model, 10.0, tol, progress=False)
        assert r["suitable"] and r["fraction_within_tolerance"] == pytest.approx(1.0, abs=1e-13)
    rng = np.random.default_rng(7)
    lam = np.sort(10.0 ** rng.uniform(-12, 0, (400, 3)), axis=1)[:, ::-1]
    lam[::7, 2] = 0.0
    cov = np.zeros((400, 3, 3))
    cov[:, [0, 1, 2], [0, 1, 2]] = lam
    r = np.sqrt(lam[:, :1]) * 10.0 ** np.linspace(-3, 14, 60)        # (400, 60): up to 1e14 σ
    P = norm_cdf(np.broadcast_to(cov[:, None], (400, 60, 3, 3)), r)
    assert P.min() >= 0 and P.max() <= 1
    assert np.all(np.diff(P, axis=1) >= -1e-12)
    np.testing.assert_allclose(P[:, -20:], 1.0, rtol=0, atol=1e-13)   # beyond ~1e8 σ
