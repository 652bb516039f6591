"""The WGS-84 Earth: constants, normal gravity, radii of curvature, Earth and transport rate, and
the conversions between geodetic coordinates, ECEF and local NED frames.

Frames (Groves 2nd ed., ch. 2):

``e`` (ECEF)
    Earth-centred, Earth-fixed: x through the equator at the prime meridian, z along the
    rotation axis; turns at :data:`OMEGA_E` about z relative to the inertial frame ``i``.
``n`` (local NED)
    North, east, down at a point: down along the ellipsoid's normal. ``C_en`` (columns N, E,
    D in ECEF) is :func:`dcm_ned_to_ecef`; ``q_en`` is :func:`quat_ned_to_ecef`, the rotation
    ``q_z(λ) ⊗ q_y(−L − π/2)``.
``i`` (inertial)
    Coincides with ``e`` at a chosen time ``t₀``; ``C_ie(t) = R_z(ω_ie (t − t₀))``
    (:func:`dcm_ecef_to_inertial`).

Geodetic coordinates are latitude ``L`` and longitude ``λ`` in radians and the height ``h``
above the ellipsoid in metres (degrees only at the edges: files, plots). Every function is
vectorised over leading axes.

Normal gravity (:func:`normal_gravity`) is Somigliana's closed form on the ellipsoid (Groves
eq. 2.134) with the second-order height expansion of NIMA TR8350.2 (3rd ed., 2000) eq. 4-3,

    γ(L, h) = γ₀(L) [1 − (2/a)(1 + f + m − 2f sin²L) h + (3/a²) h²],   m = ω_ie² a² b / GM,

acting along the ellipsoid normal (down). Against the exact normal gravity of the WGS-84 level
ellipsoid (the gradient of its normal potential, ``tests/earth/test_earth.py``) the magnitude is within
1.1e-8 of γ at 1 km, 7.2e-8 at 10 km, 2.1e-6 at 50 km and 1.7e-5 at 100 km (the truncated third
order, ~4(h/a)³). The small north component above the ellipsoid (Groves eq. 2.140, about
−8.08e-9 h sin 2L m/s²) is not modelled: 8.4e-7 of γ at 1 km, 8.5e-5 at 100 km — the larger part
of the vector's error there. The simulation on the rotating Earth and the navigation use this same
model, so an ideal IMU navigates back exactly.
Gravity ``g = G − Ω × (Ω × r)``: the gravitation ``G`` (mass attraction,
:func:`gravitation_ecef`) plus the centrifugal acceleration of the rotating frame.

ECEF → geodetic (:func:`ecef_to_geodetic`) is Vermeille's closed form (J. Geodesy 78, 2004,
94–95), exact to rounding outside the ellipsoid's evolute (within ~43 km of the Earth's centre),
checked against pymap3d and against a 50-digit iteration in ``tests/earth/test_earth.py``.

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.kernels import FloatArray, quat_mul
from imunav.core.validation import ImunavError, as_float_array

__all__ = ["A", "B", "E2", "F", "GAMMA_E", "GAMMA_P", "GM", "K_SOMIGLIANA", "M", "OMEGA_E",
           "dcm_ecef_to_inertial", "dcm_ned_to_ecef", "earth_rate_ned", "ecef_to_geodetic",
           "geodetic_kernel", "gravitation_kernel", "gradient_from_points", "gradient_points",
           "height_factor", "ecef_to_ned", "geodetic_to_ecef", "gravitation_ecef", "gravity_ecef",
           "gravity_ned", "ned_to_ecef", "normal_gravity", "quat_ned_to_ecef", "radii", "schuler_frequency",
           "transport_rate_ned", "check_origin"]

# ------------------------------------------------------------------------- WGS-84 constants

#: Semi-major axis (equatorial radius) a, m (WGS-84 defining constant).
A = 6378137.0
#: Flattening f = 1/298.257223563 (defining constant).
F = 1.0 / 298.257223563
#: Semi-minor (polar) axis b = a(1 − f), m.
B = A * (1.0 - F)
#: First eccentricity squared e² = f(2 − f).
E2 = F * (2.0 - F)
#: Earth's rotation rate ω_ie, rad/s (defining constant).
OMEGA_E = 7.292115e-5
#: Earth's gravitational constant GM, m³/s² (defining constant, atmosphere included).
GM = 3.986004418e14
#: Normal gravity on the equator γ_e and at the poles γ_p, m/s² (WGS-84, NIMA TR8350.2).
GAMMA_E = 9.7803253359
GAMMA_P = 9.8321849378
#: Somigliana's constant k = b γ_p / (a γ_e) − 1.
K_SOMIGLIANA = B * GAMMA_P / (A * GAMMA_E) - 1.0
#: m = ω_ie² a² b / GM (Groves eq. 2.139).
M = OMEGA_E**2 * A**2 * B / GM

_E4 = E2 * E2


def _angle(x, name: str) -> FloatArray:
    return as_float_array(x, name)


#: The highest origin accepted (m above the ellipsoid). Up to it the magnitude of
#: :func:`normal_gravity` holds to 1.7e-5 of γ and its direction (the ellipsoid normal) to
#: 8.5e-5 rad (see the module's docstring); above it both grow fast.
MAX_ORIGIN_HEIGHT = 1e5


def check_origin(lat: float, lon: float, h: float, what: str = "origin") -> tuple[float, float, float]:
    """A geodetic point ``(lat, lon, h)`` (rad, rad, m) checked: finite, ``|lat| ≤ π/2``.

    Parameters
    ----------
    lat, lon : float
        Latitude and longitude (rad).
    h : float
        Height above the ellipsoid (m), above −a/2 (inside that the geodetic conversion is
        not defined here).
    what : str
        The argument's name in the error.

    Returns
    -------
    tuple of float

    Raises
    ------
    ImunavError
        For a non-finite value, ``|lat| > π/2``, or a height below −a/2 or above
        :data:`MAX_ORIGIN_HEIGHT` (100 km).
    """
    vals = []
    for name, v in (("latitude", lat), ("longitude", lon), ("height", h)):
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise ImunavError(f"{what}: {name} must be a number, got {v!r}", argument=what) from None
        if not np.isfinite(x):
            raise ImunavError(f"{what}: {name} must be finite, got {x}", argument=what)
        vals.append(x)
    if abs(vals[0]) > np.pi / 2:
        raise ImunavError(f"{what}: latitude must be within ±90°, got {np.degrees(vals[0]):.10g}°",
                          argument=what)
    if vals[2] < -A / 2:
        raise ImunavError(f"{what}: height must be above −{A / 2:.0f} m, got {vals[2]:g} m",
                          argument=what)
    if vals[2] > MAX_ORIGIN_HEIGHT:
        # normal_gravity is second order in h/a: its truncation, ~4 (h/a)³, is 1.7e-5 of γ at
        # 100 km and grows fast (1.5 % at 1000 km) — above that the gravity would be wrong
        raise ImunavError(f"{what}: height must be at most {MAX_ORIGIN_HEIGHT:.0f} m above the "
                          f"ellipsoid (normal gravity, second order in height, holds there to "
                          f"1.7e-5 in magnitude and 8.5e-5 in direction), got {vals[2]:g} m",
                          argument=what)
    return vals[0], vals[1], vals[2]


# --------------------------------------------------------------------------------- gravity

def normal_gravity(lat: npt.ArrayLike, h: npt.ArrayLike = 0.0) -> FloatArray:
    """Magnitude of the WGS-84 normal gravity (m/s²) at latitude ``lat`` (rad) and height ``h``
    (m) above the ellipsoid.

    Somigliana's formula on the ellipsoid (Groves 2nd ed. eq. 2.134),
    ``γ₀ = γ_e (1 + k sin²L) / √(1 − e² sin²L)``, with the second-order height expansion of
    NIMA TR8350.2 eq. 4-3, ``γ = γ₀ [1 − (2/a)(1 + f + m − 2f sin²L) h + (3/a²) h²]``
    (``m = ω_ie² a² b / GM``).

    Its truncation, measured against the exact normal gravity of the level ellipsoid (the
    gradient of the WGS-84 normal potential, 40 digits, ``tests/earth/test_earth.py``) at 0–90° of
    latitude: at most 1.1e-8 of γ at 1 km, 7.2e-8 at 10 km, 4.8e-7 at 30 km, 2.1e-6 at 50 km,
    1.7e-5 at 100 km (it grows as ~4 (h/a)³); 6.5e-12 on the ellipsoid (the rounding of the
    published γ_e, γ_p). Without the ``−2f sin²L`` term (Groves eq. 2.139) it was 2.1e-6 at
    1 km and 2.0e-4 at 100 km at the pole. The direction is the ellipsoid normal: the exact
    field's north component, 8.4e-7 of γ at 1 km and 8.5e-5 at 100 km, is not modelled.

    Parameters
    ----------
    lat : array_like
        Geodetic latitude (rad).
    h : array_like
        Height above the ellipsoid (m); broadcast against ``lat``.

    Returns
    -------
    ndarray
        γ (m/s²), of the broadcast shape.

    Examples
    --------
    >>> round(float(normal_gravity(0.0)), 10), round(float(normal_gravity(np.pi / 2)), 10)
    (9.7803253359, 9.8321849378)
    """
    lat = _angle(lat, "lat")
    h = as_float_array(h, "h")
    s2 = np.sin(lat) ** 2
    g0 = GAMMA_E * (1.0 + K_SOMIGLIANA * s2) / np.sqrt(1.0 - E2 * s2)
    return g0 * height_factor(s2, h)


def height_factor(sin2_lat: FloatArray, h: FloatArray) -> FloatArray:
    """The second-order height factor of :func:`normal_gravity` (NIMA TR8350.2 eq. 4-3),
    ``1 − (2/a)(1 + f + m − 2f sin²L) h + (3/a²) h²``, unchecked (what hot paths call).

    Parameters
    ----------
    sin2_lat : ndarray
        ``sin²L`` of the geodetic latitude.
    h : ndarray
        Height above the ellipsoid (m).

    Returns
    -------
    ndarray
        ``γ(L, h) / γ₀(L)``.
    """
    return 1.0 - (2.0 / A) * ((1.0 + F + M) - (2.0 * F) * sin2_lat) * h + (3.0 / A**2) * (h * h)


def gravity_ned(lat: npt.ArrayLike, h: npt.ArrayLike = 0.0) -> FloatArray:
    """The normal gravity vector in local NED, ``[0, 0, γ(L, h)]`` (m/s²).

    Parameters
    ----------
    lat : array_like
        Latitude (rad).
    h : array_like
        Height (m).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    g = normal_gravity(lat, h)
    out = np.zeros(g.shape + (3,))
    out[..., 2] = g
    return out


