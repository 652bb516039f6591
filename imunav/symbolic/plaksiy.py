"""Plaksiy & Homozkova: the four-rotation quaternion eq. (3) and its angular velocity eq. (5).

Findings (each computed by a function here and shown in notebook 02):

1. Eq. (3) as printed has a typo in λ₂: the second bracket reads
   ``cos φ/2 · sin ψ/2 · cos ϑ/2 + sin φ/2 · sin ψ/2 · sin ϑ/2``; it must be
   ``cos φ/2 · cos ψ/2 · cos ϑ/2 + sin φ/2 · sin ψ/2 · sin ϑ/2`` (the scalar part of the
   three-rotation quaternion). As printed, ``|Λ| ≠ 1`` (:func:`norm_defect`).
2. With that correction eq. (3) is the product ``Λ = q₃(φ) ∘ q₂(ψ) ∘ q₁(ϑ) ∘ q₂(χ)``
   (Hamilton product, body-fixed successive turns: φ about axis 3, ψ about the new axis 2,
   ϑ about the new axis 1, then χ about the new axis 2) — :func:`identify_sequence`.
3. ``ω = 2 Λ̃ ∘ Λ̇`` derived from the corrected (3) equals the printed eq. (5) identically
   (:func:`omega_discrepancy` simplifies the difference to zero); eq. (5) is therefore the
   body-frame (Hamilton, right-multiplied) angular velocity, the same convention as imunav's
   gyro.
4. For linear angle laws (rational frequencies) the seeming turn vector θ(t) = ∫₀ᵗ ω dt —
   hence the quasi-coordinates (7) — has a closed form, a finite sum of sinusoids plus a
   secular term (:func:`seeming_turn_closed_form`), as the paper states.
5. Eq. (5) differentiated in time (:func:`omega_rate_lambdified`) gives the ω̇ that Euler's
   dynamic equations need, to ask whether (3) and (5) solve them without a torque.
6. Miller's formula (2) matches the exact rotation vector's leading non-commutativity term
   (h³ a×b for ω = a + b t + c t²) only when α + β = 90/80 — the line all three of the
   paper's coefficient sets lie on (:func:`miller_leading_term`).

May import: nothing from imunav but ``imunav.symbolic``.
"""

from __future__ import annotations

import itertools
from functools import lru_cache

import sympy as sp

from imunav.symbolic.trig import normal_form

t = sp.Symbol("t", real=True)
phi, psi, vth, chi = (sp.Function(n, real=True)(t) for n in ("varphi", "psi", "vartheta", "chi"))
ANGLES = (phi, psi, vth, chi)

Q = sp.algebras.Quaternion


def _c(x):
    return sp.cos(x / 2)


def _s(x):
    return sp.sin(x / 2)


def printed_eq3(corrected: bool = False) -> tuple[sp.Expr, ...]:
    """λ₀…λ₃ of eq. (3) transcribed from the paper (OCR ``ños`` read as ``cos``).

    ``corrected=True`` replaces the one wrong factor in λ₂ (``sin ψ/2`` → ``cos ψ/2`` in the
    first term of the second bracket).
    """
    cf, sf, cp, sp_, cv, sv, cc, sc = (_c(phi), _s(phi), _c(psi), _s(psi), _c(vth), _s(vth),
                                       _c(chi), _s(chi))
    l0 = cc * (cf * cp * cv + sf * sp_ * sv) - sc * (cf * sp_ * cv + sf * cp * sv)
    l1 = cc * (cf * cp * sv - sf * sp_ * cv) - sc * (sf * cp * cv - cf * sp_ * sv)
    first = cf * (cp if corrected else sp_) * cv  # printed: cos φ/2 · sin ψ/2 · cos ϑ/2
    l2 = cc * (cf * sp_ * cv + sf * cp * sv) + sc * (first + sf * sp_ * sv)
    l3 = cc * (sf * cp * cv - cf * sp_ * sv) + sc * (cf * cp * sv - sf * sp_ * cv)
    return (l0, l1, l2, l3)


def printed_eq5() -> tuple[sp.Expr, ...]:
    """ω₁, ω₂, ω₃ of eq. (5) as printed."""
    d = {a: sp.diff(a, t) for a in ANGLES}
    w1 = (-sp.sin(chi) * (d[phi] * sp.cos(psi) * sp.cos(vth) - d[psi] * sp.sin(vth))
          + sp.cos(chi) * (d[vth] - d[phi] * sp.sin(psi)))
    w2 = (d[chi] + sp.Rational(1, 2) * d[phi] * (sp.sin(vth + psi) + sp.sin(vth - psi))
          + d[psi] * sp.cos(vth))
    w3 = (sp.sin(chi) * (d[vth] - d[phi] * sp.sin(psi))
          + sp.cos(chi) * (d[phi] * sp.cos(psi) * sp.cos(vth) - d[psi] * sp.sin(vth)))
    return (w1, w2, w3)


