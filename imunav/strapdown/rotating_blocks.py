"""The pieces of a block of :class:`~imunav.strapdown.rotating.EarthIntegrator` that depend on
nothing but the block: the weights of the gravity quadrature (exact in rational arithmetic), the
tables of a block's times and the Earth's turn over it, the closed-form paths of the iteration's
predictor and corrections, the exact evaluation of gravitation, geodetic coordinates and the
gravity gradient along a block's path, and the change of frame of the states at the output.
Unchecked kernels: the integrator checks its inputs.

May import: ``imunav.core``, ``imunav.earth``.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache, lru_cache

import numpy as np

from imunav.core.kernels import FloatArray
from imunav.earth import (
    E2,
    OMEGA_E,
    A,
    ecef_to_geodetic,
    geodetic_kernel,
    gradient_from_points,
    gradient_points,
    gravitation_kernel,
)

__all__ = ["CRUDE", "GRADIENT_STEP", "Z", "absmax", "block_tables", "earth_turn",
           "evaluate_path", "expand", "gradient_t", "gravity_weights", "matvec", "poly_sum",
           "quadrature_weights", "rot_z", "to_local", "trapezoid"]

#: Step (m) of the central differences of the gradient.
GRADIENT_STEP = 20.0


@cache
def gravity_weights(m: int) -> tuple[FloatArray, FloatArray]:
    """Weights of the gravity quadrature on ``m`` nodes ``0 … m−1`` for the last interval
    ``[m−2, m−1]`` (unit step): ``∫ P`` and ``∫ (m−1 − s) P(s) ds`` of the interpolating
    polynomial ``P``, exactly in rational arithmetic and rounded once.

    Parameters
    ----------
    m : int
        Nodes (≥ 2).

    Returns
    -------
    a, b : ndarray, shape (m,)
        ``I ≈ h Σ a_j G_j`` and ``II ≈ h² Σ b_j G_j``.
    """
    a, b = [], []
    lo, hi = Fraction(m - 2), Fraction(m - 1)
    for j in range(m):
        c = [Fraction(1)]                                  # ascending powers of ℓ_j
        for k in range(m):
            if k == j:
                continue
            c = [Fraction(0)] + c
            for i in range(len(c) - 1):
                c[i] -= k * c[i + 1]
            c = [ci / (j - k) for ci in c]
        ia = sum(ck * (hi ** (n + 1) - lo ** (n + 1)) / (n + 1) for n, ck in enumerate(c))
        # ∫ (hi − s) s^n ds = hi (hi^{n+1} − lo^{n+1})/(n+1) − (hi^{n+2} − lo^{n+2})/(n+2)
        ib = sum(ck * (hi * (hi ** (n + 1) - lo ** (n + 1)) / (n + 1)
                       - (hi ** (n + 2) - lo ** (n + 2)) / (n + 2)) for n, ck in enumerate(c))
        a.append(float(ia))
        b.append(float(ib))
    return np.array(a), np.array(b)


@cache
def quadrature_weights(m: int, h: float) -> FloatArray:
    """``[h a; h² b]`` of :func:`gravity_weights` as a (2, m) matrix."""
    a, b = gravity_weights(m)
    W = np.stack([h * a, h * h * b])
    W.flags.writeable = False
    return W


def matvec(MT: FloatArray, x: FloatArray) -> FloatArray:
    """``M x`` for vectors ``x`` (n, [R,] 3) and one matrix per run, given as ``Mᵀ`` (3, 3) or
    (R, 3, 3): a BLAS product."""
    if MT.ndim == 2:
        return x @ MT
    return (x[..., None, :] @ MT)[..., 0, :]


def rot_z(x: FloatArray, c: FloatArray, s: FloatArray, inverse: bool = False) -> FloatArray:
    """``R_z(α) x`` (``inverse``: ``R_z(−α) x``) for vectors ``x`` (..., 3) and ``c = cos α``,
    ``s = sin α`` broadcast to ``x.shape[:-1]``."""
    out = np.empty_like(x)
    x0, x1 = x[..., 0], x[..., 1]
    if inverse:
        np.multiply(c, x0, out=out[..., 0])
        out[..., 0] += s * x1
        np.multiply(c, x1, out=out[..., 1])
        out[..., 1] -= s * x0
    else:
        np.multiply(c, x0, out=out[..., 0])
        out[..., 0] -= s * x1
        np.multiply(c, x1, out=out[..., 1])
        out[..., 1] += s * x0
    out[..., 2] = x[..., 2]
    return out


def earth_turn(ang: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``cos α``, ``sin α`` of the Earth's turn within a block: by their series when
    ``|α| ≤ 3e-3`` (every block of :data:`BLOCK_SECONDS`; the first terms left out, α⁶/720 and
    α⁷/5040, are below 1e-18), else by ``np.cos``/``np.sin``."""
    if ang.size and float(np.abs(ang).max()) > 3e-3:
        return np.cos(ang), np.sin(ang)
    a2 = ang * ang
    c = a2 * (1.0 / 24.0)
    c -= 0.5
    c *= a2
    c += 1.0
    s = a2 * (1.0 / 120.0)
    s -= 1.0 / 6.0
    s *= a2
    s += 1.0
    s *= ang
    return c, s


