"""Each sensor error term against an independent truth (issue 19): per-run constants by their
spread over many runs and by ``y = M·x`` with noise off; bias instability by the textbook
Gauss–Markov Allan peak; the Allan curves of the presets by the closed forms of each noise
(white N/√τ, rate random walk K√(τ/3), flat flicker floor), written out here.

And one authority per term (issue 24): a toy term defined in this file alone is parsed with its
units, simulated, linearised, assessed and shown; every registered term has a linearisation;
a term that forgets it fails the covariance analysis instead of being ignored.

Statistical tolerances come from the sampling error of the estimate (stated at each test) and
use fixed seeds.
"""

import numpy as np
import pytest

from imunav import ImunavError
from imunav.core import units
from imunav.sensors import terms
from imunav.sensors.allan import allan_deviation
from imunav.sensors.models import ImuModel, MeasureStream, TriadModel, TriadStream
from imunav.sensors.presets import PRESETS
from imunav.sensors.terms import Parameter, SensorErrorStates, Term, parse

RUNS = 3000          # spread of a std over 3000 runs × 3 axes: 1/√(2·9000) = 0.75 % (1σ)


def _outputs(model: TriadModel, x, runs=RUNS, seed=0, kind="rates", rate=100.0):
    """One output sample per run for the ideal input ``x`` (n, 3): shape (runs, n, 3)."""
    seeds = np.random.SeedSequence(seed).spawn(runs)
    return np.stack([TriadStream(model, kind, rate, np.random.default_rng(s)).process(x)[0]
                     for s in seeds])


def test_turn_on_bias_sigma_from_the_spread_over_runs():
    sigma = 0.02
    y = _outputs(TriadModel(bias=sigma), np.zeros((1, 3)))[:, 0]
    assert np.std(y) == pytest.approx(sigma, rel=0.03)          # 4σ of the estimate
    assert abs(np.mean(y)) < 4 * sigma / np.sqrt(y.size)
    # a bias is a constant of the run: the same at every sample
    y2 = _outputs(TriadModel(bias=sigma), np.zeros((5, 3)), runs=3)
    assert np.all(y2 == y2[:, :1])


def test_scale_factor_and_misalignment_spread_and_y_equals_M_x():
    sf, mis = 0.01, 0.004
    eye = np.eye(3)
    only_sf = _outputs(TriadModel(scale_factor=sf), eye)             # columns of M = I + diag
    assert np.std(np.diagonal(only_sf, axis1=1, axis2=2) - 1) == pytest.approx(sf, rel=0.03)
    assert np.all(only_sf[:, ~np.eye(3, dtype=bool)] == 0)
    only_mis = _outputs(TriadModel(misalignment=mis), eye)
    off = only_mis[:, ~np.eye(3, dtype=bool)]                        # 6 cross-axis terms
    assert np.std(off) == pytest.approx(mis, rel=0.03)
    assert np.all(np.diagonal(only_mis, axis1=1, axis2=2) == 1)
    # applied once and linearly: the response to any input is M x with M read off e1, e2, e3
    x = np.vstack([eye, [[0.3, -1.2, 2.0]]])
    y = _outputs(TriadModel(scale_factor=sf, misalignment=mis), x, runs=50)
    M = np.swapaxes(y[:, :3], 1, 2)                                  # y[e_j] is column j
    np.testing.assert_allclose(y[:, 3], M @ x[3], rtol=0, atol=1e-14)
    # the matrix is I + δ: applied twice its diagonal would spread by 2σ
    assert np.std(np.diagonal(M, axis1=1, axis2=2) - 1) == pytest.approx(sf, rel=0.15)


