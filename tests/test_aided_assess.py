"""The aided assessment (issue 29): the covariance analysis of the filter along the true motion
against a Monte Carlo of the real EKF (p95 position within 15 % at the outage's end — the
independent truth is the filter run on simulated sensors), the vectorised filter against the
filter run by run, the filter's own covariance equal to the true one when the models agree and
below it when the filter treats a correlated GNSS error as white, the budget adding up to the
total, and the outage search against passes with that outage and one GNSS interval more.

Reduced in size (the first 40 s of the example drive at 50 Hz, 100 runs) to keep ``make test``
short; ``benchmarks/outage_confirm.py`` runs the full drive.
"""

from pathlib import Path

import numpy as np
import pytest

from imunav.analysis import aided_assessment as A
from imunav.analysis import aided_design as D
from imunav.analysis import aided_montecarlo as MC
from imunav.analysis import outage as O
from imunav.estimation.error_model import DP
from imunav.estimation.filters import run_filter, run_filter_batch
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig, simulate_aiding
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import simulate_imu

ROOT = Path(__file__).resolve().parents[1]
DRIVE = ROOT / "examples" / "drive.toml"
RATE, DURATION = 50.0, 40.0
OUTAGE = (20.0, 35.0)


def _aiding(**gnss) -> AidingConfig:
    g = {"rate": 1, "position_sigma": 1.5, "velocity_sigma": 0.1, "outages": [list(OUTAGE)]}
    g.update(gnss)
    return AidingConfig.from_dict({"gnss": g})


@pytest.fixture(scope="module")
def drive():
    return load_motion(DRIVE)[0]


def test_covariance_matches_the_filter_monte_carlo_at_the_outage_end(drive):
    imu = ImuModel.load("BMI088")
    aiding = _aiding()
    at = A.aided_covariance(drive, imu, aiding, RATE, DURATION)
    t, truth, _, per = A.outage_p95(at, [OUTAGE])
    (o,) = per
    assert o["t_end_s"] == pytest.approx(35.9)          # one covariance step before the fix at 36
    mc = MC.aided_monte_carlo(drive, imu, aiding, RATE, DURATION, 100, seed=3,
                             times=np.array([27.0, o["t_end_s"]]), progress=False)
    mc_p95 = mc.p95()
    cov_mid = truth[np.searchsorted(t, 27.0 - 1e-9)]
    assert abs(mc_p95[-1] / o["position_p95_end_m"] - 1) < 0.15, (mc_p95, o)
    assert abs(mc_p95[0] / cov_mid - 1) < 0.15, (mc_p95, cov_mid)
    # the outage matters: the error at its end is many times that with GNSS
    assert o["position_p95_end_m"] > 5 * truth[np.searchsorted(t, 19.0)]


def test_batch_filter_agrees_with_the_filter_run_by_run(drive):
    imu = ImuModel.load("BMI088")
    aiding = AidingConfig.from_dict({"gnss": {"rate": 1, "position_sigma": 1.5,
                                              "velocity_sigma": 0.1, "outages": [[6, 9]]},
                                     "nhc": {"sigma": 0.1, "rate": 5}})
    dur = 12.0
    ideal = simulate_imu(drive, RATE, dur, kind="increments")
    seeds = np.random.SeedSequence(1).spawn(2)
    sigs, datas = [], []
    for r in range(2):
        gm, am, _ = measure(imu, ideal.gyro, ideal.accel, "increments", RATE,
                            np.random.default_rng(seeds[r]), 1)
        sigs.append(ImuSignals(ideal.t[:gm.shape[0]], gm, am, "increments", RATE, ideal.g))
        datas.append(simulate_aiding(drive, aiding, dur, seed=1, run=r, imu_rate=RATE))
    st = drive.states(np.array([0.0]))
    x0 = (st.quaternion[0], st.velocity[0], st.position[0])
    batch = run_filter_batch(sigs, *x0, aiding, datas, imu=imu)
    for r in range(2):
        one = run_filter(sigs[r], *x0, aiding, datas[r], imu=imu)
        np.testing.assert_allclose(batch.position[:, r], one.states.position, rtol=0,
                                   atol=1e-8)
        np.testing.assert_allclose(batch.P_nav[:, r], one.P_nav, rtol=1e-8, atol=1e-14)


