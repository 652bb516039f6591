# %% [markdown]
# # The rotating Earth
#
# ## What you will learn
#
# - what changes when the navigation frame is the real Earth: the WGS-84 ellipsoid, normal
#   gravity that varies with latitude and height, the Earth rate and the transport rate;
# - why horizontal errors stop growing without bound: the Schuler loop, with its 84-minute
#   period, and how the Earth's rotation turns its plane (the Foucault modulation);
# - why the vertical channel of an unaided inertial navigator diverges, and what a height aid
#   does about it;
# - the periods of the free error dynamics of a vehicle, read off the error model;
# - when the flat, non-rotating frame of notebooks 00–08 is good enough, IMU by IMU;
# - that every strapdown algorithm of the family keeps its order of accuracy on the Earth.
#
# **What you should know first:** notebook 00 (motions, IMU signals, navigation) and notebook 05
# (error terms, covariance analysis); latitude and longitude; a rotating frame's Coriolis term.
#
# **Scope.** Every cell is on the rotating WGS-84 Earth: motions are `EarthMotion`s (a motion
# given in the local NED frame of an origin fixed to the Earth), navigation runs with
# `earth="wgs84"` and the error models are the Earth's — except where a cell compares with the
# flat, non-rotating frame of notebooks 00–08 on purpose, and says so (§6's flat curve, §7's
# flat navigation of the Earth's signals, §8's flat reference). Positions are latitude,
# longitude (degrees only in printouts) and height above the ellipsoid; errors are in metres
# north, east and down.
#
# | what | where |
# |---|---|
# | the Earth in numbers: gravity, Earth rate | §1 |
# | an IMU at rest on the Earth, simulated exactly | §2 |
# | the Schuler oscillation of an accelerometer bias, and a widget | §3 |
# | the Foucault modulation | §4 |
# | the periods of the free error dynamics of a vehicle | §5 |
# | the vertical channel, free and held | §6 |
# | when does the flat frame suffice? | §7 |
# | the algorithms' orders measured on the Earth | §8 |
#
# **The equations.** imunav reads a motion in the local NED frame $n_0$ of an origin fixed to
# the Earth; its ECEF position $r_e(t)$ is then exact, and an ideal IMU measures
#
# $$ \omega_{ib}^b = \omega_{n_0 b}^b + C_{b n_0}\,\omega_{ie}^{n_0}, \qquad
#    f^b = C_{be}\,\big(\ddot r_e + 2\,\Omega \times \dot r_e - g_e(r_e)\big), $$
#
# with $\omega_{ib}^b$ the body's rate against inertial space, $\omega_{n_0 b}^b$ its rate
# against the origin's frame (what the flat frame would see), $C_{bn_0}$ and $C_{be}$ the
# rotations from that frame and from the Earth-fixed (ECEF) frame into the body,
# $\omega_{ie}^{n_0}$ the Earth's rate resolved in $n_0$, $\Omega = [0, 0, \omega_{ie}]$ the
# Earth's rate in ECEF ($\omega_{ie}$ its magnitude), $\dot r_e$, $\ddot r_e$ the ECEF velocity
# and acceleration, and $g_e$ the WGS-84 normal gravity along the ellipsoid's normal, of
# magnitude (Somigliana's formula on the ellipsoid, Groves 2nd ed. eq. 2.134, with the
# second-order height expansion of NIMA TR8350.2 eq. 4-3)
#
# $$ \gamma(L, h) = \gamma_e \frac{1 + k \sin^2 L}{\sqrt{1 - e^2 \sin^2 L}}
#    \Big[1 - \tfrac{2}{a}(1 + f + m - 2 f \sin^2 L)\,h + \tfrac{3}{a^2} h^2\Big], $$
#
# where $L$ is the geodetic latitude and $h$ the height above the ellipsoid; $a$ is the
# ellipsoid's semi-major axis (the equatorial radius), $f$ its flattening and $b = a(1 - f)$ its
# semi-minor axis; $e^2 = f(2 - f)$ the square of its first eccentricity; $\gamma_e$ and
# $\gamma_p$ the normal gravity on the equator and at the poles; $k = b\gamma_p / (a\gamma_e) - 1$
# Somigliana's constant; and $m = \omega_{ie}^2 a^2 b / GM$ (about the ratio of the centrifugal
# to the gravitational acceleration on the equator), $GM$ the Earth's gravitational constant.
# Their WGS-84 values are printed in §1.
#
# The navigation integrates in the inertial frame (the body-frame algorithm unchanged, gravity
# added) and reads the result in the local NED frame at the current position. Its errors obey,
# in the inertial frame, the flat frame's equations plus the gravity feedback $\Gamma = \partial
# G / \partial r$: $\dot{\delta v} = [f\times]\varphi + \Gamma\,\delta r + C\,\delta f$. Horizontally
# $\Gamma \approx -g/R$: a position error pulls back — an oscillator of frequency
# $\omega_s = \sqrt{g/R}$, Schuler's. Vertically $\Gamma \approx +2g/R$: a height error pushes
# further — the unstable vertical channel. Units: SI and radians in the code; degrees, minutes
# and hours only in printouts and figures.

