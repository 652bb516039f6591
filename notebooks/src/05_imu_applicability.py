# %% [markdown]
# # Can this IMU track my motion? — datasheet errors, verdict, design, models from a log
#
# The tool the Marusenkova paper's introduction asks for: preset a motion and the error
# characteristics a manufacturer specifies, simulate the sensors' signals, compute many
# potential trajectories, and judge from the spread whether the IMU suits the task — without
# building a device. Two ways to the same verdict: **Monte Carlo** (simulate and navigate many
# noisy runs) and **linear covariance analysis** (propagate the error covariance along the true
# motion once: a fraction of a second, exact per error term). Then the inverse question — the
# worst IMU that still meets a tolerance — and an IMU model fitted from a static log.
# Computation: `imunav.sensors` (error models, Allan fits), `imunav.analysis` (Monte Carlo,
# covariance, verdict, design); presets with their datasheet sources in
# `imunav.sensors.presets`. Units: SI in the API; the sliders and printouts use datasheet units
# (°/√h, °/h, µg/√Hz, µg, mg, mrad) and say so.

# %%
import time

import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import Dropdown, FloatLogSlider, GridBox, Layout, VBox, interactive_output

from imunav import (
    Motion,
    assess,
    assess_covariance,
    covariance,
    design,
    format_design,
    format_verdict,
    monte_carlo,
)
from imunav.analysis.assessment import min_sample_rate, verdict_covariance
from imunav.analysis.covariance import CovarianceResult
from imunav.papers.marusenkova2020 import motion_for
from imunav.plotting import plot_allan, plot_envelope, plot_verdict
from imunav.sensors import PRESETS, ImuModel, TriadModel, allan_deviation, apply_triad, fit_allan
from imunav.sensors.allan_report import imu_toml

SEED = 2026

# %% [markdown]
# ## 1. The presets, and their Allan curves (stationary self-check)

# %%
for name in PRESETS:
    m = ImuModel.load(name)
    print(f"{name:10s}", ", ".join(m.terms()) or "(no errors)")

# %%
fig, axs = plt.subplots(1, 2, figsize=(12, 4))
for name in ("BNO055", "BMI088", "ADIS16470", "tactical"):
    m = ImuModel.load(name)
    for ax, tri, unit, scale in ((axs[0], m.gyro, "°/h", 180 / np.pi * 3600),
                                 (axs[1], m.accel, "µg", 1e6 / 9.80665)):
        stoch = TriadModel(noise_density=tri.noise_density, bias_instability=tri.bias_instability,
                           bias_correlation_time=tri.bias_correlation_time,
                           random_walk=tri.random_walk)
        y, _ = apply_triad(stoch, np.zeros((36_000, 3)), "rates", 10.0,
                           np.random.default_rng(SEED))
        taus, adev = allan_deviation(y[:, 0], 10.0)
        ax.loglog(taus, adev * scale, label=name)
        ax.set(xlabel="τ (s)", ylabel=f"Allan deviation ({unit})")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
axs[0].set_title("gyro (x axis, 1 h at 10 Hz)")
axs[1].set_title("accelerometer")
axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 2. A walking-like motion, one IMU: Monte Carlo envelope and verdict

# %%
walk = Motion(x="1.4*t", y="0.05*sin(1.8*t)", z="-0.03*sin(3.6*t)",
              yaw="0.05*sin(0.9*t)", pitch="0.04*sin(3.6*t)", roll="0.06*sin(1.8*t)",
              duration=30.0, name="walk")
adis = ImuModel.load("ADIS16470")
r = assess(walk, adis, 100.0, runs=100, tolerance=2.0, seed=SEED, progress=False)
print(format_verdict(r))

# %%
mc = monte_carlo(walk, adis, 100.0, runs=100, seed=SEED, progress=False)
ax = plot_envelope(mc, tolerance=2.0)
ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 3. The same verdict by covariance analysis
#
# To first order the navigation errors are linear in the sensor errors, so their covariance can
# be propagated along the exact true motion — once, and separately for each error term
# (independent terms add). The 95th percentile of the position error *norm* follows exactly
# from the 3×3 covariance (the norm of a correlated Gaussian vector, not a multiple of σ).
# Below: the covariance envelope over the Monte Carlo runs of §2, and the time each takes.

