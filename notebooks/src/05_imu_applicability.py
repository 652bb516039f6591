# %% [markdown]
# # Can this IMU track my motion? — datasheet errors, Monte Carlo, verdict
#
# The tool the Marusenkova paper's introduction asks for: preset a motion and the error
# characteristics a manufacturer specifies, simulate the sensors' signals, compute many
# potential trajectories, and judge from the spread whether the IMU suits the task — without
# building a device. Computation: `imunav.sensors` (error models), `imunav.analysis` (Monte Carlo
# and verdict); presets with their datasheet sources in `imunav.sensors.presets`.

# %%
import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import Dropdown, FloatLogSlider, IntSlider, interact

from imunav import Motion, assess, format_verdict, monte_carlo
from imunav.papers.marusenkova2020 import motion_for
from imunav.plotting import plot_envelope
from imunav.sensors import PRESETS, ImuModel, allan_deviation, apply_triad

SEED = 2026

# %% [markdown]
# ## 1. The presets, and their Allan curves (stationary self-check)

# %%
for name in PRESETS:
    m = ImuModel.load(name)
    print(f"{name:10s}", ", ".join(m.terms()) or "(no errors)")

# %%
# NBVAL_IGNORE_OUTPUT
fig, axs = plt.subplots(1, 2, figsize=(12, 4))
for name in ("BNO055", "BMI088", "ADIS16470", "tactical"):
    m = ImuModel.load(name)
    for ax, tri, unit, scale in ((axs[0], m.gyro, "deg/h", 180 / np.pi * 3600),
                                 (axs[1], m.accel, "µg", 1e6 / 9.80665)):
        stoch = type(tri)(noise_density=tri.noise_density, bias_instability=tri.bias_instability,
                          bias_correlation_time=tri.bias_correlation_time,
                          random_walk=tri.random_walk)
        y, _ = apply_triad(stoch, np.zeros((36_000, 3)), "rates", 10.0,
                           np.random.default_rng(SEED))
        taus, adev = allan_deviation(y[:, 0], 10.0)
        ax.loglog(taus, adev * scale, label=name)
        ax.set(xlabel="τ (s)", ylabel=f"Allan deviation ({unit})")
axs[0].set_title("gyro")
axs[1].set_title("accelerometer")
axs[0].legend()
plt.show()

# %% [markdown]
# ## 2. A walking-like motion, one IMU, Monte Carlo envelope and verdict

# %%
walk = Motion(x="1.4*t", y="0.05*sin(1.8*t)", z="-0.03*sin(3.6*t)",
              yaw="0.05*sin(0.9*t)", pitch="0.04*sin(3.6*t)", roll="0.06*sin(1.8*t)",
              duration=30.0, name="walk")
r = assess(walk, ImuModel.load("ADIS16470"), 100.0, runs=100, tolerance=2.0, seed=SEED,
           progress=False)
print(format_verdict(r))

# %%
# NBVAL_IGNORE_OUTPUT
mc = monte_carlo(walk, ImuModel.load("ADIS16470"), 100.0, runs=100, seed=SEED, progress=False)
plot_envelope(mc, tolerance=2.0)
plt.show()

# %% [markdown]
# ## 3. Two IMUs side by side (the paper's BNO055 vs a tactical unit)

# %%
car = Motion(x="10*t + 2*sin(0.2*t)", y="5*(1 - cos(0.1*t))", yaw="0.5*(1 - cos(0.1*t))",
             duration=60.0, name="vehicle")
for name in ("BNO055", "tactical"):
    res = assess(car, ImuModel.load(name), 100.0, runs=50, tolerance=10.0, seed=SEED,
                 budget_runs=20, progress=False)
    print(format_verdict(res))
    print()

# %%
# NBVAL_IGNORE_OUTPUT
fig, ax = plt.subplots(figsize=(8, 4))
for name in ("BNO055", "tactical"):
    plot_envelope(monte_carlo(car, ImuModel.load(name), 100.0, runs=50, seed=SEED,
                              progress=False), tolerance=10.0, ax=ax, label=name)
ax.set_yscale("log")
plt.show()

# %% [markdown]
# A consumer MEMS IMU alone (turn-on bias of ~1°/s, tens of mg) cannot hold a vehicle's
# position for a minute; even the tactical unit needs aiding. The error budget says which
# specification to buy better: here it is the turn-on bias, i.e. calibration, before noise.
#
# ## 4. Explore
# Motion (the papers' trajectories, walking, vehicle), IMU, rate, tolerance.

# %%
# NBVAL_IGNORE_OUTPUT
motions = {"walk": walk, "vehicle": car, "Marusenkova fig1a": motion_for("fig1a"),
           "Marusenkova fig1b": motion_for("fig1b")}


@interact(motion=Dropdown(options=list(motions)), imu=Dropdown(options=list(PRESETS), value="BMI088"),
          rate=FloatLogSlider(value=100, base=10, min=1, max=3, continuous_update=False),
          tolerance=FloatLogSlider(value=1.0, base=10, min=-2, max=3, continuous_update=False),
          runs=IntSlider(value=40, min=10, max=200, step=10, continuous_update=False))
def explore(motion, imu, rate, tolerance, runs):
    m = motions[motion]
    res = assess(m, ImuModel.load(imu), rate, runs, tolerance, seed=SEED, budget_runs=20,
                 progress=False)
    print(format_verdict(res))
    plot_envelope(monte_carlo(m, ImuModel.load(imu), rate, runs=runs, seed=SEED,
                              progress=False), tolerance)
    plt.show()

# %% [markdown]
# ## CI hook

# %%
print(r["fraction_within_tolerance"], r["min_rate_hz"])
assert r == assess(walk, ImuModel.load("ADIS16470"), 100.0, runs=100, tolerance=2.0, seed=SEED,
                   progress=False)   # the same verdict twice with the same seed