# %%
import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import FloatSlider, interact

from imunav import ImunavError, ImuSignals, Motion, navigate, simulate_imu
from imunav import earth as E
from imunav.analysis.metrics import fit_order, nav_errors
from imunav.analysis.rotating_earth import (
    bias_response,
    error_periods,
    flat_frame_error,
    flat_frame_suffices,
)
from imunav.motion import EarthMotion
from imunav.motion.catalog import spinning_cone
from imunav.plotting import algorithm_id, figure, name, series_style, thing_style, use_book_style
from imunav.sensors import ImuModel
from imunav.sensors.presets import PRESETS
from imunav.strapdown.registry import ALGORITHMS

use_book_style()
DEG = np.pi / 180

# %% [markdown]
# ## 1. The Earth in numbers
# Normal gravity grows from the equator to the poles (the Earth is flattened and it turns) and
# falls with height; the Earth turns at 15 °/h, which is more than the whole gyro bias of a
# navigation-grade IMU.

# %%
lat = np.linspace(0, 90, 91) * DEG
g0, g10 = E.normal_gravity(lat), E.normal_gravity(lat, 1e4)
print(f"γ on the equator {g0[0]:.7f} m/s², at the poles {g0[-1]:.7f} m/s²: "
      f"+{100 * (g0[-1] / g0[0] - 1):.2f} %")
print(f"10 km up, gravity is lower by {g0[45] - g10[45]:.4f} m/s² at 45°")
print(f"the Earth rate: {np.degrees(E.OMEGA_E) * 3600:.3f} °/h; the Schuler period on the "
      f"equator {2 * np.pi / E.schuler_frequency(0.0) / 60:.1f} min")
print(f"WGS-84: a = {E.A:.1f} m, 1/f = {1 / E.F:.9f}, b = {E.B:.4f} m, e² = {E.E2:.10f}, "
      f"γ_e = {E.GAMMA_E} m/s², γ_p = {E.GAMMA_P} m/s², k = {E.K_SOMIGLIANA:.10f}, "
      f"m = {E.M:.10f}, GM = {E.GM:.9e} m³/s², ω_ie = {E.OMEGA_E} rad/s")
for preset in ("BMI088", "ADIS16470", "tactical"):
    gyro = ImuModel.load(preset).gyro
    bias = (f"{np.degrees(gyro.bias) * 3600:7.1f} °/h = {gyro.bias / E.OMEGA_E:.3g} × the Earth "
            "rate" if gyro.bias else "none in the preset")
    print(f"  {preset:10s} gyro turn-on bias {bias}; bias instability "
          f"{np.degrees(gyro.bias_instability or 0.0) * 3600:5.2f} °/h = "
          f"{(gyro.bias_instability or 0.0) / E.OMEGA_E:.3g} × the Earth rate")

# %% tags=["hide-input"]
fig, ax = figure(1, 1, height=2.6)
ax.plot(np.degrees(lat), g0, color=series_style(0)["color"], label="on the ellipsoid")
ax.plot(np.degrees(lat), g10, color=series_style(1)["color"], label="10 km above it")
ax.set(xlabel="latitude (°)", ylabel="normal gravity (m/s²)")
ax.legend(loc="upper left")
plt.show()

