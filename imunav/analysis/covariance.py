"""Linear covariance analysis of strapdown errors along the true motion.

To first order the navigation errors are linear in the sensor errors, so their distribution
follows from propagating a covariance along the exact trajectory — in one pass, and exactly per
error term (independent sources add). Error state (flat, non-rotating NED, as the navigation):

    φ   attitude error, C_est = (I − [φ×]) C_nb        φ̇  = −C_nb δω
    δv  velocity error                                δv̇ = [f_n×] φ + C_nb δf
    δp  position error                                δṗ = δv

with ``f_n = a_n − g_n`` the specific force in the navigation frame, plus the states of each
error source of the :class:`~imunav.sensors.models.ImuModel`:

=====================  ==================================================================
noise_density N        white noise: process noise of φ (gyro) or δv (accel), PSD N²
bias σ                 3 random constants, variance σ²
bias_instability B     each Gauss–Markov component of the model (the single process of
                       ``bias_correlation_time``, or the flicker bank): 3 states, decay 1/T,
                       stationary variance, driving PSD 2s²/T (the same s as the simulation)
random_walk K          3 states, integrated white noise of PSD K², starting at 0
scale_factor σ         3 random constants: δω = diag(ω_b) s (accel: diag(f_b) s)
misalignment σ         6 random constants (off-diagonal): δω_i = Σ_{j≠i} m_ij ω_j
g_sensitivity σ        9 random constants (gyro): δω_i = Σ_j G_ij f_j
resolution q           rate samples: white noise of variance q²/12 per sample (PSD q²h/12);
                       increments: the simulation carries the rounding residual, so the error of
                       increment k is e_k − e_{k−1} with e white of variance (q h)²/12 — the
                       angle (velocity) error stays bounded; modelled exactly, step by step
range                  not linear: a warning when the motion's |ω_b| or |f_b| exceeds it
bandwidth,             increments (the default): none — the filter has unit gain at low
internal_rate          frequency and the decimated increments sum the internal ones, so the
                       integrated noise is unchanged. Rate samples decimated by k (internal
                       rate / output rate): every k-th sample is kept, so the noise above the
                       output Nyquist folds onto low frequencies: the white-noise density is
                       multiplied by √(Σ_{m<k} |H(m·rate)|²) (H the filter, 1 without one:
                       √k) — :func:`aliasing_gain`
=====================  ==================================================================

Discretisation: per output step ``h``, with the motion taken at the step's midpoint, the
transition is exact: ``A_nav`` is nilpotent (A³ = 0) and the sensor-state dynamics diagonal, so
``Φ = [[e^{A h}, Γ], [0, e^{D h}]]`` with ``Γ = Σ_{i≤2} Aⁱ B φ_i(D)``, ``φ_i`` the integrals of
``(h−s)^i/i! e^{D s}`` (closed forms). The process noise is ``∫ Φ(s) Q Φ(s)ᵀ ds`` by 6-node
Gauss–Legendre on that transition (exact for the polynomial part; sub-stepped so that
``h/T ≤ 0.5`` for fast Gauss–Markov states).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``,
``imunav.analysis.gaussnorm``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.special import erf, gammaincinv, ndtri

from imunav.analysis.gaussnorm import chi3_cdf, norm_cdf, norm_quantile
from imunav.core.constants import G0
from imunav.core.kernels import quat_to_dcm
from imunav.core.rotations import FloatArray
from imunav.core.validation import check_gravity, check_positive
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel, TriadModel, _flicker_bank, bias_instability_sigma
from imunav.sensors.simulate import interval_count

#: Terms a covariance analysis propagates (range, bandwidth and internal_rate are not linear).
LINEAR_TERMS = ("noise_density", "bias", "bias_instability", "random_walk", "scale_factor",
                "misalignment", "g_sensitivity", "resolution")

_OFF = [(i, j) for i in range(3) for j in range(3) if i != j]


def _cross_matrix(v: FloatArray) -> FloatArray:
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1),
                     np.stack([-y, x, z], -1)], -2)


@dataclass
class Trajectory:
    """The true motion at the midpoints of the output steps (what linearisation needs)."""

    h: float
    t: FloatArray                  # output times t_0..t_N
    C: FloatArray                  # (N, 3, 3) C_nb at the midpoints
    f_n: FloatArray                # (N, 3) a_n − g_n
    omega: FloatArray              # (N, 3) ω_b
    f_b: FloatArray                # (N, 3) f_b
    max_rate: float = 0.0          # max |ω_b| over the motion (rad/s), for range warnings
    max_force: float = 0.0

    @classmethod
    def of(cls, motion: BaseMotion, rate: float, duration: float, g: float = G0) -> Trajectory:
        n = interval_count(rate, duration)
        h = 1.0 / check_positive(rate, "rate")
        g = check_gravity(g)
        t = np.arange(n + 1) * h
        tm = t[:-1] + h / 2
        q = motion.attitude(tm)
        a = motion.acceleration(tm) - np.array([0.0, 0.0, g])
        w = motion.angular_rate(tm)
        fb = motion.specific_force(tm, g)
        return cls(h, t, quat_to_dcm(q), a, w, fb, float(np.linalg.norm(w, axis=1).max()),
                   float(np.linalg.norm(fb, axis=1).max()))


@dataclass
class Term:
    """One independent error source as a linear system: ``k`` sensor states with decay rates
    ``D``, initial covariance ``P0``, driving PSD ``Qs``; the nav-error input matrix over the
    steps ``B`` (N, 9, k); white process noise of the nav states ``q_nav`` (9,) PSD."""

    name: str
    D: FloatArray = field(default_factory=lambda: np.zeros(0))
    P0: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    Qs: FloatArray = field(default_factory=lambda: np.zeros(0))
    B: FloatArray | None = None
    q_nav: FloatArray = field(default_factory=lambda: np.zeros(9))
    #: differenced white noise ``(variance of e, B over the steps)``: the rate error over step k
    #: is ``(e_k − e_{k−1})/h`` (quantisation with a carried residual)
    diff_white: tuple[float, FloatArray] | None = None


def _input(traj: Trajectory, triad: str, M: FloatArray) -> FloatArray:
    """Nav-error input of sensor states through ``δ = M x`` (M (N, 3, k)): gyro −C M into φ,
    accel C M into δv."""
    B = np.zeros((M.shape[0], 9, M.shape[2]))
    CM = traj.C @ M
    if triad == "gyro":
        B[:, 0:3] = -CM
    else:
        B[:, 3:6] = CM
    return B


def aliasing_gain(model: TriadModel, rate: float, decimate: int, output: str) -> float:
    """Factor on the white-noise density of ``output`` samples at ``rate`` taken every
    ``decimate``-th of the sensor's internal samples (see the module docstring): the folded
    power at zero frequency, ``√(Σ_{m=0}^{k−1} |H(m·rate)|²)``."""
    if output != "rates" or decimate <= 1:
        return 1.0
    fi = rate * decimate
    f = np.arange(decimate) * rate
    if model.bandwidth and model.bandwidth < 0.5 * fi:
        from scipy.signal import butter, sosfreqz

        sos = butter(2, model.bandwidth, fs=fi, output="sos")
        h2 = np.abs(sosfreqz(sos, worN=f, fs=fi)[1]) ** 2
    else:
        h2 = np.ones(decimate)
    return float(np.sqrt(h2.sum()))


def terms_of(model: TriadModel, triad: str, traj: Trajectory, output: str = "increments",
             decimate: int = 1) -> list[Term]:
    """The linear error terms of one triad (see the module docstring); ``decimate``: internal
    samples per output sample."""
    N = traj.C.shape[0]
    eye = np.broadcast_to(np.eye(3), (N, 3, 3))
    u = traj.omega if triad == "gyro" else traj.f_b          # the quantity the triad measures
    rows = slice(0, 3) if triad == "gyro" else slice(3, 6)
    out = []
    if model.noise_density:
        q = np.zeros(9)
        q[rows] = (model.noise_density * aliasing_gain(model, 1 / traj.h, decimate, output)) ** 2
        out.append(Term(f"{triad}.noise_density", q_nav=q))
    if model.resolution and output == "rates":
        q = np.zeros(9)
        q[rows] = model.resolution ** 2 * traj.h / 12
        out.append(Term(f"{triad}.resolution", q_nav=q))
    elif model.resolution:
        out.append(Term(f"{triad}.resolution",
                        diff_white=((model.resolution * traj.h) ** 2 / 12,
                                    _input(traj, triad, eye))))
    if model.bias:
        out.append(Term(f"{triad}.bias", np.zeros(3), model.bias ** 2 * np.eye(3), np.zeros(3),
                        _input(traj, triad, eye)))
    if model.bias_instability:
        s = bias_instability_sigma(model.bias_instability, model.bias_correlation_time)
        bank = _flicker_bank(model.bias_correlation_time)
        k = 3 * len(bank)
        D = np.repeat([-1.0 / T for T in bank], 3)
        Qs = np.repeat([2 * s * s / T for T in bank], 3)
        M = np.tile(eye, (1, 1, len(bank)))                     # δ = Σ components
        out.append(Term(f"{triad}.bias_instability", D, s * s * np.eye(k), Qs,
                        _input(traj, triad, M)))
    if model.random_walk:
        out.append(Term(f"{triad}.random_walk", np.zeros(3), np.zeros((3, 3)),
                        np.full(3, model.random_walk ** 2), _input(traj, triad, eye)))
    if model.scale_factor:
        M = np.zeros((N, 3, 3))
        M[:, [0, 1, 2], [0, 1, 2]] = u
        out.append(Term(f"{triad}.scale_factor", np.zeros(3), model.scale_factor ** 2 * np.eye(3),
                        np.zeros(3), _input(traj, triad, M)))
    if model.misalignment:
        M = np.zeros((N, 3, 6))
        for c, (i, j) in enumerate(_OFF):
            M[:, i, c] = u[:, j]
        out.append(Term(f"{triad}.misalignment", np.zeros(6), model.misalignment ** 2 * np.eye(6),
                        np.zeros(6), _input(traj, triad, M)))
    if triad == "gyro" and model.g_sensitivity:
        M = np.zeros((N, 3, 9))
        for i in range(3):
            M[:, i, 3 * i: 3 * i + 3] = traj.f_b
        out.append(Term("gyro.g_sensitivity", np.zeros(9), model.g_sensitivity ** 2 * np.eye(9),
                        np.zeros(9), _input(traj, triad, M)))
    return out


def _phi_functions(d: FloatArray, h: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``φ_i(d) = ∫_0^h (h−s)^i/i! e^{d s} ds`` for i = 0, 1, 2.

    With x = d·h, ``φ_i = h^{i+1} Σ_k x^k/(k+i+1)!``: summed (18 terms, truncation < 1e-18) for
    |x| < 0.5, where the closed forms ``(e^x − 1 − …)/x^{i+1}`` cancel catastrophically (φ2 lost
    7 digits at x = 1e-3); the closed forms, with ``expm1``, above.
    """
    x = d * h
    small = np.abs(x) < 0.5
    xs = np.where(small, 1.0, x)
    em1 = np.expm1(xs)
    s = [np.zeros_like(x, dtype=float) for _ in range(3)]
    xk = np.ones_like(x, dtype=float)
    for k in range(18):
        for i in range(3):
            s[i] = s[i] + xk / math.factorial(k + i + 1)
        xk = xk * x
    p0 = np.where(small, h * s[0], h * em1 / xs)
    p1 = np.where(small, h * h * s[1], h * h * (em1 - xs) / xs**2)
    p2 = np.where(small, h**3 * s[2], h**3 * (em1 - xs - xs * xs / 2) / xs**3)
    return p0, p1, p2


