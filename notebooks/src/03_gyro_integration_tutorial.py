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
# - what a gyroscope measures — settled by the units its data are in, and checked on real
#   hardware — and what "drift" is: the angle an integrated gyro turns by while the body
#   does not, measured on a still stretch of a real recording and on a simulated gyro.
#
# **What you should know first:** what a unit quaternion is and how $q\otimes v\otimes q^*$
# rotates a vector; a little NumPy. Nothing else.
#
# **Scope.** The tutorial's example is a pure rotation in its own frame: no gravity, no
# Earth rotation, no aiding. The real recording of §4 is short, on a bench: over it the
# Earth's rotation is far below the gyro's own errors.
#
# **Conventions.** The tutorial's own (rad, rad/s, s; its x, y, z); angles are printed in
# degrees where it helps and say so. Computation: `imunav.papers.tutorial`; the loop itself is
# written out in §1 and checked against it.

# %% [markdown]
# ## The tutorial in brief, and what this notebook finds
#
# - **What it does.** It integrates constant gyro rates with the first-order quaternion
#   update, normalises, and draws a rotated point. The code does what it says, and §1 writes
#   it out line for line.
# - **What holds.** Normalising is needed (§3); the update's error against the exact rotation
#   falls with the step, second order here (§2); a gyro integrated alone drifts (§4).
# - **What does not.** The text says the example runs 50 s, 25 s about each axis; the loop runs
#   fewer steps than its comments say (§1). And its first sentence — a gyroscope "measures the
#   angular acceleration" — is wrong: it measures angular velocity (§4).
#
# Every statement with its record in the ledger `figures/reproduction.json` and its verdict is
# tabulated in §6, at the end.

# %%
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown, display
from ipywidgets import Dropdown, FloatLogSlider, FloatSlider, interact

from imunav.core.rotations import quat_angle
from imunav.papers import records as R
from imunav.papers import tutorial as T
from imunav.plotting import figure, thing_style, use_book_style

use_book_style()
SEED = 0  # nothing here is random
LEDGER = R.load()


def say(text):
    """Show a generated sentence (its numbers come from the computation above it)."""
    display(Markdown(text))


def verdict(*ids):
    display(Markdown("\n\n".join(R.verdict_line(i, LEDGER) for i in ids)))


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
fig = plt.figure(figsize=(6.5, 3.7), layout="constrained")
ax3 = T.plot_run(res, fig.add_subplot(1, 2, 1, projection="3d"), "first-order + normalise\n(as written)")
T.plot_run(res_exact, fig.add_subplot(1, 2, 2, projection="3d"), "exact rotation")
fig.legend(*ax3.get_legend_handles_labels(), loc="outside lower center", ncols=4, markerscale=3)
plt.show()

# %% tags=["hide-input"]
P_gap = np.linalg.norm(res.P - res_exact.P, axis=1)
say(f"The key: the black dots are the point P = (1, 2, 3), the red, green and blue dots three "
    f"markers one unit from it along its x, y and z axes, joined to it every third step. The two "
    f"panels look the same because they nearly are: the first-order attitude ends "
    f"{np.degrees(quat_angle(Q_fo[-1], Q_ex[-1])):.2f}° from the exact one, which moves P by at "
    f"most {P_gap.max():.3f} (P is {np.linalg.norm(T.P0):.2f} from the origin) — less than a dot "
    f"at this scale. §2 plots the difference itself.")

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
axs[0].plot(res.t, np.degrees(err), color=thing_style("increments/first_order")["color"])
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
# **Why is the "first-order" update second order here, and first order in notebook 00?**
# "First order" names the update: it keeps the first power of Δt of the exponential
# $\exp(\tfrac12\omega\Delta t)$. Its accuracy order also depends on what the rate does
# within a step. Here the rate is *constant over each step* (the tutorial's $S_\omega$ is
# piecewise constant), so the only error is the update's own per-step deficit
# $\propto\Delta t^3$: $\Delta t^2$ in all. In notebook 00 the update is fed *samples* of a
# rate that varies within the step: using $\omega(t_k)$ for the whole step (a left-point rule)
# misses $\tfrac12\dot\omega\,\Delta t^2$ per step, $\Delta t$ in all — whatever the update,
# even the exact rotation by $\omega(t_k)\Delta t$. About a fixed axis, with the tutorial's
# rate made to vary, $\omega(t) = r\,(1 + \tfrac12\sin t)$, and the true angle
# $r\,(t + \tfrac12(1-\cos t))$ in closed form:

