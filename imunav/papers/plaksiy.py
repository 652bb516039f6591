"""Plaksiy & Homozkova: four-rotation reference model of rotation and Miller-algorithm drift.

Conventions at the boundary: the paper's quaternion Λ (``∘`` = Hamilton product, λ₀ scalar)
and its angular velocity ω = 2 Λ̃ ∘ Λ̇ (eq. (4)) are exactly imunav's ``q_nb`` and body rate
``ω_b``; the paper's "quasi-coordinates" θ*ₙ (eq. (1)) are imunav's gyro increments Δθ.
Eq. (3) as printed has a typo in λ₂ (see :mod:`imunav.symbolic.plaksiy`); the model
(:class:`~imunav.motion.quaternion_law.FourRotationMotion`, general and so in the motion layer)
uses the corrected, verified product ``Λ = q₃(φ) ∘ q₂(ψ) ∘ q₁(ϑ) ∘ q₂(χ)``.

May import: anything below the papers (``imunav.core`` … ``imunav.io``), ``imunav.symbolic``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from imunav.analysis.metrics import fit_order
from imunav.core.rotations import FloatArray, _angle, _exp
from imunav.core.validation import ImunavError, as_float_array, check_positive
from imunav.motion.base import BaseMotion
from imunav.motion.quaternion_law import PAPER_K as PAPER_K  # the paper's Fig. 1–3 frequencies
from imunav.motion.quaternion_law import FourRotationMotion
from imunav.papers.records import record
from imunav.sensors.quadrature import integrate_intervals
from imunav.strapdown.scan import cumulative_product
from imunav.symbolic import plaksiy as S

#: Table 1: (α, β) → final drift (rad) at t = 1000 s, Δt = 0.1 s.
TABLE1 = {
    "miller_33_57": ((33 / 80, 57 / 80), 1.616e-3),
    "conic_36_54": ((36 / 80, 54 / 80), 1.601e-3),
    "new_0_90": ((0.0, 90 / 80), 1.433e-3),
}

UPDATE_FORMS = ("exact", "series4")


def quasi_coordinates(motion: BaseMotion, edges: npt.ArrayLike) -> FloatArray:
    """θ*ₙ = ∫ ω dt over each ``[edges[n−1], edges[n]]`` (eqs. (1), (7)); shape (N, 3): the
    paper's quasi-coordinates are imunav's gyro increments, integrated to 1e-13 relative
    (checked against 30-digit mpmath quadrature in the tests)."""
    e = as_float_array(edges, "edges", ndim=1)
    return integrate_intervals(motion.angular_rate, e[:-1], e[1:])


def seeming_turn_vector(motion: BaseMotion, t: npt.ArrayLike) -> FloatArray:
    """θ(t) = ∫₀ᵗ ω dt (eq. (6)), for an increasing time grid starting anywhere ≥ 0."""
    t = as_float_array(t, "t", ndim=1)
    return np.cumsum(quasi_coordinates(motion, np.concatenate([[0.0], t])), axis=0)


def miller_rotation_vector(th1: npt.ArrayLike, th2: npt.ArrayLike, th3: npt.ArrayLike,
                           alpha: float, beta: float) -> FloatArray:
    """Eq. (2): θₙ = θ*ₙ + α (θ¹ × θ³) + β θ² × (θ³ − θ¹), θ*ₙ = θ¹ + θ² + θ³."""
    th1 = as_float_array(th1, "th1", last=3)
    th2 = as_float_array(th2, "th2", last=3)
    th3 = as_float_array(th3, "th3", last=3)
    return th1 + th2 + th3 + alpha * np.cross(th1, th3) + beta * np.cross(th2, th3 - th1)


def rotation_quaternion(phi: npt.ArrayLike, form: str = "exact") -> FloatArray:
    """Quaternion of a rotation vector: ``exact`` = [cos(θ/2), sin(θ/2) θ/|θ|], or ``series4``
    = the series truncated at fourth order: [1 − θ²/8 + θ⁴/384, (½ − θ²/48) θ] (the paper's
    "algorithm of the fourth order"; not unit norm — the drift metric removes the norm)."""
    phi = as_float_array(phi, "phi", last=3)
    if form == "exact":
        return _exp(phi)
    if form == "series4":
        a2 = np.sum(phi**2, axis=-1, keepdims=True)
        return np.concatenate([1 - a2 / 8 + a2**2 / 384, (0.5 - a2 / 48) * phi], axis=-1)
    raise ImunavError(f"form must be one of {UPDATE_FORMS}, got {form!r}")


@dataclass
class DriftRun:
    t: FloatArray
    drift: FloatArray
    alpha: float
    beta: float
    form: str

    @property
    def final(self) -> float:
        return float(self.drift[-1])


def sub_increments(motion: FourRotationMotion, duration: float, dt: float
                   ) -> tuple[FloatArray, FloatArray]:
    """Times ``t_n`` and the three sub-interval quasi-coordinates per step: shape (N, 3, 3)."""
    dt = check_positive(dt, "dt")
    duration = check_positive(duration, "duration")
    n = int(round(duration / dt))
    edges = np.arange(3 * n + 1) * (dt / 3)
    inc = quasi_coordinates(motion, edges).reshape(n, 3, 3)
    return np.arange(n + 1) * dt, inc


def drift(motion: FourRotationMotion, duration: float = 1000.0, dt: float = 0.1,
          alpha: float = 33 / 80, beta: float = 57 / 80, form: str = "series4",
          increments: tuple[FloatArray, FloatArray] | None = None) -> DriftRun:
    """Cumulative drift (rad) of Miller's algorithm: the angle of the error quaternion between
    the computed and the true orientation, ``2 atan2(|vec|, |w|)`` of ``Λ_true* ∘ Λ``
    ("non-removable residual": the quaternion's norm error is not counted)."""
    t, inc = increments if increments is not None else sub_increments(motion, duration, dt)
    phi = miller_rotation_vector(inc[:, 0], inc[:, 1], inc[:, 2], alpha, beta)
    dq = rotation_quaternion(phi, form)
    dq = dq / np.linalg.norm(dq, axis=-1, keepdims=True)
    truth = motion.attitude(t)
    q = cumulative_product(truth[0], dq)
    return DriftRun(t, _angle(q, truth), float(alpha), float(beta), form)


def drift_vs_alpha(motion: FourRotationMotion, alphas: npt.ArrayLike, beta_of_alpha,
                   duration: float = 1000.0, dt: float = 0.1, form: str = "series4"
                   ) -> FloatArray:
    """Final drift for each α with β = ``beta_of_alpha(α)`` (quasi-coordinates computed once)."""
    inc = sub_increments(motion, duration, dt)
    return np.array([drift(motion, alpha=a, beta=beta_of_alpha(a), form=form, increments=inc).final
                     for a in np.asarray(alphas, dtype=float)])


def optimal_alpha_on_line(motion: FourRotationMotion, duration: float = 1000.0, dt: float = 0.1,
                          form: str = "series4") -> tuple[float, float]:
    """α minimising the final drift on the line α + β = 90/80 (bounded scalar search)."""
    from scipy.optimize import minimize_scalar

    inc = sub_increments(motion, duration, dt)

    def f(a):
        return drift(motion, alpha=a, beta=90 / 80 - a, form=form, increments=inc).final

    r = minimize_scalar(f, bounds=(-10.0, 10.0), method="bounded", options={"xatol": 1e-6})
    return float(r.x), float(r.fun)


def drift_order(motion: FourRotationMotion, dts=(0.4, 0.2, 0.1, 0.05), duration: float = 200.0,
                alpha: float = 33 / 80, beta: float = 57 / 80, form: str = "exact"
                ) -> tuple[FloatArray, float]:
    """Final drift at several steps and the fitted order (slope of log drift vs log Δt)."""
    d = np.array([drift(motion, duration, dt, alpha, beta, form).final for dt in dts])
    return d, fit_order(dts, d)


# ------------------------------------------------------------------------ figures

def plot_quasi_coordinates(motion: FourRotationMotion, duration: float = 200.0, dt: float = 0.1,
                           fig=None):
    """Fig. 1: θ*ₙ (rad) on each axis vs time."""
    import matplotlib.pyplot as plt

    t = np.arange(int(round(duration / dt)) + 1) * dt
    q = quasi_coordinates(motion, t)
    fig = fig or plt.figure(figsize=(10, 6))
    for i in range(3):
        ax = fig.add_subplot(3, 1, i + 1)
        ax.plot(t[1:], q[:, i], lw=0.8)
        ax.set_ylabel(f"θ*_{i + 1} (rad)")
    ax.set_xlabel("t (s)")
    fig.suptitle(f"Fig. 1: quasi-coordinates, k = {motion.k}, Δt = {dt} s")
    fig.tight_layout()
    return fig


def plot_configuration_space(motion: FourRotationMotion, duration: float = 200.0, dt: float = 0.05,
                             fig=None):
    """Fig. 2: λ₁(λ₀), λ₂(λ₀), λ₃(λ₀), λ₂(λ₁)."""
    import matplotlib.pyplot as plt

    lam = motion.attitude(np.arange(int(round(duration / dt)) + 1) * dt)
    fig = fig or plt.figure(figsize=(9, 8))
    for n, (i, j) in enumerate([(0, 1), (0, 2), (0, 3), (1, 2)]):
        ax = fig.add_subplot(2, 2, n + 1)
        ax.plot(lam[:, i], lam[:, j], lw=0.4)
        ax.set(xlabel=f"λ{i}", ylabel=f"λ{j}", aspect="equal")
    fig.suptitle("Fig. 2: trajectories in configuration space")
    fig.tight_layout()
    return fig


def plot_drift(runs: dict[str, list[DriftRun]], fig=None):
    """Fig. 3: drift (rad) vs time for each coefficient set and update form."""
    import matplotlib.pyplot as plt

    fig = fig or plt.figure(figsize=(12, 3.6))
    for n, (key, rs) in enumerate(runs.items()):
        ax = fig.add_subplot(1, len(runs), n + 1)
        for r in rs:
            ax.plot(r.t, r.drift, label=f"{r.form}: {r.final:.3e}")
        ax.axhline(TABLE1[key][1], color="k", ls=":", lw=1, label=f"paper {TABLE1[key][1]:.3e}")
        a, b = TABLE1[key][0]
        ax.set(title=f"α = {a * 80:.0f}/80, β = {b * 80:.0f}/80", xlabel="t (s)",
               ylabel="drift (rad)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def reproduce(out) -> list[dict]:
    """Figures ``plaksiy_*.png`` and the records of the Table 1 comparison."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = FourRotationMotion()
    recs = []
    for name, fn in (("fig1_quasi_coordinates", plot_quasi_coordinates),
                     ("fig2_configuration_space", plot_configuration_space)):
        fig = fn(m)
        fig.savefig(out / f"plaksiy_{name}.png", dpi=100)
        plt.close(fig)
    inc = sub_increments(m, 1000.0, 0.1)
    runs = {k: [drift(m, alpha=a, beta=b, form=f, increments=inc) for f in UPDATE_FORMS]
            for k, ((a, b), _) in TABLE1.items()}
    fig = plot_drift(runs)
    fig.savefig(out / "plaksiy_fig3_drift.png", dpi=100)
    plt.close(fig)
    for k, ((a, b), paper) in TABLE1.items():
        ex, s4 = runs[k]
        recs.append(record(f"plaksiy.table1.{k}", f"final drift at 1000 s, α={a * 80:.0f}/80, "
                           f"β={b * 80:.0f}/80", paper, s4.final, "rad",
                           f"series4 update (fourth-order truncated quaternion series) reproduces "
                           f"the paper (ratio {s4.final / paper:.3f}); exact exponential gives "
                           f"{ex.final:.4e}"))
    # |Λ| of corrected eq. (3) at the Fig. 1 times, evaluated from the SymPy expressions
    f = S.quaternion_lambdified(True)
    tt = np.linspace(0, 1000, 20001)
    a, _ = m.angles(tt)
    lam = np.array(f(*np.moveaxis(a, -1, 0)))
    dev = float(np.max(np.abs(np.linalg.norm(lam, axis=0) - 1)))
    fp = S.quaternion_lambdified(False)
    devp = float(np.max(np.abs(np.linalg.norm(np.array(fp(*np.moveaxis(a, -1, 0))), axis=0) - 1)))
    recs.append(record("plaksiy.eq3.max_norm_deviation_corrected", "max ||Λ| − 1| of corrected "
                       "eq. (3), t ∈ [0, 1000] s", None, dev, "1",
                       f"as printed (λ₂ typo) the deviation reaches {devp:.3f}"))
    a_opt, d_opt = optimal_alpha_on_line(m, form="series4")
    a_ex, d_ex = optimal_alpha_on_line(m, form="exact")
    recs.append(record("plaksiy.optimal_alpha_on_line", "α minimising the final drift on "
                       "α + β = 90/80 (series4 update)", None, a_opt, "1",
                       f"drift {d_opt:.3e} rad there; with the exact update α = {a_ex:.3f}, "
                       f"drift {d_ex:.3e} rad"))
    return recs


def drift_grid(motion: FourRotationMotion, alphas: npt.ArrayLike, betas: npt.ArrayLike,
               duration: float = 1000.0, dt: float = 0.1, form: str = "series4") -> FloatArray:
    """Final drift on an (α, β) grid, shape (len(betas), len(alphas))."""
    inc = sub_increments(motion, duration, dt)
    return np.array([[drift(motion, alpha=a, beta=b, form=form, increments=inc).final
                      for a in np.asarray(alphas, float)] for b in np.asarray(betas, float)])


def plot_coefficient_lab(alphas, on_line: dict[str, FloatArray], grid_alphas, grid_betas,
                         grid: FloatArray, fig=None):
    """Drift vs α on α + β = 90/80 (each update form) and a map of drift over (α, β)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig = fig or plt.figure(figsize=(12, 4.5))
    ax = fig.add_subplot(1, 2, 1)
    for form, d in on_line.items():
        ax.semilogy(alphas, d, label=form)
    for key, ((a, _), paper) in TABLE1.items():
        ax.plot(a, paper, "k*", ms=8)
        ax.annotate(key, (a, paper), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set(xlabel="α (β = 90/80 − α)", ylabel="final drift at 1000 s (rad)",
           title="on the line α + β = 90/80 (★ paper)")
    ax.legend()
    ax2 = fig.add_subplot(1, 2, 2)
    im = ax2.pcolormesh(grid_alphas, grid_betas, grid, norm=LogNorm(), shading="auto")
    ax2.plot(grid_alphas, 90 / 80 - np.asarray(grid_alphas), "w--", lw=1)
    fig.colorbar(im, ax=ax2, label="final drift (rad)")
    ax2.set(xlabel="α", ylabel="β", title="off the line (series4 update)")
    fig.tight_layout()
    return fig
