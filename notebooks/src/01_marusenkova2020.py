# %% [markdown]
# # Marusenkova 2020: simulating IMU signals and restoring trajectories
#
# *A precise quaternion-based navigation algorithm for simulating signals of accelerometers
# and gyroscopes with low sample frequencies.* The paper simulates "ideal" IMU signals from a
# sampled trajectory and Euler-angle laws (Part A), restores the trajectory from them
# (Part B), finds that the classic small-rotation formulas do not restore it exactly, and
# proposes amended quaternion formulas (34)–(36) that do.
#
# `imunav.papers.marusenkova2020` implements the scheme **as printed**, in the paper's own
# conventions (which differ from imunav's — §2 computes how); `imunav.symbolic.marusenkova`
# checks its formulas symbolically. Every equation used is written below with its number; the
# source text is OCR'd, so each erratum says whether it could be an OCR artefact and what
# independent evidence settles it. Units: SI and radians; degrees only where printed.
#
# ## Coverage: every figure, numbered result and claim, and where it is settled
#
# | the paper | here | paper | imunav | verdict |
# |---|---|---|---|---|
# | eq. (5), $C_b^I$ as a product of three rotations | §1 | $C_b^I$ | the transpose of what (4) needs, $C_I^b$ | differs |
# | eq. (30), (5) expanded | §1 | — | element (3,3) $\cos\phi\cos\phi$ must be $\cos\theta\cos\phi$ | differs |
# | eqs. (31)–(33), the diagonal of $\Omega_{orig}$ | §1 | — | exact as printed (SymPy) | reproduced |
# | Ω(3,3) example: δθ = δφ = 0.1°, θ = 30°, 100 Hz | §1 | −2.63e−4 | −2.627e−4 by its simplification; exact −2.664e−4 | reproduced / differs |
# | Part A's gyroscope signal (17)–(20) | §2 | ω | −ω_n, not ω_b (7.6e−4 vs 0.99 rad/s away at t = 3 s) | differs |
# | Part A's accelerometer (21)–(22) | §2 | $a_b$ | the mirror image of a real reading | differs |
# | Fig. 3: 1 − cos α vs α − sin α | §3 | (plot) | ratio 34 at 5° | no paper value |
# | Figs. 1a, 1b, 2 a–d: restored trajectories | §4 | (plots) | the paper gives no rotation law; with ours 1.08 m (1a), 1.08 m (1b), 13.6 m (2) at 100 Hz | not reproducible |
# | observation 1: the trajectory influences the discrepancy | §5 | — | 1.08 m vs 13.6 m at 100 Hz | reproduced |
# | observation 3: a threshold frequency beyond which rate no longer helps | §5 | — | none: ∝ 1/rate up to 3200 Hz | differs |
# | observation 4 / "as can be seen from Figure 2, quaternions provide somewhat better accuracy" | §5 | — | Fig. 2: 1.79× (1.48–1.86× over rotation scales); Fig. 1a/1b: 0.82–1.65×, not general | reproduced on Fig. 2 / differs |
# | "L < M < N ⇒ the (1,3) asymmetry is the greatest, then (1,2), then (2,3)" | §6 | — | holds for 31 % of attitudes; reversed from level | differs |
# | "perfect coincidence … in x-y planes" without roll and pitch | §6 | — | z exact, x–y 0.28 m (fig1a) | differs |
# | eq. (34), Φ = 2 arccos(q₁) | §6 | — | keeps 9.6 of 16 digits at 100 Hz; harmless (1.4e−12 m either way) | no paper value |
# | amended (34)–(36) restore "any trajectory exactly" | §5, §7 | 0 | ≤ 6e−12 m — consistency: the pair inverts its own discretisation | reproduced |
# | amending only Part B | §5 | — | gains 3.7 orders (fig1a), 3.2 (fig2) | no paper value |
# | Conclusion 1: up to 1000 Hz the classic equations are "principally erroneous" | §7 | — | with real body-frame signals, high-order algorithms reach rounding at 100 Hz: the algorithm, not the rate, is the limit | differs |
# | Conclusion 2: DCMs "can scarcely be" amended | §6 | — | the exact DCM update (matrix log / Rodrigues) restores every trajectory to 9e−13 m | differs |
# | Conclusion 3: the quaternion correction eliminates the discrepancies completely | §5, §7 | — | within the paper's scheme yes; with real signals 0.9 m (rates) / 0.4 m (increments) at 100 Hz | reproduced (scheme) / differs (real signals) |
# | other slips: (3) integrates from $t_0$ to $t_0$; (18) writes $(C_{b_k}^I)^i$ for the transpose; "ψ_k, θ_k, ψ_k" lists ψ_k for φ_k | §1 | — | read off the equations | differs |

