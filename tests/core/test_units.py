"""Every unit spelling the datasheet parser accepts, against SI values computed by hand here
(issue 19): π/180 per degree, 9.80665 m/s² per g, 3600 s per hour, √3600 s = 60 √s per √h.
Nothing below is read from imunav's own unit tables."""

import math

import pytest

from imunav import ImunavError
from imunav.core import units
from imunav.sensors import terms

D, G = math.pi / 180, 9.80665

CASES = [
    # rates (range, bias, resolution, bias instability of a gyro): rad/s
    ("gyro.bias", "1 rad/s", 1.0), ("gyro.bias", "1 deg/s", D), ("gyro.bias", "1 dps", D),
    ("gyro.bias", "1 °/s", D), ("gyro.bias", "1 mdps", D / 1000),
    ("gyro.bias", "1 deg/h", D / 3600), ("gyro.bias", "1 deg/hr", D / 3600),
    ("gyro.bias", "1 °/h", D / 3600), ("gyro.bias", "1 dph", D / 3600),
    ("gyro.bias", "1 mrad/s", 1e-3),
    # accelerations: m/s²
    ("accel.bias", "1 m/s^2", 1.0), ("accel.bias", "1 m/s2", 1.0), ("accel.bias", "1 m/s²", 1.0),
    ("accel.bias", "1 g", G), ("accel.bias", "1 mg", G / 1e3), ("accel.bias", "1 ug", G / 1e6),
    ("accel.bias", "1 µg", G / 1e6), ("accel.bias", "1 μg", G / 1e6),   # micro sign and Greek mu
    # rate noise density / angle random walk: rad/s/√Hz = rad/√s
    ("gyro.noise_density", "1 rad/s/sqrt(Hz)", 1.0), ("gyro.noise_density", "1 rad/sqrt(s)", 1.0),
    ("gyro.noise_density", "1 deg/s/sqrt(Hz)", D), ("gyro.noise_density", "1 dps/sqrt(Hz)", D),
    ("gyro.noise_density", "1 °/s/√Hz", D), ("gyro.noise_density", "1 deg/s/rtHz", D),
    ("gyro.noise_density", "1 mdps/sqrt(Hz)", D / 1000),
    ("gyro.noise_density", "1 deg/h/sqrt(Hz)", D / 3600),
    ("gyro.noise_density", "1 deg/sqrt(h)", D / 60), ("gyro.noise_density", "1 deg/sqrt(hr)", D / 60),
    ("gyro.noise_density", "1 °/√h", D / 60), ("gyro.noise_density", "1 deg/√hr", D / 60),
    ("gyro.noise_density", "1 deg/sqrth", D / 60), ("gyro.noise_density", "1 deg/sqrthr", D / 60),
    ("gyro.noise_density", "1 rad/sqrts", 1.0), ("gyro.noise_density", "1 deg/√(h)", D / 60),
    ("gyro.noise_density", "1 deg/rt(h)", D / 60),
    # acceleration noise density / velocity random walk: m/s²/√Hz = m/s/√s
    ("accel.noise_density", "1 m/s^2/sqrt(Hz)", 1.0), ("accel.noise_density", "1 m/s/sqrt(s)", 1.0),
    ("accel.noise_density", "1 ug/sqrt(Hz)", G / 1e6), ("accel.noise_density", "1 µg/√Hz", G / 1e6),
    ("accel.noise_density", "1 ug/sqrtHz", G / 1e6), ("accel.noise_density", "1 μg/√Hz", G / 1e6),
    ("accel.noise_density", "1 mg/sqrt(Hz)", G / 1e3), ("accel.noise_density", "1 g/sqrt(Hz)", G),
    ("accel.noise_density", "1 m/s/sqrt(h)", 1 / 60), ("accel.noise_density", "1 m/s/sqrt(hr)", 1 / 60),
    ("accel.noise_density", "1 m/s/√h", 1 / 60),
    # rate random walk: rad/s/√s
    ("gyro.random_walk", "1 rad/s/sqrt(s)", 1.0), ("gyro.random_walk", "1 rad/s^1.5", 1.0),
    ("gyro.random_walk", "1 deg/s/sqrt(s)", D), ("gyro.random_walk", "1 deg/h/sqrt(h)", D / 3600 / 60),
    ("gyro.random_walk", "1 deg/hr/sqrt(hr)", D / 3600 / 60), ("gyro.random_walk", "1 °/h/√h", D / 3600 / 60),
    ("gyro.random_walk", "1 deg/s/sqrt(h)", D / 60),
    # acceleration random walk: m/s²/√s
    ("accel.random_walk", "1 m/s^2/sqrt(s)", 1.0), ("accel.random_walk", "1 m/s^2.5", 1.0),
    ("accel.random_walk", "1 m/s^3/sqrt(Hz)", 1.0), ("accel.random_walk", "1 ug/sqrt(s)", G / 1e6),
    ("accel.random_walk", "1 mg/sqrt(h)", G / 1e3 / 60),
    ("accel.random_walk", "1 m/s/h/sqrt(h)", 1 / 3600 / 60),
    # times, frequencies, fractions, angles
    ("gyro.bias_correlation_time", "1 s", 1.0), ("gyro.bias_correlation_time", "1 ms", 1e-3),
    ("gyro.bias_correlation_time", "4000 us", 4e-3), ("gyro.bias_correlation_time", "4000 µs", 4e-3),
    ("gyro.bias_correlation_time", "1 min", 60.0), ("gyro.bias_correlation_time", "1 h", 3600.0),
    ("gyro.internal_rate", "1 Hz", 1.0), ("gyro.internal_rate", "1 kHz", 1000.0),
    ("gyro.scale_factor", "1 ", 1.0), ("gyro.scale_factor", "1 ppm", 1e-6),
    ("gyro.scale_factor", "1 %", 0.01),
    ("gyro.misalignment", "1 rad", 1.0), ("gyro.misalignment", "1 mrad", 1e-3),
    ("gyro.misalignment", "1 deg", D), ("gyro.misalignment", "1 °", D),
    ("gyro.misalignment", "1 %", 0.01),
    # g-sensitivity: rad/s per m/s²
    ("gyro.g_sensitivity", "1 rad/s/(m/s^2)", 1.0), ("gyro.g_sensitivity", "1 deg/s/g", D / G),
    ("gyro.g_sensitivity", "1 deg/h/g", D / 3600 / G), ("gyro.g_sensitivity", "1 rad/s/g", 1 / G),
]