# %% [markdown]
# ## 2. An IMU at rest on the Earth
# At rest the gyros measure the Earth rate, resolved in the body, and the accelerometers the
# normal gravity, $\omega_{ib}^b = C_{bn}\,\omega_{ie} [\cos L, 0, -\sin L]$ and
# $f^b = -C_{bn}\,[0, 0, \gamma]$; the exact simulation gives both to rounding (printed below
# against those closed forms; the general formula above is checked in
# `tests/motion/test_geodetic.py` against an inertial-frame derivation with SymPy and against
# pyins' `generate_imu` — not repeated on this page). Here a level IMU, heading north, at 55° N,
# 150 m:

# %%
origin55 = (55 * DEG, 37 * DEG, 150.0)
still = EarthMotion(Motion(duration=10.0), origin55)
w, f = still.angular_rate([0.0])[0], still.specific_force([0.0])[0]
print("gyro  ω_ib (°/h):", np.round(np.degrees(w) * 3600, 4))
print("accel f_b (m/s²):", np.round(f, 6))
print(f"  = −γ(55°, 150 m) = −{float(E.normal_gravity(55 * DEG, 150.0)):.6f} m/s² on z")
w_closed = E.earth_rate_ned(55 * DEG)
f_closed = -E.gravity_ned(55 * DEG, 150.0)
print(f"against the closed forms: {np.abs(w - w_closed).max():.1g} rad/s, "
      f"{np.abs(f - f_closed).max():.1g} m/s²")

# %% [markdown]
# ## 3. The Schuler oscillation
# A constant accelerometer bias $b$ tilts nothing but pushes the position; on the flat frame the
# error would grow as $b t^2/2$ for ever. On the Earth, moving by $\delta p$ turns the local
# vertical by $\delta p / R$, and gravity — along the true vertical — then pulls back with
# $g\,\delta p/R$:
#
# $$ \ddot{\delta p} = b - \omega_s^2\,\delta p \quad\Rightarrow\quad
#    \delta p(t) = \frac{b}{\omega_s^2}\,(1 - \cos \omega_s t), \qquad
#    \omega_s = \sqrt{g/R}, $$
#
# with $R$ the radius of curvature along the error: the meridian radius $R_N$ for a north
# error (on the equator 6335 km, shorter than the mean radius of §1, so the period is a little
# shorter there too). Below, a north bias of 1 mg on an IMU at rest on the equator (the north channel is not coupled
# to the vertical there) for three hours, with the vertical held (a perfect height aid, §6):
# the full nonlinear navigation (simulate, add the bias, navigate on the Earth), the error model
# (`bias_response`) and the closed form.

# %%
b = 9.80665e-3                                    # 1 mg
eq = EarthMotion(Motion(duration=3 * 3600.0), (0.0, 0.0, 0.0))
resp = bias_response(eq, 0.2, 3 * 3600.0, accel=[b, 0, 0], vertical="hold")
sig = simulate_imu(eq, 1.0, kind="increments")
biased = ImuSignals(sig.t, sig.gyro, sig.accel + np.array([b, 0, 0]) / sig.rate, "increments",
                    sig.rate)


def hold_truth(t):
    st = eq.states(t)
    return st.position[:, 2], st.velocity[:, 2]


nav = navigate(biased, *eq.states([0.0]).initial(), earth="wgs84", hold=hold_truth)
north_nav = E.ned_difference(nav.position, eq.states(nav.t).position)[:, 0]
rn = E.radii(0.0)[0]
ws = np.sqrt(float(E.normal_gravity(0.0)) / rn)
closed = b * (1 - np.cos(ws * resp["t"])) / ws**2
print(f"Schuler period of the north channel {2 * np.pi / ws / 60:.2f} min (R = R_N, the meridian "
      f"radius, {rn / 1e3:.0f} km; §1's {2 * np.pi / E.schuler_frequency(0.0) / 60:.1f} min uses the "
      f"mean radius); peak 2b/ω_s² = {2 * b / ws**2:.0f} m")
print(f"error model vs closed form: largest difference {np.abs(resp['position'][:, 0] - closed).max():.2g} m")
print(f"navigation vs error model (at the model's times): largest difference "
      f"{np.abs(np.interp(resp['t'], nav.t, north_nav) - resp['position'][:, 0]).max():.2g} m")

# %% tags=["hide-input"]
fig, ax = figure(1, 1, height=2.8)
ax.plot(nav.t / 60, north_nav / 1e3, color=series_style(0)["color"], lw=3,
        label="nonlinear navigation")