def gravitation_kernel(r: FloatArray, sin_lat: FloatArray, h: FloatArray, c_rho: FloatArray
                       ) -> FloatArray:
    """The unchecked core of :func:`gravitation_ecef` at ``r`` (…, 3) from what
    :func:`geodetic_kernel` gives: ``−γ n − ω_ie² [x, y, 0]``, ``n = [c x, c y, sin L]`` the up
    normal (``c = cos L/√(x² + y²)``; no trigonometric function).

    Parameters
    ----------
    r : ndarray, shape (..., 3)
    sin_lat, h, c_rho : ndarray, shape (...)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    x2 = sin_lat * sin_lat
    g = -(GAMMA_E * (1.0 + K_SOMIGLIANA * x2) / np.sqrt(1.0 - E2 * x2) * height_factor(x2, h))
    x, y = r[..., 0], r[..., 1]
    gc = g * c_rho
    out = np.empty(np.shape(r))
    w2 = OMEGA_E * OMEGA_E
    out[..., 0] = (gc - w2) * x
    out[..., 1] = (gc - w2) * y
    out[..., 2] = g * sin_lat
    return out


def gravity_ecef(r: npt.ArrayLike) -> FloatArray:
    """The normal gravity vector ``g_e`` (m/s²) at ECEF positions ``r`` (m): γ(L, h) along the
    ellipsoid normal, pointing down.

    Parameters
    ----------
    r : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    G = gravitation_ecef(r)
    r = np.asarray(r, dtype=float)
    G[..., 0] += OMEGA_E**2 * r[..., 0]
    G[..., 1] += OMEGA_E**2 * r[..., 1]
    return G