def test_g_sensitivity_acts_on_the_gyro_from_the_specific_force():
    s, g = np.radians(0.1) / 9.80665, 9.80665          # 0.1 °/s per g
    model = ImuModel(TriadModel(g_sensitivity=s), TriadModel())
    f = np.tile([0.0, 0.0, -g], (1, 1))
    gy = []
    for seed in np.random.SeedSequence(1).spawn(RUNS):
        gm, am, _ = MeasureStream(model, "rates", 100.0, np.random.default_rng(seed)).process(
            np.zeros((1, 3)), f)
        np.testing.assert_array_equal(am, f)            # the accelerometer is untouched
        gy.append(gm[0])
    gy = np.array(gy)
    # ω = G f with G_ij ~ N(0, s²): each axis sees g·G_i3, spread s·g
    assert np.std(gy) == pytest.approx(s * g, rel=0.03)


def test_gauss_markov_bias_instability_peak_is_the_textbook_one():
    """A first-order Gauss–Markov bias of std σ has its Allan maximum 0.618σ at τ ≈ 1.89 T
    (IEEE Std 952; El-Sheimy, Hou & Niu 2008). So with ``bias_instability = B`` and
    ``bias_correlation_time = T`` the process std must be B/0.6174 and the simulated Allan
    curve must peak at B near τ = 1.89 T."""
    B, T, rate = parse("10 deg/h", "gyro.bias_instability"), 2.0, 10.0
    m = TriadModel(bias_instability=B, bias_correlation_time=T)
    n = int(20_000 * T * rate)                         # 20 000 correlation times
    y, _ = TriadStream(m, "rates", rate, np.random.default_rng(11)).process(np.zeros((n, 3)))
    # std of a GM record of 20 000 T: ≈ 1/√(20 000/2) = 1 % per axis; 3 axes: 0.6 %
    assert np.std(y) == pytest.approx(B / 0.6174, rel=0.03)
    taus = 1.893 * T * np.array([0.7, 0.85, 1.0, 1.2, 1.4])
    _, adev = allan_deviation(y, rate, taus)
    peak = adev.mean(axis=1)
    # ADEV at τ of a 20 000 T record: ≈ 1/√(2·(20 000 T/τ)/2) ≈ 1 % per axis
    assert peak.max() == pytest.approx(B, rel=0.04)   # σ off by √2 would give 0.81 B or 1.15 B
    assert np.argmax(peak) in (1, 2, 3)


def _gm_avar(tau, sigma, T):
    """Allan variance of a first-order Gauss–Markov process (std σ, correlation time T):
    (2σ²T/τ)·(1 − (3 − 4e^{−τ/T} + e^{−2τ/T})·T/(2τ))."""
    x = tau / T
    return 2 * sigma**2 * T / tau * (1 - (3 - 4 * np.exp(-x) + np.exp(-2 * x)) / (2 * x))


def _closed_form_adev(m: TriadModel, tau):
    """White noise N/√τ, rate random walk K√(τ/3) and bias instability: flat at B for flicker,
    or a Gauss–Markov process with σ = B/0.6174 when a correlation time is given."""
    var = m.noise_density**2 / tau + m.random_walk**2 * tau / 3
    if m.bias_instability and m.bias_correlation_time:
        var = var + _gm_avar(tau, m.bias_instability / 0.6174, m.bias_correlation_time)
    elif m.bias_instability:
        var = var + m.bias_instability**2
    return np.sqrt(var)


@pytest.mark.parametrize("preset", [p for p in PRESETS if p != "ideal"])
@pytest.mark.parametrize("triad", ["gyro", "accel"])
def test_preset_allan_curves_match_the_closed_forms(preset, triad):
    full = getattr(ImuModel.load(preset), triad)
    m = TriadModel(noise_density=full.noise_density, bias_instability=full.bias_instability,
                   bias_correlation_time=full.bias_correlation_time, random_walk=full.random_walk)
    rate, n = 10.0, 72_000
    y, _ = TriadStream(m, "rates", rate, np.random.default_rng(7)).process(np.zeros((n, 3)))
    taus, adev = allan_deviation(y, rate, [0.1, 1, 10, 100])
    got = adev.mean(axis=1)
    # white noise where it dominates (τ ≤ 1 s): N/√τ exactly in expectation; 72 000 samples
    # over 3 axes leave < 1 % scatter at τ = 0.1 s
    white = m.noise_density / np.sqrt(taus)
    dominant = white > 3 * (m.bias_instability + m.random_walk * np.sqrt(taus / 3))
    np.testing.assert_allclose(got[dominant], white[dominant], rtol=0.06)
    # everywhere: between 0.75 and 1.25 of the sum of the closed forms (the flicker bank's
    # floor is only approximately flat: ±15 %; statistics at τ = 100 s of a 2 h record: ±10 %)
    np.testing.assert_allclose(got, _closed_form_adev(m, taus), rtol=0.25)


