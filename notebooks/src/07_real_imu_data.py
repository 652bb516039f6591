# %% [markdown]
# # Real IMU recordings: x-IMU3 and x-IMU
#
# ## What you will learn
#
# - how to find out, from the data, what a device's stored quaternion means (element order,
#   and which frame it rotates into which);
# - how far a gyro-only integration gets from the device's own sensor fusion over short
#   windows, and why the integration update matters at a low sample rate;
# - how to find the stationary stretches of a recording, estimate sensor offsets there, and
#   see what double-integrating the accelerometers does in one second;
# - why a calibration must be judged on data it has not seen.
#
# **What you should know first:** notebook 00 (navigation from increments or rates), and the
# idea of a sensor bias (notebook 05).
#
# **Scope.** Two short recordings from x-io devices (scikit-kinematics test data,
# BSD-3-Clause, shipped in `imunav/data/real_imu`). There is no ground truth: the devices'
# onboard orientation is their own fusion (gyro + accelerometer, + magnetometer on the x-IMU),
# good for checking conventions and short-window gyro integration, not for claiming accuracy.
# The navigation is unaided on a flat, non-rotating Earth; for these MEMS gyros the Earth's
# rotation is far below the offsets they show at rest (printed in §3), so it changes nothing
# here. Computation: `imunav.analysis.recordings` (the readers are in `imunav.io.realdata`).

# %%
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown
from ipywidgets import FloatSlider, interact

from imunav import navigate
from imunav.analysis import recordings as R
from imunav.core.rotations import quat_to_dcm, quat_to_euler
from imunav.earth import OMEGA_E as OMEGA_EARTH
from imunav.earth import normal_gravity
from imunav.plotting import figure, name, styled, use_book_style
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.initial import level_attitude

use_book_style()
SEED = 0

# %%
x3 = R.read_ximu3()
x1 = R.read_ximu()
for rec in (x3, x1):
    s = rec.signals
    print(f"{rec.meta['device']:7s}: {len(s)} samples at {s.rate:.2f} Hz, {s.t[-1]:.1f} s; "
          f"|f| at start {np.linalg.norm(s.accel[:20].mean(0)):.3f} m/s²; "
          f"max |ω| {np.degrees(np.abs(s.gyro)).max():.0f}°/s in one axis, "
          f"{np.degrees(np.linalg.norm(s.gyro, axis=1)).max():.0f}°/s in norm, "
          f"{np.degrees(np.linalg.norm(s.gyro, axis=1)).max() / s.rate:.0f}° per sample at most")
    yaw, pitch, roll = np.degrees(quat_to_euler(level_attitude(s.accel[:20], s.g, tol=0.1)))
    print(f"{'':9s}levelled from its first 20 samples: roll {roll:.1f}°, pitch {pitch:.1f}°")

# %% [markdown]
# Both devices read about +g on their z axis when level: their body z axis points **up**
# (imunav's body frame has z down). Nothing needs converting for navigation — the initial
# attitude levelled from the resting accelerometer simply comes out upside down, with a roll
# of about 180° (printed above) — but remember it when reading raw plots.
#
# ## 1. What do the device quaternions mean? (checked, not assumed)
# A stored quaternion $q(t)$ can be read four ways: elements in the order $[w, x, y, z]$ or
# $[x, y, z, w]$, rotating sensor vectors into the earth frame ($q_{nb}$) or the reverse
# ($q_{bn}$). Only the right reading makes the rotation it reports between two times agree
# with the gyro's: for $q_{nb}$ the body-frame relative rotation over a window is
#
# $$ \Delta q = q(t_0)^{*} \otimes q(t_1) \;\approx\; \exp\!\Big(\int_{t_0}^{t_1}\!\boldsymbol\omega_b\,dt\Big)
#    \quad(\text{to first order in the window}), $$
#
# with $\exp$ of a rotation vector as defined in notebook 00 (the half angle is inside it),
#
# and for each reading we compare $\Delta q$ with the gyro's own integral over 2 s windows; the
# median disagreement (deg):