def _transition(F: FloatArray, B: FloatArray, D: FloatArray, h: float) -> FloatArray:
    """Exact transition over ``h`` of ``[[A_nav, B], [0, diag(D)]]`` with ``A_nav`` built from
    ``F = [f_n×]``: shape (N, 9 + k, 9 + k)."""
    N, k = F.shape[0], D.size
    n = 9 + k
    Phi = np.zeros((N, n, n))
    I3 = np.eye(3)
    Phi[:, 0:3, 0:3] = I3
    Phi[:, 3:6, 0:3] = F * h
    Phi[:, 3:6, 3:6] = I3
    Phi[:, 6:9, 0:3] = F * (h * h / 2)
    Phi[:, 6:9, 3:6] = I3 * h
    Phi[:, 6:9, 6:9] = I3
    if k:
        p0, p1, p2 = _phi_functions(D, h)
        Bphi, Bv = B[:, 0:3], B[:, 3:6]
        G = np.zeros((N, 9, k))
        G += B * p0                                  # B φ0
        G[:, 3:6] += (F @ Bphi) * p1                 # A B φ1: rows δv ← F Bφ, rows δp ← Bv
        G[:, 6:9] += Bv * p1
        G[:, 6:9] += (F @ Bphi) * p2                 # A² B φ2: rows δp ← F Bφ
        Phi[:, :9, 9:] = G
        Phi[:, 9:, 9:] = np.diag(np.exp(D * h))
    return Phi