# %%
import matplotlib.pyplot as plt
import numpy as np
from ipywidgets import Dropdown, FloatSlider, IntSlider, interact

from imunav.analysis.family import fmt_err
from imunav.papers import marusenkova2020 as M
from imunav.symbolic import marusenkova as S

SEED = 0  # nothing here is random

# %% [markdown]
# ## 1. The formulas, checked symbolically
#
# The paper's integrations and frame change (its notation: $a_i$ inertial, $a_b$ body):
#
# $$\bar v(t) = v_0 + \int_{t_0}^{t}\bar a\,dt \quad(2),\qquad
# [x\;y\;z](t) = [x_0\;y_0\;z_0] + \int_{t_0}^{t_0}\bar v\,dt \quad(3)\ \text{as printed — the upper limit must be } t,$$
#
# $$a_i = C_b^I a_b \quad (4),\qquad
# C_b^I = \begin{pmatrix}1&0&0\\0&\cos\phi&\sin\phi\\0&-\sin\phi&\cos\phi\end{pmatrix}
# \begin{pmatrix}\cos\theta&0&-\sin\theta\\0&1&0\\\sin\theta&0&\cos\theta\end{pmatrix}
# \begin{pmatrix}\cos\psi&\sin\psi&0\\-\sin\psi&\cos\psi&0\\0&0&1\end{pmatrix}\quad(5).$$
#
# **Eq. (5) is the transpose of what eq. (4) needs.** The product of the three printed
# matrices equals $(R_z(\psi)R_y(\theta)R_x(\phi))^T$: it maps *inertial* vectors into the body
# frame. Each factor is the passive (transposed) rotation, so this is not an OCR slip — a
# sign lost in OCR would break orthogonality, and the product is orthogonal; the symbolic
# identity settles it:

# %%
print("eq. (5) ≡ (R_z R_y R_x)ᵀ, i.e. C_I^b:", S.eq5_is_transpose_of_zyx())

# %% [markdown]
# **Eq. (30)**, the expansion of (5), element by element against the product of the printed
# factors (the OCR's `S_bk` in element (1,2) reads `sin ψ_k` and is right):

# %%
for i, j, printed, correct in S.eq30_mismatches():
    print(f"element ({i},{j}): printed {printed}  →  correct {correct}")

# %% [markdown]
# As printed, $C(3,3) = \cos\phi_k\cos\phi_k$; it must be $\cos\theta_k\cos\phi_k$. Could OCR
# have turned θ into φ? Possibly (the two glyphs are close in some fonts). The evidence is
# independent of typography: with the printed element the matrix is not orthogonal, while the
# corrected one equals the product (5).
#
# **Eqs. (29)–(33)**: the paper's angular-velocity matrix and its diagonal,
#
# $$\Omega_{orig} = \left((C_{b_k}^I)^T C_{b_{k+1}}^I - I_3\right)/dt \quad(29),$$
#
# $$\Omega_{orig}(3,3) = \left(\cos\delta\theta\cos\delta\phi - \sin\theta_{k+1}\sin\theta_k(\cos\delta\phi-1) - 1\right)/dt \quad(33),$$
#
# and the longer (31), (32) for (1,1), (2,2). Each printed element is compared with the exact
# element of (29) by reducing the difference to a canonical polynomial in sines and cosines
# (modulo sin² + cos² = 1):