# %%
os_ = T.order_with_sampled_rate()
for key, label in (("constant_first_order", "first-order + normalise, rate constant over the step"),
                   ("sampled_first_order", "first-order + normalise, rate sampled at the step's start"),
                   ("sampled_exponential", "exact rotation by the sampled rate × dt")):
    errs_ = ", ".join(f"{e:.1e}" for e in os_[key]["final_error_rad"])
    print(f"{label:58s}: order {os_[key]['order']:.2f}  (final error, rad: {errs_})")
print("dt (s):", ", ".join(f"{d:g}" for d in os_["dts"]))
e_s = os_["sampled_first_order"]["final_error_rad"]
local = np.log(e_s[-2] / e_s[-1]) / np.log(os_["dts"][-2] / os_["dts"][-1])
print(f"sampled first-order, order between the two smallest steps: {local:.2f}")

# %% tags=["hide-input"]
say(f"With the rate constant over each step the first-order update converges at order "
    f"{os_['constant_first_order']['order']:.2f}; fed the samples of a varying rate, at order "
    f"{os_['sampled_first_order']['order']:.2f} over these steps ({local:.2f} between the two "
    f"smallest: the update's own Δt² part fades, the sampling's Δt stays) — and the exact rotation of the same samples at "
    f"{os_['sampled_exponential']['order']:.2f}: the first order comes from sampling the rate, not "
    f"from the update. Notebook 00's rate samples are the second case.")

# %% [markdown]
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
# cannot settle what a gyroscope measures (it would only return its own definition), and
# comparing a once- with a twice-integrated signal would compare an angle with an angle times
# a second. The units settle it. A gyro's data sheet and its data state the unit of its
# output; the two recordings shipped with imunav (the manufacturer's own export) head their
# gyro columns:

# %%
for dev, cols in T.gyro_units_real().items():
    print(f"{dev:6s}: {', '.join(cols)}")

# %% [markdown]
# Degrees per second is an angular *velocity*: integrated once over time it is an angle —
# exactly what the tutorial's own code does. An angular acceleration would be in deg/s² and
# would need two integrations. The data agree with their unit: over half-second windows of the
# x-IMU3 recording, the gyro integrated once follows the rotation the device's own orientation
# (its onboard fusion, which also uses the accelerometer) reports:

# %%
real = T.gyro_is_rate_real()
print(f"{real['windows']} windows of {real['window_s']} s; the device turns by "
      f"{real['device_turn_deg']:.0f}° (median)")
print(f"gyro integrated once, as deg/s: median error {real['as_rate_error_deg']:.1f}°")
verdict("tutorial.claim.gyro_measures_angular_acceleration")

# %% [markdown]
# **"It don't work properly in practice due to the cumulated errors, this phenomena is called
# drift."** Drift is what an integrated gyro turns by while the body does not. Measuring it
# needs a truth that does not itself come from the gyro: the x-IMU's fused orientation does not
# qualify (it blends gyro, accelerometer and magnetometer; notebook 07), but *stillness* does —
# a body at rest keeps its attitude. Two measurements:
#
# - **Real.** The x-IMU3 recording starts with the device at rest (its first still stretch:
#   small gyro spread, |f| close to g). Integrate the raw gyro alone over it.
# - **Simulated.** A still body, a gyro with data-sheet errors (the BMI088 preset's turn-on
#   offset and rate noise density), a hundred seeds: once as shipped, once with the offset
#   calibrated out, to see each error's own growth.