# %%
for rec in (x3, x1):
    c = R.device_quaternion_convention(rec)
    best = min(c, key=c.get)
    print(f"{rec.meta['device']:7s}:", {k: round(v, 1) for k, v in c.items()}, "→", best)

# %% [markdown]
# The x-IMU3 stores $[w, x, y, z]$ rotating sensor vectors into its earth frame (imunav's
# $q_{nb}$); the older x-IMU stores the earth relative to the sensor ($q_{bn}$), as x-io
# documents. `R.device_as_q_nb` applies this.
#
# ## 2. Gyro-only orientation vs the onboard orientation over short windows
# Each window starts from the device's attitude and integrates the gyro alone; the median
# angle to the device attitude at the window's end (deg), for three updates: the first-order
# $q \leftarrow q + \tfrac12 q\otimes\boldsymbol\omega h$, the exponential of the mean rate, and
# the sixth-order Magnus integrator (notebook 06):

# %%
gvd = {}
for rec, start in ((x3, 1.0), (x1, 0.0)):
    for alg in ("first_order", "exact_exponential", "magnus6"):
        gvd[rec.meta["device"], alg] = r = R.gyro_vs_device(rec, algorithm=alg, start=start)
        print(f"{rec.meta['device']:7s} {name('rates/' + alg):32s}", {w: round(v, 2) for w, v in r.items()})

# %% tags=["hide-input"]
d3, d1 = x3.meta["device"], x1.meta["device"]
w = max(gvd[d3, "first_order"])
Markdown(
    f"On the {d3} (shaken hard, sampled at only {x3.signals.rate:.0f} Hz) the first-order update "
    f"is {gvd[d3, 'first_order'][w] / gvd[d3, 'magnus6'][w]:.1f} times as far from the device "
    f"after {w:g} s as the Magnus update ({gvd[d3, 'first_order'][w]:.1f}° vs "
    f"{gvd[d3, 'magnus6'][w]:.1f}°); the remaining {gvd[d3, 'magnus6'][w]:.1f}° is what separates "
    f"a {x3.signals.rate:.0f} Hz gyro integration from the device's fusion. On the {d1} "
    f"({x1.signals.rate:.0f} Hz) the three updates agree with each other to "
    f"{max(abs(gvd[d1, a][w] - gvd[d1, 'magnus6'][w]) for a in ('first_order', 'exact_exponential')):.2f}° "
    f"and drift away from the device as the window grows "
    f"({gvd[d1, 'magnus6'][min(gvd[d1, 'magnus6'])]:.1f}° at {min(gvd[d1, 'magnus6']):g} s, "
    f"{gvd[d1, 'magnus6'][w]:.1f}° at {w:g} s): the device's fusion is correcting its own gyro, "
    "so its orientation is not a gyro-only reference. Read these ratios as rough sizes: each "
    "is a median over the few windows a short recording holds, and on the "
    f"{d3} the distance does not even grow steadily with the window ("
    + ", ".join(f"{v:.1f}° at {k:g} s" for k, v in gvd[d3, "magnus6"].items()) + ").")

# %% [markdown]
# ## 3. Static segments and bias estimation
# A stretch is *static* where, over every 0.5 s window in it, each gyro axis spreads by less
# than 3°/s and $|\boldsymbol f|$ stays within 3 % of $g$. There the sensors' true inputs are
# known — $\boldsymbol\omega_b = 0$ and $\boldsymbol f_b = -C_{bn}\,\boldsymbol g_n$ — so their
# means are the offsets:
#
# $$ \hat{\boldsymbol b}_g = \frac1n\sum_{i}\boldsymbol\omega_i, \qquad
#    \hat{\boldsymbol b}_a = \frac1n\sum_{i}\big(\boldsymbol f_i + C_{bn}\,\boldsymbol g_n\big). $$

# %%
s3 = x3.signals
segs = R.static_segments(s3)
print("x-IMU3 static segments (s):", [(round(a / s3.rate, 2), round(b / s3.rate, 2)) for a, b in segs])
a, b = max(segs, key=lambda ab: ab[1] - ab[0])
bias = s3.gyro[a:b].mean(0)
print("gyro bias over it (deg/s):", np.round(np.degrees(bias), 3))
print(f"largest gyro offset {np.degrees(np.abs(bias).max()) * 3600:.0f} °/h; the Earth's rotation "
      f"{np.degrees(OMEGA_EARTH) * 3600:.1f} °/h")