# %%
f = S.diagonal_findings()
for k in ("omega11", "omega22", "omega33"):
    print(f"Ω_orig({k[-2]},{k[-1]}) printed ≡ exact: {f[k]}")

# %% [markdown]
# All three are correct as printed. Other slips, read off the equations (not computable, and
# each could be typesetting rather than OCR): (3)'s upper limit $t_0$ must be $t$; (18) writes
# $\Omega_{orig} = (C_{b_k}^I)^i\,\dot C_b^I$ where the transpose $(\cdot)^T$ is meant; the text's
# list "ψ_k, θ_k, ψ_k, ψ_{k+1}, …" repeats ψ_k for φ_k.
#
# ### The numeric example: Ω_orig(3,3) for δθ = δφ = 0.1°, θ = 30°, 100 Hz
# The paper replaces $\sin\theta_{k+1}\sin\theta_k$ by $\theta_k^2 + \theta_k\delta\theta$
# ("sin θ ≈ θ") and prints −2.63e−4:

# %%
ex = S.omega33_example()
print(f"paper (printed)                 : {-2.63e-4:.3e}")
print(f"exact, eq. (33) ≡ eq. (29)      : {ex['exact']:.4e}")
print(f"paper's simplification sin θ ≈ θ: {ex['sin_as_angle']:.4e}  (θ in radians)")
print(f"classic assumption cos δ = 1    : {ex['cos_as_one']:.1f}")

# %% [markdown]
# The printed −2.63e−4 is exactly the paper's simplification with θ in radians; the exact
# value is −2.66e−4 (1.3 % away — sin 30° ≠ 0.524). The paper's point stands: the element is
# not 0.
#
# ## 2. The paper's conventions vs physics (computed)
# Part A's gyroscope signals:
#
# $$\dot C_b^I = \frac{C_{b_{k+1}}^I - C_{b_k}^I}{dt}\ (17),\quad
# \Omega_{orig} = (C_{b_k}^I)^T\dot C_b^I\ (18),\quad
# [\omega_x\ \omega_y\ \omega_z] = [-\Omega(2,3)\ \ \Omega(1,3)\ \ -\Omega(1,2)];$$
#
# $$[\omega_x\ \omega_y\ \omega_z] = \left[\tfrac{2q_{S.R.2}}{dt}\ \tfrac{2q_{S.R.3}}{dt}\ \tfrac{2q_{S.R.4}}{dt}\right]\ (19),\qquad
# q_{S.R.} = \left(q_{k+1}\otimes q_k^*/\lVert q_k\rVert\right)^*\ (20);$$
#
# and its accelerometer signals
#
# $$a_b = (C_{b_{k+1}}^I)^T(a_i - [0\ 0\ g])^T\ (21),\qquad
# [0\ a_b] = q_{k+1}\otimes[0,\ a_i - [0\ 0\ g]]\otimes q_{k+1}^*\ (22).$$
#
# With (5) being $C_I^b$ and the quaternion that makes (22) agree with (21), Part A's "gyro" is
# **minus the navigation-frame rate** $-\omega_n = -C_{nb}\,\omega_b$, not the body rate a real
# gyro measures; at the start, with a level body, the two coincide, so they are compared where
# they differ — at t = 3 s on Fig. 1a's motion (both at the interval's midpoint, where the
# paper's forward difference is centred):

# %%
g3 = M.gyro_vs_rates(3.0, 100.0)
np.set_printoptions(precision=4, suppress=True)
print(f"t = {g3['t']} s, fig1a, 100 Hz (rad/s)")
print("paper gyro, eq. (18):", g3["paper"])
print("−ω_n = −C_nb ω_b    :", g3["minus_omega_n"], f"  |Δ| = {g3['to_minus_omega_n']:.1e}")
print("real gyro ω_b       :", g3["omega_b"], f"  |Δ| = {g3['to_omega_b']:.2f}")