def poly_sum(powers: FloatArray, coef: FloatArray, like: FloatArray) -> FloatArray:
    """``Σ_j powers[:, j] coef[j]`` for per-node powers (n, k) and vector coefficients (k, [R,]
    3): one BLAS product, shaped as ``like`` (n, [R,] 3) (a broadcast multiply-add of an (n, 1)
    column by a vector costs ~10 ns a node in numpy)."""
    return (powers @ coef.reshape(coef.shape[0], -1)).reshape(like.shape)


def trapezoid(e: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """Velocity ``V_k`` and displacement ``D_k`` of :meth:`EarthIntegrator._displacement` for
    the trapezoid rule (``I_j = h (e_{j−1} + e_j)/2``, ``II_j = h² (e_{j−1}/3 + e_j/6)``,
    ``e_{−1} = 0``) in closed form: with ``S = Σ e`` and ``SS = Σ S``,
    ``V = h (S − e/2)`` and ``D = h² (SS − S + e/6)``.

    The rule of the iteration's corrections to the predicted gravitation: the predictor is
    exact to first order in the departure d from a point at rest, so the corrections are its
    second-order term, ∇Γ d²/2 ≈ 1e-8 m/s² for d = 200 m, and the rule's error h³/12 of their
    curvature is ~1e-16 m/s a step (measured: the default algorithm's errors over 10 s at 40 Hz
    change by 2e-16 m/s against 8 nodes)."""
    S = np.cumsum(e, axis=0)
    SS = np.cumsum(S, axis=0)
    V = S * h
    V -= e * (0.5 * h)
    SS -= S
    SS += e * (1.0 / 6.0)
    SS *= h * h
    return V, SS


def gradient_t(r: FloatArray) -> FloatArray:
    """``(∂G/∂r)ᵀ`` at ``r`` ([R,] 3): :func:`imunav.earth.gravitation_gradient` with steps of
    :data:`GRADIENT_STEP`, unchecked and transposed (what :func:`matvec` takes): the first
    block's (each later one gets it from :func:`evaluate_path`)."""
    pts = gradient_points(r, GRADIENT_STEP)
    sl, _, hh, c = geodetic_kernel(pts)
    return gradient_from_points(gravitation_kernel(pts, sl, hh, c), GRADIENT_STEP)


@lru_cache(maxsize=8)
def block_tables(n: int, h: float) -> dict[str, FloatArray]:
    """What a block of ``n`` steps of ``h`` needs that depends on nothing else (read-only):
    ``tau`` (n,), the powers ``p012 = [1, τ, τ²]`` and ``p234 = [τ², τ³, τ⁴]`` (n, 3), ``steps =
    [1, k]`` (n, 2), the Earth's turn ``ang = ω τ`` and its ``cos``, ``sin``."""
    tau = np.arange(1, n + 1) * h
    t2 = tau * tau
    out = {"tau": tau, "p012": np.column_stack([np.ones(n), tau, t2]),
           "p234": np.column_stack([t2, t2 * tau, t2 * t2]),
           "steps": np.column_stack([np.ones(n), np.arange(1.0, n + 1.0)]),
           "ang": OMEGA_E * tau}
    out["cos"], out["sin"] = earth_turn(out["ang"])
    for x in out.values():
        x.flags.writeable = False
    return out


#: ``last @ CRUDE`` → the rows ``[½ G, (ω/6) ẑ × G, (ω²/24) ẑ × (ẑ × G)]`` of the predictor's
#: closed-form path of a gravitation ``G`` turning with the Earth (to third order in ω τ).
CRUDE = np.zeros((3, 3, 3))
CRUDE[:, 0] = 0.5 * np.eye(3)
CRUDE[1, 1, 0], CRUDE[0, 1, 1] = -OMEGA_E / 6.0, OMEGA_E / 6.0
CRUDE[0, 2, 0], CRUDE[1, 2, 1] = -OMEGA_E**2 / 24.0, -OMEGA_E**2 / 24.0
CRUDE = CRUDE.reshape(3, 9)


def evaluate_path(r: FloatArray) -> tuple[tuple, FloatArray, FloatArray]:
    """The exact evaluation at a block's path ``r`` (n, [R,] 3): its geodetic coordinates
    (:func:`geodetic_kernel`) and gravitation, and — in the same call, the six points added —
    the gradient (transposed) about its last node, for the next block."""
    pts = gradient_points(r[-1], GRADIENT_STEP)              # ([R,] 6, 3)
    both = np.concatenate([r.reshape(-1, 3), pts.reshape(-1, 3)])
    geo = geodetic_kernel(both)
    G = gravitation_kernel(both, geo[0], geo[2], geo[3])
    m = r.size // 3
    gbt = gradient_from_points(G[m:].reshape(pts.shape), GRADIENT_STEP)
    return (tuple(x[:m].reshape(r.shape[:-1]) for x in geo), G[:m].reshape(r.shape), gbt)


#: The generator of a turn about the Earth's axis (R_z(α) ≈ I + α Z).
Z = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])


