"""Exact increments by Chebyshev blocks (issue 17) against high-precision mpmath quadrature.

The reference integrands are built here from the motions' SymPy laws — ω_b as the vector part
of 2 q*⊗q̇ of the attitude quaternion, f_b = C_bn(a − g_n) with C_bn from that quaternion — and
integrated by ``mpmath.quad`` (Gauss–Legendre, 24 digits) over random sample intervals. Nothing of
imunav's numeric code is used for the truth.

Bound: within 1e-13 of the increment vector's norm, plus 1e-15·h·max|f| (where the vector is
small against the integrand over its block), plus the integrand's own rounding: evaluating
sin(Ωt) in double precision errs by about ε·Ωt (the rounding of the argument), which grows with
t and which no method removes (measured: 1.6e-13 relative at Ωt = 223 on the cone) — taken
here as 4ε·Ω_max·t·max|f|·h with Ω_max the motion's highest angular frequency.
"""

import mpmath
import numpy as np
import pytest
import sympy as sp

from imunav import Motion, simulate_imu
from imunav.motion import catalog
from imunav.motion.laws import T
from imunav.sensors import quadrature as Q

G = 9.80665
EPS = np.finfo(float).eps


def _quat_of(m) -> list:
    """The attitude quaternion of a motion as SymPy expressions in T (from its laws)."""
    Qn = sp.algebras.Quaternion
    if isinstance(m, Motion):
        psi, th, ph = (m.laws[k] for k in ("yaw", "pitch", "roll"))
        q = (Qn(sp.cos(psi / 2), 0, 0, sp.sin(psi / 2)) * Qn(sp.cos(th / 2), 0, sp.sin(th / 2), 0)
             * Qn(sp.cos(ph / 2), sp.sin(ph / 2), 0, 0))
        return [q.a, q.b, q.c, q.d]
    if hasattr(m, "laws") and isinstance(m.laws, list):            # FourRotationMotion
        ph, ps, th, ch = m.laws
        axis = {1: lambda a: Qn(sp.cos(a / 2), sp.sin(a / 2), 0, 0),
                2: lambda a: Qn(sp.cos(a / 2), 0, sp.sin(a / 2), 0),
                3: lambda a: Qn(sp.cos(a / 2), 0, 0, sp.sin(a / 2))}
        q = axis[3](ph) * axis[2](ps) * axis[1](th) * axis[2](ch)
        return [q.a, q.b, q.c, q.d]
    return list(m.expressions["quaternion"])                        # QuaternionLawMotion


def _acc_of(m) -> list:
    if hasattr(m, "expressions") and "acceleration" in m.expressions:
        return list(m.expressions["acceleration"])
    return [0, 0, 0]


def _reference(m, g=G):
    """mpmath functions of t: the 3 components of ω_b and of f_b."""
    q = _quat_of(m)
    Qn = sp.algebras.Quaternion
    qq = Qn(*q)
    w = 2 * Qn(q[0], -q[1], -q[2], -q[3]) * Qn(*[sp.diff(c, T) for c in q])
    a = _acc_of(m)
    an = Qn(0, a[0], a[1], a[2] - g)
    fb = Qn(q[0], -q[1], -q[2], -q[3]) * an * qq                   # C_bn (a − g_n)
    exprs = [w.b, w.c, w.d, fb.b, fb.c, fb.d]
    return [sp.lambdify(T, e, "mpmath", cse=True) for e in exprs]


#: name → (factory, highest angular frequency in rad/s: the integrand's rounding grows as Ω·t)
MOTIONS = {
    "coning": (lambda: catalog.coning(duration=30.0), 2 * 4 * np.pi),
    "spinning_cone": (lambda: catalog.spinning_cone(duration=30.0), 2 * 5 * np.pi),
    "sculling": (lambda: catalog.sculling(duration=30.0), 2 * 4 * np.pi),
    "four_rotation": (lambda: catalog.four_rotation(duration=30.0), 4.0),
    "stationary": (lambda: catalog.stationary(duration=30.0), 0.0),
    "figure_eight": (lambda: catalog.figure_eight(duration=30.0), 2.2),
    # fast (6 Hz) and slow content together, in position and attitude
    "fast_and_slow": (lambda: Motion(x="0.02*sin(40*t) + 0.001*t**3", y="3*sin(0.05*t)",
                                     z="-0.01*cos(37*t)", yaw="0.2*sin(30*t) + 0.01*t",
                                     pitch="0.001*t**2 - 0.1*sin(0.3*t)",
                                     roll="0.05*sin(25*t)", duration=30.0), 80.0),
}