# %% [markdown]
# Its "accelerometer" of a body rolled 30° at rest is the **mirror image** of the real reading
# $[0, -g\sin 30°, -g\cos 30°]$:

# %%
d = M.convention_demo()
print("paper accel, rolled 30°:", d["paper_accel_rolled_30"])
print("real accel,  rolled 30°:", d["real_accel_rolled_30"])

# %% [markdown]
# Part B inverts Part A consistently (its (23) and (27) use the same matrix), so round trips
# close regardless — but signals from Part A cannot be compared with a real IMU's. The
# physically correct signals come from `imunav.simulate_imu` (§7).
#
# ## 3. Fig. 3: cosines and sines of small angles

# %%
deg, omc, ams = M.fig3_data()
print(f"at α = 5°: 1 − cos α = {omc[-1]:.4e}, α − sin α = {ams[-1]:.4e}, "
      f"ratio {omc[-1] / ams[-1]:.2f}")

# %%
plt.figure(figsize=(6.5, 3.8))
plt.plot(deg, omc, label="1 − cos α")
plt.plot(deg, ams, label="α − sin α")
plt.xlabel("α (deg)")
plt.title("Fig. 3: cosines and sines of small angles")
plt.legend()
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 4. Figs. 1 and 2: original vs restored trajectories
# Part B restores with
#
# $$C_{b_{k+1}}^I = C_{b_k}^I + C_{b_k}^I\,\Omega_{restored}\,dt\ (23),\quad
# \Omega_{restored} = \begin{pmatrix}0&-G_z&G_y\\G_z&0&-G_x\\-G_y&G_x&0\end{pmatrix}(24),\quad
# \Delta q = \left[1\ \ \tfrac12G_x dt\ \ \tfrac12G_y dt\ \ \tfrac12G_z dt\right](25),\quad
# q_{k+1} = \Delta q^*\otimes q_k\ (26),$$
#
# then (27)/(28), the inverses of (21)/(22), and the rectangle sums of (2), (3). The paper gives
# no rotation law for its figures; we use one that turns about all three axes (so the figures
# are "not reproducible" as numbers, and their qualitative content is what is compared):

# %%
print(M.DEFAULT_ROTATION, "| durations (s):", M.DURATION)

# %%
for fig, rate, a, b in (("fig1a", 100, "dcm", "dcm"), ("fig1b", 100, "dcm", "dcm"),
                        ("fig1b", 800, "dcm", "dcm"), ("fig2", 100, "dcm", "dcm"),
                        ("fig2", 1000, "dcm", "dcm"), ("fig2", 100, "quat", "quat"),
                        ("fig2", 1000, "quat", "quat")):
    M.plot_round_trip(M.round_trip(fig, rate, a, b), f"{fig}, {rate} Hz, A={a}, B={b}")
    plt.tight_layout()
    plt.show()

# %% [markdown]
# ## 5. Every A/B combination at 100, 800 and 1000 Hz
# Maximum position discrepancy in metres; below 1e-9 m is rounding. `dcm_amended` is not in
# the paper — it is imunav's answer to Conclusion 2 (§6).

# %%
rows = M.combination_table()
combos = [(a, b) for a in M.PAPER_SCHEMES for b in M.PAPER_SCHEMES] + [("dcm_amended",
                                                                        "dcm_amended")]
for fig in ("fig1a", "fig1b", "fig2"):
    print(f"--- {fig}")
    print(f"{'A → B':32s}" + "".join(f"{r:>11d} Hz" for r in (100, 800, 1000)))
    for a, b in combos:
        vals = [r["max"] for r in rows if (r["fig"], r["A"], r["B"]) == (fig, a, b)]
        cells = "".join(f"{v:14.3e}" if v >= 1e-9 else f"{'<1e-9':>14s}" for v in vals)
        print(f"{a + ' → ' + b:32s}{cells}")