# %%
rc = assess_covariance(walk, adis, 100.0, tolerance=2.0)
print(format_verdict(rc))
t0 = time.perf_counter()
cov_walk = covariance(walk, adis, 100.0)                 # every term: the budget comes with it
t_cov = time.perf_counter() - t0
t0 = time.perf_counter()
mc1000 = monte_carlo(walk, adis, 100.0, runs=1000, seed=SEED, progress=False)   # all terms only
t_mc = time.perf_counter() - t0
p95_mc = np.percentile(mc1000.position[:, -1], 95)
print(f"\nfinal 95th percentile: covariance {rc['final_p95_position_m']:.3f} m, "
      f"1000-run Monte Carlo {p95_mc:.3f} m "
      f"({100 * (rc['final_p95_position_m'] / p95_mc - 1):+.1f} %)")

# %%
# NBVAL_IGNORE_OUTPUT
print(f"time: covariance, every term {t_cov:.2f} s; Monte Carlo, 1000 runs of all terms "
      f"together {t_mc:.1f} s ({t_mc / t_cov:.0f}×; its error budget would take 200 more runs "
      "per term)")

# %%
fig, axs = plt.subplots(1, 2, figsize=(13, 4))
for ax, key, env_key, unit in ((axs[0], "position", "position_p95_m", "m"),
                               (axs[1], "attitude", "attitude_p95_rad", "rad")):
    ax.plot(mc1000.t, np.percentile(getattr(mc1000, key), 95, axis=0), color="C0", lw=3,
            alpha=0.5, label="Monte Carlo, 1000 runs")
    ax.plot(rc["envelope"]["t"], rc["envelope"][env_key], "C1--", lw=1.5, label="covariance")
    ax.set(xlabel="t (s)", ylabel=f"{key} error, 95th percentile ({unit})")
axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
plt.tight_layout()
plt.show()

# %%
plot_verdict(rc, cov_walk)
plt.tight_layout()
plt.show()

# %% [markdown]
# The error budget is exact by linearity: each term's own covariance is propagated alone, and
# the variances (not the percentiles) add up to the total.
#
# ## 4. Two IMUs side by side (the paper's BNO055 vs a tactical unit)

# %%
car = Motion(x="10*t + 2*sin(0.2*t)", y="5*(1 - cos(0.1*t))", yaw="0.5*(1 - cos(0.1*t))",
             duration=60.0, name="vehicle")
for name in ("BNO055", "tactical"):
    res = assess(car, ImuModel.load(name), 100.0, runs=50, tolerance=10.0, seed=SEED,
                 budget_runs=20, progress=False)
    print(format_verdict(res))
    print()

# %%
fig, ax = plt.subplots(figsize=(9, 4))
for name in ("BNO055", "tactical"):
    plot_envelope(monte_carlo(car, ImuModel.load(name), 100.0, runs=50, seed=SEED,
                              progress=False), tolerance=10.0, ax=ax, label=name)
ax.set_yscale("log")
ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
plt.tight_layout()
plt.show()

# %% [markdown]
# A consumer MEMS IMU alone (turn-on bias of ~1°/s, tens of mg) cannot hold a vehicle's
# position for a minute; even the tactical unit needs aiding. The error budget says which
# specification to buy better: here it is the turn-on bias, i.e. calibration, before noise.
# The BNO055's 1 °/s bias also takes the attitude error beyond the small-angle model: the
# covariance analysis says so, and Monte Carlo is the method there.

# %%
print(format_verdict(assess_covariance(car, ImuModel.load("BNO055"), 100.0, tolerance=10.0)))

# %% [markdown]
# ## 5. The worst IMU that still does: inverse design
#
# Each term's covariance scales with the square of its datasheet value, so the largest value
# that alone keeps the 95th percentile within the tolerance is exact — as is the largest common
# scale of all the terms together.

