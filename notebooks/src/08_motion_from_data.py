# %% [markdown]
# # Motion from data: recorded poses and waypoint routes
#
# ## What you will learn
#
# - how timed poses (motion capture, a camera) or a few waypoints become a smooth motion with
#   exact derivatives, so that a simulated IMU — and every navigation error measured against
#   it — stays as trustworthy as with analytic laws;
# - how accurate those derivatives are, and how fast they converge with the pose rate;
# - why a millimetre of capture noise becomes tens of m/s² of specific force, and what a
#   smoothing spline does about it;
# - how to assess an IMU on a recorded trajectory and on a route.
#
# **What you should know first:** notebook 00 (motions, IMU signals) and notebook 05 for the
# verdicts; splines as piecewise polynomials.
#
# **Scope.** A flat, non-rotating Earth and unaided navigation, as everywhere in this book: the
# verdicts of §3–§4 are the IMU's alone.
#
# | what | where |
# |---|---|
# | poses → spline → ω_b, f_b vs the analytic motion, and their convergence order | §1 |
# | millimetre capture noise, and what smoothing does | §2 |
# | a recorded trajectory → simulate → assess an IMU | §3 |
# | a waypoint route, attitude following the path | §4 |
# | pose rate and smoothing swept, and a widget | §5 |
#
# **The splines** (`imunav.motion.PoseMotion`, `WaypointMotion`). Position: a quintic spline
# (scipy `make_interp_spline`, k = 5) — velocity $v = \dot p$, acceleration $a = \ddot p$ and the
# specific force are exact derivatives of one piecewise polynomial:
#
# $$ f_b = C_{bn}\,(\ddot p - g_n), \qquad g_n = [0, 0, g]^T. $$
#
# Attitude: scipy's `RotationSpline`, cubic in rotation vectors, whose angular rate is the body
# rate $\omega_b$ (the vector part of $2\,q^* \otimes \dot q$), continuous with its derivative; it
# passes through every given attitude (a cumulative B-spline would only approximate them).
# Units: SI and radians throughout; noise levels print in mm and mrad.

# %%
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown
from ipywidgets import FloatSlider, interact

from imunav import Motion, simulate_imu
from imunav.analysis.assessment import assess_covariance, format_verdict
from imunav.analysis.family import fmt_err
from imunav.analysis.metrics import fit_order
from imunav.core.rotations import quat_mul, quat_to_euler
from imunav.io import load_motion
from imunav.motion.catalog import figure_eight
from imunav.motion.trajectory import PoseMotion, WaypointMotion
from imunav.plotting import figure, series_style, styled, use_book_style
from imunav.sensors import ImuModel

use_book_style()
SEED = 0
rng = np.random.default_rng(SEED)

# %% [markdown]
# ## 1. A recorded-style trajectory, and how exact the spline is
# The "recording" is an analytic walk with a hand-held device (1.4 m/s forward, body sway and
# bounce at the step frequency, slow heading changes, the device swinging), sampled at 100 Hz
# exactly as a capture system would store it. Because the walk is analytic, the spline's
# $\omega_b$ and $f_b$ can be compared with the true ones.

# %%
STEP = 11.3          # rad/s: the bounce (and pitch) frequency of the steps below
walk = Motion(x="1.4*t + 0.3*sin(0.2*t)", y="2*sin(0.15*t) + 0.04*sin(5.65*t)",
              z=f"-0.03*sin({STEP}*t)", yaw="0.3*sin(0.15*t) + 0.1*sin(0.5*t)",
              pitch=f"0.15*sin(2.0*t) + 0.05*sin({STEP}*t)", roll="0.2*sin(1.3*t) + 0.08*sin(5.65*t)",
              duration=30.0, name="hand-held walk")
print(f"steps at {STEP / (2 * np.pi):.2f} Hz")