_GL = np.polynomial.legendre.leggauss(6)


def _propagate_diff_white(term: Term, traj: Trajectory) -> FloatArray:
    """Nav errors from a differenced white input: augmented with the last ``e`` (3 states);
    over each step the rate error is constant, ``(e_k − e_{k−1})/h``."""
    var, B = term.diff_white
    N, h = traj.C.shape[0], traj.h
    F = _cross_matrix(traj.f_n)
    Phi = _transition(F, np.zeros((N, 9, 0)), np.zeros(0), h)
    # response at the step's end to a unit constant input through B: Γ = Σ Aⁱ B hⁱ⁺¹/(i+1)!
    G = _transition(F, B, np.zeros(3), h)[:, :9, 9:]
    P = np.zeros((12, 12))
    out = np.empty((N + 1, 9, 9))
    out[0] = 0.0
    for i in range(N):
        T = np.zeros((12, 12))
        T[:9, :9] = Phi[i]
        T[:9, 9:] = -G[i] / h                        # − e_{k−1}/h
        W = np.concatenate([G[i] / h, np.eye(3)])    # + e_k/h, and e_k becomes the new state
        P = T @ P @ T.T + var * W @ W.T
        out[i + 1] = P[:9, :9]
    return out


def _discretise(term: Term, traj: Trajectory, F: FloatArray
                ) -> tuple[FloatArray, FloatArray, int, FloatArray]:
    """``(Φ, Q_d, sub, P₀)``: the exact transition and process noise of one sub-step (``sub``
    sub-steps per output step) and the initial covariance of ``[nav, sensor states]``."""
    N = traj.C.shape[0]
    k = term.D.size
    B = term.B if term.B is not None else np.zeros((N, 9, 0))
    sub = max(1, int(np.ceil(np.max(np.abs(term.D), initial=0.0) * traj.h / 0.5)))
    h = traj.h / sub
    Phi = _transition(F, B, term.D, h)
    # process noise over one sub-step: ∫_0^h Φ(s) Q Φ(s)ᵀ ds, 6-node Gauss–Legendre
    Qc = np.concatenate([term.q_nav, term.Qs])
    Qd = np.zeros_like(Phi)
    if np.any(Qc):
        x, w = _GL
        for xi, wi in zip((x + 1) / 2 * h, w / 2 * h, strict=True):
            Ps = _transition(F, B, term.D, xi)
            Qd += wi * (Ps * Qc[None, None, :]) @ np.swapaxes(Ps, 1, 2)
    P0 = np.zeros((9 + k, 9 + k))
    P0[9:, 9:] = term.P0
    return Phi, Qd, sub, P0