ax.plot(resp["t"] / 60, resp["position"][:, 0] / 1e3, color=series_style(1)["color"], lw=1.5,
        label="error model (coincides)")
ax.plot(resp["t"] / 60, closed / 1e3, "--", color="black", lw=1, label=r"$(b/\omega_s^2)(1-\cos\omega_s t)$ (coincides)")
ax.set(xlabel="t (min)", ylabel="north error (km)", title="1 mg north bias at rest on the equator",
       ylim=(-0.5, 1.45 * 2 * b / ws**2 / 1e3))
ax.legend(loc="upper center", ncol=3)
plt.show()

# %% [markdown]
# With a kernel: the north error of an accelerometer bias at rest (vertical held) for a
# latitude, a bias and a duration of your choice, with the closed form; away from the equator
# the Earth's rotation turns the oscillation's plane (§4), so the north error leaks east. The
# figure below is the widget's starting state, at 45° N (the equator's is the figure above).

# %% tags=["hide-input"]
def schuler(lat_deg=0.0, bias_mg=1.0, hours=3.0):
    m = EarthMotion(Motion(duration=hours * 3600.0), (lat_deg * DEG, 0.0, 0.0))
    r = bias_response(m, 0.1, hours * 3600.0, accel=[bias_mg * 9.80665e-3, 0, 0],
                      vertical="hold")
    w2 = float(E.normal_gravity(lat_deg * DEG)) / E.radii(lat_deg * DEG)[0]
    fig, ax = figure(1, 1, height=2.8)
    ax.plot(r["t"] / 60, r["position"][:, 0], color=series_style(0)["color"], label="north")
    ax.plot(r["t"] / 60, r["position"][:, 1], color=series_style(2)["color"], label="east")
    ax.plot(r["t"] / 60, bias_mg * 9.80665e-3 * (1 - np.cos(np.sqrt(w2) * r["t"])) / w2, "--",
            color="black", lw=1, label="closed form (no Earth rotation)")
    top = np.abs(r["position"][:, :2]).max()
    ax.set(xlabel="t (min)", ylabel="position error (m)",
           title=f"{bias_mg:g} mg north bias at {lat_deg:g}°", ylim=(-1.05 * top, 1.5 * top))
    ax.legend(loc="upper center", ncol=3)
    plt.show()
    print(f"largest error {np.abs(r['position'][:, :2]).max():.3g} m")


schuler(45.0)

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(schuler, lat_deg=FloatSlider(value=45, min=0, max=89, step=1, continuous_update=False),
             bias_mg=FloatSlider(value=1, min=0.1, max=10, step=0.1, continuous_update=False),
             hours=FloatSlider(value=3, min=0.5, max=30, step=0.5, continuous_update=False))

# %% [markdown]
# ## 4. The Foucault modulation
# Away from the equator the Coriolis term $2\,\omega_{ie}\sin L$ couples north and east: the
# plane of the Schuler oscillation turns, as Foucault's pendulum does, once every
# $2\pi / (\omega_{ie} \sin L)$ (a sidereal day at the pole). Thirty hours of the same bias at
# 60° N, from the error model:

# %%
lat60 = 60 * DEG
long_run = EarthMotion(Motion(duration=30 * 3600.0), (lat60, 0.0, 0.0))
r60 = bias_response(long_run, 0.05, 30 * 3600.0, accel=[b, 0, 0], vertical="hold")
print(f"Foucault period at 60° N: {2 * np.pi / (E.OMEGA_E * np.sin(lat60)) / 3600:.2f} h "
      f"(at the pole: {2 * np.pi / E.OMEGA_E / 3600:.2f} h)")
east_max = np.abs(r60["position"][:, 1]).max()
print(f"north error up to {np.abs(r60['position'][:, 0]).max():.0f} m, east up to {east_max:.0f} m")

# %% tags=["hide-input"]
fig, axs = figure(1, 2, height=2.9)
axs[0].plot(r60["t"] / 3600, r60["position"][:, 0] / 1e3, color=series_style(0)["color"],
            lw=0.8, label="north")
axs[0].plot(r60["t"] / 3600, r60["position"][:, 1] / 1e3, color=series_style(2)["color"],
            lw=0.8, label="east")