def test_filter_and_true_covariance_agree_when_the_models_do(drive):
    imu = ImuModel.load("MPU-6050")
    aiding = _aiding(correlated_sigma=2.0, correlation_time=60.0)
    at = A.aided_covariance(drive, imu, aiding, RATE, 25.0)
    wf, wt, _ = at.weights(initial_error=True)
    res = at.propagate(wf, wt)
    np.testing.assert_allclose(res.truth_post[0, 0], res.filter_post[0], rtol=1e-9,
                               atol=1e-12)


def test_a_correlated_error_treated_as_white_is_worse_than_the_filter_believes(drive):
    imu = ImuModel.load("BMI088")
    aiding = _aiding(correlated_sigma=3.0, correlation_time=100.0, correlated_model="white",
                     outages=[])
    at = A.aided_covariance(drive, imu, aiding, RATE, 25.0)
    assert at.filter_states.sum() < at.n           # the filter lacks the correlated states
    t, truth, filt, _ = A.outage_p95(at, [])
    late = t > 10
    # the white treatment averages the fixes as if independent: the truth is worse, the more
    # so the more fixes it has averaged
    assert np.all(truth[late] > filt[late]) and truth[-1] > 1.3 * filt[-1]
    # and the real filter, on sensors with the correlated error, shows the true covariance
    mc = MC.aided_monte_carlo(drive, imu, aiding, RATE, 25.0, 80, seed=5,
                             times=np.array([25.0]), progress=False)
    assert abs(mc.p95()[0] / truth[-1] - 1) < 0.15, (mc.p95(), truth[-1], filt[-1])
    r = A.assess_aided(drive, imu, aiding, RATE, 50.0, 25.0, budget=False, progress=False)
    assert any("believes its position better" in w for w in r["warnings"])


def test_the_budget_adds_up_to_the_total(drive):
    imu = ImuModel.load("BMI088")
    aiding = _aiding()
    at = A.aided_covariance(drive, imu, aiding, RATE, DURATION, terms=True)
    act = A.active_fixes(at, [[OUTAGE]])
    wf, wt, names = at.weights(split=True)
    split = at.propagate(wf, wt, act, keep=False).final[0, 1:]
    wf1, wt1, _ = at.weights()
    total = at.propagate(wf1, wt1, act, keep=False).final[0, 1]
    np.testing.assert_allclose(split.sum(axis=0)[DP, DP], total[DP, DP], rtol=1e-9)
    budget = A.outage_budget(at, [OUTAGE], 35.9)
    assert set(budget) <= set(names) and list(budget.values()) == sorted(budget.values(),
                                                                         reverse=True)
    assert "gyro.noise_density" in budget


def test_find_outage_is_the_longest_within_the_tolerance(drive):
    imu = ImuModel.load("BMI088")
    aiding = _aiding()
    at = A.aided_covariance(drive, imu, aiding, RATE, 120.0)
    tol = 15.0
    f = O.find_outage(drive, imu, aiding, RATE, tol, 120.0, at=at, budget=False)
    L, s = f["max_outage_s"], f["outage_start_s"]
    assert 3 <= L and not f["limited_by_motion"]
    # an independent pass with that outage stays within; one GNSS interval longer does not
    (o,) = A.outage_p95(at, [(s, s + L)])[3]
    assert o["position_p95_max_m"] <= tol
    assert o["position_p95_end_m"] == pytest.approx(f["position_p95_end_m"], rel=1e-9)
    (o2,) = A.outage_p95(at, [(s, s + L + 1.0)])[3]
    assert o2["position_p95_max_m"] > tol
    # placed elsewhere, it bridges at least as long (s is where it hurts most)
    for s2 in (30.0, 60.0):
        g = O.find_outage(drive, imu, aiding, RATE, tol, 120.0, at=at, start=s2, budget=False)
        assert g["max_outage_s"] >= L


