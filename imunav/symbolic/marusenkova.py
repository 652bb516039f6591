"""Marusenkova 2020: the DCM of eq. (5), its printed expansion (30), and Ω_orig, eqs. (29)–(33).

Findings (each computed here and shown in notebook 01):

1. Eq. (5) is ``R_x(φ)ᵀ R_y(θ)ᵀ R_z(ψ)ᵀ = (R_z(ψ) R_y(θ) R_x(φ))ᵀ``: it maps *inertial*
   vectors into the body frame (it is C_I^b = imunav's ``C_bn``), although eq. (4) uses it as
   ``a_i = C_b^I a_b`` (body → inertial) — :func:`eq5_is_transpose_of_zyx`.
2. The printed expansion (30) has a typo in element (3,3): ``cos φ_k cos φ_k`` must be
   ``cos θ_k cos φ_k`` (:func:`eq30_mismatches`); the OCR's ``S_bk`` in (1,2) is ``sin ψ_k``.
3. The printed diagonal terms (31)–(33) of Ω_orig are checked against the exact
   ``((C_k)ᵀ C_{k+1} − I)/dt`` by :func:`diagonal_findings`.
4. The numeric example (δθ = δφ = 0.1°, θ = 30°, 100 Hz) — :func:`omega33_example`.

May import: nothing from imunav but ``imunav.symbolic``.
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from imunav.symbolic.trig import normal_form

psi0, th0, ph0, psi1, th1, ph1 = sp.symbols("psi_k theta_k phi_k psi_k1 theta_k1 phi_k1",
                                             real=True)
dt = sp.Symbol("dt", positive=True)
ANGLES = (psi0, th0, ph0, psi1, th1, ph1)


def eq5(psi, theta, phi) -> sp.Matrix:
    """Eq. (5) literally: the product of the three printed elementary matrices."""
    A = sp.Matrix([[1, 0, 0], [0, sp.cos(phi), sp.sin(phi)], [0, -sp.sin(phi), sp.cos(phi)]])
    B = sp.Matrix([[sp.cos(theta), 0, -sp.sin(theta)], [0, 1, 0],
                   [sp.sin(theta), 0, sp.cos(theta)]])
    C = sp.Matrix([[sp.cos(psi), sp.sin(psi), 0], [-sp.sin(psi), sp.cos(psi), 0], [0, 0, 1]])
    return A * B * C


def zyx_active(psi, theta, phi) -> sp.Matrix:
    """imunav's ``C_nb`` = R_z(ψ) R_y(θ) R_x(φ) (active rotations; body → navigation)."""
    Rz = sp.Matrix([[sp.cos(psi), -sp.sin(psi), 0], [sp.sin(psi), sp.cos(psi), 0], [0, 0, 1]])
    Ry = sp.Matrix([[sp.cos(theta), 0, sp.sin(theta)], [0, 1, 0],
                    [-sp.sin(theta), 0, sp.cos(theta)]])
    Rx = sp.Matrix([[1, 0, 0], [0, sp.cos(phi), -sp.sin(phi)], [0, sp.sin(phi), sp.cos(phi)]])
    return Rz * Ry * Rx


def eq5_is_transpose_of_zyx() -> bool:
    """True iff eq. (5) ≡ C_nbᵀ (so it maps navigation vectors into the body frame)."""
    d = eq5(psi0, th0, ph0) - zyx_active(psi0, th0, ph0).T
    return all(normal_form(x, ANGLES) == 0 for x in d)


def printed_eq30(psi, theta, phi) -> sp.Matrix:
    """Eq. (30) as printed (OCR ``S_bk`` read as ``sin ψ_k``; (3,3) printed ``cos φ cos φ``)."""
    c, s = sp.cos, sp.sin
    return sp.Matrix([
        [c(psi) * c(theta), s(psi) * c(theta), -s(theta)],
        [-s(psi) * c(phi) + c(psi) * s(theta) * s(phi), c(psi) * c(phi) + s(psi) * s(theta) * s(phi),
         c(theta) * s(phi)],
        [s(psi) * s(phi) + c(psi) * s(theta) * c(phi), -c(psi) * s(phi) + s(psi) * s(theta) * c(phi),
         c(phi) * c(phi)],
    ])


