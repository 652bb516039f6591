# %% [markdown]
# # imunav quickstart: prescribe a motion, simulate an ideal IMU, navigate back
#
# **Reading order.** The notebooks are numbered in the order they were written, not the order
# to read them. Read the tools first, then the question most readers bring (is my IMU good
# enough?), then real data and the wider world, and the paper forensics last — they take the
# rest for granted and argue with a paper line by line:
#
# - notebook 00, this quickstart: a motion, an ideal IMU, navigation back, the error;
# - notebook 05, applicability: sensor errors, the covariance analysis, a verdict for an IMU
#   and a motion;
# - notebook 06, the strapdown algorithms: coning, sculling, the orders of the family;
# - notebook 03, a tutorial on integrating gyro rates into a quaternion (it needs nothing but
#   quaternions: read it first if that is new to you);
# - notebooks 07 and 08, real data: what recorded IMUs drift, and motion from captured poses;
# - notebook 09, the rotating WGS-84 Earth;
# - notebook 10, aided navigation: GNSS, zero-velocity updates, the Kalman filter and smoother;
# - notebook 11, real recordings with truth: a car's GNSS outages against withheld RTK fixes,
#   foot-mounted walks against motion capture;
# - notebooks 01, 02 and 04, three papers reproduced claim by claim (Marusenkova; Plaksiy and
#   Homozkova; Dickson and Rae).
#
# ## What you will learn
#
# - how a motion is written as analytic laws, and what an ideal IMU measures along it (the
#   body rate $\omega_b$ and the specific force $f_b$);
# - how a strapdown algorithm turns those measurements back into attitude, velocity and
#   position, and how to measure its error against the exact truth;
# - why the error falls with the sample rate at a rate set by the algorithm's *order*, and which
#   algorithms reach the rounding floor on a smooth motion.
#
# **What you should know first:** Python with NumPy; what a rotation (quaternion or rotation
# matrix) does to a vector. Nothing about inertial navigation.
#
# **Scope.** Everything here is on a flat, non-rotating Earth with constant gravity, and the IMU
# is ideal and unaided: the errors you will see are those of the *algorithms* alone. A real
# IMU adds sensor errors that dwarf them (notebook 05), and on the real Earth its rotation and
# the curvature add terms this model leaves out — read the numbers below as the floor that
# integration itself sets, not as what a device achieves.
#
# Conventions (the same everywhere in imunav): navigation frame **NED** (north, east, down)
# with gravity $g_n = [0, 0, +g]$; scalar-first Hamilton quaternions $q_{nb}$ with
# $v_n = q \otimes v_b \otimes q^*$; Euler angles yaw ψ, pitch θ, roll φ, intrinsic Z-Y-X. The
# gyro measures the body rate $\omega_b$, the accelerometer the specific force
# $f_b = C_{bn}(a_n - g_n)$. For a rotation vector $\boldsymbol\phi$ (axis × angle) we write
# $\exp(\boldsymbol\phi) = [\cos\frac{|\boldsymbol\phi|}{2},\ \sin\frac{|\boldsymbol\phi|}{2}\,
# \boldsymbol\phi/|\boldsymbol\phi|]$ for its unit quaternion (the quaternion exponential of
# the pure quaternion $\frac12\boldsymbol\phi$), so that $q \otimes \exp(\boldsymbol\phi)$ turns
# $q$ further by $\boldsymbol\phi$ in body axes; every notebook of the book uses this notation.
# All computation lives in `imunav`; this notebook calls, prints and plots.

# %%
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown
from ipywidgets import Dropdown, FloatLogSlider, interact

import imunav
from imunav import Motion, nav_errors, navigate, plotting, simulate_imu
from imunav.analysis import roundtrip as rt
from imunav.analysis.family import fmt_err
from imunav.plotting import name, styled

plotting.use_book_style()
SEED = 0  # nothing here is random; every notebook sets one seed in its first cell
np.set_printoptions(precision=6, suppress=False)
# One rounding floor for the whole notebook: below these, an error is double-precision
# rounding (orders are fitted above them, tables and figures show "<floor").
FLOOR_M, FLOOR_DEG = rt.FLOOR_POS, float(np.degrees(rt.FLOOR_ATT))
print(f"rounding floor: {FLOOR_M:g} m in position, {rt.FLOOR_ATT:g} rad "
      f"({FLOOR_DEG:.0e}°) in attitude")