# %%
still = T.drift_still_real()
print(f"x-IMU3, still for {still['duration_s']:.2f} s (mean |f| = {still['accel_over_g']:.4f} g): "
      f"the integrated gyro turns by {still['final_deg']:.3f}° (at most {still['max_deg']:.3f}°)")
print(f"its mean rate over the stretch (a bias): {still['bias_deg_s']:.3f}°/s; the device's fused "
      f"orientation moves {still['device_change_deg']:.2f}° meanwhile")
sim = T.drift_simulated()
print(f"simulated gyro {sim['gyro']}, median of {sim['runs']} seeds at {sim['rate_hz']:g} Hz:")
print(f"{'t (s)':>6s}  {'as shipped (°)':>14s}  {'offset removed (°)':>18s}")
for t_, a_, b_ in zip(sim["times_s"], sim["as_shipped"]["median_deg"],
                      sim["bias_removed"]["median_deg"], strict=True):
    print(f"{t_:6g}  {a_:14.3f}  {b_:18.4f}")
print(f"growth ∝ t^p: p = {sim['as_shipped']['exponent']:.2f} as shipped, "
      f"{sim['bias_removed']['exponent']:.2f} with the offset removed")
verdict("tutorial.claim.drift")

# %% tags=["hide-input"]
fig, axs = figure(1, 2, height=3.1)
c_ship, c_noise = "#E25822", "#0067A5"
axs[0].plot(still["t"], still["angle_deg"], color=c_ship, label="gyro integrated alone")
axs[0].plot(still["t"], still["bias_deg_s"] * still["t"], "k:", lw=1, label="mean rate × t")
axs[0].set(xlabel="t (s)", ylabel="angle turned (°)", title="x-IMU3 at rest (real)")
axs[0].legend(loc="upper left")
ts = np.asarray(sim["times_s"])
for key, col, lab in (("as_shipped", c_ship, "as shipped"), ("bias_removed", c_noise,
                                                              "offset removed")):
    axs[1].loglog(ts, sim[key]["median_deg"], "o-", color=col,
                  label=f"{lab}: ∝ t^{sim[key]['exponent']:.2f}")
for p_, key, ls in ((1.0, "as_shipped", "--"), (0.5, "bias_removed", ":")):
    ref = 3 * sim[key]["median_deg"][0] * (ts / ts[0]) ** p_      # 3× above: off the curve
    axs[1].loglog(ts, ref, color="k", ls=ls, lw=1, label=f"guide ∝ t^{p_:g} (×3 above)")
axs[1].set_xticks(ts, [f"{t_:g}" for t_ in ts])
dec = 10.0 ** np.arange(-2, 5)
axs[1].set_yticks(dec, [f"{d:g}" for d in dec])
axs[1].minorticks_off()
axs[1].set(xlabel="t (s)", ylabel="median drift (°)", title="still body, simulated gyro",
           ylim=(0.01, 3e4))                               # room above the curves for the key
axs[1].legend(loc="upper left")
plt.show()

# %% tags=["hide-input"]
say(f"At rest the real gyro turns by {still['final_deg']:.3f}° in {still['duration_s']:.2f} s, "
    f"following its mean rate × t: a bias of {still['bias_deg_s']:.3f}°/s, which integrated alone "
    f"would reach {60 * still['bias_deg_s']:.1f}° in a minute. Meanwhile the fused orientation "
    f"moves {still['device_change_deg']:.2f}°, more than the gyro — one more reason it is no "
    f"gyro-only reference. Simulated, the drift as shipped grows as "
    f"t^{sim['as_shipped']['exponent']:.2f} — the turn-on offset b integrated, b·t — and reaches "
    f"{sim['as_shipped']['median_deg'][-1]:.0f}° after {sim['times_s'][-1]:g} s; with the offset "
    f"removed, as t^{sim['bias_removed']['exponent']:.2f} — white rate noise of density N "
    f"integrated, the angle random walk N√t — and reaches {sim['bias_removed']['median_deg'][-1]:.2f}°.")