axs[0].set(xlabel="t (h)", ylabel="position error (km)")
axs[1].plot(r60["position"][:, 1] / 1e3, r60["position"][:, 0] / 1e3, color=series_style(0)["color"],
            lw=0.5)
axs[1].set(xlabel="east error (km)", ylabel="north error (km)", aspect="equal")
fig.suptitle("1 mg north bias at rest at 60° N, vertical held")
fig.legend(loc="outside lower center", ncols=2)
plt.show()

# %% [markdown]
# ## 5. The free error dynamics of a vehicle
# For a vehicle driving east at 90 m/s at 30° N the local error dynamics are constant, and
# their eigenvalues are the modes every inertial navigator shows. `error_periods` reads them
# off the error model; beside them, the textbook formulas — Schuler $\omega_s = \sqrt{g/R}$
# split by the Foucault rate $\omega_{ie} \sin L + v \tan L / R$, the Earth-rate loop at
# $\omega_{ie} + v/(R \cos L)$ (the vehicle adds to the Earth's turn), the vertical pair
# $\pm\sqrt{2g/R}$:

# %%
lat30, v90 = 30 * DEG, 90.0
modes = error_periods(lat30, v90)
rn30, re30 = E.radii(lat30)
g30 = float(E.normal_gravity(lat30))
R = np.sqrt(rn30 * re30)
foucault = E.OMEGA_E * np.sin(lat30) + v90 * np.tan(lat30) / re30
formula = {"Schuler − Foucault": np.sqrt(g30 / R) - foucault,
           "Schuler + Foucault": np.sqrt(g30 / R) + foucault,
           "Earth-rate loop (+ transport rate)": E.OMEGA_E + v90 / (re30 * np.cos(lat30)),
           "vertical, growing": np.sqrt(2 * g30 / R), "vertical, decaying": -np.sqrt(2 * g30 / R)}
print(f"{'mode':48s} {'model':>14s} {'formula':>14s}")
for mo in modes:
    f_ = formula.get(mo["mode"])
    if mo["period_s"] is not None:
        print(f"{mo['mode']:48s} {mo['period_s'] / 60:10.2f} min {2 * np.pi / f_ / 60:10.2f} min")
    elif f_ is not None:
        print(f"{mo['mode']:48s} {1 / abs(mo['rate_rad_s']):10.1f} s   {1 / abs(f_):10.1f} s"
              "   (e-folding time)")
    else:
        print(f"{mo['mode']:48s} {mo['rate_rad_s']:14.2g} (rad/s: no feedback)")

# %% [markdown]
# The Schuler periods differ from the 84-minute one of a body at rest by the Foucault split;
# the Earth-rate loop is shorter than a day because driving east adds to the Earth's turn;
# the vertical pair is the instability of §6 (and its mirror).
#
# ## 6. The vertical channel, free and held
# Vertically gravity *grows* as the height falls ($\partial g/\partial h \approx -2g/R$), so a
# height error feeds itself: $\ddot{\delta h} = b + (2g/R)\,\delta h$, $\delta h =
# (b/\omega_v^2)(\cosh \omega_v t - 1)$ with $\omega_v = \sqrt{2 g / R}$ — an e-folding of about
# ten minutes. Every unaided inertial navigator has it; real ones hold the height with a
# barometer or GNSS. `imunav assess … --earth wgs84 --vertical hold` holds it at the true
# height (a perfect height aid). A down bias of 1 mg at rest at 45° N, free and held:

# %%
still45 = EarthMotion(Motion(duration=1800.0), (45 * DEG, 0.0, 0.0))
free = bias_response(still45, 1.0, 1800.0, accel=[0, 0, b])
held = bias_response(still45, 1.0, 1800.0, accel=[0, 0, b], vertical="hold")
wv = np.sqrt(2 * float(E.normal_gravity(45 * DEG)) / E.A)
print(f"after 30 min: free height error {abs(free['position'][-1, 2]):.0f} m "
      f"(closed form {b * (np.cosh(wv * 1800) - 1) / wv**2:.0f} m; on the flat frame, constant "
      f"gravity, b t²/2 = {b * 1800**2 / 2:.0f} m), held {abs(held['position'][-1, 2]):.1e} m")