def eq30_mismatches() -> list[tuple[int, int, sp.Expr, sp.Expr]]:
    """Elements (1-based) where the printed (30) differs from eq. (5): (i, j, printed, eq5)."""
    P = printed_eq30(psi0, th0, ph0)
    E = eq5(psi0, th0, ph0)
    return [(i + 1, j + 1, P[i, j], sp.factor(E[i, j])) for i in range(3) for j in range(3)
            if normal_form(P[i, j] - E[i, j], ANGLES) != 0]


def omega_orig_exact() -> sp.Matrix:
    """Eq. (29): Ω_orig = ((C_k)ᵀ C_{k+1} − I)/dt with C from eq. (5)."""
    return (eq5(psi0, th0, ph0).T * eq5(psi1, th1, ph1) - sp.eye(3)) / dt


def printed_diagonal() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Eqs. (31), (32), (33) as printed, with δx = x_{k+1} − x_k."""
    c, s = sp.cos, sp.sin
    dps, dth, dph = psi1 - psi0, th1 - th0, ph1 - ph0
    o11 = (c(dth) * c(dps) + s(psi0) * s(psi1) * (c(dph) - c(dth))
           - s(psi0) * c(psi1) * s(th1) * s(dph) + c(psi0) * s(psi1) * s(th0) * s(dph)
           + c(psi0) * c(psi1) * s(th0) * s(th1) * (c(dph) - 1) - 1) / dt
    o22 = (c(psi0) * c(psi1) * c(dph)
           + s(dph) * (c(psi0) * s(psi1) * s(th1) - s(psi0) * c(psi1) * s(th0))
           + s(psi0) * s(psi1) * (c(dth) * c(dph) + c(th0) * c(th1) * (1 - c(dph))) - 1) / dt
    o33 = (c(dth) * c(dph) - s(th1) * s(th0) * (c(dph) - 1) - 1) / dt
    return o11, o22, o33


@lru_cache(maxsize=1)
def diagonal_findings() -> dict[str, object]:
    """For each printed diagonal term: does it equal the exact Ω_orig(i,i)? (normal forms)"""
    W = omega_orig_exact()
    out = {}
    for i, p in enumerate(printed_diagonal()):
        d = normal_form(sp.expand((p - W[i, i]) * dt), ANGLES)
        out[f"omega{i + 1}{i + 1}"] = d == 0
        out[f"omega{i + 1}{i + 1}_difference_times_dt"] = sp.factor(d)
    return out


def omega33_example(dtheta_deg: float = 0.1, dphi_deg: float = 0.1, theta_deg: float = 30.0,
                    rate_hz: float = 100.0) -> dict[str, float]:
    """The paper's numeric example for Ω_orig(3,3) (it does not depend on ψ):

    - ``exact``: eq. (33) (≡ the exact element) with θ_k = θ, θ_{k+1} = θ + δθ;
    - ``sin_as_angle``: the paper's simplification sin θ ≈ θ (θ in radians) — this gives the
      printed −2.63e−4;
    - ``cos_as_one``: the classic assumption cos δ = 1, which gives 0.
    """
    r = sp.pi / 180
    th, dth, dph = theta_deg * r, dtheta_deg * r, dphi_deg * r
    h = 1 / sp.Float(rate_hz, 30)
    exact = (sp.cos(dth) * sp.cos(dph) - sp.sin(th + dth) * sp.sin(th) * (sp.cos(dph) - 1) - 1) / h
    simp = (sp.cos(dth) * sp.cos(dph) - (th**2 + th * dth) * (sp.cos(dph) - 1) - 1) / h
    return {"exact": float(sp.N(exact, 30)), "sin_as_angle": float(sp.N(simp, 30)),
            "cos_as_one": 0.0}


def omega33_lambdified():
    """Eq. (33) as a numpy function ``f(θ_k, θ_{k+1}, δφ, dt)``."""
    dph = sp.Symbol("dphi", real=True)
    o33 = (sp.cos(th1 - th0) * sp.cos(dph) - sp.sin(th1) * sp.sin(th0) * (sp.cos(dph) - 1) - 1) / dt
    return sp.lambdify((th0, th1, dph, dt), o33, "numpy")