# %% [markdown]
# ## 1. A motion from analytic laws
# Position laws in metres (NED), attitude laws in radians. The simulator differentiates them
# exactly (SymPy), so the body rate is known in closed form:

# %%
motion = Motion(
    x="10*sin(0.3*t)", y="5*sin(0.6*t)", z="-0.05*t**2",
    yaw="0.8*sin(0.25*t) + 0.1*t", pitch="0.3*sin(0.7*t)", roll="0.5*sin(1.1*t)",
    duration=20.0,
)
for sym, expr in zip("ω_x ω_y ω_z".split(), motion.expressions["angular_rate"], strict=True):
    print(f"{sym}(t) = {expr}")

# %% [markdown]
# At rest and level the accelerometer reads $[0, 0, -g]$: it measures the reaction to
# gravity, not gravity. Rolled by an angle φ it reads $[0, -g\sin\varphi, -g\cos\varphi]$:

# %%
roll_deg = 30
print("level:      ", simulate_imu(Motion(), 10, 1.0).accel[0], "m/s²")
print(f"rolled {roll_deg}°:", simulate_imu(Motion(roll=f"{roll_deg}*pi/180"), 10, 1.0).accel[0],
      "m/s²")

# %% [markdown]
# ## 2. Simulate and navigate
# An IMU can output *rate samples* (ω and f at each instant) or *increments*: the exact
# integrals $\Delta\theta = \int\omega_b\,dt$ and $\Delta v = \int f_b\,dt$ over each sample
# interval, which is what a good IMU delivers. `navigate` integrates them back from the
# initial state with the default algorithm for increments, an 8-node polynomial fit with a
# sixth-order Magnus step (registry id `poly8_m6`; notebook 06 explains the family).

# %%
sig = simulate_imu(motion, rate=100.0, kind="increments")
t0 = np.array([0.0])
nav = navigate(sig, motion.attitude(t0)[0], motion.velocity(t0)[0], motion.position(t0)[0])
err = nav_errors(nav, motion)
print(f"{len(sig)} increments at {sig.rate:g} Hz, algorithm: {name(nav.algorithm)} (the default)")
print(f"max position error  {fmt_err(err.position.max(), FLOOR_M)} m")
print(f"max velocity error  {err.velocity.max():.1e} m/s")
print(f"max attitude error  {fmt_err(np.degrees(err.attitude.max()), FLOOR_DEG)} deg")
print("(\"<\" marks the rounding floor: the ideal signals are integrated back essentially "
      "exactly)")

# %% tags=["hide-input"]
res = rt.round_trip(motion, rate=100.0, kind="increments")
plotting.plot_run(res)
plt.show()

# %% [markdown]
# The navigated path lies on the truth; the error norms below it sit at the rounding level of
# double precision, growing slowly as rounding accumulates.
#
# ## 3. Every algorithm at several rates
# An algorithm of order $p$ makes a global error proportional to $h^p$, $h$ the sample
# interval: halve the step and the error falls by $2^p$. The table gives each algorithm's
# maximum error at four rates and the order fitted to them (only on errors above the rounding
# floor; "—" where fewer than three rates are above it). Rows are named in words, as in the
# figure under the table; "(rates)" marks the algorithms that read rate samples, the others
# read increments. The *mean-rate exponential* turns the attitude by $\exp(\bar\omega h)$, the
# step's mean rate: exact only for a constant rate, second order otherwise. The *first-order
# update* $q + \frac12 q\otimes\omega\,h$ uses the rate at one instant of each interval (its
# start), which makes it first order here; notebook 03 applies the same update to a rate held
# constant over each step, where it measures order 2.

# %%
rates = (50, 100, 200, 400)
rows = rt.error_table(motion, rates)
print(f"{'algorithm':34s}" + "".join(f"{r:>10d} Hz" for r in rates) + "   order")


def _o(x):
    return "  —" if x is None else f"{x:.1f}"


