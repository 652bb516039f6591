"""Studies of the rotating Earth (imunav.analysis.rotating_earth) against closed forms: the
periods of the free error dynamics, the Schuler response of a bias, the cost of the flat frame."""

import numpy as np
import pytest

from imunav import ImunavError, Motion
from imunav import earth as E
from imunav.analysis.rotating_earth import (
    bias_response,
    error_periods,
    flat_frame_error,
    flat_frame_suffices,
)
from imunav.motion import EarthMotion
from imunav.sensors import ImuModel

DEG = np.pi / 180


def test_error_periods_are_the_textbook_modes():
    """30° N, 90 m/s east: Schuler split by Ω sin L + v tan L/R, the Earth-rate loop at
    Ω + v/(R cos L), the vertical pair ±√(2g/R) (within the ellipsoid's and the centrifugal
    corrections to g/R: measured 0.15 %, 0.04 %)."""
    lat, v = 30 * DEG, 90.0
    modes = {m["mode"]: m["rate_rad_s"] for m in error_periods(lat, v)}
    rn, re = E.radii(lat)
    g, R = float(E.normal_gravity(lat)), np.sqrt(rn * re)
    fou = E.OMEGA_E * np.sin(lat) + v * np.tan(lat) / re
    assert modes["Schuler − Foucault"] == pytest.approx(np.sqrt(g / R) - fou, rel=3e-3)
    assert modes["Schuler + Foucault"] == pytest.approx(np.sqrt(g / R) + fou, rel=3e-3)
    # the split itself, to 1 %: the Foucault rate
    split = (modes["Schuler + Foucault"] - modes["Schuler − Foucault"]) / 2
    assert split == pytest.approx(fou, rel=1e-2)
    assert modes["Earth-rate loop (+ transport rate)"] == pytest.approx(
        E.OMEGA_E + v / (re * np.cos(lat)), rel=1e-6)
    assert modes["vertical, growing"] == pytest.approx(np.sqrt(2 * g / R), rel=2e-3)
    assert modes["vertical, decaying"] == pytest.approx(-np.sqrt(2 * g / R), rel=2e-3)
    assert abs(modes["heading (no feedback)"]) < 1e-7


def test_bias_response_is_the_schuler_closed_form_on_the_equator():
    b = 1e-3
    m = EarthMotion(Motion(duration=6000.0), (0.0, 0.0, 0.0))
    r = bias_response(m, 0.5, 6000.0, accel=[b, 0, 0], vertical="hold")
    ws = np.sqrt(float(E.normal_gravity(0.0)) / E.radii(0.0)[0])
    np.testing.assert_allclose(r["position"][:, 0], b * (1 - np.cos(ws * r["t"])) / ws**2,
                               rtol=0, atol=1e-4 * b / ws**2)
    assert np.abs(r["position"][:, 2]).max() < 1e-6


def test_the_flat_frame_costs_g_omega_cos_l_t3_over_6_at_rest():
    lat = 45 * DEG
    f = flat_frame_error(Motion(duration=60.0), (lat, 0.1, 0.0), 10.0)
    t = f["t"][1:]
    closed = float(E.normal_gravity(lat)) * E.OMEGA_E * np.cos(lat) * t**3 / 6
    np.testing.assert_allclose(f["position"][1:], closed, rtol=2e-3)   # measured 6e-4
    np.testing.assert_allclose(f["attitude"][1:], E.OMEGA_E * t, rtol=1e-6)


def test_flat_frame_suffices_for_mems_not_for_tactical():
    rows = flat_frame_suffices(Motion(duration=300.0), (45 * DEG, 0.1, 0.0),
                               {k: ImuModel.load(k) for k in ("BMI088", "tactical")}, rate=5.0)
    by = {r["imu"]: r for r in rows}
    assert by["BMI088"]["seconds"] is None
    assert 100 < by["tactical"]["seconds"] < 300          # measured 185 s (notebook 09)


def test_bad_latitude():
    with pytest.raises(ImunavError, match="latitude must be within ±90°"):
        error_periods(2.0)