held2 = bias_response(still45, 2.0, 1800.0, accel=[0, 0, b], vertical="hold")
print(f"horizontal error: free {np.hypot(*free['position'][-1, :2]):.1f} m "
      f"(the Coriolis term of the vertical velocity error), held "
      f"{np.hypot(*held['position'][-1, :2]):.2g} m with the height held once a second, "
      f"{np.hypot(*held2['position'][-1, :2]):.2g} m held twice a second")

# %% tags=["hide-input"]
fig, ax = figure(1, 1, height=2.7)
ax.semilogy(free["t"] / 60, np.abs(free["position"][:, 2]) + 1e-3, color=series_style(3)["color"],
            label="height error, free")
ax.semilogy(free["t"] / 60, b * (np.cosh(wv * free["t"]) - 1) / wv**2 + 1e-3, "--", color="black",
            lw=1, label=r"$(b/\omega_v^2)(\cosh\omega_v t - 1)$ (coincides)")
ax.semilogy(free["t"] / 60, b * free["t"] ** 2 / 2 + 1e-3, color=series_style(1)["color"],
            label=r"flat frame: $b t^2/2$")
ax.semilogy(held["t"] / 60, np.hypot(held["position"][:, 0], held["position"][:, 1]) + 1e-3,
            color=series_style(0)["color"], label="horizontal error, held")
ax.set(xlabel="t (min)", ylabel="error + 1 mm (m)", title="1 mg down bias at rest at 45° N")
fig.legend(loc="outside lower center", ncols=2)
plt.show()

# %% [markdown]
# On the flat frame, with gravity constant, the same bias gives $b t^2/2$: the two agree for
# the first few minutes ($\cosh x - 1 \approx x^2/2$), then the Earth's vertical channel runs
# away from the parabola — gravity's fall with height is the feedback the flat frame lacks.
# The held horizontal error is the hold's own step: between two holds the vertical velocity
# error grows by $b\,\Delta t$ and its Coriolis term pushes east, so the error halves when the
# height is held twice as often (above): it vanishes for a continuous height aid. (The
# navigation's `hold=` holds at every IMU sample, so its share shrinks with the sample step.)
#
# ## 7. When does the flat frame suffice?
# Notebooks 00–08 navigate on a flat, non-rotating Earth. On the real one that frame is wrong —
# the gyros sense the Earth's turn and the navigation takes it for the body's — and the error
# grows like $g\,\omega_{ie} \cos L\, t^3/6$ at rest. Whether that matters depends on the IMU:
# below, for each preset, the first time the flat frame's own error (an ideal IMU at rest at
# 45° N, its exact Earth signals navigated in the flat frame) exceeds the IMU's 95th-percentile
# position error (a covariance analysis of the same ten minutes).

# %%
origin45 = (45 * DEG, 7 * DEG, 100.0)
ten_min = Motion(duration=600.0)
cost = flat_frame_error(ten_min, origin45, 10.0)
k = np.searchsorted(cost["t"], [10.0, 60.0, 600.0])
print("the flat frame's cost at rest: " + ", ".join(
    f"{p:.3g} m after {t:g} s" for p, t in zip(cost["position"][k], cost["t"][k], strict=True)))
models = {p: ImuModel.load(p) for p in PRESETS if p != "ideal"}
table = flat_frame_suffices(ten_min, origin45, models, rate=10.0, cov_rate=1.0)
print(f"\n{'IMU':10s} {'gyro turn-on bias':>18s} {'bias instability':>17s} "
      f"{'flat frame suffices for':>24s} {'IMU error at 10 min':>20s}")
for row in table:
    gyro = models[row["imu"]].gyro
    bias, bi = (np.degrees(x or 0.0) * 3600 for x in (gyro.bias, gyro.bias_instability))
    span = "all 10 min" if row["seconds"] is None else f"{row['seconds']:.0f} s"
    print(f"{row['imu']:10s} {bias:13.3g} °/h {bi:12.3g} °/h {span:>24s} "
          f"{row['own_error_at_end_m']:17.3g} m")