# ------------------------------------------------------------- one authority per term (issue 24)


class ThermalDrift(Term):
    """A toy term defined here and nowhere else: a first-order Gauss–Markov bias with a fixed
    20 s time constant, 1σ = the value (a warm-up drift)."""

    name, stage = "thermal_drift", "drift"
    T = 20.0
    parameters_ = (Parameter("thermal_drift", {"gyro": units.RATE, "accel": units.ACCEL},
                             {"gyro": "thermal drift (1σ)", "accel": "thermal drift (1σ)"}),)
    display = {"gyro": ("deg/h", "°/h", "rad/s"), "accel": ("mg", "mg", "m/s²")}

    def start(self, model, stream, rng):
        child = rng.spawn(1)[0]
        return [child, child.normal(0.0, model.thermal_drift, 3)]

    def add_drift(self, model, state, stream, drift):
        a = np.exp(-stream.dt / self.T)
        w = state[0].normal(0.0, model.thermal_drift * np.sqrt(1 - a * a), drift.shape)
        x = state[1]
        for i in range(drift.shape[0]):
            x = a * x + w[i]
            drift[i] += x
        state[1] = x

    def linearise(self, model, ctx):
        s = model.thermal_drift
        if not s:
            return []
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.full(3, -1 / self.T),
                                  s * s * np.eye(3), np.full(3, 2 * s * s / self.T),
                                  lambda u, f: np.broadcast_to(np.eye(3), (u.shape[0], 3, 3)))]


@pytest.fixture
def thermal_drift():
    term = terms.register(ThermalDrift())
    try:
        yield term
    finally:
        terms.unregister(term.name)


def test_a_term_defined_in_a_test_is_parsed_simulated_linearised_assessed_and_shown(
        thermal_drift):
    from imunav import covariance, design, format_design, monte_carlo
    from imunav.analysis.assessment import assess_covariance
    from imunav.motion.catalog import stationary
    from imunav.sensors.simulate import simulate_imu

    # parsed, with its units, from an IMU file's table
    model = ImuModel.from_dict({"gyro": {"thermal_drift": "50 deg/h"}}, "warm")
    s = np.radians(50) / 3600
    assert model.gyro.thermal_drift == pytest.approx(s, rel=1e-14)
    assert model.terms() == ["gyro.thermal_drift"]
    with pytest.raises(ImunavError, match="not a unit of thermal drift"):
        ImuModel.from_dict({"gyro": {"thermal_drift": "50 m/s"}})
    # simulated: std σ and lag-1 correlation e^{−h/T} (20 000 s = 1000 T: ±2.5 % on the std)
    motion, rate = stationary(duration=20_000.0), 2.0
    ideal = simulate_imu(motion, rate, kind="rates")
    err = simulate_imu(motion, rate, kind="rates", imu=model, seed=1).gyro - ideal.gyro
    assert np.std(err) == pytest.approx(s, rel=0.08)
    r1 = np.mean([np.corrcoef(err[:-1, i], err[1:, i])[0, 1] for i in range(3)])
    assert r1 == pytest.approx(np.exp(-1 / (rate * thermal_drift.T)), abs=0.01)
    # linearised: on a level, still IMU the attitude error of a stationary Gauss–Markov bias has
    # variance 2σ²T²(t/T − 1 + e^{−t/T}) per axis (the integral of its autocovariance)
    short = stationary(duration=60.0)
    cov = covariance(short, model, 10.0)
    assert list(cov.terms) == ["gyro.thermal_drift"]
    t, T = cov.t, thermal_drift.T
    want = 2 * s * s * T * T * (t / T - 1 + np.exp(-t / T))
    np.testing.assert_allclose(cov.total[:, 0, 0], want, rtol=1e-9, atol=1e-30)
    # assessed: covariance and Monte Carlo agree on the final attitude error (300 runs: the
    # p95 of a χ₃-like norm is known to ±6 %)
    mc = monte_carlo(short, model, 10.0, runs=300, seed=3, progress=False)
    assert np.percentile(mc.attitude[:, -1], 95) == pytest.approx(
        float(cov.attitude_quantile(index=-1)), rel=0.12)
    r = assess_covariance(short, model, 10.0, tolerance=1.0)
    assert list(r["error_budget"]) == ["gyro.thermal_drift"]
    # shown in its datasheet unit by design
    d = design(short, model, 10.0, tolerance=1.0)
    assert d["terms"]["gyro.thermal_drift"]["base"] == "50 deg/h"
    assert "gyro.thermal_drift" in format_design(d)