@pytest.mark.parametrize("key, text, si", CASES)
def test_each_spelling_converts_to_the_hand_computed_si_value(key, text, si):
    number, _, unit = text.partition(" ")
    assert terms.parse(text, key) == pytest.approx(si, rel=1e-14)
    # the number is multiplied, not added or ignored
    assert terms.parse(f"{2.5 * float(number):g} {unit}", key) == pytest.approx(2.5 * si,
                                                                                  rel=1e-14)


def _table(key):
    triad, _, name = key.partition(".")
    return id(terms.parameters(triad)[name][1].units[triad])


def test_every_accepted_spelling_is_covered_here():
    """A new unit added to the tables without a hand-computed value here fails this test."""
    covered = {(_table(k), units.normalise(t.partition(" ")[2])) for k, t, _ in CASES}
    for triad in terms.TRIADS:
        for name, (_, p) in terms.parameters(triad).items():
            table = p.units[triad]
            for spelling in table:
                assert (id(table), spelling) in covered, \
                    f"{triad}.{name}: {spelling!r} has no hand-computed case"


@pytest.mark.parametrize("key, text", [
    ("gyro.noise_density", "1 deg/s"),        # a rate is not a density
    ("gyro.random_walk", "1 deg/sqrt(h)"),    # angle random walk is not rate random walk
    ("accel.bias", "1 deg/s"), ("gyro.bias", "1 g"), ("gyro.internal_rate", "1 s"),
])
def test_units_of_another_dimension_are_refused(key, text):
    with pytest.raises(ImunavError, match="is not a unit of"):
        terms.parse(text, key)


def test_plain_numbers_are_si_and_bools_are_not_numbers():
    assert terms.parse(0.25, "accel.bias") == 0.25
    with pytest.raises(ImunavError, match="must be a number"):
        terms.parse(True, "accel.bias")


def test_parse_error_messages_in_full():
    """Each refusal names the key, the value and what was expected (hand-written)."""
    from imunav.sensors.terms import parse

    def msg(value, key):
        with pytest.raises(ImunavError) as e:
            parse(value, key)
        return str(e.value)

    assert msg(1.0, "gyro.nosie").startswith("unknown error parameter 'gyro.nosie'; known: "
                                             "gyro.noise_density, gyro.bias, ")
    assert msg(1.0, "gyro").startswith("unknown error parameter 'gyro'; known: ")
    assert msg(True, "gyro.bias") == "gyro.bias must be a number or a string with units, got True"
    assert msg([1], "gyro.bias") == "gyro.bias must be a number or a string with units, got list"
    assert msg("fast", "gyro.bias") == "gyro.bias = 'fast': expected '<number> <unit>'"
    assert msg("1 furlong", "gyro.internal_rate") == (
        "gyro.internal_rate = '1 furlong': unit 'furlong' is not a unit of internal sample rate; "
        "accepted: Hz, kHz")
    assert msg(-1.0, "gyro.bias") == "gyro.bias must be a finite non-negative value, got -1"
    assert msg("-2 deg/s", "gyro.bias") == (
        "gyro.bias must be a finite non-negative value, got '-2 deg/s'")
    assert msg(2e6, "gyro.internal_rate") == (
        "gyro.internal_rate = 2e+06 is outside 1–1e+06 (SI): no inertial sensor samples faster "
        "than 1 MHz internally")
    # zero and the limits themselves are accepted; exponents in either case
    assert parse(0.0, "gyro.bias") == 0.0
    assert parse(1e6, "gyro.internal_rate") == 1e6 and parse(1.0, "gyro.internal_rate") == 1.0
    assert parse("2E-3 rad/s", "gyro.bias") == parse("2e-3 rad/s", "gyro.bias") == 2e-3