# %% [markdown]
# The drift grows with the time integrated, without bound, and nothing in the gyro's own
# signal can tell its errors from a real turn: calibrating the offset out slows it, from ∝ t
# to ∝ √t, but does not stop it (notebook 07 removes a real gyro's bias from a still stretch
# and measures what is left; notebook 05 teaches the Allan variance that separates the two
# terms). It is the reason every real system aids the gyro with something absolute — gravity,
# a magnetometer, GNSS.
#
# ## 5. Explore: the rate
# The widget below (in a live kernel) sets the step, the two rates and the update. A reader of
# the book cannot move it. §2 swept the step already (its figure); here is the rate about X
# swept instead, at the tutorial's dt = 0.5 s and with the rate about Y as written. Each
# normalised step about a fixed axis falls short by $\lvert\omega\rvert\Delta t -
# 2\arctan(\lvert\omega\rvert\Delta t/2) \approx (\lvert\omega\rvert\Delta t)^3/12$ (§2), so
# doubling the rate should multiply the error at the end of the X phase by about 2³:

# %%
RATES_X = (np.pi / 16, np.pi / 8, np.pi / 4, np.pi / 2)
sweep = {w: (T.run(0.5, rate_x=w, duration=49.5).t, T.angle_error(0.5, duration=49.5, rate_x=w))
         for w in RATES_X}
x_end = sch["x_s"]                                     # the switch from X to Y
at_switch = {w: np.degrees(e[np.searchsorted(t, x_end)]) for w, (t, e) in sweep.items()}
for w, a in at_switch.items():
    grow = "" if w == RATES_X[0] else f", × {a / at_switch[w / 2]:.2f} the half rate's"
    print(f"ω about X = π/{np.pi / w:.0f} rad/s: error at t = {x_end:g} s {a:.4f}°{grow}")

# %% tags=["hide-input"]
fig, axs = figure(2, 2, height=4.4, sharex=True)
for ax, (w, (t, e)) in zip(axs.flat, sweep.items(), strict=True):
    ax.plot(t, np.degrees(e), color=thing_style("increments/first_order")["color"])
    ax.set_title(f"ω about X = π/{np.pi / w:.0f} rad/s")
for ax in axs[-1]:
    ax.set_xlabel("t (s)")
for ax in axs[:, 0]:
    ax.set_ylabel("first-order error (°)")
fig.suptitle("the tutorial's example at dt = 0.5 s: first-order + normalise vs the exact "
             "rotation")
plt.show()

# %% [markdown]
# Close to 2³ while a step turns little; less at the fastest rate, where a step turns so far
# that the cubic term alone overstates the deficit. At the slowest rate the Y phase, turning
# as fast (π/16 rad/s as written), adds visibly to the error; beside the faster X phases it is
# negligible.


# %%
# NBVAL_IGNORE_OUTPUT
def explore(dt=0.5, rate_x=np.pi / 8, rate_y=np.pi / 16, update="first_order"):
    r = T.run(dt, rate_x=rate_x, rate_y=rate_y, update=update, duration=49.5)
    e = T.angle_error(dt, duration=49.5, rate_x=rate_x, rate_y=rate_y)
    fig = plt.figure(figsize=(6.5, 3.2), layout="constrained")
    T.plot_run(r, fig.add_subplot(1, 2, 1, projection="3d"), T.UPDATE_NAMES[update])
    ax = fig.add_subplot(1, 2, 2)
    ax.plot(r.t, np.degrees(e), color=thing_style("increments/first_order")["color"])
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
# ## 6. Every statement and its verdict
#
# One row per record of the ledger `figures/reproduction.json` (written by
# `imunav reproduce`), rendered from it — never typed by hand: the tutorial's value, imunav's,
# the record's id and its verdict. The verdict rule is written once, in
# `imunav.papers.records`. The schedule's durations are counted from the loop exactly, so they
# need no tolerance.

