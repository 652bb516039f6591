"""imunav.earth — the WGS-84 Earth — against independent truths: the WGS-84 defining document's
derived constants (NIMA TR8350.2), pyins' Earth model (an independent implementation of the same
formulas), pymap3d's conversions and a 50-digit fixed-point iteration of geodetic latitude."""

import mpmath as mp
import numpy as np
import pymap3d
import pytest
from pyins import earth as pe
from pyins import transform as pt

from imunav import ImunavError
from imunav import earth as E

DEG = np.pi / 180


def test_derived_constants_are_those_of_the_wgs84_document():
    # NIMA TR8350.2 (3rd ed., 2000) table 3.3: b, e², k (Somigliana), m
    assert E.B == pytest.approx(6356752.3142, abs=1e-4)
    assert E.E2 == pytest.approx(6.69437999014e-3, rel=1e-12)
    # k from the published γ_e, γ_p (rounded to 1e-10 m/s², 1e-11 relative): 6e-12 off the
    # table's k, computed from the unrounded ones
    assert E.K_SOMIGLIANA == pytest.approx(0.00193185265241, abs=1e-11)
    assert E.M == pytest.approx(0.00344978650684, rel=1e-10)
    assert pe.RATE == E.OMEGA_E and pe.A == E.A and pe.E2 == pytest.approx(E.E2, rel=1e-13)


def test_normal_gravity_on_the_ellipsoid_against_pyins_and_the_end_values():
    lat = np.linspace(-np.pi / 2, np.pi / 2, 181)
    np.testing.assert_allclose(E.normal_gravity(lat), pe.gravity(np.degrees(lat), 0.0),
                               rtol=2e-15)
    # the defining values at the equator and the poles (TR8350.2 eq. 4-1)
    assert float(E.normal_gravity(0.0)) == pytest.approx(9.7803253359, abs=1e-15)
    assert float(E.normal_gravity(np.pi / 2)) == pytest.approx(9.8321849378, abs=2e-15)


def test_normal_gravity_above_the_ellipsoid_has_the_second_order_height_terms():
    lat, h = np.radians([0.0, 30.0, 55.0, 80.0]), np.array([0.0, 150.0, 1e4, 3e4])
    g0 = E.normal_gravity(lat)
    g = E.normal_gravity(lat, h)
    # Groves eq. 2.139, written out here from the constants
    expected = g0 * (1 - 2 / E.A * (1 + E.F + E.M) * h + 3 * h**2 / E.A**2)
    np.testing.assert_allclose(g, expected, rtol=1e-15)
    # the quadratic term is there: at 30 km it is 3h²/a² γ0 = 6.5e-5 m/s² above the linear one
    linear = g0 * (1 - 2 / E.A * (1 + E.F + E.M) * h)
    assert g[-1] - linear[-1] == pytest.approx(3 * 3e4**2 / E.A**2 * g0[-1], rel=1e-9)
    assert g[-1] - linear[-1] > 6e-5
    # against TR8350.2 eq. 4-3 (which keeps a −2f sin²φ term that Groves drops): within
    # 4 f sin²φ h γ/a, 1.1e-6 m/s² at 30 km and 80°
    tr = g0 * (1 - 2 / E.A * (1 + E.F + E.M - 2 * E.F * np.sin(lat) ** 2) * h + 3 * h**2 / E.A**2)
    assert np.all(np.abs(g - tr) <= 4 * E.F * np.sin(lat) ** 2 * h * g0 / E.A * 1.0001)


def test_gravity_vector_points_down_and_gravitation_adds_the_centrifugal_part():
    lat, lon, h = 55 * DEG, 37 * DEG, 150.0
    r = E.geodetic_to_ecef(lat, lon, h)
    g_n = E.dcm_ned_to_ecef(lat, lon).T @ E.gravity_ecef(r)
    np.testing.assert_allclose(g_n, [0, 0, E.normal_gravity(lat, h)], atol=1e-14)
    G = E.gravitation_ecef(r)
    # g = G − Ω×(Ω×r): the centrifugal acceleration is +ω²[x, y, 0]
    w = np.array([0, 0, E.OMEGA_E])
    np.testing.assert_allclose(E.gravity_ecef(r), G - np.cross(w, np.cross(w, r)), atol=1e-14)
    # pyins' gravitation (its gravity has the linear height term: compare on the ellipsoid)
    r0 = E.geodetic_to_ecef(lat, lon, 0.0)
    np.testing.assert_allclose(E.gravitation_ecef(r0),
                               pe.gravitation_ecef([np.degrees(lat), np.degrees(lon), 0.0]),
                               atol=5e-15)
    # symmetric about the Earth's axis: the same function in any frame turned about z
    C = E.dcm_ecef_to_inertial(1234.5)
    np.testing.assert_allclose(E.gravitation_ecef(C @ r), C @ G, atol=2e-15)


def test_schuler_period_is_84_minutes():
    assert 2 * np.pi / E.schuler_frequency(0.0) / 60 == pytest.approx(84.4, abs=0.1)