def axis_quaternion(angle, axis: int) -> Q:
    """Turn by ``angle`` about body axis 1, 2 or 3: ``[cos a/2, sin a/2 · e_axis]``."""
    comps = [sp.cos(angle / 2), 0, 0, 0]
    comps[axis] = sp.sin(angle / 2)
    return Q(*comps)


def composed(axes=(3, 2, 1, 2), left_to_right: bool = True) -> tuple[sp.Expr, ...]:
    """``q_a(φ) ∘ q_b(ψ) ∘ q_c(ϑ) ∘ q_d(χ)`` (or the reverse product order)."""
    qs = [axis_quaternion(a, ax) for a, ax in zip(ANGLES, axes, strict=True)]
    if not left_to_right:
        qs = qs[::-1]
    q = qs[0] * qs[1] * qs[2] * qs[3]
    return (q.a, q.b, q.c, q.d)


def _numeric_points(n: int = 3, seed: int = 1):
    import random

    r = random.Random(seed)
    return [{a: sp.Float(r.uniform(-3, 3), 30) for a in ANGLES} for _ in range(n)]


def identify_sequence(corrected: bool = True) -> list[tuple[tuple[int, ...], bool, list[bool]]]:
    """Search every axis sequence (a, b, c, d) ∈ {1,2,3}⁴ and both product orders for the one
    that reproduces eq. (3), component by component, at random angles (30-digit arithmetic).

    Returns the candidates that match at least three of the four components:
    ``(axes, left_to_right, [λ₀ ok, λ₁ ok, λ₂ ok, λ₃ ok])``.
    """
    target = printed_eq3(corrected)
    pts = _numeric_points()
    tv = [[sp.N(c.subs(p), 25) for c in target] for p in pts]
    hits = []
    for axes in itertools.product((1, 2, 3), repeat=4):
        for order in (True, False):
            cand = composed(axes, order)
            ok = [all(abs(sp.N(cand[i].subs(p), 25) - tv[j][i]) < 1e-20
                      for j, p in enumerate(pts)) for i in range(4)]
            if sum(ok) >= 3:
                hits.append((axes, order, ok))
    return hits


_H = sp.symbols("h0:4", real=True)        # half angles
_R = sp.symbols("r0:4", real=True)        # angle rates


def trig_normal_form(expr: sp.Expr) -> sp.Expr:
    """Canonical polynomial of an expression in the four angles (functions of t) and their
    rates: angles written as twice a half angle, then :func:`imunav.symbolic.trig.normal_form`.
    Two expressions are identical iff their normal forms are; an identity is proved when the
    normal form of the difference is 0.
    """
    e = expr.subs({sp.diff(a, t): r for a, r in zip(ANGLES, _R, strict=True)})
    e = e.subs({a: 2 * h for a, h in zip(ANGLES, _H, strict=True)})
    return normal_form(e, _H, _R)


def norm_defect(corrected: bool) -> sp.Expr:
    """Normal form of ``λ₀² + λ₁² + λ₂² + λ₃² − 1`` for eq. (3): 0 iff |Λ| ≡ 1."""
    lam = printed_eq3(corrected)
    return trig_normal_form(sum(c**2 for c in lam) - 1)


def derive_omega(lam: tuple[sp.Expr, ...]) -> tuple[sp.Expr, ...]:
    """Vector part of ``ω = 2 Λ̃ ∘ Λ̇`` (eq. (4)) for a symbolic quaternion."""
    L = Q(*lam)
    Ld = Q(*(sp.diff(c, t) for c in lam))
    w = 2 * Q(L.a, -L.b, -L.c, -L.d) * Ld
    return (w.b, w.c, w.d)


@lru_cache(maxsize=2)
def omega_discrepancy(corrected: bool = True) -> tuple[sp.Expr, ...]:
    """Normal form of ``derive_omega(eq. 3) − eq. (5)``, component by component (0 = identical)."""
    derived = derive_omega(printed_eq3(corrected))
    return tuple(trig_normal_form(d - p) for d, p in zip(derived, printed_eq5(), strict=True))


def omega_lambdified():
    """Eq. (5) as a numpy function ``f(φ, ψ, ϑ, χ, φ̇, ψ̇, ϑ̇, χ̇) → (ω₁, ω₂, ω₃)``."""
    a = sp.symbols("a0:4", real=True)
    r = sp.symbols("r0:4", real=True)
    sub = {sp.diff(x, t): ri for x, ri in zip(ANGLES, r, strict=True)}
    sub2 = dict(zip(ANGLES, a, strict=True))
    exprs = [e.subs(sub).subs(sub2) for e in printed_eq5()]
    return sp.lambdify(a + r, exprs, "numpy")


