# %% [markdown]
# # The gyroscope quaternion-integration tutorial
#
# A short web tutorial (after Madgwick's quaternion library for MATLAB) integrates gyroscope
# rates into an orientation quaternion with the first-order update, normalised, and runs a
# MATLAB example: a point and its axis markers rotated by π/8 rad/s about X, then π/16 rad/s
# about Y. This notebook reads it without the original open: every equation it uses is
# written below, every claim is checked by computation, and the verdicts are those of
# `figures/reproduction.json`. Computation: `imunav.papers.tutorial`. Units: the tutorial's
# own (rad, rad/s, s); angles are printed in degrees where it helps and say so.
#
# ## Coverage: everything the tutorial states, and where it is settled
#
# | the tutorial says | here | tutorial | imunav | verdict |
# |---|---|---|---|---|
# | "a gyroscope measures the angular acceleration … integrating twice" | §4 | acceleration | angular velocity: on the real x-IMU3, once-integrated 4.9° off the device's orientation, twice-integrated 56° off | differs |
# | the update $\hat Q_k = \hat Q_{k-1} + \Delta t\,\tfrac12 \hat Q_{k-1}\otimes S_\omega$, normalised | §1–2 | — | reproduced as written; second order in Δt (1.99) against the exact rotation | no paper value |
# | "for some applications, the quaternion must be normalized" | §3 | — | without it $\lvert Q\rvert$ grows to 1.3385 (closed form $\prod\sqrt{1+(\lvert\omega\rvert\Delta t/2)^2}$) and the rotated point leaves its sphere by 109 % | no paper value |
# | the example "simulates … during 50 seconds … 25 first seconds … 25 last seconds" | §1 | 50 s, 25 s + 25 s | 49.5 s: 24 s + 25.5 s (99 steps; `i<50` is 48 of them) | differs |
# | the code's comments "50 first steps" / "50 last steps" | §1 | 50 + 50 | 48 + 51 | differs |
# | the 3-D plot of the rotated point and its axes | §1 | (figure) | drawn, as written and with the exact update | no paper value |

# %%
import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import Dropdown, FloatLogSlider, FloatSlider, interact

from imunav.papers import tutorial as T

SEED = 0  # nothing here is random

# %% [markdown]
# ## 1. The example as written
#
# The tutorial's equations (its notation: $S_\omega$ the pure quaternion of the gyro reading,
# $\hat Q$ the estimate, $\otimes$ the Hamilton product):
#
# $$S_\omega = \begin{bmatrix}0 & \omega_x & \omega_y & \omega_z\end{bmatrix},\qquad
# \frac{dQ_k}{dt} = \tfrac12\,\hat Q_{k-1}\otimes S_\omega,\qquad
# \hat Q_k = \hat Q_{k-1} + \Delta t\,\frac{dQ_k}{dt},\qquad
# Q_k^n = \frac{\hat Q_k}{\lvert \hat Q_k\rvert}.$$
#
# The MATLAB loop runs `for i=2:100` with `dt=0.5`, `Sw=[0 pi/8 0 0]` while `i<50`, else
# `[0 0 pi/16 0]`. Counting its steps (not its comments):

# %%
sch = T.schedule()
print(f"steps: {sch['x_steps']} about X + {sch['y_steps']} about Y = "
      f"{sch['x_steps'] + sch['y_steps']}; durations {sch['x_s']} s + {sch['y_s']} s = "
      f"{sch['total_s']} s  (the text: 25 s + 25 s = 50 s)")
res = T.run()
np.set_printoptions(precision=6, suppress=True)
print("final Q (first-order):", res.Q[-1])
print("final point P        :", res.P[-1])

# %% [markdown]
# Convention note: Madgwick's `quatern2rotMat` returns the **transpose** of the rotation
# matrix of `q` (his quaternions describe the earth relative to the sensor), so the plotted
# point turns opposite to the body. The reproduction keeps it (tested against his formula).
# The axes are the tutorial's own x, y, z (no navigation frame is involved).

# %%
fig = plt.figure(figsize=(12, 5.5))
T.plot_run(res, fig.add_subplot(1, 2, 1, projection="3d"), "first-order + normalise (as written)")
T.plot_run(T.run(update="exact"), fig.add_subplot(1, 2, 2, projection="3d"), "exact update")
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 2. How far is the first-order update from the truth?
# The rate is constant over each step, so the exact update
# $Q_k = Q_{k-1}\otimes\exp(\tfrac12\,\omega\,\Delta t)$ *is* the true rotation, an independent
# truth for the first-order one.

# %%
err = T.angle_error()
print(f"final angle error: {np.degrees(err[-1]):.3f}°  (after {sch['total_s']} s)")
dts = (0.5, 0.25, 0.125, 0.0625, 0.03125)
errs, order = T.error_vs_dt(dts)
for dt, e in zip(dts, errs, strict=True):
    print(f"dt = {dt:7.5f} s: final error {np.degrees(e):.4f}°")
print(f"fitted order: {order:.2f}")

# %%
fig, axs = plt.subplots(1, 2, figsize=(12, 4))
axs[0].plot(res.t, np.degrees(err))
axs[0].set(xlabel="t (s)", ylabel="angle to the true attitude (deg)",
           title="first-order + normalise, dt = 0.5 s")