def propagate_many(terms: list[Term], traj: Trajectory) -> list[FloatArray]:
    """Covariance of the nav errors [φ, δv, δp] at every output time, (N + 1, 9, 9), for each
    term. Terms with the same state size and sub-stepping are propagated together (one batched
    product per step instead of one per term and step)."""
    F = _cross_matrix(traj.f_n)
    N = traj.C.shape[0]
    out: list[FloatArray | None] = [None] * len(terms)
    groups: dict[tuple[int, int], list] = {}
    for j, term in enumerate(terms):
        if term.diff_white is not None:
            out[j] = _propagate_diff_white(term, traj)
            continue
        Phi, Qd, sub, P0 = _discretise(term, traj, F)
        groups.setdefault((P0.shape[0], sub), []).append((j, Phi, Qd, P0))
    for (_, sub), members in groups.items():
        Phi = np.stack([m[1] for m in members], axis=1)          # (N, T, n, n)
        Qd = np.stack([m[2] for m in members], axis=1)
        PhiT = np.swapaxes(Phi, -1, -2)
        P = np.stack([m[3] for m in members])                     # (T, n, n)
        hist = np.empty((N + 1, len(members), 9, 9))
        hist[0] = P[:, :9, :9]
        for i in range(N):
            Pi, PiT, Qi = Phi[i], PhiT[i], Qd[i]
            for _ in range(sub):
                P = Pi @ P @ PiT + Qi
            hist[i + 1] = P[:, :9, :9]
        for c, m in enumerate(members):
            out[m[0]] = hist[:, c]
    return out


