# %% [markdown]
# # Plaksiy & Homozkova: four-rotation reference model and the drift of Miller's algorithm
#
# Source: *New reference model of rotation for orientation algorithms analysis* (OCR'd text).
# The paper's orientation quaternion Λ (λ₀ scalar, `∘` the Hamilton product) and its angular
# velocity `ω = 2 Λ̃ ∘ Λ̇` (eq. 4) are exactly imunav's `q_nb` and body rate `ω_b`, and its
# quasi-coordinates θ*ₙ (eq. 1) are imunav's gyro increments Δθ — no conversion is needed at
# this paper's boundary. Computation: `imunav.papers.plaksiy` and `imunav.symbolic.plaksiy`.
# Units: radians, seconds.
#
# ## Coverage: every figure, table and claim, and where it is settled
#
# | the paper | here | paper | imunav | verdict |
# |---|---|---|---|---|
# | eq. (3), Λ of four successive turns | §1–2 | — | λ₂ as printed is wrong (‖Λ‖ ≠ 1, up to 0.55 off); corrected: Λ = q₃(φ)∘q₂(ψ)∘q₁(ϑ)∘q₂(χ) | differs (typo) |
# | eq. (5), ω from (3) | §3 | — | derived from the corrected (3) identically (SymPy) | reproduced |
# | eqs. (6)–(7): "(5) leads to the analytical representations for the quasi-coordinates" | §4 | — | closed form by SymPy for linear laws; equals quadrature to 2e-12 rad over 1000 s | reproduced |
# | Fig. 1: quasi-coordinates, k = (0.15, 1.55, 0.35, −1.55) | §4 | (plot) | drawn | no paper value |
# | Fig. 2: configuration-space trajectories | §4 | (plot) | drawn | no paper value |
# | "more generalized case … in comparison with the regular precession" | §5 | — | regular precession is the special case φ = Ωt, ψ₀, ϑ₀, χ = ω_s t (5e-16 rad vs an independent construction); the Fig. 1 motion is not one (‖ω‖ 0.20–3.14 rad/s) | reproduced |
# | "can be used to model … vibrations … considering χ = −ψ" | §5 | — | with the Fig. 1 laws the body turns steadily at −1.55 rad/s about axis 2 (1554 rad in 1000 s) | differs |
# | Table 1: drift at 1000 s, 33/57, 36/54, 0/90 | §6 | 1.616, 1.601, 1.433 e−3 | 1.629, 1.645, 1.459 e−3 (fourth-order series update) | reproduced (each within 3 %) |
# | Table 1 / Fig. 3 b: "the optimized algorithm results in a smaller drift error" (36/54 below 33/57) | §6 | 0.991 | 1.010 | differs |
# | Conclusion: α = 0, β = 90/80 drifts less than both | §6 | 0.887 | 0.895 (relative to 33/57) | reproduced |
# | Fig. 3 a–c: drift vs time | §6 | (plot) | drawn beside the table values | no paper value |

# %%
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp
from ipywidgets import Dropdown, FloatSlider, interact

from imunav.papers import plaksiy as P
from imunav.symbolic import plaksiy as S

SEED = 0  # nothing here is random

# %% [markdown]
# ## 1. Eq. (3) as printed is not a unit quaternion
# The model: three turns in Krylov angles φ, ψ, ϑ, then a fourth by χ about the second rotated
# axis. Eq. (3) as printed (half angles written $c_x = \cos\frac{x}{2}$, $s_x = \sin\frac{x}{2}$):
#
# $$\begin{aligned}
# \lambda_0 &= c_\chi(c_\varphi c_\psi c_\vartheta + s_\varphi s_\psi s_\vartheta) - s_\chi(c_\varphi s_\psi c_\vartheta + s_\varphi c_\psi s_\vartheta)\\
# \lambda_1 &= c_\chi(c_\varphi c_\psi s_\vartheta - s_\varphi s_\psi c_\vartheta) - s_\chi(s_\varphi c_\psi c_\vartheta - c_\varphi s_\psi s_\vartheta)\\
# \lambda_2 &= c_\chi(c_\varphi s_\psi c_\vartheta + s_\varphi c_\psi s_\vartheta) + s_\chi(c_\varphi\,\mathbf{s_\psi}\,c_\vartheta + s_\varphi s_\psi s_\vartheta)\quad\text{(printed)}\\
# \lambda_2 &= c_\chi(c_\varphi s_\psi c_\vartheta + s_\varphi c_\psi s_\vartheta) + s_\chi(c_\varphi\,\mathbf{c_\psi}\,c_\vartheta + s_\varphi s_\psi s_\vartheta)\quad\text{(corrected)}\\
# \lambda_3 &= c_\chi(s_\varphi c_\psi c_\vartheta - c_\varphi s_\psi s_\vartheta) + s_\chi(c_\varphi c_\psi s_\vartheta - s_\varphi s_\psi c_\vartheta)
# \end{aligned}\qquad(3)$$
#
# (The OCR renders "cos" in front of χ/2 as "ños"; that is plainly an artefact.) `norm_defect`
# reduces `λ₀²+λ₁²+λ₂²+λ₃² − 1` to a canonical polynomial in the sines and cosines of the half
# angles (modulo `s² + c² − 1`): zero means `|Λ| ≡ 1`.