# %% [markdown]
# Read off the table: the trajectory matters (observation 1: 1.08 m on Fig. 1a, 13.6 m on
# Fig. 2 at 100 Hz); amended quaternions in both parts restore every trajectory to rounding
# (the paper's claim — but see §7 for why that is consistency, not accuracy); amending only
# Part B already gains three to four orders of magnitude:

# %%
for fig in ("fig1a", "fig2"):
    c = [r["max"] for r in rows if (r["fig"], r["A"], r["B"], r["rate"]) == (fig, "quat", "quat", 100)][0]
    b = [r["max"] for r in rows if (r["fig"], r["A"], r["B"], r["rate"]) == (fig, "quat", "quat_amended", 100)][0]
    print(f"{fig}: classic {c:.3g} m → Part B amended {b:.3g} m: {np.log10(c / b):.1f} orders")

# %% [markdown]
# **Do quaternions beat DCMs?** ("As can be seen from Figure 2, quaternions provide somewhat
# better accuracy"; observation 4: "quaternions generally demonstrate better accuracy".) The
# classic DCM / classic quaternion discrepancy ratio per figure, for rotation laws from half to
# three times ours:

# %%
for scale in (0.5, 1.0, 2.0, 3.0):
    rot = {k: f"{scale}*({v})" for k, v in M.DEFAULT_ROTATION.items()}
    ratio = [M.round_trip(f, 100, "dcm", "dcm", rot)["max"]
             / M.round_trip(f, 100, "quat", "quat", rot)["max"] for f in ("fig1a", "fig1b", "fig2")]
    print(f"rotation × {scale}: DCM/quaternion  fig1a {ratio[0]:.2f}  fig1b {ratio[1]:.2f}  "
          f"fig2 {ratio[2]:.2f}")

# %% [markdown]
# On Fig. 2 quaternions win at every scale (1.5–1.9×), as the paper reads off its figure; on
# Figs. 1a/1b the ranking depends on the rotation law (DCMs win at half our rotation): not a
# general property.
#
# ### Is there a "threshold frequency"? (observation 3)

# %%
rates = (25, 50, 100, 200, 400, 800, 1600, 3200)
curves = M.error_vs_rate("fig1a", rates)
for (a, b), e in curves.items():
    cells = " ".join(f"{x:8.1e}" if x >= 1e-9 else f"{'<1e-9':>8s}" for x in e)
    print(f"{a:>12s} → {b:12s} {cells}")

# %%
M.plot_error_vs_rate(curves, rates)
plt.tight_layout()
plt.show()

# %% [markdown]
# No. Within the paper's own scheme the classic discrepancy falls as 1/rate (first order) all
# the way to 3200 Hz, and classic-A/amended-B as 1/rate². Whatever stopped improving in the
# paper's experiments is not in the scheme as printed.
#
# ## 6. The paper's reasoning about Ω_orig, and its Conclusion 2
#
# **The asymmetry ordering.** "If the body moves L degrees around x-axis, N degrees around
# y-axis and M degrees around z-axis and L < M < N, then the difference between |Ω(1,3)| and
# |Ω(3,1)| will be the greatest, followed by (1,2) and then (2,3)." Per step δφ = 0.1°,
# δψ = 0.2°, δθ = 0.3° (L < M < N), from 20 000 attitudes drawn at random:

# %%
asym = M.omega_asymmetry()
print(f"the stated ordering 13 > 12 > 23 holds for {100 * asym['holds']:.1f} % of attitudes")
print("how often each ordering occurs:", {k: round(v, 3) for k, v in asym["orderings"].items()})
print("from the level attitude:", {k: f"{v:.2e}" for k, v in asym["level"].items()})

# %% [markdown]
# The ordering depends on the attitude, not on L < M < N: from the level attitude it is exactly
# reversed (23 > 12 > 13).
#
# **"Perfect coincidence of trajectories in x-y planes when there are no rotations around axes
# x and y."** Yaw only (our yaw law, pitch = roll = 0), classic DCM in both parts:

# %%
for r in M.xy_coincidence():
    print(f"{r['fig']}: max x–y discrepancy {r['xy']:.3g} m, max z discrepancy {r['z']:.1g} m")

# %% [markdown]
# With yaw only, (33) gives Ω(3,3) = 0 exactly, and the third axis is restored exactly — but
# Ω(1,1) = Ω(2,2) = (cos δψ − 1)/dt ≠ 0, so x and y are not. The coincidence the paper's
# reasoning supports is along z; "x-y planes" does not hold (perhaps it meant the planes
# containing z, but x–y is what is written).
#
# **Eq. (34)'s Φ = 2 arccos(q₁).** Near q₁ = 1 the arccos amplifies the rounding of q₁ by
# $1/\sin(\Phi/2)$:

# %%
dg = M.arccos_digits()
print(f"median step {dg['median_step_rad']:.1e} rad: Φ keeps {dg['digits_kept']:.1f} of 16 "
      f"digits (worst relative error {dg['max_rel_error']:.1e})")
print(f"amended round trip: arccos {fmt_err(dg['round_trip_arccos'], 1e-10)} m, "
      f"atan2 {fmt_err(dg['round_trip_atan2'], 1e-10)} m  (below 1e-10 m: rounding)")

# %% [markdown]
# Six digits are lost at 100 Hz, and it does not matter here: both round trips are at rounding.
#
# **Conclusion 2: DCMs "can scarcely be" amended.** The paper amends the quaternion of a small
# rotation (its (34)–(36)):
#
# $$\omega = \frac{q_{S.R.(2..4)}\,\lvert\Phi\rvert}{\sin\frac{\lvert\Phi\rvert}{2}\,dt}\ (34),\quad
# \Phi = dt\sqrt{G_x^2+G_y^2+G_z^2}\ (35),\quad
# \Delta q = \left[\cos\tfrac{\lvert\Phi\rvert}{2}\ \ G\,\sin\tfrac{\lvert\Phi\rvert}{2}\tfrac{dt}{\lvert\Phi\rvert}\right]\ (36).$$
#
# The same amendment exists for DCMs, exactly: in Part A the rotation vector of
# $(C_{b_k}^I)^T C_{b_{k+1}}^I$ (the matrix logarithm; scipy's, independent of the quaternion
# code), in Part B Rodrigues' formula
# $C_{b_{k+1}}^I = C_{b_k}^I\left(I + \frac{\sin\varphi}{\varphi}K + \frac{1-\cos\varphi}{\varphi^2}K^2\right)$,
# $K = [G\,dt\times]$, $\varphi = \lvert G\rvert dt$:

# %%
for fig in ("fig1a", "fig1b", "fig2"):
    v = [M.round_trip(fig, 100, a, b)["max"] for a, b in
         (("dcm", "dcm"), ("dcm_amended", "dcm_amended"), ("quat_amended", "quat_amended"))]
    print(f"{fig} at 100 Hz: classic DCM {v[0]:.3g} m | exact DCM {fmt_err(v[1], 1e-10)} m | "
          f"amended quaternion {fmt_err(v[2], 1e-10)} m")

# %% [markdown]
# A DCM scheme is amended as exactly as the quaternion one — Conclusion 2 does not hold. The
# Euler angles "that change from step to step" do not enter: the logarithm of the relative
# rotation does the work, whatever represents it.
#
# ## 7. The honest part: why "amended" is exact, and what a real sensor changes
# **What it inverts.** Part A turns positions into V and A by forward differences and attitudes
# into "rates" by the exact logarithm of consecutive attitudes (34); Part B undoes exactly those
# operations — rectangle sums and the exact exponential (36). The round trip is exact by
# construction: a consistency check, not accuracy. Give Part A the *true* velocity and
# acceleration instead of its finite differences, and the amended round trip is first-order
# again:

# %%
for rate in (100, 1000):
    r = M.amended_with_exact_kinematics("fig1a", rate)
    fd = "< 1e-9" if r["finite_differences"] < 1e-9 else f"{r['finite_differences']:.3e}"
    print(f"{rate:5d} Hz: finite differences {fd} m (rounding) | "
          f"exact kinematics {r['exact_kinematics']:.3e} m")

# %% [markdown]
# **Real sensors.** A real IMU outputs body-frame rates sampled at instants, or increments
# integrated over each interval — `imunav.simulate_imu` produces both from the analytic motion.
# Restoring Fig. 1a's motion from them with the paper's Part B updates (transcribed to
# body-frame conventions, with its rectangle integration) and with imunav's algorithms:

# %%
phys = M.physical_table("fig1a")
print(f"{'signals':10s} {'restoration':28s} {'100 Hz pos (m)':>15s} {'1000 Hz pos (m)':>16s}")
for kind in ("rates", "increments"):
    for sch in dict.fromkeys(r["scheme"] for r in phys if r["kind"] == kind):
        v = [r["max_pos"] for r in phys if (r["kind"], r["scheme"]) == (kind, sch)]
        cells = "".join(f"{x:15.2e} " if x >= 1e-9 else f"{'<1e-9':>15s} " for x in v)
        print(f"{kind:10s} {sch:28s} {cells}")

# %% [markdown]
# With real signals the amended scheme is no longer exact: 0.9 m (rates) and 0.4 m
# (increments) at 100 Hz, first order. Its attitude update is fine — the same exponential in
# imunav's `exact_exponential` gives millimetres — the rectangle-rule velocity/position is
# what costs. The winners are imunav's high-order offline algorithms (`magnus6` on rates,
# `poly8_m6` on increments), at rounding level even at 100 Hz. Against Conclusion 1: the low
# sample rate of a BNO055-class sensor (100 Hz) is not, by itself, what prevents exact
# restoration; the integration algorithm is.
#
# ## 8. Explore
# Trajectory, rotation scale, rate and the A/B schemes (including the exact DCM). The figure
# below is the starting state; in a live kernel the widget under it redraws.

# %%
def explore(fig="fig1a", rot_scale=1.0, rate=100, A="dcm", B="dcm"):
    rot = {k: f"{rot_scale}*({v})" for k, v in M.DEFAULT_ROTATION.items()}
    M.plot_round_trip(M.round_trip(fig, rate, A, B, rotation=rot), f"{fig}, {rate} Hz, {A} → {B}")
    plt.tight_layout()
    plt.show()


explore()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(explore, fig=Dropdown(options=list(M.TRAJECTORIES), description="trajectory"),
             rot_scale=FloatSlider(value=1.0, min=0.0, max=3.0, step=0.1,
                                   continuous_update=False, description="rotation ×"),
             rate=IntSlider(value=100, min=20, max=2000, step=20, continuous_update=False,
                            description="rate (Hz)"),
             A=Dropdown(options=M.SCHEMES, description="Part A"),
             B=Dropdown(options=M.SCHEMES, description="Part B"))

# %% [markdown]
# ## CI hook

# %%
cl = {fig: [r["max"] for r in rows if (r["fig"], r["A"], r["B"], r["rate"]) == (fig, "dcm", "dcm", 100)][0]
      for fig in ("fig1a", "fig1b", "fig2")}
print({k: f"{v:.3g}" for k, v in cl.items()})
assert np.isclose(ex["sin_as_angle"], -2.63e-4, rtol=3e-3)   # paper's printed value (3 digits)
assert all(r["max"] < 1e-9 for r in rows
           if (r["A"], r["B"]) in (("quat_amended", "quat_amended"), ("dcm_amended", "dcm_amended")))
assert all(v > 0.5 for v in cl.values())
assert asym["holds"] < 0.5 and g3["to_omega_b"] > 100 * g3["to_minus_omega_n"]