def gravitation_ecef(r: npt.ArrayLike) -> FloatArray:
    """The gravitation ``G = g + Ω × (Ω × r)`` (m/s²): normal gravity without the centrifugal
    acceleration ``ω_ie² [x, y, 0]`` of the rotating frame.

    The field is symmetric about the rotation axis, so the same function gives the gravitation
    in any frame whose z axis is the Earth's axis — the inertial frame of
    :func:`dcm_ecef_to_inertial` included.

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Position (m) in ECEF (or in the inertial frame).

    Returns
    -------
    ndarray, shape (..., 3)

    Raises
    ------
    ImunavError
        For a position within 43 km of the Earth's centre or not finite.
    """
    r = as_float_array(r, "r", last=3)
    sl, _, h, c = geodetic_kernel(r)
    if np.any(~np.isfinite(h)):
        raise ImunavError("r must be further than 43 km from the Earth's centre", argument="r")
    return gravitation_kernel(r, sl, h, c)


def schuler_frequency(lat: float = 0.0, h: float = 0.0) -> float:
    """The Schuler frequency ``ω_s = √(g/R)`` (rad/s), g the normal gravity and R the
    geometric mean radius of curvature ``√(R_N R_E) + h`` at ``lat``.

    Parameters
    ----------
    lat : float
        Latitude (rad).
    h : float
        Height (m).

    Returns
    -------
    float
        About 1.24e-3 rad/s: a period ``2π/ω_s`` of 84.4 minutes.
    """
    rn, re = radii(lat)
    return float(np.sqrt(normal_gravity(lat, h) / (np.sqrt(rn * re) + h)))