# %% tags=["hide-input"]
display(Markdown(R.coverage_table(T.COVERAGE, LEDGER)))

# %% [markdown]
# ## Takeaways
#
# - The first-order update is a dozen lines; normalising it keeps the quaternion a rotation,
#   and without normalisation everything downstream that assumes a unit quaternion goes wrong.
# - Against the exact rotation its error is second order in the step for a rate of fixed
#   direction: halving the step quarters it.
# - "First order" names the update, not its accuracy: with the rate constant over each step it
#   converges at order 2; fed samples of a varying rate, at order 1, whatever the update.
# - A gyroscope measures angular velocity: its data are in deg/s, and integrated once they
#   follow a real device. Integrated alone it drifts even at rest — as t from a bias, as √t
#   from white noise — which is why real systems aid it.
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
# dt = 0.05 s (same 49.5 s, about X for the first 24 s)? First derive the loop's `steps` (its
# last `i`) and `switch` (about X while `i < switch`) for that step — the example's are 100 and
# 50 — then use the closed form, and check with `T.unnormalised`.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
dt3 = 0.05
steps3 = int(round(49.5 / dt3)) + 1       # the loop runs i = 2..steps: 49.5 s of dt3 steps
switch3 = int(round(24.0 / dt3)) + 2      # about X while i < switch: the first 24 s
sch3 = T.schedule(dt3, steps3, switch3)
print(f"steps = {steps3}, switch = {switch3}: {sch3['x_steps']} steps about X ({sch3['x_s']:g} s) "
      f"+ {sch3['y_steps']} about Y ({sch3['y_s']:g} s) = {sch3['total_s']:g} s")
u = T.unnormalised(dt=dt3, steps=steps3, switch=switch3)
closed = (np.sqrt(1 + (np.pi / 8 * dt3 / 2) ** 2) ** sch3["x_steps"]
          * np.sqrt(1 + (np.pi / 16 * dt3 / 2) ** 2) ** sch3["y_steps"])
print(f"|Q| = {u['final_norm']:.6f}, closed form {closed:.6f}")
assert (sch3["x_s"], sch3["y_s"]) == (24.0, 25.5)
assert abs(u["final_norm"] / closed - 1) < 1e-12


# %% tags=["hide-cell"] jupyter={"source_hidden": true}
# Checks (run by the tests, not part of the lesson): this notebook's numbers are the ledger's,
# which `imunav reproduce` wrote; they fail if the two have drifted apart.
print(f"{np.degrees(err[-1]):.3f}")
assert np.abs(Q_fo - res.Q).max() < 1e-12 and np.abs(Q_ex - res_exact.Q).max() < 1e-12
assert np.isclose(LEDGER["tutorial.final_angle_error_first_order_deg"]["imunav"],
                  np.degrees(err[-1]), rtol=1e-9)
assert np.isclose(LEDGER["tutorial.update_order_in_dt"]["imunav"], order, rtol=1e-9)
assert np.isclose(LEDGER["tutorial.claim.drift"]["imunav"], still["final_deg"], rtol=1e-9)
assert np.isclose(LEDGER["tutorial.claim.gyro_measures_angular_acceleration"]["imunav"],
                  real["as_rate_error_deg"], rtol=1e-9)
assert (sch["x_s"], sch["y_s"]) == (LEDGER["tutorial.schedule.x_rotation_s"]["imunav"],
                                    LEDGER["tutorial.schedule.y_rotation_s"]["imunav"])
assert abs(un["final_norm"] / un["closed_form_norm"] - 1) < 1e-12
assert real["as_rate_error_deg"] < 0.15 * real["device_turn_deg"]
assert 0.9 < sim["as_shipped"]["exponent"] < 1.1 and 0.4 < sim["bias_removed"]["exponent"] < 0.6
assert 1.9 < os_["constant_first_order"]["order"] < 2.1 and os_["sampled_exponential"]["order"] < 1.1