print("max position error (m)")
for row in rows:
    cells = "".join(fmt_err(row[f"pos_{r}"], FLOOR_M, 13) for r in rates)
    print(f"{name(row['kind'] + '/' + row['algorithm']):34s}{cells}   {_o(row['order_pos'])}")
print("max attitude error (deg)")
for row in rows:
    cells = "".join(fmt_err(np.degrees(row[f"att_{r}"]), FLOOR_DEG, 13) for r in rates)
    print(f"{name(row['kind'] + '/' + row['algorithm']):34s}{cells}   {_o(row['order_att'])}")

# %% tags=["hide-input"]
by = {f"{r['kind']}/{r['algorithm']}": r for r in rows}


def first_floor_rate(row, key, floor):
    """The lowest rate from which the error stays below ``floor``, or None."""
    below = [r for r in rates if all(row[f"{key}_{s}"] < floor for s in rates if s >= r)]
    return below[0] if below else None


lines = []
for i in ("increments/poly8_m6", "rates/magnus6", "increments/poly6_m4", "rates/magnus4"):
    rp = first_floor_rate(by[i], "pos", FLOOR_M)
    ra = first_floor_rate(by[i], "att", rt.FLOOR_ATT)
    reach = (f"below the rounding floor from {rp} Hz in position and from "
             f"{ra} Hz in attitude" if rp and ra else
             f"below the floor in position from {rp} Hz, but not in attitude up to 400 Hz"
             if rp else "above the rounding floor at every rate up to 400 Hz")
    lines.append(f"- **{name(i)}**: {reach}; at 100 Hz "
                 f"{fmt_err(by[i]['pos_100'], FLOOR_M).strip()} m and "
                 f"{fmt_err(np.degrees(by[i]['att_100']), FLOOR_DEG).strip()}°.")
fo = by["rates/first_order"]
classic = ("increments/coning2", "increments/ignagni2", "increments/miller3",
           "increments/ignagni3", "increments/ignagni4")
Markdown("\n".join(lines) + f"\n- **{name('rates/first_order')}** (the textbook "
         f"$q + \\frac12 q\\otimes\\omega\\,h$) is still {fo['pos_400']:.1f} m off after "
         f"{motion.duration:g} s at 400 Hz: order {fo['order_pos']:.1f}.\n"
         f"- The classic coning algorithms ({', '.join(name(i) for i in classic)}) correct the "
         f"attitude to order {min(by[i]['order_att'] for i in classic):.1f}, but share one "
         f"second-order velocity and position scheme: their position errors coincide "
         f"({by['increments/coning2']['pos_100']:.1e} m at 100 Hz, order "
         f"{by['increments/coning2']['order_pos']:.1f}).")

# %% tags=["hide-input"]
plotting.plot_error_vs_rate(rows, rates, floors=(FLOOR_M, FLOOR_DEG))
plt.show()

# %% [markdown]
# Only offline high-order algorithms (they use samples on both sides of each interval) reach
# the floor on this motion — the two sixth-order ones soonest — and not every one of them: the
# fourth-order Magnus integrator on rate samples stays above it up to 400 Hz. Notebook 06
# compares the family on motions designed to stress them (coning, sculling).
#
# ## 4. The sample rate, swept
# The figure a slider would show, at four rates side by side: the attitude error of a
# first-order rate integration, the two-sample coning algorithm and the default, against time.

# %% tags=["hide-input"]
sweep_rates = (25, 50, 100, 200)
compare = [("rates", "first_order"), ("increments", "coning2"), ("increments", "poly8_m6")]
fig, axs = plotting.figure(2, 2, height=4.8, sharex=True, sharey=True)
for ax, r in zip(axs.flat, sweep_rates, strict=True):
    plotting.plot_error_vs_time(motion, r, compare, ax=ax)
    ax.set_title(f"{r} Hz")
    ax.label_outer()
fig.legend(*axs[0, 0].get_legend_handles_labels(), loc="outside lower center", ncols=3)
plt.show()

# %% [markdown]
# With a kernel, pick any rate and algorithm: the widget under the next figure redraws it when
# the slider is released. Its starting state, drawn below, is one the figures above leave out:
# the position and attitude errors over time of the fourth-order Magnus integrator on rate
# samples — the one high-order algorithm the table left above the rounding floor — at 30 Hz.