def test_the_toy_term_is_gone_once_unregistered(thermal_drift):
    terms.unregister(thermal_drift.name)
    try:
        with pytest.raises(TypeError, match="thermal_drift"):
            TriadModel(thermal_drift=1.0)
        with pytest.raises(ImunavError, match="unknown key"):
            ImuModel.from_dict({"gyro": {"thermal_drift": 1.0}})
    finally:
        terms.register(thermal_drift)


@pytest.mark.parametrize("name", list(terms.TERMS))
def test_every_term_realised_in_the_simulation_has_a_linearisation(name):
    """Each registered term says how it enters the error model (states, white noise, or —
    range, filter, internal rate — explicitly nothing, with a warning where the motion leaves
    the linear model), and is shown in a datasheet unit if it is an error with states."""
    term = terms.TERMS[name]
    assert type(term).linearise is not Term.linearise, f"{name} has no linearisation"
    assert term.stage in terms.STAGES
    for triad in term.triads:
        params = {p.key: (1e-3 if p.default == 0.0 else 10.0) for p in term.parameters_}
        m = TriadModel(**params)
        ctx = terms.LinearisationContext(triad, 0.01, "increments", 1, peak=1e9)
        out = term.linearise(m, ctx)
        assert isinstance(out, list)
        if term.linear:
            assert out, f"{name} is linear but gave no error states"
            assert term.show(1e-3, triad)                 # it has a datasheet unit
        else:
            assert not out


def test_a_term_without_a_linearisation_fails_loudly_in_the_covariance():
    """The default assess must not silently ignore a term it cannot linearise."""
    from imunav import covariance
    from imunav.motion.catalog import stationary

    class Forgotten(ThermalDrift):
        name = "forgotten"
        parameters_ = (Parameter("forgotten", {"gyro": units.RATE, "accel": units.ACCEL},
                                 {"gyro": "x", "accel": "x"}),)
        linearise = Term.linearise

        def start(self, model, stream, rng):
            return [rng.spawn(1)[0], np.zeros(3)]

    terms.register(Forgotten())
    try:
        model = ImuModel(TriadModel(forgotten=1e-3), TriadModel())
        with pytest.raises(NotImplementedError, match="forgotten"):
            covariance(stationary(duration=1.0), model, 10.0)
    finally:
        terms.unregister("forgotten")


def test_register_refuses_a_clash_and_an_unknown_stage():
    with pytest.raises(ImunavError, match="registered already"):
        terms.register(terms.TERMS["bias"])

    class Odd(ThermalDrift):
        name, stage = "odd", "somewhere"

    with pytest.raises(ImunavError, match="stage must be one of"):
        terms.register(Odd())