def propagate(term: Term, traj: Trajectory) -> FloatArray:
    """Covariance of the nav errors [φ, δv, δp] at every output time: (N + 1, 9, 9)."""
    return propagate_many([term], traj)[0]


@dataclass
class CovarianceResult:
    """Nav-error covariances (N + 1, 9, 9) per error term and in total, at the output times."""

    t: FloatArray
    terms: dict[str, FloatArray]
    total: FloatArray
    rate: float
    model: str
    max_rate: float
    max_force: float
    warnings: list[str]

    def position_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp(t)| ≤ tolerance)`` at every output time."""
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """``max_t`` of the ``p``-quantile of the position error: exact quantiles only where
        the bounds from the largest eigenvalue (``|N(0, λ₁)|`` ≤ q ≤ ``√λ₁·χ₃``) leave the
        maximum possible."""
        P = (self.total if term is None else self.terms[term])[:, 6:9, 6:9]
        top = np.sqrt(np.maximum(np.linalg.eigvalsh(P)[:, -1], 0.0))
        lo, hi = top * ndtri((1 + p) / 2), top * np.sqrt(2 * gammaincinv(1.5, p))
        cand = hi >= lo.max()
        return float(norm_quantile(P[cand], p).max())

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """``(min_t P(|δp(t)| ≤ tol), first index where it is below level)`` — exact CDFs
        only where the bounds ``F_χ₃(tol/√λ₁) ≤ P ≤ erf(tol/√(2λ₁))`` (λ₁ the largest
        eigenvalue) leave the answer open."""
        P = self.total[:, 6:9, 6:9]
        lam = np.maximum(np.linalg.eigvalsh(P)[:, -1], 0.0)
        with np.errstate(divide="ignore"):
            s = tolerance / np.sqrt(lam)                     # inf where the error is 0
        lower, upper = chi3_cdf(s), erf(s / np.sqrt(2))
        sure = np.nonzero(upper < level)[0]
        stop = sure[0] if sure.size else lam.size
        cand = (lower <= upper.min()) | ((lower < level) & (np.arange(lam.size) <= stop))
        idx = np.nonzero(cand)[0]
        exact = norm_cdf(P[idx], tolerance)
        below = idx[exact < level]
        first = min(int(below[0]) if below.size else lam.size, int(stop))
        return float(exact.min()), (first if first < lam.size else None)

    def min_position_within(self, tolerance: float) -> float:
        """``min_t P(|δp(t)| ≤ tolerance)`` (see :meth:`within_summary`)."""
        return self.within_summary(tolerance, 0.0)[0]


#: Above this 95th-percentile attitude error (rad) the small-angle model is no longer reliable.
LINEAR_LIMIT = 0.3


def covariance(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
               g: float = G0, output: str = "increments", trajectory: Trajectory | None = None
               ) -> CovarianceResult:
    """Propagate every linear error term of ``model`` along ``motion`` at ``rate`` Hz, for
    ``output`` signals (``increments``: quantisation with a carried residual).
    ``trajectory``: the motion already sampled by :meth:`Trajectory.of` (to reuse it)."""
    duration = span(motion, rate, duration)
    traj = trajectory or Trajectory.of(motion, rate, duration, g)
    linear = [term for triad in ("gyro", "accel")
              for term in terms_of(getattr(model, triad), triad, traj, output,
                                   model.decimation(rate))]
    terms = dict(zip([t.name for t in linear], propagate_many(linear, traj), strict=True))
    total = sum(terms.values()) if terms else np.zeros((traj.t.size, 9, 9))
    warnings = []
    for triad, peak, what in (("gyro", traj.max_rate, "angular rate"),
                              ("accel", traj.max_force, "specific force")):
        rng = getattr(model, triad).range
        if rng and peak > rng:
            warnings.append(f"the motion's {what} reaches {peak:.3g}, beyond the {triad} range "
                            f"{rng:.3g} (SI): clipping is not in the covariance; use Monte Carlo")
    res = CovarianceResult(traj.t, terms, total, float(rate), model.name, traj.max_rate,
                           traj.max_force, warnings)
    att = float(res.attitude_quantile(index=-1)) if terms else 0.0
    if att > LINEAR_LIMIT:
        warnings.append(f"the 95th-percentile attitude error reaches {att:.2g} rad: beyond about "
                        f"{LINEAR_LIMIT} rad the small-angle error model is not reliable; use "
                        "--method montecarlo")
    return res