T.plot_error_vs_dt(dts, errs, order, axs[1])
plt.tight_layout()
plt.show()

# %% [markdown]
# The normalised first-order step turns by $2\arctan(\lvert\omega\rvert\Delta t/2)$ instead of
# $\lvert\omega\rvert\Delta t$: a deficit of $(\lvert\omega\rvert\Delta t)^3/12$ per step about
# a fixed axis, $T\lvert\omega\rvert^3\Delta t^2/12$ in all — second order in Δt here (the axis
# is constant within each phase). With a rate that changes direction continuously, the coning
# error adds to it (notebook 06).
#
# ## 3. Without the normalisation line
# $\hat Q\otimes S_\omega$ is orthogonal to $\hat Q$, so each step multiplies the norm by
# exactly $\sqrt{1+(\lvert\omega\rvert\Delta t/2)^2}$; the direction is the same as with
# normalisation (the update is linear in $\hat Q$). What goes wrong is everything that assumes a
# unit quaternion — here `quatern2rotMat`, which scales and shears the points:

# %%
un = T.unnormalised()
print(f"|Q| after the example: {un['final_norm']:.13f}  (closed form "
      f"{un['closed_form_norm']:.13f})")
print("direction vs the normalised run: "
      + ("< 1e-10° (rounding)" if un["angle_to_normalised_deg"] < 1e-10 else
         f"{un['angle_to_normalised_deg']:.2g}°"))
print(f"largest change of the point's distance from the origin: "
      f"{100 * un['max_radius_change']:.0f} %")

# %%
fig, axs = plt.subplots(1, 2, figsize=(12, 3.8))
axs[0].plot(res.t, un["norms"], label="|Q| computed")
axs[0].set(xlabel="t (s)", ylabel="|Q|", title="norm without normalisation")
axs[1].plot(res.t, un["radius"], color="C1")
axs[1].axhline(1.0, color="k", ls=":", lw=1, label="|P| / |P₀| should stay 1")
axs[1].set(xlabel="t (s)", ylabel="|P| / |P₀|", title="rotated point, raw quatern2rotMat")
axs[1].legend()
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 4. "A gyroscope measures the angular acceleration"? No — angular velocity
# The tutorial opens with that claim ("by integrating twice these angular accelerations…"),
# then assumes velocities "to avoid a double integration". A simulator cannot settle what a
# gyroscope measures (it would only return its own definition), so we use real hardware: the
# x-IMU3 recording shipped with imunav, whose onboard fusion (gyro *and* accelerometer) gives
# the device's own orientation. Over half-second windows, integrate the gyro output once (as an
# angular velocity) and twice (as an angular acceleration) and compare each with the rotation
# the device reports:

# %%
real = T.gyro_is_rate_real()
print(f"{real['windows']} windows of {real['window_s']} s; the device turns by "
      f"{real['device_turn_deg']:.0f}° (median)")
print(f"gyro integrated once  (rate):         median error {real['as_rate_error_deg']:.1f}°")
print(f"gyro integrated twice (acceleration): median error {real['as_acceleration_error_deg']:.1f}°")

# %% [markdown]
# Read as a rate, the gyro follows the device within a few degrees (what separates a 50 Hz gyro
# integration from the device's fusion, notebook 07); read as an acceleration it misses by
# most of the rotation. A gyroscope measures angular *velocity* (rad/s), and orientation
# follows from a *single* integration — as the tutorial's own code does.
#
# ## 5. Explore
# Step, rates and update. The figure below is the starting state; in a live kernel the widget
# under it redraws when a control is released.

# %%
def explore(dt=0.5, rate_x=np.pi / 8, rate_y=np.pi / 16, update="first_order"):
    r = T.run(dt, rate_x=rate_x, rate_y=rate_y, update=update, duration=49.5)
    e = T.angle_error(dt, duration=49.5, rate_x=rate_x, rate_y=rate_y)
    fig = plt.figure(figsize=(12, 4.5))
    T.plot_run(r, fig.add_subplot(1, 2, 1, projection="3d"), update)
    ax = fig.add_subplot(1, 2, 2)
    ax.plot(r.t, np.degrees(e))
    ax.set(xlabel="t (s)", ylabel="first-order error vs truth (deg)",
           title=f"dt = {dt:.3g} s")
    plt.tight_layout()
    plt.show()


explore()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(explore,
         dt=FloatLogSlider(value=0.5, base=10, min=-2, max=0, continuous_update=False,
                           description="dt (s)"),
         rate_x=FloatSlider(value=np.pi / 8, min=0, max=2, step=0.01, continuous_update=False,
                            description="ω about X"),
         rate_y=FloatSlider(value=np.pi / 16, min=0, max=2, step=0.01, continuous_update=False,
                            description="ω about Y"),
         update=Dropdown(options=T.UPDATES, description="update"))

# %% [markdown]
# ## CI hook

# %%
print(f"{np.degrees(err[-1]):.3f}")
assert np.isclose(np.degrees(err[-1]), 1.740, atol=0.01)
assert abs(order - 2) < 0.1
assert (sch["x_s"], sch["y_s"]) == (24.0, 25.5)
assert abs(un["final_norm"] / un["closed_form_norm"] - 1) < 1e-12
assert real["as_acceleration_error_deg"] > 5 * real["as_rate_error_deg"]
