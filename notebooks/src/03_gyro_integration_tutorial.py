# %% [markdown]
# # A gyroscope quaternion-integration tutorial, read with numbers
#
# **Source.** A short web tutorial, *integrating gyroscope rates into an orientation
# quaternion*, with a MATLAB example; the text (OCR'd) names no author, date or venue and
# credits "Madgwick's quaternion library for Matlab". It integrates the rates with the
# first-order update, normalised, and rotates a point and its axis markers by π/8 rad/s about
# X, then π/16 rad/s about Y.

# %% [markdown]
# ## What you will learn
#
# - the first-order quaternion update $\hat Q_k = \hat Q_{k-1} + \Delta t\,\tfrac12\hat
#   Q_{k-1}\otimes S_\omega$ in a dozen lines of Python, and why it must be normalised;
# - how far it is from the exact rotation, and how that error shrinks with the step;
# - what a gyroscope measures — settled on real hardware, not by a simulator's definition —
#   and what "drift" looks like when a real gyro is integrated alone.
#
# **What you should know first:** what a unit quaternion is and how $q\otimes v\otimes q^*$
# rotates a vector; a little NumPy. Nothing else.
#
# **Scope.** The tutorial's example is a pure rotation in its own frame: no gravity, no
# Earth rotation, no aiding. The real recordings of §4 are short, on a bench: over them the
# Earth's rotation is far below the gyros' own errors.
#
# **Conventions.** The tutorial's own (rad, rad/s, s; its x, y, z); angles are printed in
# degrees where it helps and say so. Computation: `imunav.papers.tutorial`; the loop itself is
# written out in §1 and checked against it.

# %% [markdown]
# ## Coverage: everything the tutorial states, and where it is settled
#
# One row per record of the ledger `figures/reproduction.json`, rendered from it (the verdict
# rule: `imunav.papers.records`). The schedule's durations are counted from the loop exactly,
# so they need no tolerance.

# %%
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown, display
from ipywidgets import Dropdown, FloatLogSlider, FloatSlider, interact

from imunav.core.rotations import quat_angle
from imunav.papers import records as R
from imunav.papers import tutorial as T
from imunav.plotting import figure, style, use_book_style

use_book_style()
SEED = 0  # nothing here is random
LEDGER = R.load()


def say(text):
    """Show a generated sentence (its numbers come from the computation above it)."""
    display(Markdown(text))


def verdict(*ids):
    display(Markdown("\n\n".join(R.verdict_line(i, LEDGER) for i in ids)))


# %% tags=["hide-input"]
display(Markdown(R.coverage_table(T.COVERAGE, LEDGER)))

# %% [markdown]
# ## 1. The example as written — the whole algorithm
#
# The tutorial's equations (its notation: $S_\omega$ the pure quaternion of the gyro reading,
# $\hat Q$ the estimate, $\otimes$ the Hamilton product):
#
# $$S_\omega = \begin{bmatrix}0 & \omega_x & \omega_y & \omega_z\end{bmatrix},\qquad
# \frac{dQ_k}{dt} = \tfrac12\,\hat Q_{k-1}\otimes S_\omega,\qquad
# \hat Q_k = \hat Q_{k-1} + \Delta t\,\frac{dQ_k}{dt},\qquad
# Q_k^n = \frac{\hat Q_k}{\lvert \hat Q_k\rvert}.$$
#
# Here it is in Python, line for line with the MATLAB loop (`for i=2:100`, `dt=0.5`,
# `Sw=[0 pi/8 0 0]` while `i<50`, else `[0 0 pi/16 0]`), with the exact update beside it — for a
# rate constant over the step, $Q_k = Q_{k-1}\otimes\exp(\tfrac12\omega\Delta t)$ is the true
# rotation:

# %%
def hamilton(p, q):
    """p ⊗ q, scalar first."""
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return np.array([p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3, p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
                     p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1, p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0])


def tutorial_loop(dt=0.5, last=100, switch=50, exact=False):
    Q = [np.array([1.0, 0.0, 0.0, 0.0])]                # Q(1,:) = [1 0 0 0]
    for i in range(2, last + 1):                        # for i=2:100
        w = np.array([np.pi / 8, 0, 0]) if i < switch else np.array([0, np.pi / 16, 0])
        if exact:                                       # Q ⊗ exp(ω dt / 2): the true rotation
            a = np.linalg.norm(w) * dt
            step = np.concatenate([[np.cos(a / 2)], np.sin(a / 2) * w / np.linalg.norm(w)])
            Q.append(hamilton(Q[-1], step))
        else:
            Qdot = hamilton(0.5 * Q[-1], np.concatenate([[0.0], w]))   # quaternProd(0.5*Q, Sw)
            q = Q[-1] + Qdot * dt                       # Q(i,:) = Q(i-1,:) + Qdot*dt
            Q.append(q / np.linalg.norm(q))             # normalise
    return np.array(Q)


