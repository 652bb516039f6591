# %% [markdown]
# # The strapdown algorithm family on closed-form benchmarks
#
# Every algorithm in `imunav.ALGORITHMS`, run on motions whose attitude and body rate are
# known in closed form (coning, spinning cone, sculling, the Plaksiy four-rotation model,
# stationary). Errors are against the analytic truth, with an `atan2`-based angle that
# resolves errors far below 1e-6°.

# %%
import matplotlib.pyplot as plt
from ipywidgets import Dropdown, FloatLogSlider, FloatSlider, interact

import imunav
from imunav import plotting
from imunav.analysis import family as F
from imunav.motion import catalog as B

SEED = 0  # nothing here is random

# %% [markdown]
# ## 1. The algorithms

# %%
for kind, table in imunav.ALGORITHMS.items():
    for name, a in table.items():
        flag = "causal " if a.causal else "offline"
        print(f"{kind:10s} {name:18s} order {a.order}  {flag}  {a.source}")

# %% [markdown]
# ## 2. Classical coning: 5° half-angle, 2 Hz, 60 s
# The case on which open tools are usually compared: the best open Python integrator
# (exact increments plus a two-sample coning correction, as in pyins) ends ≈ 0.0013° off,
# rate-based integrators 0.2–0.9°. Here is the whole family at 100 Hz and 400 Hz:

# %%
cone = B.coning(5.0, 2.0, duration=60.0)
fam100 = F.run_family(cone, 100.0)
print("100 Hz")
print(F.format_family(fam100))
fam400 = F.run_family(cone, 400.0)
print("400 Hz")
print(F.format_family(fam400))

# %%
best = {r["algorithm"]: r for r in fam100 if r["kind"] == "increments"}
ratio = best["coning2"]["max_att_deg"] / best["poly8_m6"]["max_att_deg"]
print(f"default (poly8_m6) vs coning2: {ratio:.1e}× better")
causal = [r for r in fam100 if r["causal"] and r["kind"] == "increments"]
bc = min(causal, key=lambda r: r["final_att_deg"])
print(f"best causal at 100 Hz (final error, at its major updates): {bc['algorithm']}, "
      f"{bc['final_att_deg']:.1e}°; max over all outputs {bc['max_att_deg']:.1e}°")

# %% [markdown]
# The multi-sample (Ignagni, Miller) algorithms update once per 3 or 4 increments; at those
# instants Ignagni's 4-sample set ends 1.8e-6° off, but the attitudes between major updates
# (second-order product of exponentials) are ≈ 2e-4° off. The best *causal* algorithm that is
# accurate at every sample is `coning2` (the 1+1 "previous interval" form).
#
# ## 3. Why exact increments plus a coning term beat exponentials of rate samples
# `q ⊗ exp(Δθ)` assumes the rotation axis is fixed within each interval. In coning it is not,
# and the exponential misses the non-commutativity term ½∫α×ω dt of every interval. That
# missing term, summed, *is* the drift:

# %%
budget = F.coning_correction_budget(cone, 100.0)
for k, v in budget.items():
    print(f"{k:34s} {v:.3e} rad")

# %% [markdown]
# The exact-exponential error on exact increments (7.53e-3 rad) equals the accumulated
# two-sample coning terms Σ Δθₖ₋₁×Δθₖ/12 to 0.3 %; adding them (`coning2`) removes 99.7 % of
# the error. Rate samples are worse still (1.5e-2 rad): a sample is the rate at one instant,
# and a constant-rate step through it misses both the coning term and the curvature of ω
# across the interval. The Marusenkova paper's "amended" exponential (its eq. 36) is
# `exact_exponential` here: exact for a constant rate, but not for real motion.
#
# ## 4. Which offline configuration is cheapest under the target (1.3e-6° at 100 Hz)?
# A centred polynomial fit of the cumulative increments (exact at every node) and Magnus
# steps of order 4 or 6. Cost counted in rate evaluations per interval:

# %%
configs = [(4, 4, 1), (6, 4, 1), (6, 4, 2), (6, 6, 1), (8, 4, 1), (8, 4, 2), (8, 4, 4), (8, 6, 1),
           (10, 6, 1)]
sweep = F.poly_sweep(cone, 100.0, configs)
print(f"{'nodes':>5s} {'Magnus':>6s} {'substeps':>8s} {'evals':>5s} {'max att (deg)':>14s}  target met")
for r in sweep:
    print(f"{r['nodes']:5d} {r['magnus']:6d} {r['substeps']:8d} {r['evals_per_interval']:5d} "
          f"{r['max_att_deg']:14.2e}  {r['max_att_deg'] <= 1.3e-6}")

# %%
# NBVAL_IGNORE_OUTPUT
for r in sweep:
    print(f"{r['nodes']}-node fit, Magnus-{r['magnus']} × {r['substeps']}: "
          f"{r['seconds'] / 6000 * 1e6:.2f} µs per sample (this machine)")