# %% [markdown]
# A consumer or industrial MEMS IMU (BNO055 to ADIS16470) drifts far more than the flat frame
# costs: for them the Earth does not matter, and the flat frame is the faster, simpler choice.
# (The consumer IMUs' figures, tens to hundreds of thousands of kilometres, are not distances
# to read: a gyro bias
# of thousands to tens of thousands of °/h tilts them by radians within the ten minutes, far
# outside the covariance analysis's linear range — they say "lost unaided", which is all the
# verdict needs.)
# From tactical grade on, the Earth's turn is the larger error within minutes: navigate with
# `--earth wgs84`. (Aided by GNSS, the question changes: notebook 10 §6 puts a tactical IMU's
# longest bridgeable outage on both frames.)
#
# ## 8. Every algorithm on the Earth, its order kept
# The navigation on the Earth runs the body-frame algorithm of notebook 06 unchanged and adds
# the Earth's terms (gravity, the Earth rate, the transport rate) around it. Its own error
# should then be the algorithm's: of the same order in the sample step $\Delta t$ — the error
# falls as $\Delta t^p$, $p$ the algorithm's order — and of the same size as on the flat frame
# for the same local motion. Below, a few algorithms of each kind on a tumbling, translating
# motion (rolling, pitching and turning while it moves; 10 s) placed at 55° N, 37° E, 150 m,
# at three rates each, against the exact truth; the sixth-order increment algorithm reaches
# rounding on that motion, so its order is measured on a spinning cone instead (notebook 06's
# coning motion, which does not translate). The order is the slope of the largest attitude
# error against the step on log–log axes; the last column is the error on the Earth over the
# error of the same local motion navigated on the flat frame (the flat frame's own truth), at
# the middle rate.

# %%
MOVING = Motion(x="3*sin(0.4*t)", y="2*t + 0.1*t**2", z="-0.5*cos(0.6*t)",
                yaw="0.6*sin(0.5*t) + 0.1*t", pitch="0.25*sin(0.8*t)", roll="0.4*sin(1.2*t)",
                duration=10.0)
CONE = spinning_cone(30.0, 2.0, 1.0, duration=10.0)
MOVING_NAME = "tumbling, moving"
CASES = [("rates", "first_order", MOVING, (50.0, 100.0, 200.0)),
         ("rates", "magnus4", MOVING, (50.0, 100.0, 200.0)),
         ("rates", "magnus6", MOVING, (10.0, 20.0, 40.0)),
         ("increments", "first_order", MOVING, (50.0, 100.0, 200.0)),
         ("increments", "coning2", MOVING, (50.0, 100.0, 200.0)),
         ("increments", "poly6_m4", MOVING, (50.0, 100.0, 200.0)),
         ("increments", "poly8_m6", CONE, (50.0, 100.0, 200.0))]


def attitude_error(local, kind, algorithm, rate, earth):
    motion = EarthMotion(local, origin55) if earth == "wgs84" else local
    sig = simulate_imu(motion, rate, kind=kind)
    nav = navigate(sig, *motion.states([sig.t0]).initial(), algorithm=algorithm, earth=earth)
    return nav_errors(nav, motion).attitude.max()


orders = []
for kind, algo, local, rates in CASES:
    errs = [attitude_error(local, kind, algo, r, "wgs84") for r in rates]
    flat = attitude_error(local, kind, algo, rates[1], "flat")
    orders.append({"id": algorithm_id(kind, algo), "rates": rates, "errors": errs,
                   "motion": "spinning cone" if local is CONE else MOVING_NAME,
                   "order": fit_order([1 / r for r in rates], errs),
                   "documented": ALGORITHMS[kind][algo].order[0], "earth_over_flat": errs[1] / flat})
print(f"{'algorithm':34s} {'motion':>16s} {'rates (Hz)':>12s} {'measured order':>15s} "
      f"{'documented':>11s} {'Earth / flat':>13s}")
for o in orders:
    print(f"{name(o['id']):34s} {o['motion']:>16s} {'/'.join(f'{r:g}' for r in o['rates']):>12s} "
          f"{o['order']:15.2f} {o['documented']:11d} {o['earth_over_flat']:13.4f}")

# %% tags=["hide-input"]
fig, ax = figure(1, 1, height=3.0)
for o in orders:
    ax.loglog(1 / np.array(o["rates"]), np.degrees(o["errors"]), marker="o", ms=4,
              **thing_style(o["id"]), label=name(o["id"]) + (" (cone)" if o["motion"] != MOVING_NAME
                                                       else ""))
ax.set(xlabel="sample step Δt (s)", ylabel="largest attitude error (°)",
       title="on the Earth, 55° N: attitude error against the step")