Q_fo, Q_ex = tutorial_loop(), tutorial_loop(exact=True)
res, res_exact = T.run(), T.run(update="exact")
print("these lines vs imunav.papers.tutorial: first-order",
      R.small(np.abs(Q_fo - res.Q).max()), "| exact", R.small(np.abs(Q_ex - res_exact.Q).max()))
print("final Q, first-order:", np.round(Q_fo[-1], 6) + 0.0, " exact:", np.round(Q_ex[-1], 6) + 0.0)
print(f"angle between them: {np.degrees(quat_angle(Q_fo[-1], Q_ex[-1])):.3f}°")

# %% [markdown]
# **How long does the example run?** The text says 50 seconds, 25 about X and 25 about Y, and
# the code's comments say "the 50 first steps" and "the 50 last steps". Counting the loop:

# %%
sch = T.schedule()
print(f"steps: {sch['x_steps']} about X + {sch['y_steps']} about Y = "
      f"{sch['x_steps'] + sch['y_steps']}; durations {sch['x_s']} s + {sch['y_s']} s = "
      f"{sch['total_s']} s")
verdict("tutorial.schedule.total_s", "tutorial.schedule.x_rotation_s",
        "tutorial.schedule.y_rotation_s", "tutorial.schedule.x_steps", "tutorial.schedule.y_steps")

# %% [markdown]
# The tutorial's 3-D plot, as written (first-order, normalised) and with the exact update.
# Madgwick's `quatern2rotMat` returns the **transpose** of the rotation matrix of `q` (his
# quaternions describe the earth relative to the sensor), so the plotted point turns opposite
# to the body; the reproduction keeps that (tested against his formula):

# %% tags=["hide-input"]
fig = plt.figure(figsize=(6.5, 3.4), layout="constrained")
T.plot_run(res, fig.add_subplot(1, 2, 1, projection="3d"), "first-order + normalise\n(as written)")
T.plot_run(res_exact, fig.add_subplot(1, 2, 2, projection="3d"), "exact rotation")
plt.show()

# %% [markdown]
# ## 2. How far is the first-order update from the truth?
# The rate is constant over each step, so the exact update *is* the true rotation — an
# independent truth for the first-order one.

# %%
err = T.angle_error()
dts = (0.5, 0.25, 0.125, 0.0625, 0.03125)
errs, order = T.error_vs_dt(dts)
for dt, e in zip(dts, errs, strict=True):
    print(f"dt = {dt:7.5f} s: final error {np.degrees(e):.4f}°")
print(f"fitted order: {order:.2f}")
verdict("tutorial.final_angle_error_first_order_deg", "tutorial.update_order_in_dt")

# %% tags=["hide-input"]
fig, axs = figure(1, 2, height=3.0)
axs[0].plot(res.t, np.degrees(err), color=style("increments/first_order")["color"])
axs[0].set(xlabel="t (s)", ylabel="angle to the true attitude (°)",
           title="first-order + normalise, dt = 0.5 s")
T.plot_error_vs_dt(dts, errs, order, axs[1])
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
print(f"|Q| after the example: {un['final_norm']:.12f}  (closed form "
      f"{un['closed_form_norm']:.12f})")
print("direction vs the normalised run: "
      + ("< 1e-10° (rounding)" if un["angle_to_normalised_deg"] < 1e-10 else
         f"{un['angle_to_normalised_deg']:.2g}°"))
print(f"largest change of the point's distance from the origin: "
      f"{100 * un['max_radius_change']:.0f} %")
verdict("tutorial.unnormalised.final_norm", "tutorial.unnormalised.max_point_radius_change")

# %% tags=["hide-input"]
fig, axs = figure(1, 2, height=2.9)
axs[0].plot(res.t, un["norms"], color="#0067A5")
axs[0].set(xlabel="t (s)", ylabel="|Q|", title="norm without normalisation")
axs[1].plot(res.t, un["radius"], color="#E25822", label="computed")
axs[1].axhline(1.0, color="k", ls=":", lw=1, label="should stay 1")
axs[1].set(xlabel="t (s)", ylabel="|P| / |P₀|", title="rotated point, raw quatern2rotMat")
axs[1].legend(loc="upper left")
plt.show()

# %% [markdown]
# ## 4. What a gyroscope measures, and drift
# **"A gyroscope measures the angular acceleration … by integrating twice …"** The tutorial
# opens with that claim, then assumes velocities "to avoid a double integration". A simulator
# cannot settle what a gyroscope measures (it would only return its own definition), so we use
# real hardware: the x-IMU3 recording shipped with imunav, whose onboard fusion (gyro *and*
# accelerometer) gives the device's own orientation. Over half-second windows, integrate the
# gyro output once (as an angular velocity) and twice (as an angular acceleration) and compare
# each with the rotation the device reports:

# %%
real = T.gyro_is_rate_real()
print(f"{real['windows']} windows of {real['window_s']} s; the device turns by "
      f"{real['device_turn_deg']:.0f}° (median)")
print(f"gyro integrated once  (rate):         median error {real['as_rate_error_deg']:.1f}°")
print(f"gyro integrated twice (acceleration): median error {real['as_acceleration_error_deg']:.1f}°")
verdict("tutorial.claim.gyro_measures_angular_acceleration")

# %% [markdown]
# Read as a rate, the gyro follows the device within a few degrees; read as an acceleration it
# misses by most of the rotation. A gyroscope measures angular *velocity* (rad/s), and
# orientation follows from a *single* integration — as the tutorial's own code does.
#
# **"It don't work properly in practice due to the cumulated errors, this phenomena is called
# drift."** On the longer x-IMU recording, the gyro integrated alone from the device's own
# orientation, compared with that orientation at the end of windows of growing length:

# %%
dr = T.drift_real()
for w, e in zip(dr["windows_s"], dr["median_error_deg"], strict=True):
    print(f"window {w:5.1f} s: median error {e:5.1f}°")
print(f"growth ∝ window^{dr['growth_exponent']:.2f} (x-IMU, {dr['duration_s']:.0f} s at "
      f"{dr['rate_hz']:.0f} Hz, raw gyro)")
verdict("tutorial.claim.drift")

# %% tags=["hide-input"]
fig, ax = figure(1, 1, width=4.6, height=3.0)
ax.loglog(dr["windows_s"], dr["median_error_deg"], "o-", color="#E25822",
          label="gyro alone vs the device")
ax.set(xlabel="integration window (s)", ylabel="median angle error (°)",
       title="a real gyro integrated alone drifts")
ax.set_xticks(dr["windows_s"], [f"{w:g}" for w in dr["windows_s"]])
ax.minorticks_off()
ax.legend(loc="upper left")
plt.show()

# %% [markdown]
# The drift grows steadily with the time integrated, without bound: nothing in the gyro's own
# signal can tell its errors from a real turn (notebook 07 removes the gyro's bias from a
# still stretch and measures what is left). It is the reason every real system aids the gyro
# with something absolute — gravity, a magnetometer, GNSS.
#
# ## 5. Explore: the step
# The widget below (in a live kernel) sets the step, the two rates and the update. A reader of
# the book cannot move it, so here is its first parameter swept: the first-order error over the
# example's 49.5 s for four steps.

# %%
STEPS = (0.5, 0.25, 0.125, 0.0625)
sweep = {dt: (T.run(dt, duration=49.5).t, T.angle_error(dt, duration=49.5)) for dt in STEPS}
for dt, (_, e) in sweep.items():
    print(f"dt = {dt:6.4f} s: final error {np.degrees(e[-1]):.4f}°")

# %% tags=["hide-input"]
fig, axs = figure(2, 2, height=4.4, sharex=True)
for ax, (dt, (t, e)) in zip(axs.flat, sweep.items(), strict=True):
    ax.plot(t, np.degrees(e), color=style("increments/first_order")["color"])
    ax.set_title(f"dt = {dt:g} s")
for ax in axs[-1]:
    ax.set_xlabel("t (s)")
for ax in axs[:, 0]:
    ax.set_ylabel("first-order error (°)")
fig.suptitle("the tutorial's example: first-order + normalise vs the exact rotation")
plt.show()


# %%
# NBVAL_IGNORE_OUTPUT
def explore(dt=0.5, rate_x=np.pi / 8, rate_y=np.pi / 16, update="first_order"):
    r = T.run(dt, rate_x=rate_x, rate_y=rate_y, update=update, duration=49.5)
    e = T.angle_error(dt, duration=49.5, rate_x=rate_x, rate_y=rate_y)
    fig = plt.figure(figsize=(6.5, 3.2), layout="constrained")
    T.plot_run(r, fig.add_subplot(1, 2, 1, projection="3d"), T.UPDATE_NAMES[update])
    ax = fig.add_subplot(1, 2, 2)
    ax.plot(r.t, np.degrees(e), color=style("increments/first_order")["color"])
    ax.set(xlabel="t (s)", ylabel="first-order error (°)", title=f"dt = {dt:.3g} s")
    plt.show()


_ = interact(explore,
             dt=FloatLogSlider(value=0.5, base=10, min=-2, max=0, continuous_update=False,
                               description="dt (s)"),
             rate_x=FloatSlider(value=np.pi / 8, min=0.01, max=2, step=0.01,
                                continuous_update=False, description="ω about X"),
             rate_y=FloatSlider(value=np.pi / 16, min=0.01, max=2, step=0.01,
                                continuous_update=False, description="ω about Y"),
             update=Dropdown(options=[(T.UPDATE_NAMES[u], u) for u in T.UPDATES],
                             description="update"))