# %%
print("printed eq. (3):   |Λ|² − 1 ≡ 0 ?", S.norm_defect(False) == 0)
print("corrected eq. (3): |Λ|² − 1 ≡ 0 ?", S.norm_defect(True) == 0)

# %% [markdown]
# ## 2. Which rotation sequence is eq. (3)?
# Search all 81 axis sequences and both product orders, component by component, at random
# angles in 30-digit arithmetic:

# %%
for axes, left_to_right, ok in S.identify_sequence(corrected=False):
    print("printed  :", axes, "left-to-right" if left_to_right else "right-to-left",
          "components matching:", ok)
for axes, left_to_right, ok in S.identify_sequence(corrected=True):
    print("corrected:", axes, "left-to-right" if left_to_right else "right-to-left",
          "components matching:", ok)

# %% [markdown]
# Only `Λ = q₃(φ) ∘ q₂(ψ) ∘ q₁(ϑ) ∘ q₂(χ)` fits: φ about axis 3, then ψ about the new
# axis 2, ϑ about the new axis 1 (the Krylov/Tait–Bryan Z-Y-X sequence), then χ about the
# new axis 2 ("the second rotated axis"). λ₀, λ₁, λ₃ match as printed; **λ₂ does not**.
# The erratum — the first term of λ₂'s second bracket must carry cos ψ/2, not sin ψ/2:

# %%
l2_printed = S.printed_eq3(False)[2]
l2_corrected = S.printed_eq3(True)[2]
print("printed   λ₂ − corrected λ₂ =", sp.simplify(l2_printed - l2_corrected))

# %% [markdown]
# Corrected: λ₂ = cos χ/2 (cos φ/2 sin ψ/2 cos ϑ/2 + sin φ/2 cos ψ/2 sin ϑ/2)
# + sin χ/2 (cos φ/2 **cos** ψ/2 cos ϑ/2 + sin φ/2 sin ψ/2 sin ϑ/2).
#
# Could the printed sin ψ/2 be an OCR artefact? An OCR engine rarely turns a whole "cos" into
# "sin", but a typesetting slip in the original is just as possible; either way the mathematics
# is settled independently of the typography: the printed form is not a unit quaternion, the
# corrected one is exactly the rotation sequence above, and (next) the paper's own eq. (5)
# follows from the corrected form — so the corrected (3) is the model the paper used.
#
# ## 3. Eq. (5) follows from the corrected eq. (3)
#
# $$\vec\omega(t) = 2\tilde\Lambda(t)\circ\dot\Lambda(t)\quad(4)$$
#
# $$\begin{aligned}
# \omega_1 &= -\sin\chi(\dot\varphi\cos\psi\cos\vartheta - \dot\psi\sin\vartheta) + \cos\chi(\dot\vartheta - \dot\varphi\sin\psi)\\
# \omega_2 &= \dot\chi + \tfrac12\dot\varphi(\sin(\vartheta+\psi) + \sin(\vartheta-\psi)) + \dot\psi\cos\vartheta\\
# \omega_3 &= \sin\chi(\dot\vartheta - \dot\varphi\sin\psi) + \cos\chi(\dot\varphi\cos\psi\cos\vartheta - \dot\psi\sin\vartheta)
# \end{aligned}\qquad(5)$$
#
# Derive (4) symbolically for arbitrary angle laws φ(t), ψ(t), ϑ(t), χ(t) and subtract the
# printed eq. (5):