print("x-IMU static segments:", R.static_segments(x1.signals),
      "— hand-held throughout (gyro spread ≥ 3°/s in every 0.5 s window)")

# %% [markdown]
# ## 4. Double-integrating the accelerometers
# Over the x-IMU3's static stretch the true position stays at zero, so whatever the
# navigation produces is drift. The attitude is levelled from the first 0.5 s at rest, which
# absorbs the *horizontal* accelerometer offset into the initial tilt (notebook 05, §5). What
# remains are two offsets, in different directions: the vertical accelerometer offset
# $b_{a,D}$ integrates twice into $\tfrac12 b_{a,D} t^2$ along the vertical, and a gyro offset
# tilts the attitude by $\boldsymbol b_g t$ (in navigation axes), which leaks gravity into the
# horizontal and integrates into a cubic there:
#
# $$ p_D \approx \tfrac12 b_{a,D}\,t^2, \qquad
#    p_N \approx -\tfrac16 g\,b_{g,E}\,t^3, \qquad p_E \approx \tfrac16 g\,b_{g,N}\,t^3 . $$
#
# Each component is fitted by $c_2 t^2 + c_3 t^3$ (fitting the norm $|\boldsymbol p|$ instead
# would add the lengths of perpendicular vectors).
# The fit says what the data hold and nothing beyond them — what a MEMS IMU does over minutes
# is the question `imunav assess` answers from its error model (notebook 05), not an
# extrapolation of one second.

# %%
raw = R.drift_from_rest(s3, a, b)
print(f"raw: drift after {raw['t'][-1]:.2f} s = {raw['drift'][-1] * 1e3:.1f} mm")
# the same navigation as R.drift_from_rest, keeping the components
q_rest = level_attitude(s3.accel[a:a + int(0.5 * s3.rate)], s3.g, tol=0.1)
nav = navigate(ImuSignals(s3.t[a:b] - s3.t[a], s3.gyro[a:b], s3.accel[a:b], "rates",
                          s3.rate, s3.g), q_rest, algorithm="magnus6")
tn, pn = nav.t, nav.position
A = np.stack([tn ** 2, tn ** 3], 1)
coef = np.array([np.linalg.lstsq(A, pn[:, k], rcond=None)[0] for k in range(3)])   # (N,E,D)×(c2,c3)
bg_n = quat_to_dcm(q_rest) @ s3.gyro[a:b].mean(0)          # the gyro offset in navigation axes
pred = s3.g * np.array([-bg_n[1], bg_n[0]]) / 6             # c3 north, east from it
print(f"{'':7s} {'c₂ (m/s²)':>11s} {'c₃ (m/s³)':>11s}   c₃ from the gyro offset")
for k, ax in enumerate("NED"):
    print(f"{ax:7s} {coef[k, 0]:11.2e} {coef[k, 1]:11.2e}   "
          + (f"{pred[k]:.2e}" if k < 2 else "— (no tilt term)"))
collinear = (tn ** 5).sum() / np.sqrt((tn ** 4).sum() * (tn ** 6).sum())
print(f"t² and t³ over these {tn[-1]:.2f} s: correlation {collinear:.3f}")

# %% tags=["hide-input"]
Markdown(
    f"The vertical drift is the quadratic: $c_2$ = {coef[2, 0]:.2e} m/s², an offset "
    f"$b_{{a,D}}$ = {2 * coef[2, 0] * 1e3:.0f} mm/s², with no cubic. Northward the cubic is the "
    f"one the gyro offset predicts ({coef[0, 1]:.2e} against {pred[0]:.2e} m/s³). Eastward the "
    f"fit returns {coef[1, 1]:.2e} against {pred[1]:.2e} m/s³ and a quadratic of "
    f"{coef[1, 0]:.2e} m/s² that levelling should have removed: over {tn[-1]:.1f} s the two "
    f"shapes $t^2$ and $t^3$ are {collinear:.3f} correlated, so one second of data barely tells "
    "them apart, and the split between them is not to be trusted beyond its sum.")