def test_filter_monte_carlo_on_dask_is_the_local_run_bit_for_bit(drive):
    distributed = pytest.importorskip("dask.distributed")
    imu = ImuModel.load("BMI088")
    aiding = _aiding(outages=[[4, 6]])
    kw = {"seed": 4, "times": np.array([5.0, 8.0]), "progress": False}
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        d = MC.aided_monte_carlo(drive, imu, aiding, 20.0, 8.0, MC.MC_CHUNK + 2,
                                scheduler=cluster.scheduler_address, **kw)
    loc = MC.aided_monte_carlo(drive, imu, aiding, 20.0, 8.0, MC.MC_CHUNK + 2, **kw)
    assert d.runs == MC.MC_CHUNK + 2
    assert np.array_equal(d.position_error, loc.position_error)



def test_aided_monte_carlo_on_two_worker_processes_is_the_serial_run_bit_for_bit(drive):
    """Issue 39: ``workers=2`` spreads the fixed chunks over two local processes (a Dask
    ``LocalCluster``); every run's numbers are those of the serial run, bit for bit — the
    errors, the gate's rejections and the NEES."""
    pytest.importorskip("dask.distributed")
    imu = ImuModel.load("BMI088")
    aiding = _aiding(outages=[[4, 6]])
    kw = {"seed": 5, "times": np.array([5.0, 8.0]), "progress": False, "nees": True}
    runs = MC.MC_CHUNK + 2                                     # two chunks: one per process
    two = MC.aided_monte_carlo(drive, imu, aiding, 20.0, 8.0, runs, workers=2, **kw)
    one = MC.aided_monte_carlo(drive, imu, aiding, 20.0, 8.0, runs, **kw)
    assert two.runs == runs
    assert np.array_equal(two.position_error, one.position_error)
    assert two.rejected == one.rejected
    for b in MC.BLOCKS:
        assert np.array_equal(two.filter[b], one.filter[b])

def test_common_scale_is_the_largest_imu_factor_within_the_tolerance(drive):
    at = A.aided_covariance(drive, ImuModel.load("BMI088"), _aiding(), RATE, 60.0)
    tol = 15.0
    k = D.common_scale(at, tol, [OUTAGE])
    assert A.outage_p95(at, [OUTAGE], imu_scale=k)[1].max() <= tol
    assert A.outage_p95(at, [OUTAGE], imu_scale=k * 1.05)[1].max() > tol


def test_outage_answers_without_bias_instability_say_so(drive):
    """Issue 38: a preset whose datasheet is silent on the in-run bias instability (the
    BMI088's accelerometer) answers with a warning that names it; one that has it does not."""
    aiding = _aiding()
    bmi = ImuModel.load("BMI088")
    r = A.assess_aided(drive, bmi, aiding, RATE, 10.0, DURATION, budget=False, progress=False)
    assert sum("bias instability" in w for w in r["warnings"]) == 1, r["warnings"]
    f = O.find_outage(drive, bmi, aiding, RATE, 10.0, DURATION, budget=False, starts=2)
    assert sum("bias instability" in w for w in f["warnings"]) == 1, f["warnings"]
    d = D.design_aided(drive, bmi, aiding, RATE, 10.0, DURATION, find="outage", presets=False)
    assert sum("bias instability" in w for w in d["warnings"]) == 1, d["warnings"]
    (row,) = O.bridgeable_outages(drive, aiding, RATE, 10.0, DURATION, presets=["BMI088"],
                                  starts=2)
    assert any("accel.bias_instability" in w for w in row["warnings"])
    adis = A.assess_aided(drive, ImuModel.load("ADIS16470"), aiding, RATE, 10.0, DURATION,
                          budget=False, progress=False)
    assert not any("bias instability" in w for w in adis["warnings"])