def absmax(x: FloatArray) -> float:
    """``max |x|`` without the temporary of ``np.abs``."""
    return max(float(x.max()), -float(x.min()))


def expand(a: FloatArray, like: FloatArray) -> FloatArray:
    """A per-node scalar (n,) shaped to broadcast against the components ``like[..., i]`` of
    vectors ``like`` (n, [R,] 3)."""
    return a.reshape(a.shape + (1,) * (like.ndim - 2))


def to_local(q_ib: FloatArray, v_i: FloatArray, r_i: FloatArray, r1: FloatArray, geo: tuple,
             ang: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Inertial states → ``q_nb``, NED velocity and ``[lat, lon, h]``; the geodetic
    coordinates from those of the nearby ``r1`` (``geo``: :func:`geodetic_kernel`'s) plus
    the NED components of the small difference (second order: below 1e-15 m). ``ang`` is
    the Earth's turn ``ω_ie (t − t₀)`` at the nodes.

    Parameters
    ----------
    q_ib : ndarray, shape (n, [R,] 4)
    v_i, r_i : ndarray, shape (n, [R,] 3)
        Inertial velocity and position.
    r1 : ndarray, shape (n, [R,] 3)
        Nearby points whose geodetic coordinates ``geo`` are known.
    geo : tuple
        :func:`~imunav.earth.geodetic_kernel` of ``r1``.
    ang : ndarray, shape (n,)

    Returns
    -------
    q_nb, v_n, p : ndarray
    """
    sl, cl, alt1, c_rho = geo
    x1, y1 = r1[..., 0], r1[..., 1]
    inv = c_rho / cl                                      # 1/√(x₁² + y₁²)
    cn, sn = x1 * inv, y1 * inv                          # cos λ_i, sin λ_i of r1
    d = r_i - r1
    d0, d1, d2 = d[..., 0], d[..., 1], d[..., 2]
    radial = cn * d0
    radial += sn * d1
    dn = cl * d2
    dn -= sl * radial
    de = cn * d1
    de -= sn * d0
    dd = -cl * radial
    dd -= sl * d2
    x = 1.0 - E2 * sl * sl
    re = A / np.sqrt(x)
    rn = re * (1.0 - E2) / x
    dlat = dn / (rn + alt1)
    dlon = de / ((re + alt1) * cl)
    lat = np.arctan2(sl, cl) + dlat
    lon_i = np.arctan2(y1, x1) + dlon
    alt = alt1 - dd
    if d.size and absmax(d) > 1e-3:                      # never expected: be exact
        lat, lon_i, alt = ecef_to_geodetic(r_i)
        sL, cL, cn, sn = np.sin(lat), np.cos(lat), np.cos(lon_i), np.sin(lon_i)
        y1 = sn
    else:
        # sines and cosines at the corrected point: the corrections are below 2e-10 rad,
        # their squares below the rounding of 1
        sL = sl + cl * dlat
        cL = cl - sl * dlat
        cn, sn = cn - sn * dlon, sn + cn * dlon
    # v_n = C_ni (v_i − Ω × r_i): the local NED axes in the inertial frame
    vx = v_i[..., 0] + OMEGA_E * r_i[..., 1]
    vy = v_i[..., 1] - OMEGA_E * r_i[..., 0]
    vz = v_i[..., 2]
    v_n = np.empty_like(v_i)
    w = cn * vx
    w += sn * vy
    np.multiply(cL, vz, out=v_n[..., 0])
    v_n[..., 0] -= sL * w
    np.multiply(cn, vy, out=v_n[..., 1])
    v_n[..., 1] -= sn * vx
    np.multiply(cL, w, out=v_n[..., 2])
    v_n[..., 2] += sL * vz
    np.negative(v_n[..., 2], out=v_n[..., 2])
    # q_ni = q_en* = [C, 0, S, 0] ⊗ [ca, 0, 0, −sa] (q_en = q_z(λ) ⊗ q_y(−L − π/2)) with
    # a = λ_i/2 and C, S = cos, sin of (L + π/2)/2, the half angles from the sines and
    # cosines, each by the better-conditioned formula; the branch of λ_i is arctan2's
    # (the sign of y₁ at λ_i = ±π)
    with np.errstate(divide="ignore", invalid="ignore"):
        up = sL >= 0.0
        half = np.sqrt(0.5 * (1.0 + np.where(up, sL, -sL)))
        other = cL / (2.0 * half)
        S, C = np.where(up, half, other), np.where(up, other, half)
        right = cn >= 0.0
        half = np.sqrt(0.5 * (1.0 + np.where(right, cn, -cn)))
        half = np.where(right, half, np.copysign(half, y1))
        other = sn / (2.0 * half)
        ca, sa = np.where(right, half, other), np.where(right, other, half)
    # q_nb = q_ni ⊗ q_ib as the two turns, one factor at a time (24 products and sums
    # instead of the 16 + 12 of a general product after building q_ni)
    qw, qx, qy, qz = q_ib[..., 0], q_ib[..., 1], q_ib[..., 2], q_ib[..., 3]
    uw = ca * qw
    uw += sa * qz
    ux = ca * qx
    ux += sa * qy
    uy = ca * qy
    uy -= sa * qx
    uz = ca * qz
    uz -= sa * qw
    q_nb = np.empty(q_ib.shape)
    np.multiply(C, uw, out=q_nb[..., 0])
    q_nb[..., 0] -= S * uy
    np.multiply(C, ux, out=q_nb[..., 1])
    q_nb[..., 1] += S * uz
    np.multiply(C, uy, out=q_nb[..., 2])
    q_nb[..., 2] += S * uw
    np.multiply(C, uz, out=q_nb[..., 3])
    q_nb[..., 3] -= S * ux
    p = np.empty_like(v_n)
    p[..., 0] = lat
    lon = p[..., 1]
    np.subtract(lon_i, ang.reshape(ang.shape + (1,) * (lon_i.ndim - 1)), out=lon)
    if lon.size and (float(lon.max()) > np.pi or float(lon.min()) <= -np.pi):
        lon[...] = np.where(lon > np.pi, lon - 2 * np.pi,
                            np.where(lon <= -np.pi, lon + 2 * np.pi, lon))
    p[..., 2] = alt
    return q_nb, v_n, p