# %%
print("corrected (3): derived ω − printed (5) =", S.omega_discrepancy(True))
print("printed   (3): each component of derived ω − printed (5) vanishes?",
      [d == 0 for d in S.omega_discrepancy(False)])

# %% [markdown]
# Eq. (5) is right as printed (its `½ φ̇ (sin(ϑ+ψ) + sin(ϑ−ψ))` is `φ̇ sin ϑ cos ψ`). It is the
# body-frame rate of the **corrected** (3) — the typo in λ₂ is a typesetting slip, not a
# different model. The numeric model uses the verified product and eq. (5); the tests check
# it against the lambdified SymPy expressions.
#
# ## 4. The reference model: quasi-coordinates (Fig. 1, Fig. 2)
# The quasi-coordinates (the gyro's output over each step) and the seeming turn vector:
#
# $$\theta^*_{ni} = \int_{t_{n-1}}^{t_n}\omega_i(t)\,dt\ (1),\qquad
# \vec\theta(t) = \int_0^t\vec\omega\,dt\ (6),\qquad
# \theta^*_{ni} = \theta_i(t_n) - \theta_i(t_{n-1})\ (7).$$
#
# With linear laws φ = k₁t, ψ = k₂t, ϑ = k₃t, χ = k₄t, "the relation (5) leads to the analytical
# representations for the quasi-coordinates". It does: every product of sines and cosines of
# linear arguments is a sum of sinusoids, and SymPy integrates (5) in closed form. For the
# paper's k = (0.15, 1.55, 0.35, −1.55):

# %%
closed = S.seeming_turn_closed_form(P.PAPER_K)
for i, e in enumerate(closed, 1):
    print(f"θ{i}(t) =", e)
cf = P.closed_form_check()
print("max |closed form − adaptive quadrature| over 1000 s:",
      "< 1e-10 rad (rounding of θ ≈ 1500 rad)" if cf < 1e-10 else f"{cf:.1e} rad")

# %% [markdown]
# The numeric model integrates the quasi-coordinates by adaptive Gauss–Legendre quadrature,
# converged to 1e-13 relative (the tests compare with 30-digit mpmath quadrature) — an
# independent check on the closed form. Fig. 1 and Fig. 2:

# %%
motion = P.FourRotationMotion()
print("k =", motion.k, " laws:", [str(e) for e in motion.laws])

# %%
P.plot_quasi_coordinates(motion)
plt.show()

# %%
P.plot_configuration_space(motion)
plt.show()

# %% [markdown]
# ## 5. "More general than regular precession"; "χ = −ψ models vibration"
# **Regular precession** — a symmetric body spinning at ω_s about its symmetry axis while the
# axis precesses at Ω about a fixed axis at a constant tilt — is the special case φ = Ωt,
# ψ = ψ₀, ϑ = ϑ₀ (constants), χ = ω_s t of the model (the symmetry axis is the body's axis 2).
# Compared with an independent construction (scipy: $R_z(\Omega t)R_y(\psi_0)R_x(\vartheta_0)R_y(\omega_s t)$),
# and with the hallmarks of regular precession — constant |ω| and a constant angle between ω
# and the spin axis:

# %%
rp = P.regular_precession_check()
print("max angle, model vs independent regular precession:",
      "< 1e-14 rad" if rp["max_quaternion_difference"] < 1e-14 else rp["max_quaternion_difference"])
print("spread of |ω| and of the angle between ω and the spin axis:",
      "< 1e-12" if max(rp["omega_norm_spread"], rp["axis_angle_spread"]) < 1e-12 else
      (rp["omega_norm_spread"], rp["axis_angle_spread"]))
print(f"the paper's Fig. 1 motion: |ω| from {rp['paper_omega_norm_range'][0]:.2f} to "
      f"{rp['paper_omega_norm_range'][1]:.2f} rad/s — not a regular precession")

# %% [markdown]
# So the model contains regular precession and goes beyond it: the paper's claim holds.
#
# **Vibration with χ = −ψ.** A vibration turns the body back and forth, so its seeming turn
# vector θ(t) stays bounded. With χ = −ψ, $\omega_2 = k_2(\cos\vartheta - 1) + \dot\varphi\sin\vartheta\cos\psi$;
# for the paper's linear ϑ = k₃t, cos ϑ averages to 0 and the body turns steadily at −k₂ —
# the secular term of the closed form above (θ₂ = −31t/20 + …). Mean rates of θ over 1000 s:

# %%
vb = P.vibration_check()
print("secular rates of the closed form (rad/s):", vb["secular_rate_closed_form"])
print("mean rate of θ, paper's laws (rad/s):    ", np.round(vb["mean_rate_paper"], 5))
print(f"mean rate of θ, constant ϑ = {vb['small_vartheta']} (rad/s):",
      np.round(vb["mean_rate_small_vartheta"], 5),
      f" (−k₂(1 − cos ϑ) = {vb['expected_small']:.5f} on axis 2)")

# %% [markdown]
# With the paper's laws there is no vibration: 1554 rad about axis 2 in 1000 s. χ = −ψ cancels
# the ψ turn only when ϑ is small, and φ = k₁t still turns the body steadily about axis 3; a
# vibration needs bounded (e.g. sinusoidal) angle laws, which the model accepts (`phi=`,
# `psi=`, … take any law).

# %% [markdown]
# ## 6. Table 1: drift of Miller's algorithm at t = 1000 s, Δt = 0.1 s
# Each step's three sub-interval quasi-coordinates feed Miller's formula
#
# $$\bar\theta_n = \bar\theta^*_n + \alpha(\bar\theta^1_n\times\bar\theta^3_n) + \beta\,\bar\theta^2_n\times(\bar\theta^3_n - \bar\theta^1_n)\quad(2),\qquad
# \alpha = \tfrac{33}{80},\ \beta = \tfrac{57}{80}\ \text{(Miller)},\ \tfrac{36}{80},\tfrac{54}{80}\ \text{(conic)},\ 0,\tfrac{90}{80}\ \text{(8)};$$
#
# the rotation vector becomes a quaternion either **exactly** or by the fourth-order truncated
# series the paper calls "the algorithm of the fourth order": `[1 − θ²/8 + θ⁴/384,
# (½ − θ²/48) θ]`. The drift is the angle of the error quaternion `Λ_true* ∘ Λ` (its norm
# error removed — the paper's "non-removable residual").

# %%
inc = P.sub_increments(motion, 1000.0, 0.1)
runs = {k: [P.drift(motion, alpha=a, beta=b, form=f, increments=inc) for f in P.UPDATE_FORMS]
        for k, ((a, b), _) in P.TABLE1.items()}
print(f"{'(α, β)':14s} {'paper':>10s} {'series4':>10s} {'ratio':>6s} {'exact':>10s} {'ratio':>6s}")
for k, ((a, b), paper) in P.TABLE1.items():
    ex, s4 = runs[k]
    print(f"{a*80:3.0f}/80,{b*80:3.0f}/80  {paper:10.3e} {s4.final:10.3e} {s4.final/paper:6.3f} "
          f"{ex.final:10.3e} {ex.final/paper:6.3f}")

# %%
P.plot_drift(runs)
plt.show()

# %%
o = P.table1_ordering({k: r[1] for k, r in runs.items()})
print(f"conic/Miller: paper {o['paper_conic_over_miller']:.4f}, imunav {o['imunav_conic_over_miller']:.4f}")
print(f"new/Miller:   paper {o['paper_new_over_miller']:.4f}, imunav {o['imunav_new_over_miller']:.4f}")

# %% [markdown]
# The truncated series reproduces all three values to within 3 %; the exact update gives
# drifts ≈ 25 % lower — so about a quarter of the paper's drift is the series truncation,
# not Miller's formula. One thing we cannot reproduce is the paper's ordering of the first two
# rows (conic-optimised 36/54 *below* Miller's 33/57). On this motion the final drift is an
# almost exactly linear function of α along α + β = 90/80, increasing with α, under either
# update form — so any α > 33/80 on the line must drift more than Miller's set:

# %%
alphas = np.linspace(-0.5, 1.2, 18)
on_line = {f: P.drift_vs_alpha(motion, alphas, lambda a: 90 / 80 - a, form=f)
           for f in P.UPDATE_FORMS}
for f, d in on_line.items():
    slope, icpt = np.polyfit(alphas, d, 1)
    resid = np.abs(np.polyval([slope, icpt], alphas) - d).max()
    print(f"{f:8s}: d(drift)/dα = {slope:.3e} rad per unit α; linear to < 1e-6 rad: {resid < 1e-6}")