fig.legend(loc="outside right center")
plt.show()

# %% [markdown]
# Each line's slope is its order; the measured orders are the documented ones, and on the
# Earth each algorithm's error is that of the same local motion on the flat frame: the
# Earth's terms, integrated beside the algorithm, add nothing to its error.
#
# ## Checks run by the tests

# %%
assert np.abs(resp["position"][:, 0] - closed).max() < 1e-3 * 2 * b / ws**2
assert np.abs(np.interp(resp["t"], nav.t, north_nav) - resp["position"][:, 0]).max() < 1.0
assert abs(2 * np.pi / ws / 60 - 84.3) < 0.1
assert 0.4 < np.hypot(*held2["position"][-1, :2]) / np.hypot(*held["position"][-1, :2]) < 0.6
per = {mo["mode"]: mo for mo in modes}
for key in ("Schuler − Foucault", "Schuler + Foucault"):
    assert abs(per[key]["rate_rad_s"] / formula[key] - 1) < 5e-3
assert abs(held["position"][:, 2]).max() < 1e-6 < abs(free["position"][-1, 2])
tac = next(r for r in table if r["imu"] == "tactical")
assert tac["seconds"] is not None and tac["seconds"] < 600
assert next(r for r in table if r["imu"] == "BNO055")["seconds"] is None
for o in orders:
    assert abs(o["order"] - o["documented"]) < 0.3 and abs(o["earth_over_flat"] - 1) < 0.01, o
print("checks passed")

# %% [markdown]
# ## Takeaways
#
# - On the real Earth the IMU measures the Earth's turn and a gravity that varies with latitude
#   and height; imunav simulates both exactly, and the algorithms measured in §8 (some of each
#   kind) keep their orders and their flat-frame errors there.
# - Horizontal errors are bounded by the Schuler loop (an 84-minute oscillation), whose plane
#   the Earth's rotation turns; the vertical channel diverges, e-folding in about ten minutes,
#   unless a height aid holds it.
# - The error model reproduces the closed forms and the nonlinear navigation; its eigenvalues
#   are the periods of a vehicle's free error dynamics.
# - For MEMS IMUs over minutes the flat frame suffices; for tactical-grade IMUs and long runs it
#   does not.
#
# ## Exercises
#
# **Exercise 1.** The Schuler period depends on where you are. Compute it on the equator and at
# the pole (R the geometric mean radius of curvature there). Gravity is larger at the pole —
# is the period shorter there?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
p_eq = 2 * np.pi / E.schuler_frequency(0.0) / 60
p_pole = 2 * np.pi / E.schuler_frequency(np.pi / 2) / 60
r_eq, r_pole = np.sqrt(np.prod(E.radii(0.0))), np.sqrt(np.prod(E.radii(np.pi / 2)))
print(f"Schuler period: {p_eq:.2f} min on the equator, {p_pole:.2f} min at the pole")
print(f"g grows by {100 * (E.GAMMA_P / E.GAMMA_E - 1):.2f} %, the radius of curvature by "
      f"{100 * (r_pole / r_eq - 1):.2f} %: the period is longer at the pole")
assert p_pole > p_eq

# %% [markdown]
# **Exercise 2.** How long does the Foucault turn take at 30° N for an IMU at rest? Compare the
# value of `error_periods` (half the difference of the two Schuler rates) with the formula.

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
m0 = {mo["mode"]: mo["rate_rad_s"] for mo in error_periods(lat30, 0.0)}
split = (m0["Schuler + Foucault"] - m0["Schuler − Foucault"]) / 2
print(f"Foucault rate {split:.4e} rad/s (model), {E.OMEGA_E * np.sin(lat30):.4e} rad/s "
      f"(ω_ie sin L): a turn in {2 * np.pi / split / 3600:.1f} h")
assert abs(split / (E.OMEGA_E * np.sin(lat30)) - 1) < 1e-2

# %% [markdown]
# **Exercise 3.** An origin at 91° N does not exist. What does `EarthMotion` say?

# %% tags=["hide-cell"] jupyter={"source_hidden": true, "outputs_hidden": true}
# Solution
try:
    EarthMotion(Motion(duration=1.0), (91 * DEG, 0.0, 0.0))
except ImunavError as exc:
    print(exc)
    assert "latitude must be within ±90°" in str(exc)