# %% tags=["hide-input"]
choices = {f"{name(f'{k}/{n}')}": f"{k}/{n}" for k, table in imunav.ALGORITHMS.items()
           for n in table}


def explore(rate=30.0, algorithm="rates/magnus4"):
    kind, alg = algorithm.split("/")
    fig, axs = plotting.figure(1, 2, height=2.8)
    e = rt.round_trip(motion, rate=rate, kind=kind, algorithm=alg).errors
    axs[0].semilogy(e.t[1:], np.maximum(e.position[1:], 1e-16), **styled(algorithm))
    axs[0].set(xlabel="t (s)", ylabel="position error (m)")
    axs[1].semilogy(e.t[1:], np.maximum(np.degrees(e.attitude[1:]), 1e-16), **styled(algorithm))
    axs[1].set(xlabel="t (s)", ylabel="attitude error (deg)")
    fig.suptitle(f"{name(algorithm)} at {rate:.3g} Hz")
    plt.show()


explore()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(explore,
             rate=FloatLogSlider(value=30, base=10, min=1, max=3, step=0.05,
                                 continuous_update=False, description="rate (Hz)"),
             algorithm=Dropdown(options=choices, value="rates/magnus4",
                                description="algorithm"))

# %% [markdown]
# ## Takeaways
#
# - An ideal IMU along an analytic motion gives signals whose integral is known exactly, so
#   the navigation error measures the algorithm alone.
# - The error of an algorithm of order $p$ falls as $h^p$: at order 2, doubling the rate buys a
#   factor $2^2$; at order 6, a factor $2^6$ — until double-precision rounding is reached.
# - Increments (integrals over each interval) carry more than rate samples: the offline
#   fourth-order fit on increments is far more accurate than the fourth-order Magnus
#   integrator on rate samples, and the best increment algorithm integrates this motion to
#   rounding already at 50 Hz.
# - The default algorithm for increments is the 8-node fit with a sixth-order Magnus step;
#   for rates, the sixth-order Magnus integrator.
#
# ## Exercises
#
# **Exercise 1.** The two-sample coning algorithm has attitude order 3. By what factor should
# its maximum attitude error fall from 100 Hz to 200 Hz? Check it against the table.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
c2 = by["increments/coning2"]
factor = c2["att_100"] / c2["att_200"]
print(f"expected 2³ = 8; measured {factor:.2f}")
assert abs(factor - 8) < 0.5

# %% [markdown]
# **Exercise 2.** Make the roll four times faster (`roll="0.5*sin(4.4*t)"`, the rest
# unchanged). At which of 50, 100, 200 and 400 Hz does the default algorithm first keep the
# attitude error below the rounding floor printed at the top?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
fast = Motion(x="10*sin(0.3*t)", y="5*sin(0.6*t)", z="-0.05*t**2",
              yaw="0.8*sin(0.25*t) + 0.1*t", pitch="0.3*sin(0.7*t)", roll="0.5*sin(4.4*t)",
              duration=20.0)
att = {r: np.degrees(rt.round_trip(fast, r, "increments").errors.attitude.max()) for r in rates}
print({r: f"{a:.1e}" for r, a in att.items()})
first = next(r for r in rates if att[r] < FLOOR_DEG)
print(f"first below the floor ({FLOOR_DEG:.0e}°): {first} Hz")
assert all(att[r] < FLOOR_DEG for r in rates if r >= first)             # and it stays below
assert first > rates[0] and att[rates[0]] > by["increments/poly8_m6"]["att_50"]   # faster: harder

# %% tags=["hide-cell"] jupyter={"source_hidden": true}
# Checks (run by the tests, not part of the lesson): the headline numbers above.
order = {(r["kind"], r["algorithm"]): r["order_att"] for r in rows}
print({k: None if v is None else round(v) for k, v in order.items()})
assert err.position.max() < 1e-9 and err.attitude.max() < 1e-12
assert np.isclose(order["rates", "magnus4"], 4, atol=0.3)
assert np.isclose(order["increments", "coning2"], 3, atol=0.3)
assert by["rates/magnus4"]["pos_100"] > 1e-8          # the fourth-order method is not at rounding