# %%
d = design(walk, adis, 100.0, tolerance=2.0)
print(format_design(d))

# %% [markdown]
# ## 6. Live: datasheet sliders, envelope and verdict
#
# Because covariances scale with the squares of the datasheet values, the per-term covariances
# are computed once at unit value; moving a slider only rescales and adds them, and the verdict
# is recomputed from the total — fast enough to follow the slider. The figure below is the
# sliders' starting state (the ADIS16470's values, plus a 0.5 mg / 20 °/h turn-on bias it leaves
# calibrated out); in a live kernel, the widget under it redraws as they move.

# %%
D2R, G = np.pi / 180, 9.80665
#: slider: (term, datasheet unit, SI per unit, start value, min, max)
SLIDERS = [
    ("gyro.noise_density", "°/√h", D2R / 60, 0.34, 0.01, 10),
    ("gyro.bias_instability", "°/h", D2R / 3600, 8.0, 0.1, 100),
    ("gyro.bias", "°/h", D2R / 3600, 20.0, 0.1, 3600),
    ("gyro.misalignment", "mrad", 1e-3, 0.873, 0.01, 20),
    ("accel.noise_density", "µg/√Hz", 1e-6 * G, 62.9, 5, 1000),
    ("accel.bias_instability", "µg", 1e-6 * G, 13.0, 1, 1000),
    ("accel.bias", "mg", 1e-3 * G, 0.5, 0.01, 100),
    ("accel.misalignment", "mrad", 1e-3, 0.873, 0.01, 20),
]
UNIT = ImuModel(TriadModel(noise_density=1.0, bias_instability=1.0, bias=1.0, misalignment=1.0),
                TriadModel(noise_density=1.0, bias_instability=1.0, bias=1.0, misalignment=1.0),
                "unit")
MOTIONS = {"walk": walk, "vehicle": car, "Marusenkova fig1a": motion_for("fig1a"),
           "Marusenkova fig1b": motion_for("fig1b")}
_unit_cache, _rate_cache = {}, {}


def unit_covariances(motion_name, rate):
    """Per-term covariances at unit SI value (cached per motion and rate)."""
    key = (motion_name, rate)
    if key not in _unit_cache:
        _unit_cache[key] = covariance(MOTIONS[motion_name], UNIT, rate)
    return _unit_cache[key]


def live_verdict(motion_name, rate, tolerance, values):
    """The verdict for datasheet ``values`` (datasheet units, in SLIDERS order)."""
    u = unit_covariances(motion_name, rate)
    terms = {name: (v * si) ** 2 * u.terms[name]
             for (name, _, si, *_), v in zip(SLIDERS, values, strict=True) if v > 0}
    cov = CovarianceResult(u.t, terms, sum(terms.values()), rate, "datasheet sliders",
                           u.max_rate, u.max_force, [])
    att = float(cov.attitude_quantile(index=-1))
    if att > 0.3:
        cov.warnings.append(f"the 95th-percentile attitude error reaches {att:.2g} rad: beyond "
                            "about 0.3 rad the small-angle model is not reliable")
    if (motion_name, tolerance) not in _rate_cache:
        _rate_cache[motion_name, tolerance] = min_sample_rate(MOTIONS[motion_name], tolerance)
    r = verdict_covariance(cov, tolerance, _rate_cache[motion_name, tolerance],
                           motion=motion_name, imu="datasheet sliders")
    return r, cov


def draw(motion_name, rate, tolerance, *values):
    r, cov = live_verdict(motion_name, rate, tolerance, values)
    print(format_verdict(r))
    plot_verdict(r, cov, log=True)
    plt.tight_layout()
    plt.show()


draw("walk", 100.0, 2.0, *[s[3] for s in SLIDERS])