# ------------------------------------------------------------------ radii and frame rates

def radii(lat: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The principal radii of curvature of the ellipsoid at latitude ``lat`` (rad).

    Parameters
    ----------
    lat : array_like

    Returns
    -------
    R_N : ndarray
        Meridian radius (north–south), ``a (1 − e²) / (1 − e² sin²L)^{3/2}`` (Groves eq. 2.105).
    R_E : ndarray
        Transverse (prime-vertical, east–west) radius, ``a / √(1 − e² sin²L)`` (eq. 2.106).
    """
    lat = _angle(lat, "lat")
    x = 1.0 - E2 * np.sin(lat) ** 2
    re = A / np.sqrt(x)
    return re * (1.0 - E2) / x, re


def earth_rate_ned(lat: npt.ArrayLike) -> FloatArray:
    """The Earth rate in local NED, ``ω_ie^n = ω_ie [cos L, 0, −sin L]`` (rad/s).

    Parameters
    ----------
    lat : array_like
        Latitude (rad).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    lat = _angle(lat, "lat")
    out = np.zeros(lat.shape + (3,))
    out[..., 0] = OMEGA_E * np.cos(lat)
    out[..., 2] = -OMEGA_E * np.sin(lat)
    return out


def transport_rate_ned(lat: npt.ArrayLike, h: npt.ArrayLike, v_ned: npt.ArrayLike) -> FloatArray:
    """The transport rate (the turn of local NED over the ellipsoid),
    ``ω_en^n = [v_E/(R_E + h), −v_N/(R_N + h), −v_E tan L/(R_E + h)]`` (rad/s, Groves eq. 5.44).

    Parameters
    ----------
    lat : array_like
        Latitude (rad).
    h : array_like
        Height (m).
    v_ned : array_like, shape (..., 3)
        Velocity relative to the Earth in NED (m/s).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    lat = _angle(lat, "lat")
    h = as_float_array(h, "h")
    v = as_float_array(v_ned, "v_ned", last=3)
    rn, re = radii(lat)
    out = np.empty(np.broadcast_shapes(lat.shape, h.shape, v.shape[:-1]) + (3,))
    out[..., 0] = v[..., 1] / (re + h)
    out[..., 1] = -v[..., 0] / (rn + h)
    out[..., 2] = -v[..., 1] * np.tan(lat) / (re + h)
    return out


# ---------------------------------------------------------------------------- conversions

def geodetic_to_ecef(lat: npt.ArrayLike, lon: npt.ArrayLike, h: npt.ArrayLike = 0.0) -> FloatArray:
    """ECEF position (m) of geodetic coordinates (Groves eq. 2.112).

    Parameters
    ----------
    lat, lon : array_like
        Latitude and longitude (rad).
    h : array_like
        Height above the ellipsoid (m).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    lat, lon = _angle(lat, "lat"), _angle(lon, "lon")
    h = as_float_array(h, "h")
    sl, cl = np.sin(lat), np.cos(lat)
    re = A / np.sqrt(1.0 - E2 * sl * sl)
    shape = np.broadcast_shapes(lat.shape, lon.shape, h.shape)
    out = np.empty(shape + (3,))
    out[..., 0] = (re + h) * cl * np.cos(lon)
    out[..., 1] = (re + h) * cl * np.sin(lon)
    out[..., 2] = ((1.0 - E2) * re + h) * sl
    return out


def ecef_to_geodetic(r: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Geodetic latitude, longitude (rad) and height (m) of ECEF positions ``r`` (m).

    Vermeille's closed form (J. Geodesy 78, 2004): no iteration, exact to rounding for points
    more than ~43 km from the Earth's centre.

    Parameters
    ----------
    r : array_like, shape (..., 3)

    Returns
    -------
    lat, lon, h : ndarray, shape (...)

    Raises
    ------
    ImunavError
        For a point within 43 km of the centre (inside the ellipsoid's evolute) or not finite.
    """
    r = as_float_array(r, "r", last=3)
    sl, cl, h, _ = geodetic_kernel(r)
    if np.any(~np.isfinite(h)):
        raise ImunavError("r must be further than 43 km from the Earth's centre (outside the "
                          "ellipsoid's evolute)", argument="r")
    return np.arctan2(sl, cl), np.arctan2(r[..., 1], r[..., 0]), h


def geodetic_kernel(r: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The unchecked core of :func:`ecef_to_geodetic`: ``sin L``, ``cos L`` and ``h`` of ECEF
    positions ``r`` (…, 3) without a trigonometric function (Vermeille 2004: ``tan L = z/D``),
    and ``cos L / √(x² + y²)`` (finite at the poles), which turns ``x``, ``y`` into the
    horizontal components of the up normal.

    What hot paths call (the navigation's gravity at every step); NaN inside the evolute.

    Parameters
    ----------
    r : ndarray, shape (..., 3)

    Returns
    -------
    sin_lat, cos_lat, h, c_rho : ndarray, shape (...)
    """
    if np.ndim(r) == 1:                                  # one point: scalars out
        return tuple(x[0] for x in geodetic_kernel(np.asarray(r)[None]))
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    rho2 = x * x
    rho2 += y * y
    p = rho2 * (1.0 / (A * A))
    q = z * z
    q *= (1.0 - E2) / (A * A)
    s6 = p + q
    s6 -= _E4
    s6 *= 1.0 / 6.0
    if s6.size and float(s6.min()) > 0:                  # every point outside the evolute
        return _vermeille(rho2, z, p, q, s6)
    with np.errstate(invalid="ignore", divide="ignore"):
        return _vermeille(rho2, z, p, q, np.where(s6 > 0, s6, np.nan))


def _vermeille(rho2, z, p, q, s6):
    """The rest of :func:`geodetic_kernel` (Vermeille 2004), in place where it can be (the
    same operations in the same order as the textbook expressions, so the same bits)."""
    s = (_E4 * 0.25) * p
    s *= q
    s /= (s6 * s6) * s6
    t = 2.0 + s
    t *= s
    np.sqrt(t, out=t)
    t += 1.0 + s
    np.cbrt(t, out=t)
    u = 1.0 + t
    u += 1.0 / t
    u *= s6
    v = u * u
    v += _E4 * q
    np.sqrt(v, out=v)
    w = u + v
    w -= q
    w *= 0.5 * E2
    w /= v
    k = u + v
    k += w * w
    np.sqrt(k, out=k)
    k -= w
    kE = k + E2
    D = k * np.sqrt(rho2)
    D /= kE
    dz = D * D
    dz += z * z
    np.sqrt(dz, out=dz)
    h = k + E2 - 1.0
    h /= k
    h *= dz
    kE *= dz
    np.divide(k, kE, out=k)
    return z / dz, D / dz, h, k


def dcm_ned_to_ecef(lat: npt.ArrayLike, lon: npt.ArrayLike) -> FloatArray:
    """``C_en``: the columns are the north, east and down unit vectors in ECEF.

    Parameters
    ----------
    lat, lon : array_like
        Latitude and longitude (rad).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``v_e = C_en @ v_n``.
    """
    lat, lon = _angle(lat, "lat"), _angle(lon, "lon")
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    shape = np.broadcast_shapes(lat.shape, lon.shape)
    C = np.empty(shape + (3, 3))
    C[..., 0, 0], C[..., 0, 1], C[..., 0, 2] = -sl * co, -so, -cl * co
    C[..., 1, 0], C[..., 1, 1], C[..., 1, 2] = -sl * so, co, -cl * so
    C[..., 2, 0], C[..., 2, 1], C[..., 2, 2] = cl, 0.0, -sl
    return C


def quat_ned_to_ecef(lat: npt.ArrayLike, lon: npt.ArrayLike) -> FloatArray:
    """``q_en`` (scalar first): the rotation of :func:`dcm_ned_to_ecef`,
    ``q_z(λ) ⊗ q_y(−L − π/2)``.

    Parameters
    ----------
    lat, lon : array_like
        Latitude and longitude (rad).

    Returns
    -------
    ndarray, shape (..., 4)
    """
    lat, lon = _angle(lat, "lat"), _angle(lon, "lon")
    a = 0.5 * lon
    b = -0.5 * (lat + np.pi / 2)
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    # q_z(λ) ⊗ q_y(β) = [ca cb, −sa sb, ca sb, sa cb]
    shape = np.broadcast_shapes(lat.shape, lon.shape)
    q = np.empty(shape + (4,))
    q[..., 0] = ca * cb
    q[..., 1] = -sa * sb
    q[..., 2] = ca * sb
    q[..., 3] = sa * cb
    return q


def dcm_ecef_to_inertial(t: npt.ArrayLike, t0: float = 0.0) -> FloatArray:
    """``C_ie(t) = R_z(ω_ie (t − t₀))``: ECEF vectors in the inertial frame that coincides with
    ECEF at ``t₀``.

    Parameters
    ----------
    t : array_like
        Times (s).
    t0 : float
        The time the frames coincide.

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    t = as_float_array(t, "t")
    a = OMEGA_E * (t - t0)
    c, s = np.cos(a), np.sin(a)
    C = np.zeros(t.shape + (3, 3))
    C[..., 0, 0], C[..., 0, 1], C[..., 1, 0], C[..., 1, 1] = c, -s, s, c
    C[..., 2, 2] = 1.0
    return C


def ned_to_ecef(p_ned: npt.ArrayLike, origin: tuple[float, float, float]) -> FloatArray:
    """ECEF positions (m) of points given in the local NED tangent frame at ``origin``.

    Parameters
    ----------
    p_ned : array_like, shape (..., 3)
        North, east, down from the origin (m), in the NED frame fixed at the origin.
    origin : tuple of float
        ``(lat, lon, h)`` (rad, rad, m).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    p = as_float_array(p_ned, "p_ned", last=3)
    lat, lon, h = check_origin(*origin)
    return geodetic_to_ecef(lat, lon, h) + p @ dcm_ned_to_ecef(lat, lon).T


def ecef_to_ned(r: npt.ArrayLike, origin: tuple[float, float, float]) -> FloatArray:
    """Local NED coordinates (m) at ``origin`` of ECEF positions ``r`` (m).

    Parameters
    ----------
    r : array_like, shape (..., 3)
    origin : tuple of float
        ``(lat, lon, h)`` (rad, rad, m).

    Returns
    -------
    ndarray, shape (..., 3)
    """
    r = as_float_array(r, "r", last=3)
    lat, lon, h = check_origin(*origin)
    return (r - geodetic_to_ecef(lat, lon, h)) @ dcm_ned_to_ecef(lat, lon)


def quat_ecef_to_inertial(t: npt.ArrayLike, t0: float = 0.0) -> FloatArray:
    """``q_ie(t)``: the rotation of :func:`dcm_ecef_to_inertial` as a quaternion.

    Parameters
    ----------
    t : array_like
        Times (s).
    t0 : float

    Returns
    -------
    ndarray, shape (..., 4)
    """
    t = as_float_array(t, "t")
    a = 0.5 * OMEGA_E * (t - t0)
    q = np.zeros(t.shape + (4,))
    q[..., 0], q[..., 3] = np.cos(a), np.sin(a)
    return q


def quat_nb_from_ecef(q_eb: FloatArray, lat: FloatArray, lon: FloatArray) -> FloatArray:
    """``q_nb = q_en* ⊗ q_eb``: body attitude relative to local NED from the attitude in ECEF.

    Parameters
    ----------
    q_eb : ndarray, shape (..., 4)
    lat, lon : ndarray
        Where the local NED frame is (rad).

    Returns
    -------
    ndarray, shape (..., 4)
    """
    q_en = quat_ned_to_ecef(lat, lon)
    q_en[..., 1:] *= -1.0
    return quat_mul(q_en, q_eb)


__all__ += ["quat_ecef_to_inertial", "quat_nb_from_ecef"]


def ned_difference(lla: npt.ArrayLike, lla_ref: npt.ArrayLike) -> FloatArray:
    """The position ``lla`` relative to ``lla_ref`` in metres, in the local NED frame at
    ``lla_ref``: the navigation error of an estimate on the Earth.

    Parameters
    ----------
    lla, lla_ref : array_like, shape (..., 3)
        ``[lat, lon, h]`` (rad, rad, m).

    Returns
    -------
    ndarray, shape (..., 3)
        North, east, down (m).
    """
    a = as_float_array(lla, "lla", last=3)
    b = as_float_array(lla_ref, "lla_ref", last=3)
    d = geodetic_to_ecef(a[..., 0], a[..., 1], a[..., 2]) - geodetic_to_ecef(
        b[..., 0], b[..., 1], b[..., 2])
    return np.einsum("...ji,...j->...i", dcm_ned_to_ecef(b[..., 0], b[..., 1]), d)


__all__ += ["ned_difference"]


def gravitation_gradient(r: npt.ArrayLike, step: float = 20.0) -> FloatArray:
    """The gradient ``∂G/∂r`` (s⁻²) of the gravitation of :func:`gravitation_ecef` at ``r``, by
    central differences of the exact field: the feedback of a position error through gravity
    (vertical ≈ +2g/R, horizontal ≈ −g/R: the Schuler loop).

    With steps of ``step`` metres the truncation is ~(step/R)² ≈ 1e-11 of the gradient and the
    rounding ~1e-15 g/step ≈ 1e-16 s⁻².

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Positions (m), ECEF or inertial.
    step : float
        Difference step (m).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``[i, j] = ∂G_i/∂r_j``.
    """
    r = as_float_array(r, "r", last=3)
    pts = gradient_points(r, step)
    sl, _, h, c = geodetic_kernel(pts)
    return np.swapaxes(gradient_from_points(gravitation_kernel(pts, sl, h, c), step), -1, -2)


def gradient_points(r: FloatArray, step: float) -> FloatArray:
    """The six points ``r ± step`` along x, y and z of the central differences of
    :func:`gravitation_gradient` (unchecked; what hot paths evaluate with other points).

    Parameters
    ----------
    r : ndarray, shape (..., 3)
        Positions (m), ECEF or inertial.
    step : float
        Difference step (m).

    Returns
    -------
    ndarray, shape (..., 6, 3)
        ``r + step e_x``, ``r − step e_x``, then y and z alike.
    """
    offsets = np.repeat(np.eye(3), 2, axis=0) * np.tile([step, -step], 3)[:, None]
    return r[..., None, :] + offsets


def gradient_from_points(G: FloatArray, step: float) -> FloatArray:
    """The central differences of the gravitation at :func:`gradient_points`.

    Parameters
    ----------
    G : ndarray, shape (..., 6, 3)
        The gravitation (m/s²) at the six points.
    step : float
        Their difference step (m).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        The gradient *transposed*: ``[j, i] = ∂G_i/∂r_j`` (s⁻²).
    """
    return (G[..., 0::2, :] - G[..., 1::2, :]) / (2.0 * step)


def gravitation_hessian(r: npt.ArrayLike, step: float = 200.0) -> FloatArray:
    """The second derivatives ``∂²G_i/∂r_j∂r_k`` (s⁻² m⁻¹, ~3g/R² ≈ 7e-13) of the gravitation
    at ``r``, by central differences of :func:`gravitation_gradient` (steps of ``step`` metres:
    truncation ~1e-9 and rounding ~4e-6 of it).

    Parameters
    ----------
    r : array_like, shape (..., 3)
    step : float
        Difference step (m).

    Returns
    -------
    ndarray, shape (..., 3, 3, 3)
        ``[i, j, k]``.
    """
    r = as_float_array(r, "r", last=3)
    pts = np.empty(r.shape[:-1] + (6, 3))
    pts[...] = r[..., None, :]
    for k in range(3):
        pts[..., 2 * k, k] += step
        pts[..., 2 * k + 1, k] -= step
    J = gravitation_gradient(pts)                                  # (..., 6, 3, 3)
    return np.stack([(J[..., 2 * k, :, :] - J[..., 2 * k + 1, :, :]) / (2.0 * step)
                     for k in range(3)], axis=-1)


def curvature_matrix(lat: npt.ArrayLike, h: npt.ArrayLike) -> FloatArray:
    """``K`` with ``δθ = K δp``: the small rotation (rad, in NED) of the local NED frame when the
    point moves by ``δp`` (m, NED) — the transport rate is ``K v``.

    Parameters
    ----------
    lat, h : array_like
        Latitude (rad) and height (m).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``[[0, 1/(R_E+h), 0], [−1/(R_N+h), 0, 0], [0, −tan L/(R_E+h), 0]]``.
    """
    lat = _angle(lat, "lat")
    h = as_float_array(h, "h")
    rn, re = radii(lat)
    K = np.zeros(np.broadcast_shapes(lat.shape, h.shape) + (3, 3))
    K[..., 0, 1] = 1.0 / (re + h)
    K[..., 1, 0] = -1.0 / (rn + h)
    K[..., 2, 1] = -np.tan(lat) / (re + h)
    return K


__all__ += ["curvature_matrix", "gravitation_gradient", "gravitation_hessian"]