def quaternion_lambdified(corrected: bool = True):
    """Eq. (3) as a numpy function ``f(φ, ψ, ϑ, χ) → (λ₀, λ₁, λ₂, λ₃)``."""
    a = sp.symbols("a0:4", real=True)
    exprs = [e.subs(dict(zip(ANGLES, a, strict=True))) for e in printed_eq3(corrected)]
    return sp.lambdify(a, exprs, "numpy")


def seeming_turn_closed_form(k) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """θ(t) = ∫₀ᵗ ω dt in closed form for the linear laws φ = k₁t, ψ = k₂t, ϑ = k₃t, χ = k₄t
    (the paper's eqs. (5)–(6)); ``k`` rational (e.g. ``sp.Rational(31, 20)``) for exact
    results. Each product of sines and cosines is turned into a sum (``TR8``) and integrated
    term by term."""
    from sympy.simplify.fu import TR8

    u = sp.Symbol("u", real=True)
    kk = [sp.nsimplify(x) for x in k]
    laws = {a: ki * u for a, ki in zip(ANGLES, kk, strict=True)}
    rates = {sp.diff(a, t): ki for a, ki in zip(ANGLES, kk, strict=True)}
    out = []
    for w in printed_eq5():
        e = sp.expand(TR8(sp.expand(w.subs(rates).subs(laws))))
        out.append(sp.integrate(e, (u, 0, t)))
    return tuple(out)


def omega_rate_lambdified():
    """ω̇ of eq. (5) as a numpy function ``f(angles (4), rates (4), accelerations (4)) →
    (ω̇₁, ω̇₂, ω̇₃)``: eq. (5) differentiated in time by SymPy (the chain rule through the four
    angle laws), for Euler's dynamic equations."""
    a = sp.symbols("a0:4", real=True)
    r = sp.symbols("r0:4", real=True)
    acc = sp.symbols("acc0:4", real=True)
    sub2 = {sp.diff(x, t, 2): ai for x, ai in zip(ANGLES, acc, strict=True)}
    sub1 = {sp.diff(x, t): ri for x, ri in zip(ANGLES, r, strict=True)}
    sub0 = dict(zip(ANGLES, a, strict=True))
    exprs = [sp.diff(e, t).subs(sub2).subs(sub1).subs(sub0) for e in printed_eq5()]
    return sp.lambdify(a + r + acc, exprs, "numpy")


def miller_leading_term(order: int = 3) -> dict:
    """Why the paper's sets lie on α + β = 90/80: Miller's rotation vector (2) against the exact
    one, term by term in the step h, for an angular velocity ω(t) = a + b t + c t² (vectors).

    The exact rotation vector over [0, h] is ∫ω dt + ½∫θ×ω dt + O(h⁴) (Bortz's equation; the
    φ×(φ×ω) term starts at h⁴), θ(t) = ∫₀ᵗ ω; Miller's (2) uses the three sub-interval
    increments θ¹, θ², θ³. Their difference, expanded to ``order`` in h, is a multiple of
    a × b at h³: (2/27)(α + β) − 1/12, which vanishes only for α + β = 9/8 = 90/80. Returns the
    coefficient of h³ a×b (as a SymPy expression in α, β), the solution of it = 0 for α + β,
    whether the whole h³ term of the difference is that multiple of a×b, and whether the
    terms below h³ vanish (for every α, β)."""
    h, tau, al, be = sp.symbols("h tau alpha beta", real=True)
    a = sp.Matrix(sp.symbols("a1:4", real=True))
    b = sp.Matrix(sp.symbols("b1:4", real=True))
    c = sp.Matrix(sp.symbols("c1:4", real=True))
    w = a + b * tau + c * tau**2

    def theta(lo, hi):
        return w.applyfunc(lambda e: sp.integrate(e, (tau, lo, hi)))

    th = theta(0, tau)
    exact = theta(0, h) + (th.cross(w) / 2).applyfunc(lambda e: sp.integrate(e, (tau, 0, h)))
    t1, t2, t3 = theta(0, h / 3), theta(h / 3, 2 * h / 3), theta(2 * h / 3, h)
    miller = t1 + t2 + t3 + al * t1.cross(t3) + be * t2.cross(t3 - t1)
    diff = (miller - exact).applyfunc(sp.expand)
    h3 = diff.applyfunc(lambda e: e.coeff(h, order))
    axb = a.cross(b)
    coef = sp.simplify(h3[0] / axb[0])
    ok = all(sp.expand(h3[i] - coef * axb[i]) == 0 for i in range(3))
    lower = all(e.coeff(h, k) == 0 for e in diff for k in range(order))
    s = sp.Symbol("s")
    return {"coefficient": sp.nsimplify(coef), "alpha_plus_beta": sp.solve(
        coef.subs(be, s - al), s), "only_a_cross_b": ok, "lower_orders_vanish": lower}