# %% [markdown]
# **Calibration judged on data it has not seen.** Estimating the offsets on the same samples
# the drift is measured on would flatter the calibration (it would fit its own noise). So the
# static stretch is split: offsets are estimated on the first part and the navigation is
# judged on the second, from rest, raw and calibrated. Where to split is a trade: a longer
# estimate is less noisy, but leaves a shorter stretch to judge. Four splits side by side:

# %%
splits = (0.3, 0.5, 0.7, 0.9)
held = {}
for sp in splits:
    held[sp] = R.holdout_bias(s3, a, b, a + int(round(sp * s3.rate)))
    hh = held[sp]
    print(f"split at {sp:.1f} s: estimate over {hh['estimation_s']:.2f} s, judged over "
          f"{hh['test_s']:.2f} s: drift raw {hh['raw']['final'] * 1e3:.2f} mm, calibrated "
          f"{hh['out_of_sample']['final'] * 1e3:.2f} mm")

# %% tags=["hide-input"]
fig, axs = figure(2, 2, height=4.8, sharex=True, sharey=True)
for ax, sp in zip(axs.flat, splits, strict=True):
    hh = held[sp]
    ax.plot(hh["raw"]["t"], hh["raw"]["drift"] * 1e3, **styled("measured", label="raw"))
    ax.plot(hh["out_of_sample"]["t"], hh["out_of_sample"]["drift"] * 1e3,
            **styled("estimate", ls="-", label="calibrated on the first part"))
    ax.set(title=f"{hh['estimation_s']:.2f} s estimate, {hh['test_s']:.2f} s judged",
           xlabel="t from the split (s)", ylabel="position drift (mm)")
    ax.label_outer()
axs[0, 0].legend(loc="upper left")
plt.show()

# %% tags=["hide-input"]
best = min(splits, key=lambda sp: held[sp]["out_of_sample"]["final"])
Markdown(
    "On data it has not seen, the calibration removes most of the drift at every split: "
    + "; ".join(f"{held[sp]['raw']['final'] * 1e3:.1f} → "
                f"{held[sp]['out_of_sample']['final'] * 1e3:.1f} mm with a "
                f"{held[sp]['estimation_s']:.2f} s estimate" for sp in splits)
    + ". The recording holds a single static stretch (the x-IMU none at all: it is hand-held "
    "throughout), so the estimate and the judgement come from two halves of one stretch — a bias "
    "that wanders between separate stops would be judged more harshly.")

# %% [markdown]
# With a kernel, move the split: the figure below is the widget's starting state (the whole
# stretch with its fit, and the held-out part after a 0.66 s estimate); the widget under it
# redraws it.

# %% tags=["hide-input"]
def show_split(split_s=0.66):
    """Drift over the held-out part for a split at ``split_s`` seconds into the stretch."""
    k = a + int(round(split_s * s3.rate))
    hh = R.holdout_bias(s3, a, b, min(max(k, a + 5), b - 5))
    fig, axs = figure(1, 2, height=3.0)
    axs[0].plot(raw["t"], raw["drift"] * 1e3, **styled("measured", label="whole stretch, raw"))
    axs[0].plot(tn, np.linalg.norm(A @ coef.T, axis=1) * 1e3, "k:",
                label="|fit per component|")
    axs[0].axvspan(0, hh["estimation_s"], color="C2", alpha=0.12, label="estimation part")
    axs[0].set(xlabel="t (s)", ylabel="position drift (mm)", title="x-IMU3 at rest")
    axs[0].legend(loc="upper left")
    axs[1].plot(hh["raw"]["t"], hh["raw"]["drift"] * 1e3, **styled("measured", label="raw"))
    axs[1].plot(hh["out_of_sample"]["t"], hh["out_of_sample"]["drift"] * 1e3,
                **styled("estimate", ls="-", label="calibrated"))
    axs[1].set(xlabel="t from the split (s)", ylabel="position drift (mm)",
               title=f"held out {hh['test_s']:.2f} s after {hh['estimation_s']:.2f} s")
    axs[1].legend(loc="upper left")
    plt.show()