def sample_poses(motion, rate, noise_m=0.0, noise_rad=0.0, rng=None):
    """Timed poses as a capture system would store them, with optional white noise."""
    t = np.arange(0.0, motion.duration + 1e-9, 1.0 / rate)
    p, q = motion.position(t), motion.attitude(t)
    if noise_m or noise_rad:
        p = p + rng.normal(0.0, noise_m, p.shape)
        rv = rng.normal(0.0, noise_rad, (t.size, 3))
        half = np.linalg.norm(rv, axis=1, keepdims=True) / 2
        q = quat_mul(q, np.concatenate([np.cos(half), np.sinc(half / np.pi) * rv / 2], axis=1))
    return t, p, q


# The file route: a pose CSV, exactly as `imunav simulate poses.csv` reads it.
work = Path(tempfile.mkdtemp())
t, p, q = sample_poses(walk, 100.0)
np.savetxt(work / "poses.csv", np.hstack([t[:, None], p, q]), delimiter=",",
           header="t,x,y,z,qw,qx,qy,qz", comments="", fmt="%.17g")
poses, duration, _ = load_motion(work / "poses.csv")
print(f"{type(poses).__name__}: {poses.breakpoints.size} poses over {duration:g} s")
print(f"through the poses: position {fmt_err(np.abs(poses.position(t) - p).max(), 1e-12, 0)} m, "
      f"attitude {fmt_err(np.abs(poses.attitude(t) - q).max(), 1e-12, 0)}  (below 1e-12: rounding)")

interior = np.linspace(1.0, 29.0, 8001)          # away from the spline's two ends
rows = []
for rate in (25.0, 50.0, 100.0, 200.0):
    pm = PoseMotion(*sample_poses(walk, rate))
    rows.append((rate, np.abs(pm.angular_rate(interior) - walk.angular_rate(interior)).max(),
                 np.abs(pm.specific_force(interior) - walk.specific_force(interior)).max()))
rows = np.array(rows)
print("\npose rate   max |ω error| (rad/s)   max |f error| (m/s²)")
for r, ew, ef in rows:
    print(f"{r:6.0f} Hz   {ew:18.2e}   {ef:18.2e}")
h = 1 / rows[:, 0]
print(f"fitted orders: 25–100 Hz ω {fit_order(h[:3], rows[:3, 1]):.2f}, f {fit_order(h[:3], rows[:3, 2]):.2f}; "
      f"100→200 Hz ω {fit_order(h[2:], rows[2:, 1]):.2f}, f {fit_order(h[2:], rows[2:, 2]):.2f}")

# the README's figure-eight, sampled the same way
f8 = figure_eight()
pm8 = PoseMotion(*sample_poses(f8, 100.0))
i8 = np.linspace(1.0, 19.0, 4001)
e8w = np.abs(pm8.angular_rate(i8) - f8.angular_rate(i8)).max()
e8f = np.abs(pm8.specific_force(i8) - f8.specific_force(i8)).max()
print(f"figure-eight, 100 Hz poses: max |ω error| {e8w:.1e} rad/s, max |f error| {e8f:.1e} m/s²")

# %% tags=["hide-input"]
o_w, o_f = fit_order(h[2:], rows[2:, 1]), fit_order(h[2:], rows[2:, 2])
Markdown(
    f"The attitude spline is cubic in rotation vectors, so its rate converges at order 3; the "
    f"quintic position spline gives the specific force at order 4 — and from 100 to 200 Hz poses "
    f"the errors still fall at those orders ({o_w:.1f} and {o_f:.1f}): rounding, which grows as "
    f"positions are differentiated twice (≈ 1e-16 · |p| · rate²), is not reached yet. The errors "
    f"scale with the motion's fast content: the walk's steps at {STEP / (2 * np.pi):.1f} Hz make "
    f"them {rows[2, 1] / e8w:.0f} (ω) and {rows[2, 2] / e8f:.0f} (f) times those of the slow "
    f"figure-eight of notebook 00 at 100 Hz ({e8w:.1e} rad/s, {e8f:.1e} m/s²). Where the errors "
    "sit in time, with 100 Hz poses:")