def _check(m, rate, duration, t0, n_intervals, rng, omega=0.0):
    sig = simulate_imu(m, rate, duration, kind="increments", t0=t0)
    ref = _reference(m)
    h = 1.0 / rate
    for k in rng.choice(len(sig), n_intervals, replace=False):
        # the exact interval (the doubles t_k − h and t_k would differ from it by an ulp of t)
        with mpmath.workdps(24):           # 24 digits: the truth to ~1e-20 of its size
            a = mpmath.mpf(t0) + mpmath.mpf(int(k)) / rate
            b = mpmath.mpf(t0) + mpmath.mpf(int(k) + 1) / rate
            exact = np.array([float(mpmath.quad(f, [a, b], method="gauss-legendre"))
                              for f in ref])
        a, b = float(a), float(b)
        got = np.concatenate([sig.gyro[k], sig.accel[k]])
        # the integrand's size over the interval's block (only the scale of the absolute part
        # of the bound, so double precision suffices)
        blk = np.linspace(a - 32 * h, b + 32 * h, 65)
        fmax = np.abs(np.concatenate([m.angular_rate(blk), m.specific_force(blk)], -1)).max(0)
        for s in (slice(0, 3), slice(3, 6)):
            err = np.linalg.norm(got[s] - exact[s])
            F = max(fmax[s])
            bound = (1e-13 * np.linalg.norm(exact[s]) + 1e-15 * h * F
                     + 4 * EPS * omega * b * F * h)
            assert err <= bound, (k, s, err, bound)


@pytest.mark.parametrize("name", sorted(MOTIONS))
def test_increments_match_mpmath_on_every_benchmark_motion(name, rng):
    make, omega = MOTIONS[name]
    _check(make(), 100.0, 20.0, 0.0, 6, rng, omega)


def test_far_from_t0_within_the_integrands_own_rounding(rng):
    """At t ≈ 5000 s a 2 Hz motion evaluates sin at Ωt ≈ 6e4: its values carry ε·Ωt rounding,
    which no method removes; the blocks accept that plateau instead of refining forever."""
    m = catalog.coning(duration=5010.0)
    _check(m, 100.0, 10.0, 5000.0, 6, rng, MOTIONS["coning"][1])


def test_fallback_when_sampling_is_far_slower_than_the_motion(rng, monkeypatch):
    """Coning at 2 Hz sampled at 3 Hz: a 64-interval block spans 43 cone periods, beyond what
    degree 128 resolves; those blocks fall back to adaptive Gauss–Legendre per interval."""
    calls = {"n": 0}
    real = Q.integrate_intervals

    def counting(*a, **k):
        calls["n"] += 1
        return real(*a, **k)

    monkeypatch.setattr(Q, "integrate_intervals", counting)
    m = catalog.coning(duration=100.0)
    _check(m, 3.0, 60.0, 0.0, 5, rng, MOTIONS["coning"][1])
    assert calls["n"] > 0


def test_block_rule_equals_the_adaptive_quadrature_it_replaces():
    """The fast path against the plain one (composite Gauss–Legendre per interval) on every
    interval of a run: the same integrals to 1e-13 of their norm plus both methods' rounding
    of the integrand (4ε·Ω·t·|f|·h, as above)."""
    make, omega = MOTIONS["fast_and_slow"]
    m = make()
    h = 1 / 200.0
    sig = simulate_imu(m, 200.0, 5.0, kind="increments")
    gl = Q.integrate_intervals(lambda s: np.concatenate([m.angular_rate(s),
                                                         m.specific_force(s)], -1),
                               sig.t - h, sig.t, width=6)
    for got, ref in ((sig.gyro, gl[:, :3]), (sig.accel, gl[:, 3:])):
        err = np.linalg.norm(got - ref, axis=1)
        F = np.abs(ref / h).max()
        assert np.all(err <= 1e-13 * np.linalg.norm(ref, axis=1) + 1e-15 * h * F
                      + 4 * EPS * omega * sig.t * F * h)


def test_weights_are_correctly_rounded():
    """The block weights from extended precision against 34-digit mpmath (independent sum)."""
    n, r = 32, 64
    x, W, C = Q._rule(n, r)
    with mpmath.workdps(34):
        nodes = [mpmath.cos(mpmath.pi * j / n) for j in range(n + 1)]

        def cardinal(j, u):
            return mpmath.fprod((u - nodes[i]) / (nodes[j] - nodes[i])
                                for i in range(n + 1) if i != j)

        for k in (0, 17, 63):
            for j in (0, 5, 16, 32):
                ref = mpmath.quad(lambda u, j=j: cardinal(j, u),
                                  [-1 + mpmath.mpf(2) * k / r, -1 + mpmath.mpf(2) * (k + 1) / r])
                assert abs(W[k, j] - float(ref)) <= 4e-16 * np.abs(W[k]).sum()


def test_chunking_does_not_change_increments():
    """Blocks start at multiples of 64 whatever the chunking; only BLAS's summation order of a
    differently sized batch can differ (rounding)."""
    from imunav.sensors import simulate as S

    m = MOTIONS["fast_and_slow"][0]()
    whole = simulate_imu(m, 100.0, 10.0, kind="increments")
    parts = list(S.ideal_chunks(m, 100.0, 10.0, kind="increments", chunk=128))
    for i, ref in ((1, whole.gyro), (2, whole.accel)):
        got = np.concatenate([p[i] for p in parts])
        assert np.abs(got - ref).max() <= 4 * EPS * np.abs(ref).max()
