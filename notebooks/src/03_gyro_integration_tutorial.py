# %% [markdown]
# # The gyroscope quaternion-integration tutorial
#
# The tutorial (after Madgwick's quaternion library) integrates gyro rates with the
# first-order update `Q + ½ Q ⊗ ω dt`, normalised, over 100 steps of 0.5 s: π/8 rad/s about X
# while `i < 50`, then π/16 rad/s about Y. We reproduce it exactly as written, then compare
# with the exact update — which here *is* the true rotation, because the rate is constant
# over every step. Computation: `imunav.papers.tutorial`.
#
# Convention note: Madgwick's `quatern2rotMat` returns the **transpose** of the rotation
# matrix of `q` (his quaternions describe the earth relative to the sensor), so the plotted
# point turns opposite to the body. The reproduction keeps it (tested against his formula).

# %%
import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import Dropdown, FloatLogSlider, FloatSlider, interact

from imunav.papers import tutorial as T

SEED = 0  # nothing here is random

# %% [markdown]
# ## 1. The example as written

# %%
res = T.run()
np.set_printoptions(precision=6, suppress=True)
print("steps:", len(res.Q), "| X-rate steps:", int((res.rates[:, 0] > 0).sum()),
      "| Y-rate steps:", int((res.rates[:, 1] > 0).sum()))
print("final Q (first-order):", res.Q[-1])
print("final point P        :", res.P[-1])

# %%
# NBVAL_IGNORE_OUTPUT
fig = plt.figure(figsize=(11, 5))
T.plot_run(res, fig.add_subplot(1, 2, 1, projection="3d"), "first-order + normalise (as written)")
T.plot_run(T.run(update="exact"), fig.add_subplot(1, 2, 2, projection="3d"), "exact update")
plt.show()

# %% [markdown]
# ## 2. How far is the first-order update from the truth?

# %%
err = T.angle_error()
print(f"final angle error: {np.degrees(err[-1]):.3f}°  (after 49.5 s)")
errs, order = T.error_vs_dt()
for dt, e in zip((0.5, 0.25, 0.125, 0.0625, 0.03125), errs, strict=True):
    print(f"dt = {dt:7.5f} s: final error {np.degrees(e):.4f}°")
print(f"fitted order: {order:.2f}")

# %% [markdown]
# The normalised first-order step turns by `2 atan(|ω|dt/2)` instead of `|ω|dt`: a deficit of
# `(|ω|dt)³/12` per step about a fixed axis, `T |ω|³ dt²/12` in all — second order in dt here
# (the axis is constant within each phase). With a rate that changes direction continuously,
# the coning error is added on top (see `06_strapdown_algorithms`).
#
# ## 3. "A gyroscope measures the angular acceleration"? No — angular velocity
# The tutorial opens with that claim (then assumes velocities "to avoid a double
# integration"). An ideal gyro on a body turning at a constant π/8 rad/s about x, from
# `imunav.simulate_imu`:

# %%
d = T.gyro_measures_rate_demo()
print(f"gyro x reading: {d['gyro_x_rad_s'].min():.6f} … {d['gyro_x_rad_s'].max():.6f} rad/s "
      f"(π/8 = {np.pi/8:.6f})")
print(f"angular acceleration: max |dω/dt| = {np.abs(d['angular_acceleration']).max():.1e} rad/s²")

# %% [markdown]
# Zero angular acceleration, non-zero reading: the gyroscope measures angular *velocity*
# (rad/s), and orientation follows from a *single* integration, as the tutorial's own code does.
#
# ## 4. Explore

# %%
# NBVAL_IGNORE_OUTPUT
@interact(dt=FloatLogSlider(value=0.5, base=10, min=-2, max=0, continuous_update=False),
          rate_x=FloatSlider(value=np.pi / 8, min=0, max=2, step=0.01, continuous_update=False),
          rate_y=FloatSlider(value=np.pi / 16, min=0, max=2, step=0.01, continuous_update=False),
          update=Dropdown(options=T.UPDATES))
def explore(dt, rate_x, rate_y, update):
    r = T.run(dt, rate_x=rate_x, rate_y=rate_y, update=update, duration=49.5)
    e = T.angle_error(dt, duration=49.5, rate_x=rate_x, rate_y=rate_y)
    fig = plt.figure(figsize=(11, 4.5))
    T.plot_run(r, fig.add_subplot(1, 2, 1, projection="3d"), update)
    ax = fig.add_subplot(1, 2, 2)
    ax.plot(r.t, np.degrees(e))
    ax.set(xlabel="t (s)", ylabel="first-order error (deg)")
    plt.show()

# %% [markdown]
# ## CI hook

# %%
print(f"{np.degrees(err[-1]):.3f}")
assert np.isclose(np.degrees(err[-1]), 1.740, atol=0.01)
assert abs(order - 2) < 0.1