# %% tags=["hide-input"]
pm = PoseMotion(*sample_poses(walk, 100.0))
tt = np.linspace(0.0, 30.0, 30001)
fig, axs = figure(2, 1, height=4.6, sharex=True)
axs[0].semilogy(tt, np.linalg.norm(pm.angular_rate(tt) - walk.angular_rate(tt), axis=1),
                color=series_style(0)["color"])
axs[0].set(ylabel=r"$\omega_b$ error (rad/s)", title="spline through 100 Hz poses − analytic walk")
axs[1].semilogy(tt, np.linalg.norm(pm.specific_force(tt) - walk.specific_force(tt), axis=1),
                color=series_style(1)["color"])
axs[1].set(xlabel="t (s)", ylabel=r"$f_b$ error (m/s²)")
plt.show()

# %% [markdown]
# Larger only in the first and last tenth of a second; everywhere else at the level of the
# table. No derivative is known at the ends, so the spline uses *not-a-knot* end conditions
# (the first two and the last two polynomial pieces are one polynomial each): with no data
# beyond the ends, that last stretch is extrapolated more than interpolated.
#
# ## 2. Capture noise, and what smoothing does
# A real capture system adds noise — typically a millimetre and a milliradian. Differentiated
# twice, position noise of standard deviation σ at pose rate $r$ becomes acceleration noise of
# order $\sigma (\pi r)^2$ (printed below for 1 mm at 100 Hz). An interpolating spline passes
# through every noisy pose and hands this noise to the accelerometer. A smoothing spline
# (scipy `splrep`, FITPACK) accepts a residual sum $\sum_i |p_i - s(t_i)|^2 \le n\sigma^2$ instead
# — FITPACK's rule for white noise of standard deviation σ.

# %%
noisy = sample_poses(walk, 100.0, 1e-3, 1e-3, rng)
print(f"σ (π r)² for 1 mm at 100 Hz: {1e-3 * (np.pi * 100) ** 2:.0f} m/s²")


def rms(m, f):
    return np.sqrt(np.mean(np.sum((getattr(m, f)(interior) - getattr(walk, f)(interior)) ** 2, axis=1)))


print(" σ (mm, mrad)   f rms error (m/s²)   ω rms error (rad/s)   position rms (mm)")
smooth_rows, table = {}, {}
for s in (None, 0.3e-3, 1e-3, 3e-3, 10e-3):
    m = PoseMotion(*noisy, smoothing=s, attitude_smoothing=s)
    smooth_rows[s] = m
    pos = 1e3 * np.sqrt(np.mean(np.sum((m.position(interior) - walk.position(interior)) ** 2, axis=1)))
    table[s] = (rms(m, "specific_force"), rms(m, "angular_rate"), pos)
    label = "interpolating" if s is None else f"{1e3 * s:13.1f}"
    print(f"{label:>13s}   {table[s][0]:18.3g}   {table[s][1]:19.3g}   {pos:17.3f}")

# %% tags=["hide-input"]
win = (interior > 10) & (interior < 13)
fig, axs = figure(2, 1, height=5.0, sharex=True)
for ax, f, unit in ((axs[0], "specific_force", r"$f_x$ (m/s²)"), (axs[1], "angular_rate", r"$\omega_x$ (rad/s)")):
    ax.plot(interior[win], getattr(smooth_rows[None], f)(interior[win])[:, 0], lw=0.6,
            color="0.7", label="interpolating, noisy poses")
    ax.plot(interior[win], getattr(walk, f)(interior[win])[:, 0], **styled("truth", lw=3,
            alpha=0.45, label="analytic truth"))
    ax.plot(interior[win], getattr(smooth_rows[1e-3], f)(interior[win])[:, 0],
            **styled("estimate", lw=1.3, label="smoothing, σ = 1 mm / 1 mrad"))
    ax.set(ylabel=unit)