# %% [markdown]
# The slope is ≈ 4.1e-4 rad per unit α, so going from α = 33/80 to 36/80 adds
# ≈ 1.5e-5 rad — the difference we find (1.645e-3 vs 1.629e-3). The paper reports the
# opposite sign (−1.5e-5). Under our model this needs a different motion or a different
# drift measure; with the paper's data unavailable we state the discrepancy rather than tune it
# away.
#
# ## 7. Coefficient lab
# Along the line the drift keeps falling as α decreases, through the paper's α = 0, to an
# optimum well outside the usual range:

# %%
a_opt, d_opt = P.optimal_alpha_on_line(motion, form="series4")
a_ex, d_ex = P.optimal_alpha_on_line(motion, form="exact")
print(f"series4: optimum α = {a_opt:.3f} (β = {90/80 - a_opt:.3f}), drift {d_opt:.2e} rad")
print(f"exact  : optimum α = {a_ex:.3f} (β = {90/80 - a_ex:.3f}), drift {d_ex:.2e} rad")
print(f"paper's best (α = 0): {P.TABLE1['new_0_90'][1]:.3e} rad")

# %% [markdown]
# This optimum is specific to this motion (it tunes the coefficient to one spectrum, just as
# 36/54 is tuned to coning): it is a statement about the reference model, not a recommended
# algorithm. Off the line (series4 update):

# %%
ga = np.linspace(-1.0, 1.5, 11)
gb = np.linspace(0.4, 1.9, 11)
grid = P.drift_grid(motion, ga, gb)
P.plot_coefficient_lab(alphas, on_line, ga, gb, grid)
plt.show()

# %% [markdown]
# How the drift scales with the step (exact update, Miller's coefficients, 200 s):

# %%
dts = (0.4, 0.2, 0.1, 0.05)
d, order = P.drift_order(motion, dts)
for dt, x in zip(dts, d, strict=True):
    print(f"Δt = {dt:5.2f} s: drift {x:.3e} rad")
print(f"fitted order: {order:.2f}")

# %% [markdown]
# ## 8. Explore
# Change the frequencies, the step, the coefficients and the update form (200 s runs). The
# figure below is the starting state; in a live kernel the widget under it redraws.

# %%
def explore(k1=0.15, k2=1.55, k3=0.35, k4=-1.55, dt=0.1, alpha=33 / 80, beta=57 / 80,
            form="series4"):
    m = P.FourRotationMotion(k=(k1, k2, k3, k4))
    r = P.drift(m, 200.0, dt, alpha, beta, form)
    plt.figure(figsize=(8, 3.2))
    plt.plot(r.t, r.drift)
    plt.xlabel("t (s)")
    plt.ylabel("drift (rad)")
    plt.title(f"k = ({k1:g}, {k2:g}, {k3:g}, {k4:g}), α = {alpha:.4g}, β = {beta:.4g}, {form}: "
              f"final {r.final:.3e} rad")
    plt.tight_layout()
    plt.show()


explore()

# %%
# NBVAL_IGNORE_OUTPUT
def _slider(v, lo, hi, step, desc):
    return FloatSlider(value=v, min=lo, max=hi, step=step, description=desc,
                       continuous_update=False)


_ = interact(explore, k1=_slider(0.15, -2, 2, 0.05, "k₁"), k2=_slider(1.55, -2, 2, 0.05, "k₂"),
             k3=_slider(0.35, -2, 2, 0.05, "k₃"), k4=_slider(-1.55, -2, 2, 0.05, "k₄"),
             dt=_slider(0.1, 0.02, 0.5, 0.01, "Δt (s)"),
             alpha=_slider(33 / 80, -4, 2, 0.0125, "α"), beta=_slider(57 / 80, -2, 4, 0.0125, "β"),
             form=Dropdown(options=P.UPDATE_FORMS, value="series4", description="update"))

# %% [markdown]
# ## CI hook

# %%
finals = {k: runs[k][1].final for k in runs}
print({k: f"{v:.3e}" for k, v in finals.items()})
for k, ((_, _), paper) in P.TABLE1.items():
    assert np.isclose(finals[k], paper, rtol=0.03)   # paper Table 1, within 3 %
assert S.norm_defect(True) == 0 and S.omega_discrepancy(True) == (0, 0, 0)
assert a_opt < 0 and d_opt < 0.1 * P.TABLE1["new_0_90"][1]
assert o["imunav_conic_over_miller"] > 1 > o["paper_conic_over_miller"]   # the ranking differs
assert rp["max_quaternion_difference"] < 1e-14 and abs(vb["mean_rate_paper"][1] + 1.55) < 0.05