# %% [markdown]
# An 8-node fit with a single sixth-order Magnus step (3 evaluations per interval) is the
# cheapest configuration that meets the target, with ~70× margin: it is `poly8_m6`, the
# default for increments. The first and last intervals use one-sided (shifted) stencils; their
# one-step errors are ≈10× the interior ones but they are 2 of 6000 intervals and contribute
# < 1 % of the final error (checked in `tests/test_strapdown.py`).
#
# ## 5. Convergence orders
# Maximum error vs sample rate, with the documented order as a dotted line. Sixth-order
# methods reach rounding (1e-15 rad) quickly, so they are measured on a 30° spinning cone.

# %%
sc = B.spinning_cone(30.0, 2.0, 1.0, duration=10.0)
conv_inc = F.convergence(sc, (50, 100, 200), "increments")
conv_rates = F.convergence(B.four_rotation(20.0), (25, 50, 100), "rates")
for r in conv_inc + conv_rates:
    print(f"{r['kind']:10s} {r['algorithm']:18s} documented {r['documented'][0]}  "
          f"measured {r['order_att']:.1f}")

# %%
fig, axs = plt.subplots(1, 2, figsize=(15, 5))
plotting.plot_convergence(conv_inc, axs[0])
axs[0].set_title("increments, 30° spinning cone")
plotting.plot_convergence(conv_rates, axs[1])
axs[1].set_title("rates, four-rotation model")
plt.tight_layout()
plt.show()

# %% [markdown]
# The multi-sample coning algorithms (and `coning2`) converge at order 4 on this cone-type
# motion — the motion their coefficients are designed for — but at order 3 on general motion
# (the documented order, measured in `tests/test_strapdown.py` on a motion that translates and
# turns about all axes): the neglected Bortz term ⅟₁₂ φ×(φ×ω) is O(h⁴) per step there. The
# polynomial-fit and Magnus algorithms show their documented order on both.
#
# ## 6. Every benchmark at 100 Hz (final errors; below 1e-11 is rounding)

# %%
for make in B.BENCHMARKS.values():
    m = make(duration=20.0)
    rows = F.run_family(m, 100.0)
    print(f"--- {m.name}")
    for r in rows:
        if r["algorithm"] in ("exact_exponential", "coning2", "magnus4", "magnus6", "poly8_m6"):
            print(f"{r['kind']:10s} {r['algorithm']:18s} att {F.fmt_err(r['final_att_deg'])}° "
                  f"vel {F.fmt_err(r['max_vel'])} m/s  pos {F.fmt_err(r['max_pos'])} m")

# %%
fig, axs = plt.subplots(1, 2, figsize=(15, 4))
names = [("rates", "exact_exponential"), ("rates", "magnus6"), ("increments", "exact_exponential"),
         ("increments", "coning2"), ("increments", "ignagni4"), ("increments", "poly8_m6")]
plotting.plot_error_vs_time(cone, 100.0, names, ax=axs[0])
plotting.plot_error_vs_time(B.sculling(duration=20.0), 100.0, names, ax=axs[1])
plt.tight_layout()
plt.show()

# %% [markdown]
# ## 7. Explore
# Cone half-angle and frequency, sample rate, two algorithms. The figure below is the starting
# state; in a live kernel the widget under it redraws when a control is released.

# %%
choices = [f"{k}/{n}" for k, t in imunav.ALGORITHMS.items() for n in t]


def explore(half_angle=5.0, freq=2.0, rate=100.0, a="increments/coning2",
            b="increments/poly8_m6"):
    m = B.coning(half_angle, freq, duration=20.0)
    ax = plotting.plot_error_vs_time(m, rate, [tuple(a.split("/")), tuple(b.split("/"))])
    ax.set_title(f"coning β = {half_angle:g}°, {freq:g} Hz, sampled at {rate:.3g} Hz")
    plt.tight_layout()
    plt.show()


explore()

# %%
# NBVAL_IGNORE_OUTPUT
_ = interact(explore,
             half_angle=FloatSlider(value=5, min=0.5, max=45, step=0.5, continuous_update=False,
                                    description="β (deg)"),
             freq=FloatSlider(value=2, min=0.1, max=10, step=0.1, continuous_update=False,
                              description="f (Hz)"),
             rate=FloatLogSlider(value=100, base=10, min=1.3, max=3, continuous_update=False,
                                 description="rate (Hz)"),
             a=Dropdown(options=choices, value="increments/coning2", description="algorithm A"),
             b=Dropdown(options=choices, value="increments/poly8_m6", description="algorithm B"))

# %% [markdown]
# ## CI hook

# %%
print(f"poly8_m6 coning 100 Hz: {best['poly8_m6']['max_att_deg']:.2e} deg")
assert best["poly8_m6"]["max_att_deg"] <= 1.3e-6
assert 1e-3 < best["coning2"]["max_att_deg"] < 1.7e-3
motion_independent = {"first_order", "exact_exponential", "poly6_m4", "poly8_m6", "magnus4",
                      "magnus6"}
for r in conv_inc + conv_rates:
    if r["algorithm"] in motion_independent and (r["kind"], r["algorithm"]) != ("rates", "first_order"):
        assert abs(r["order_att"] - r["documented"][0]) < 0.35, r["algorithm"]