amp = np.abs(walk.specific_force(interior[win])[:, 0]).max()
peak = np.abs(smooth_rows[None].specific_force(interior[win])[:, 0]).max()
axs[0].set_ylim(-4 * amp, 4 * amp)                  # the noisy curve runs far off this scale
axs[0].lines[0].set_label("interpolating, noisy poses (clipped at the axis)")
axs[0].text(0.99, 0.03, f"grey: up to ±{peak:.0f} m/s², off this scale",
            transform=axs[0].transAxes, ha="right", va="bottom", fontsize=8,
            bbox={"fc": "white", "ec": "0.7"})
axs[0].set_title("1 mm / 1 mrad capture noise at 100 Hz: the signals a simulated IMU would read")
# the key under both panels: inside, the noisy curve runs under it whatever its place
fig.legend(*axs[0].get_legend_handles_labels(), loc="outside lower center", ncols=2, fontsize=8)
axs[1].set(xlabel="t (s)")
plt.show()

# %% tags=["hide-input"]
best_s = min((s for s in table if s), key=lambda s: table[s][0])
Markdown(
    f"Without smoothing the noise reaches the simulated accelerometer as {table[None][0]:.0f} m/s² "
    f"rms (and {table[None][1]:.2f} rad/s in the gyro); with σ = 1 mm / 1 mrad it drops to "
    f"{table[1e-3][0]:.2f} m/s² and {table[1e-3][1]:.3f} rad/s. Of the σ tried, "
    f"{1e3 * best_s:g} mm gives the smallest specific-force error; much larger rounds off the real "
    f"motion — at 10 mm the step-frequency sway is flattened and the error is back up to "
    f"{table[10e-3][0]:.2f} m/s². The two sides are not alike: *under*estimating σ is "
    f"catastrophic — at σ = 0.3 mm, a third of the true noise, the spline still follows the "
    f"noise ({table[0.3e-3][0]:.0f} m/s² rms, against {table[1e-3][0]:.2f} at 1 mm) — while "
    f"*over*estimating it is mild ({table[3e-3][0]:.2f} m/s² at three times the noise). Set σ "
    "to the capture system's stated noise, and when unsure err on the high side. On the "
    "command line: `imunav simulate poses.csv --smoothing 0.001 --attitude-smoothing 0.001 …`.")

# %% [markdown]
# ## 3. Can this IMU track the recorded walk?
# The smoothed recording is an ordinary motion: simulation, navigation and assessment take it
# unchanged. The verdict on it, on the unsmoothed (interpolating) recording and on the analytic
# walk they were recorded from:

# %%
adis = ImuModel.load("ADIS16470")
recorded = smooth_rows[1e-3]
recorded.name = "recorded walk (σ = 1 mm)"
raw = smooth_rows[None]
raw.name = "recorded walk, unsmoothed"
p95 = {}
for m in (walk, recorded, raw):
    r = assess_covariance(m, adis, 100.0, tolerance=2.0)
    p95[m.name] = r["final_p95_position_m"]
    print(format_verdict(r).splitlines()[0])
    print(format_verdict(r).splitlines()[1], f"final 95th pct {r['final_p95_position_m']:.3f} m\n")
sig = simulate_imu(recorded, 100.0, kind="increments")
print(f"simulated: {len(sig)} increment samples at {sig.rate:g} Hz over {sig.t[-1]:.2f} s")
peak_f = {m.name: float(np.linalg.norm(m.specific_force(interior), axis=1).max())
          for m in (walk, recorded, raw)}
print("peak |f_b| the IMU is asked to measure:",
      ", ".join(f"{k} {v:.3g} m/s²" for k, v in peak_f.items()))

# %% tags=["hide-input"]
Markdown(
    f"Unsmoothed, the simulated IMU is asked to measure the noise as motion: specific forces up "
    f"to {peak_f[raw.name]:.0f} m/s² where the walk has {peak_f[walk.name]:.1f} m/s² "
    f"({peak_f[raw.name] / 9.80665:.0f} g: beyond the range of many consumer accelerometers, "
    f"which would clip). The ADIS16470's 95th percentile on it is {p95[raw.name]:.3f} m: close to "
    "the walk's, because on this short walk its errors come from bias instability, noise and "
    "misalignment, which the jitter hardly feeds — the signals, not the verdict, are what the "
    "noise spoils here (an IMU with a smaller range, or scale-factor and g-sensitivity terms, "
    f"would show it). Smoothed, the verdict and the 95th percentile are those of the true walk "
    f"({p95[recorded.name]:.3f} m against {p95[walk.name]:.3f} m).")