def test_radii_rates_and_frames_against_pyins():
    lat = np.radians([-89.0, -30.0, 0.0, 45.0, 55.0, 89.9])
    lon = np.radians([-170.0, -20.0, 0.0, 37.0, 120.0, 179.0])
    rn, re = E.radii(lat)
    prn, pre, _ = pe.principal_radii(np.degrees(lat), 0.0)
    np.testing.assert_allclose(rn, prn, rtol=1e-15)
    np.testing.assert_allclose(re, pre, rtol=1e-15)
    np.testing.assert_allclose(E.earth_rate_ned(lat), pe.rate_n(np.degrees(lat)), atol=1e-19)
    v = np.array([[3.0, -40.0, 1.5]] * lat.size)
    h = np.full(lat.size, 250.0)
    F = pe.curvature_matrix(np.degrees(lat), h)
    np.testing.assert_allclose(E.transport_rate_ned(lat, h, v), np.einsum("nij,nj->ni", F, v),
                               rtol=1e-13, atol=1e-20)
    C = E.dcm_ned_to_ecef(lat, lon)
    np.testing.assert_allclose(C, pt.mat_en_from_ll(np.degrees(lat), np.degrees(lon)), atol=1e-15)
    from imunav.core.rotations import quat_to_dcm

    np.testing.assert_allclose(quat_to_dcm(E.quat_ned_to_ecef(lat, lon)), C, atol=1e-15)


def _geodetic_50_digits(x, y, z):
    """Latitude and height of a double ECEF point by Bowring's fixed point in 50 digits."""
    mp.mp.dps = 50
    a, f = mp.mpf(E.A), 1 / mp.mpf("298.257223563")
    e2 = f * (2 - f)
    x, y, z = mp.mpf(x), mp.mpf(y), mp.mpf(z)
    p = mp.sqrt(x * x + y * y)
    L = mp.atan2(z, p * (1 - e2))
    for _ in range(80):
        N = a / mp.sqrt(1 - e2 * mp.sin(L) ** 2)
        L = mp.atan2(z + e2 * N * mp.sin(L), p)
    N = a / mp.sqrt(1 - e2 * mp.sin(L) ** 2)
    h = p / mp.cos(L) - N if abs(L) < 1.3 else z / mp.sin(L) - N * (1 - e2)
    return float(L), float(h)


def test_ecef_to_geodetic_is_exact_to_rounding_against_50_digits(rng):
    n = 60
    lat = rng.uniform(-np.pi / 2, np.pi / 2, n)
    lon = rng.uniform(-np.pi, np.pi, n)
    h = rng.choice([-400.0, 0.0, 150.0, 9e3, 4e5, 2.02e7], n) * rng.uniform(0, 1, n)
    r = E.geodetic_to_ecef(lat, lon, h)
    la, lo, hh = E.ecef_to_geodetic(r)
    for i in range(n):
        L, H = _geodetic_50_digits(*r[i])
        assert abs(L - la[i]) <= 2.3e-16              # measured ≤ 2.2e-16 rad (1 ulp)
        assert abs(H - hh[i]) <= 4 * np.spacing(max(abs(H), np.linalg.norm(r[i])))
    np.testing.assert_allclose(lo, lon, atol=1e-15)


def test_geodetic_and_local_ned_against_pymap3d(rng):
    n = 200
    lat = rng.uniform(-89.9, 89.9, n) * DEG
    lon = rng.uniform(-180, 180, n) * DEG
    h = rng.uniform(-300, 3e4, n)
    r = E.geodetic_to_ecef(lat, lon, h)
    np.testing.assert_allclose(r, np.stack(pymap3d.geodetic2ecef(lat, lon, h, deg=False), -1),
                               atol=1e-8)
    la, lo, hh = E.ecef_to_geodetic(r)
    pl, plo, ph = pymap3d.ecef2geodetic(*r.T, deg=False)
    # pymap3d's one-step method (You 2000) is good to ~1 µm here; ours to rounding (above)
    assert np.abs(la - pl).max() * E.A < 5e-6 and np.abs(hh - ph).max() < 5e-6
    origin = (55 * DEG, 37 * DEG, 150.0)
    ned = rng.normal(scale=5e3, size=(20, 3))
    rr = E.ned_to_ecef(ned, origin)
    np.testing.assert_allclose(rr, np.stack(pymap3d.ned2ecef(*ned.T, *origin, deg=False), -1),
                               atol=2e-8)
    np.testing.assert_allclose(E.ecef_to_ned(rr, origin), ned, atol=2e-8)
    np.testing.assert_allclose(
        E.ned_difference(np.stack(E.ecef_to_geodetic(rr), -1), np.array(origin)), ned, atol=2e-8)


def test_origin_and_position_errors_name_what_was_expected():
    with pytest.raises(ImunavError, match="origin: latitude must be within ±90°, got 91°"):
        E.check_origin(91 * DEG, 0.0, 0.0)
    with pytest.raises(ImunavError, match="origin: longitude must be a number, got 'x'"):
        E.check_origin(0.0, "x", 0.0)
    with pytest.raises(ImunavError, match="origin: height must be finite"):
        E.check_origin(0.0, 0.0, np.inf)
    with pytest.raises(ImunavError, match="43 km"):
        E.ecef_to_geodetic([1.0, 2.0, 3.0])