show_split()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(show_split, split_s=FloatSlider(value=0.66, min=0.2, max=1.1, step=0.02,
                                             continuous_update=False, description="split (s)"))

# %% [markdown]
# ## Takeaways
#
# - A device's quaternion convention is a claim to check against its own gyro, not to assume.
# - At a low sample rate and a high angular rate the attitude update matters: the first-order
#   update falls well behind the exponential and Magnus updates.
# - A static stretch gives the offsets; double-integrated, even small ones make millimetres of
#   drift within a second — quadratically from the accelerometer (vertically, once levelling
#   has absorbed the horizontal offset), cubically from the gyro (horizontally); fit each
#   component, not the norm.
# - Judge a calibration on data it has not seen.
#
# ## Exercises
#
# **Exercise 1.** The vertical fit of §4 says $c_2 = \tfrac12 b_{a,D}$. What offset does it
# imply, and how does it compare with the offsets the hold-out calibration estimated (with the
# 0.5 s estimate)? Along which body axis is it? Is it the accelerometer's?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
ba_fit = 2 * coef[2, 0]
hh = held[0.5]
ba_est = hh["accel_bias_est"]
f_rest = np.linalg.norm(s3.accel[a:b].mean(0))
g_range = normal_gravity(np.radians([0.0, 90.0]))
print(f"from c₂: {ba_fit * 1e3:.1f} mm/s²; estimated offsets (body axes): "
      f"{np.round(ba_est * 1e3, 1)} mm/s², |b_a| = {np.linalg.norm(ba_est) * 1e3:.1f} mm/s², "
      f"along body {'xyz'[np.argmax(np.abs(ba_est))]}")
print(f"|f| at rest {f_rest:.4f} m/s² against the assumed g = {s3.g:.5f}: "
      f"{(f_rest - s3.g) * 1e3:+.0f} mm/s²; normal gravity on the Earth runs from "
      f"{g_range[0]:.4f} (equator) to {g_range[1]:.4f} m/s² (poles)")
assert abs(ba_fit / np.linalg.norm(ba_est) - 1) < 0.1     # the same offset, seen two ways
Markdown(
    f"The offset is {abs(ba_fit) * 1e3:.0f} mm/s² along the body z axis — but it is simply "
    f"$|\\boldsymbol f|$ at rest ({f_rest:.4f} m/s²) minus the standard gravity "
    f"{s3.g:.5f} m/s² assumed. Local gravity differs from that by up to "
    f"{max(abs(g_range - s3.g)) * 1e3:.0f} mm/s² between the equator and the poles "
    "(`imunav.earth.normal_gravity`), more with height, and the recording does not say where "
    "it was made: the vertical offset cannot be attributed to the accelerometer without the "
    "local gravity.")

# %% [markdown]
# **Exercise 2.** Which reading of the x-IMU's quaternion is *second* best, and by how much is
# it worse than the best? What does that say about how distinct the four readings are?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
c1 = R.device_quaternion_convention(x1)
ranked = sorted(c1, key=c1.get)
print(f"best {ranked[0]} ({c1[ranked[0]]:.1f}°), second {ranked[1]} ({c1[ranked[1]]:.1f}°)")
assert c1[ranked[1]] > 3 * c1[ranked[0]]        # the readings are far apart: the test is sharp

# %% tags=["hide-cell"] jupyter={"source_hidden": true}
# Checks (run by the tests, not part of the lesson): the convention, the hold-out, the stretch.
c3 = R.device_quaternion_convention(x3)
print(min(c3, key=c3.get))
assert min(c3, key=c3.get) == "wxyz/q_nb"
h = R.holdout_bias(s3, a, b, (a + b) // 2)
assert h["out_of_sample"]["final"] < 0.3 * h["raw"]["final"]
# the static stretch ends before the motion resumes: its last 0.1 s is as quiet as the rest
tail = s3.gyro[b - int(0.1 * s3.rate):b]
assert np.ptp(tail, axis=0).max() < np.radians(3.0)