# %% [markdown]
# ## 4. A waypoint route
# Five waypoints of a 60 s drive around a block (`examples/route.toml`), the attitude following
# the path: yaw along the horizontal velocity, pitch along the climb, and the roll of a
# coordinated turn,
#
# $$ \psi = \operatorname{atan2}(v_E, v_N), \quad \theta = \operatorname{atan2}(-v_D, |v_h|),
#    \quad \phi = \arctan\frac{|v|\,\dot\psi}{g}. $$
#
# The route starts and ends at rest (velocity and acceleration zero), which the clamped quintic
# enforces. There the velocity vanishes as $\tau^2$, $\tau$ the time from the nearer end, so
# the heading is taken from $v/\tau^2$ — a polynomial that does not vanish — and yaw stays
# defined.

# %%
wt = [0.0, 15.0, 30.0, 45.0, 60.0]
wp = [[0, 0, 0], [120, 5, -1], [130, 110, -3], [20, 120, -2], [0, 20, 0]]
route = WaypointMotion(wt, wp, orientation="follow", name="block drive")
tt = np.linspace(0.0, 60.0, 6001)
pos, vel = route.position(tt), route.velocity(tt)
ypr = quat_to_euler(route.attitude(tt))
print(f"through the waypoints: {fmt_err(np.abs(route.position(np.array(wt)) - np.array(wp)).max(), 1e-12, 0)} m; "
      f"speed at the ends {fmt_err(np.linalg.norm(route.velocity(np.array([0.0, 60.0])), axis=1).max(), 1e-12, 0)} m/s"
      "  (below 1e-12: rounding)")
print(f"north: the path reaches {pos[:, 0].max():.0f} m, the waypoints {np.max(np.array(wp)[:, 0]):.0f} m; "
      f"east: {pos[:, 1].max():.0f} m against {np.max(np.array(wp)[:, 1]):.0f} m")
print(f"top speed {np.linalg.norm(vel, axis=1).max():.1f} m/s, max |roll| "
      f"{np.degrees(np.abs(ypr[:, 2])).max():.1f}°, max |f_b| {np.linalg.norm(route.specific_force(tt), axis=1).max():.2f} m/s²")

# %% tags=["hide-input"]
fig = plt.figure(figsize=(6.5, 4.2), layout="constrained")
gs = fig.add_gridspec(2, 2)
ax0 = fig.add_subplot(gs[:, 0])
ax0.plot(pos[:, 1], pos[:, 0], color=series_style(0)["color"], label="spline path")
ax0.plot(np.array(wp)[:, 1], np.array(wp)[:, 0], "ko", label="waypoints")
k = slice(0, None, 400)
ax0.quiver(pos[k, 1], pos[k, 0], np.sin(ypr[k, 0]), np.cos(ypr[k, 0]), color="C3", width=0.008,
           scale=9, zorder=3, label="heading (yaw)")
ax0.set(xlabel="east (m)", ylabel="north (m)", title="route, top view", aspect="equal")
ax0.legend(loc="center", fontsize=8)
ax1 = fig.add_subplot(gs[0, 1])
ax1.plot(tt, np.linalg.norm(vel, axis=1), color=series_style(0)["color"])
ax1.set(ylabel="speed (m/s)", title="following the path")
ax2 = fig.add_subplot(gs[1, 1], sharex=ax1)
ax2.plot(tt, np.degrees(ypr[:, 2]), color=series_style(1)["color"], label="roll")
ax2.plot(tt, np.degrees(ypr[:, 1]), color=series_style(2)["color"], label="pitch")
ax2.set(xlabel="t (s)", ylabel="angle (°)")
ax2.legend(loc="upper right", fontsize=8)
plt.show()