# %% [markdown]
# ### Checks: this notebook's numbers are the ledger's

# %%
print(f"{np.degrees(err[-1]):.3f}")
assert np.abs(Q_fo - res.Q).max() < 1e-12 and np.abs(Q_ex - res_exact.Q).max() < 1e-12
assert np.isclose(LEDGER["tutorial.final_angle_error_first_order_deg"]["imunav"],
                  np.degrees(err[-1]), rtol=1e-9)
assert np.isclose(LEDGER["tutorial.update_order_in_dt"]["imunav"], order, rtol=1e-9)
assert np.isclose(LEDGER["tutorial.claim.drift"]["imunav"], dr["median_error_deg"][-1], rtol=1e-9)
assert (sch["x_s"], sch["y_s"]) == (LEDGER["tutorial.schedule.x_rotation_s"]["imunav"],
                                    LEDGER["tutorial.schedule.y_rotation_s"]["imunav"])
assert abs(un["final_norm"] / un["closed_form_norm"] - 1) < 1e-12
assert real["as_acceleration_error_deg"] > 5 * real["as_rate_error_deg"]

# %% [markdown]
# ## Takeaways
#
# - The first-order update is a dozen lines; normalising it keeps the quaternion a rotation,
#   and without normalisation everything downstream that assumes a unit quaternion goes wrong.
# - Against the exact rotation its error is second order in the step for a rate of fixed
#   direction: halving the step quarters it.
# - A gyroscope measures angular velocity: integrated once it follows a real device, integrated
#   twice it does not. Integrated alone it drifts, steadily, with time — why real systems aid it.
# - Count the loop, not the comments: the example runs 99 steps, not 100.
#
# ## Exercises
#
# **Exercise 1.** Show with `tutorial_loop` that one first-order normalised step about a fixed
# axis turns by $2\arctan(\lvert\omega\rvert\Delta t/2)$: run the loop for one step with
# ω = π/8 rad/s about X and dt = 0.5 s.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
Q1 = tutorial_loop(dt=0.5, last=2)[-1]
turned = 2 * np.arctan2(np.linalg.norm(Q1[1:]), Q1[0])
print(f"turned {turned:.10f} rad, 2 arctan(|ω|dt/2) = {2 * np.arctan(np.pi / 8 * 0.5 / 2):.10f}")
assert abs(turned - 2 * np.arctan(np.pi / 8 * 0.5 / 2)) < 1e-14

# %% [markdown]
# **Exercise 2.** Each first-order normalised step about a fixed axis turns by
# $2\arctan(\lvert\omega\rvert\Delta t/2)$ (Exercise 1). Build the example's first-order result
# as one rotation about X (48 such steps at π/8 rad/s) followed by one about Y (51 at π/16 rad/s,
# dt = 0.5 s), and compare its angle to the exact rotation with the computed final error. Is the
# error the sum of the two phases' deficits?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
from imunav.core.rotations import quat_exp, quat_mul  # noqa: E402

a1, a2 = np.pi / 8 * 0.5, np.pi / 16 * 0.5
fo = quat_mul(quat_exp([48 * 2 * np.arctan(a1 / 2), 0, 0]), quat_exp([0, 51 * 2 * np.arctan(a2 / 2), 0]))
ex = quat_mul(quat_exp([48 * a1, 0, 0]), quat_exp([0, 51 * a2, 0]))
deficits = 48 * (a1 - 2 * np.arctan(a1 / 2)) + 51 * (a2 - 2 * np.arctan(a2 / 2))
print(f"composed {np.degrees(quat_angle(fo, ex)):.4f}°, computed {np.degrees(err[-1]):.4f}°, "
      f"sum of the deficits {np.degrees(deficits):.4f}°")
# The deficits are about different axes (X, then Y): rotations compose, they do not add.
assert abs(quat_angle(fo, ex) - err[-1]) < 1e-12 and deficits > 1.05 * err[-1]


# %% [markdown]
# **Exercise 3.** Without normalisation, how large would the norm be after the example with
# dt = 0.05 s (same 49.5 s)? Use the closed form, then check with `T.unnormalised`.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
u = T.unnormalised(dt=0.05, steps=991, switch=482)
closed = np.sqrt(1 + (np.pi / 8 * 0.05 / 2) ** 2) ** 480 * np.sqrt(1 + (np.pi / 16 * 0.05 / 2) ** 2) ** 510
print(f"|Q| = {u['final_norm']:.6f}, closed form {closed:.6f}")
assert abs(u["final_norm"] / closed - 1) < 1e-12