# %%
# NBVAL_IGNORE_OUTPUT
controls = {"motion_name": Dropdown(options=list(MOTIONS), value="walk", description="motion"),
            "rate": FloatLogSlider(value=100, base=10, min=1, max=3, description="rate (Hz)",
                                   continuous_update=False),
            "tolerance": FloatLogSlider(value=2.0, base=10, min=-2, max=3,
                                        description="tolerance (m)", continuous_update=False)}
for name, unit, _, start, lo, hi in SLIDERS:
    controls[name.replace(".", "__")] = FloatLogSlider(
        value=start, base=10, min=np.log10(lo), max=np.log10(hi), continuous_update=False,
        description=f"{name.split('.')[0]} {name.split('.')[1].replace('_', ' ')} ({unit})",
        style={"description_width": "210px"}, layout=Layout(width="460px"))


def _draw(motion_name, rate, tolerance, **vals):
    draw(motion_name, rate, tolerance, *[vals[s[0].replace(".", "__")] for s in SLIDERS])


out = interactive_output(_draw, controls)
VBox([GridBox(list(controls.values()), layout=Layout(grid_template_columns="repeat(2, 480px)")),
      out])

# %% [markdown]
# ## 7. A model from a static log: the Allan deviation fit
#
# `imunav allan LOG.csv --fit IMU.toml` does this from the command line. Here: two hours of a
# static ADIS16470 at 50 Hz (simulated; a real recording works the same), the overlapping Allan
# deviation of each axis, and σ²(τ) = N²/τ + B² + K²τ/3 fitted by weighted least squares. A
# term is kept only where it dominates over at least half a decade of τ; otherwise the file
# says why. B is the Allan floor, as datasheets quote bias instability (the IEEE 952 flicker
# coefficient is B/0.664).

# %%
n = 2 * 3600 * 50
rng = np.random.default_rng(SEED)
gyro_log, _ = apply_triad(TriadModel(noise_density=adis.gyro.noise_density,
                                     bias_instability=adis.gyro.bias_instability),
                          np.zeros((n, 3)), "rates", 50.0, rng)
accel_log, _ = apply_triad(TriadModel(noise_density=adis.accel.noise_density,
                                      bias_instability=adis.accel.bias_instability),
                           np.tile([0.0, 0.0, -G], (n, 1)), "rates", 50.0, rng)
fits = {"gyro": fit_allan(gyro_log, 50.0), "accel": fit_allan(accel_log, 50.0)}
print(imu_toml(fits, "a simulated 2-hour static ADIS16470"))

# %%
plot_allan(fits)
plt.show()

# %%
fitted = ImuModel.from_dict({"gyro": {k: v["value"] for k, v in fits["gyro"]["terms"].items()
                                      if v["value"]},
                             "accel": {k: v["value"] for k, v in fits["accel"]["terms"].items()
                                       if v["value"]}}, "fitted")
for triad, unit, scale in (("gyro", "°/√h, °/h", (180 / np.pi * 60, 180 / np.pi * 3600)),
                           ("accel", "µg/√Hz, µg", (1e6 / G, 1e6 / G))):
    a, b = getattr(adis, triad), getattr(fitted, triad)
    print(f"{triad}: datasheet N, B = {a.noise_density * scale[0]:.3g}, "
          f"{a.bias_instability * scale[1]:.3g}   fitted = {b.noise_density * scale[0]:.3g}, "
          f"{b.bias_instability * scale[1]:.3g}  ({unit})")
print(format_verdict(assess_covariance(walk, fitted, 100.0, tolerance=2.0)).splitlines()[1])

# %% [markdown]
# ## CI hook

# %%
print(r["fraction_within_tolerance"], r["min_rate_hz"])
assert r == assess(walk, adis, 100.0, runs=100, tolerance=2.0, seed=SEED,
                   progress=False)   # the same verdict twice with the same seed
# covariance and 1000-run Monte Carlo: the same 95th percentile within 10 % (sampling ≈ 3 %)
assert abs(rc["final_p95_position_m"] / p95_mc - 1) < 0.1
assert abs(fitted.gyro.noise_density / adis.gyro.noise_density - 1) < 0.05