# %% tags=["hide-input"]
Markdown(
    f"The path swings wide of its waypoints: north it reaches {pos[:, 0].max():.0f} m where no "
    f"waypoint is beyond {np.max(np.array(wp)[:, 0]):.0f} m. A quintic through five points "
    "15 s apart has to carry its speed round each corner, and overshoots; more waypoints (or "
    "closer in time) hold it nearer the intended route. The verdicts of two IMUs on it:")

# %%
for preset in ("tactical", "BMI088"):
    print(format_verdict(assess_covariance(route, ImuModel.load(preset), 100.0, tolerance=5.0)))
    print()

# %% [markdown]
# ## 5. Pose rate and smoothing, swept
# What the widget below explores, swept: the rms specific-force and rate errors of the spline
# against the analytic walk, for 1 mm / 1 mrad of noise, as the smoothing σ grows, at three
# pose rates (σ = 0 is the interpolating spline).

# %%
def spline_errors(pose_rate, noise_mm, smoothing_mm, seed=SEED):
    """rms |f_b| and |ω_b| errors (m/s², rad/s) of the spline through noisy poses."""
    data = sample_poses(walk, pose_rate, noise_mm * 1e-3, noise_mm * 1e-3,
                        np.random.default_rng(seed))
    s = smoothing_mm * 1e-3 if smoothing_mm > 0 else None
    m = PoseMotion(*data, smoothing=s, attitude_smoothing=s)
    ef = np.linalg.norm(m.specific_force(interior) - walk.specific_force(interior), axis=1)
    ew = np.linalg.norm(m.angular_rate(interior) - walk.angular_rate(interior), axis=1)
    return ef, ew


sig_mm = (0.0, 0.3, 1.0, 3.0, 10.0)
sweep = {r: [tuple(np.sqrt(np.mean(e ** 2)) for e in spline_errors(r, 1.0, s)) for s in sig_mm]
         for r in (50.0, 100.0, 200.0)}
for r, vals in sweep.items():
    print(f"{r:5.0f} Hz poses:", "  ".join(f"σ {s:g} mm → {f:.3g} m/s², {w:.3g} rad/s"
                                         for s, (f, w) in zip(sig_mm, vals, strict=True)))

# %% tags=["hide-input"]
fig, axs = figure(1, 2, height=2.9)
x = np.array(sig_mm)                             # σ = 0 (interpolating) on the linear part
for i, (r, vals) in enumerate(sweep.items()):
    axs[0].plot(x, [v[0] for v in vals], "o-", ms=3.5, color=series_style(i)["color"],
                label=f"{r:g} Hz poses")
    axs[1].plot(x, [v[1] for v in vals], "o-", ms=3.5, color=series_style(i)["color"])
for ax in axs:
    ax.set_xscale("symlog", linthresh=0.3, linscale=0.5)
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{v:g}" for v in x])
for ax in axs:                                   # one σ smooths both: mm of position, mrad of attitude
    ax.set_xlabel("smoothing σ, 0 = interpolating\n(mm of position and mrad of attitude)")
axs[0].set(ylabel=r"rms $f_b$ error (m/s²)")
axs[1].set(ylabel=r"rms $\omega_b$ error (rad/s)")
axs[0].legend(loc="upper right", fontsize=8)       # the errors are large at the left
plt.show()

# %% [markdown]
# With a kernel: the walk of §1 re-sampled at the chosen pose rate with the chosen noise, and
# the spline's errors against the analytic walk over time (smoothing 0 = interpolating). The
# figure below is the widget's starting state.

# %% tags=["hide-input"]
def explore(pose_rate=100.0, noise_mm=1.0, smoothing_mm=1.0):
    ef, ew = spline_errors(pose_rate, noise_mm, smoothing_mm)
    fig, axs = figure(2, 1, height=4.2, sharex=True)
    axs[0].semilogy(interior, ef, color=series_style(1)["color"])
    axs[0].set(ylabel=r"$f_b$ error (m/s²)",
               title=f"{pose_rate:g} Hz poses, noise {noise_mm:g} mm/mrad, smoothing {smoothing_mm:g} mm/mrad")
    axs[1].semilogy(interior, ew, color=series_style(0)["color"])
    axs[1].set(xlabel="t (s)", ylabel=r"$\omega_b$ error (rad/s)")
    plt.show()
    print(f"rms: f {np.sqrt(np.mean(ef ** 2)):.3g} m/s², ω {np.sqrt(np.mean(ew ** 2)):.3g} rad/s")


explore()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(explore, pose_rate=FloatSlider(value=100, min=20, max=400, step=10,
                                            continuous_update=False),
             noise_mm=FloatSlider(value=1.0, min=0.0, max=5.0, step=0.1, continuous_update=False),
             smoothing_mm=FloatSlider(value=1.0, min=0.0, max=20.0, step=0.1,
                                      continuous_update=False))

# %% [markdown]
# ## Takeaways
#
# - A quintic position spline and a cubic rotation spline turn poses into a motion whose
#   specific force and body rate are exact derivatives; their errors fall at orders 4 and 3
#   with the pose rate.
# - Differentiating twice multiplies capture noise by about $(\pi r)^2$: never feed raw
#   capture data to an IMU simulation; smooth it with σ set to the system's noise — too small
#   a σ lets the noise through almost unchanged, too large only rounds off some motion.
# - A recording is assessed like any motion. On this walk it gives the verdict of the motion
#   it recorded smoothed or not (§3: the ADIS16470's errors here hardly feel the jitter);
#   what smoothing restores is the signals — unsmoothed, the simulated IMU is asked to measure
#   the capture noise as specific forces of tens of g, which a real one would clip.
#
# ## Exercises
#
# **Exercise 1.** The specific-force error of the interpolating spline through noisy poses
# should scale as $\sigma(\pi r)^2$. Check the scaling with the pose rate: compute the rms
# $f_b$ error for 1 mm of noise at 50 and 100 Hz and compare their ratio with $2^2$.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
e50 = np.sqrt(np.mean(spline_errors(50.0, 1.0, 0.0)[0] ** 2))
e100 = np.sqrt(np.mean(spline_errors(100.0, 1.0, 0.0)[0] ** 2))
print(f"rms f error: {e50:.3g} m/s² at 50 Hz, {e100:.3g} m/s² at 100 Hz: ratio {e100 / e50:.2f}")
assert 3 < e100 / e50 < 5

# %% [markdown]
# **Exercise 2.** Build a route of your own: a straight 100 m run north in 20 s, from rest to
# rest. What is its top speed, and where along the run is it reached?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
run = WaypointMotion([0.0, 20.0], [[0, 0, 0], [100, 0, 0]], orientation="follow")
ts = np.linspace(0.0, 20.0, 2001)
speed = np.linalg.norm(run.velocity(ts), axis=1)
print(f"top speed {speed.max():.2f} m/s at t = {ts[speed.argmax()]:.1f} s "
      f"(mean speed {100 / 20:.1f} m/s)")
assert abs(ts[speed.argmax()] - 10.0) < 0.05 and speed.max() > 100 / 20   # symmetric, above the mean

# %% tags=["hide-cell"] jupyter={"source_hidden": true}
# Checks (run by the tests, not part of the lesson): the orders, the smoothing, the verdict.
print(f"orders 25–100 Hz: ω {fit_order(h[:3], rows[:3, 1]):.1f}, f {fit_order(h[:3], rows[:3, 2]):.1f}")
assert abs(fit_order(h[:3], rows[:3, 1]) - 3) < 0.2 and abs(fit_order(h[:3], rows[:3, 2]) - 4) < 0.2
assert table[1e-3][0] < 0.01 * table[None][0]                 # smoothing removes the noise
assert abs(p95[recorded.name] / p95[walk.name] - 1) < 0.01     # the same verdict
