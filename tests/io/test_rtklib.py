"""RTKLIB readers (issue 36): a hand-made position solution with known values, time-tag files
built byte by byte with struct, the IMU timing of a tag, and every refusal. No shared data: every
file is written here."""

from __future__ import annotations

import doctest
import math
import struct
import warnings
from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from imunav import ImunavError
from imunav.io import rtklib as R

HEADER = ("%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   "
          "sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio    vn(m/s)    ve(m/s)    "
          "vu(m/s)      sdvn     sdve     sdvu    sdvne    sdveu    sdvun")
ROW1 = ("2025/07/08 19:34:18.499   40.096626800 -105.147448300  1601.4740   1  21   0.0100   "
        "0.0200   0.0300  -0.0050   0.0040  -0.0030   0.00    0.0    0.10000   -0.20000    "
        "0.50000   0.05000  0.06000  0.07000  0.01000 -0.02000  0.00000")
ROW2 = ("2025/07/08 19:34:18.749   40.096636800 -105.147448300  1601.9740   2  19   0.0400   "
        "0.0400   0.0900   0.0000   0.0000   0.0000   1.50    2.5    1.00000    0.00000    "
        "-0.25000   0.10000  0.10000  0.20000  0.00000  0.00000  0.00000")


def _write(tmp_path, *lines, name="sol.pos"):
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n")
    return p


def test_pos_values_units_and_frames(tmp_path):
    p = _write(tmp_path, "% program   : RTKLIB demo5",
               "% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single)",
               HEADER, ROW1, ROW2)
    sol = R.read_pos(p)
    assert len(sol) == 2
    # GPST seconds since 1970 by calendar (datetime's UTC arithmetic has no leap seconds either)
    t0 = datetime(2025, 7, 8, 19, 34, 18, 499000, tzinfo=UTC).timestamp()
    np.testing.assert_allclose(sol.t, [t0, t0 + 0.25], rtol=0, atol=1e-6)
    np.testing.assert_allclose(sol.llh[0], [math.radians(40.0966268), math.radians(-105.1474483),
                                            1601.474], rtol=0, atol=1e-12)
    assert sol.quality.tolist() == [1, 2] and sol.satellites.tolist() == [21, 19]
    np.testing.assert_allclose(sol.age, [0.0, 1.5])
    np.testing.assert_allclose(sol.ratio, [0.0, 2.5])
    # σ north, east, down; RTKLIB's covariance columns are sign(c)·√|c|, up → down flips the
    # signs of the covariances with the vertical
    np.testing.assert_allclose(sol.position_sd[0], [0.01, 0.02, 0.03])
    C = sol.position_cov[0]
    assert C[0, 1] == pytest.approx(-0.005 ** 2) and C[1, 0] == C[0, 1]        # n-e
    assert C[1, 2] == pytest.approx(-(0.004 ** 2)) and C[2, 1] == C[1, 2]      # e-d = −e-u
    assert C[0, 2] == pytest.approx(+(0.003 ** 2)) and C[2, 0] == C[0, 2]      # n-d = −(u-n)
    np.testing.assert_allclose(sol.velocity, [[0.1, -0.2, -0.5], [1.0, 0.0, 0.25]])
    np.testing.assert_allclose(sol.velocity_sd[1], [0.1, 0.1, 0.2])
    Cv = sol.velocity_cov[0]
    assert Cv[0, 1] == pytest.approx(0.01 ** 2) and Cv[1, 2] == pytest.approx(0.02 ** 2)


def test_pos_ned_offsets_against_the_meridian_radius(tmp_path):
    """The second fix is 1e-5° north and 0.5 m higher: north = (M + h) Δφ with the meridian
    radius of curvature M = a(1 − e²)/(1 − e² sin²φ)^{3/2} (a closed form, not the reader's
    ECEF path), down = −0.5 m less the tangent plane's drop (< 1 mm here)."""
    sol = R.read_pos(_write(tmp_path, HEADER, ROW1, ROW2))
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    phi = math.radians(40.0966318)                       # the midpoint latitude
    M = a * (1 - e2) / (1 - e2 * math.sin(phi) ** 2) ** 1.5
    ned = sol.ned()
    np.testing.assert_allclose(ned[0], 0.0, atol=1e-9)
    assert ned[1, 0] == pytest.approx((M + 1601.724) * math.radians(1e-5), abs=1e-5)
    assert abs(ned[1, 1]) < 1e-6
    assert ned[1, 2] == pytest.approx(-0.5, abs=1e-3)


def test_pos_without_velocity_week_seconds_and_commas(tmp_path):
    head = "%  GPST, latitude(deg), longitude(deg), height(m), Q, ns, sdn(m), sde(m), sdu(m), " \
           "sdne(m), sdeu(m), sdun(m), age(s), ratio"
    p = _write(tmp_path, head, "2369,154800.000,10.0,20.0,30.0,5,4,1,1,2,0,0,0,0,0")
    sol = R.read_pos(p)
    assert sol.velocity is None and sol.velocity_sd is None
    # GPS week 2369, 154800 s of week, by the calendar from 1980-01-06
    expected = (datetime(1980, 1, 6, tzinfo=UTC) + timedelta(weeks=2369, seconds=154800)
                ).timestamp()
    assert sol.t[0] == expected and sol.quality[0] == 5
    assert R.GPST_EPOCH == datetime(1980, 1, 6, tzinfo=UTC).timestamp()


def test_pos_select_keeps_epochs(tmp_path):
    sol = R.read_pos(_write(tmp_path, HEADER, ROW1, ROW2))
    fixed = sol.select(sol.quality == 1)
    assert len(fixed) == 1 and fixed.velocity.shape == (1, 3) and fixed.path == sol.path


@pytest.mark.parametrize("lines, msg", [
    (["%  GPST  x-ecef(m)  y-ecef(m)  z-ecef(m)  Q  ns  sdx(m)  sdy(m)  sdz(m)  sdxy(m)  "
      "sdyz(m)  sdzx(m) age(s) ratio", "2025/07/08 19:34:18.499 1 2 3 1 9 0 0 0 0 0 0 0 0"],
     r"line 1: a solution in ECEF x/y/z; imunav reads latitude/longitude/height"),
    (["%  GPST  e-baseline(m)  n-baseline(m)  u-baseline(m)  Q  ns  sde(m)  sdn(m)  sdu(m)  "
      "sden(m)  sdnu(m)  sdue(m) age(s) ratio"], "east/north/up baseline"),
    (["%  GPST  latitude(d'\")  longitude(d'\")  height(m)  Q  ns  sdn(m)  sde(m)  sdu(m)  "
      "sdne(m)  sdeu(m)  sdue(m) age(s) ratio"], "degrees-minutes-seconds"),
    ([HEADER.replace("GPST", "UTC "), ROW1], "times are UTC; imunav needs GPST"),
    (["% (lat/lon/height=WGS84/geodetic,Q=1:fix)", HEADER, ROW1], "heights are geodetic"),
    ([ROW1], "no RTKLIB column header"),
    ([HEADER.replace("ratio", "ratio2"), ROW1], "unknown column.*ratio2"),
    ([HEADER], "no solution epochs"),
    ([HEADER, ROW1.rsplit(" ", 1)[0]], r"line 2: expected 24 values .* got 23"),
    ([HEADER, ROW1.replace("1601.4740", "high")], r"line 2, column height\(m\): 'high'"),
    ([HEADER, ROW1.replace("1601.4740", "nan")], r"line 2, column height\(m\): NaN"),
    ([HEADER, ROW2, ROW1], "line 3: time .* does not follow"),
    ([HEADER, ROW1.replace("2025/07/08", "2025/13/08")], "line 2: '2025/13/08' is not a date"),
    ([HEADER, ROW1.replace("40.096626800", "140.0966")], r"line 2: latitude 140.097° is not"),
])
def test_pos_refusals_name_the_file_and_line(tmp_path, lines, msg):
    p = _write(tmp_path, *lines)
    with pytest.raises(ImunavError, match=msg) as exc:
        R.read_pos(p)
    assert str(p) in str(exc.value) and "\n" not in str(exc.value)


def test_pos_missing_and_binary_files(tmp_path):
    with pytest.raises(ImunavError, match="not found"):
        R.read_pos(tmp_path / "none.pos")
    p = tmp_path / "bin.pos"
    p.write_bytes(b"\xff\xfe\x00\x01")
    with pytest.raises(ImunavError, match="not a text file"):
        R.read_pos(p)


def _tag(tmp_path, records, start=(1752003261, 0.854), head=b"TIMETAG RTKLIB demo5",
         name="imu.csv.tag", tail=b""):
    body = head.ljust(60, b"\0") + struct.pack("<IId", 1132621244, *start)
    body += b"".join(struct.pack("<II", t, f) for t, f in records) + tail
    p = tmp_path / name
    p.write_bytes(body)
    return p


def test_tag_fields(tmp_path):
    tag = R.read_tag(_tag(tmp_path, [(131, 37), (146, 99), (548731, 2530622)]))
    assert tag.start == 1752003261 + 0.854
    assert tag.tick.tolist() == [131, 146, 548731] and tag.fpos.tolist() == [37, 99, 2530622]
    assert tag.header == "TIMETAG RTKLIB demo5" and tag.tick_start == 1132621244
    assert tag.duration == 548.731


@pytest.mark.parametrize("kw, msg", [
    (dict(head=b"TIMETAG XYZ"), "not an RTKLIB time-tag file"),
    (dict(tail=b"\x01\x02\x03"), "not a whole number of 8-byte records"),
    (dict(records=[]), "no time-tag records"),
    (dict(records=[(100, 10), (90, 20)]), "record 1: the tick goes backwards"),
    (dict(records=[(100, 10), (110, 5)]), "record 1: the file position goes backwards"),
    (dict(start=(1752003261, 1.5)), r"fraction 1.5 is not in \[0, 1\)"),
])
def test_tag_refusals(tmp_path, kw, msg):
    args = dict(records=[(100, 10), (200, 20)])
    args.update(kw)
    p = _tag(tmp_path, **args)
    with pytest.raises(ImunavError, match=msg):
        R.read_tag(p)


def test_tag_too_short_and_missing(tmp_path):
    p = tmp_path / "short.tag"
    p.write_bytes(b"TIMETAG RTKLIB demo5")
    with pytest.raises(ImunavError, match="shorter than a tag file's 76-byte header"):
        R.read_tag(p)
    with pytest.raises(ImunavError, match="not found"):
        R.read_tag(tmp_path / "none.tag")


def _tag_obj(start, last_tick_ms):
    return R.TimeTag(start, np.array([120, last_tick_ms]), np.array([40, 4000]), "TIMETAG RTKLIB")


def test_imu_times_the_authors_mapping():
    """regular=False is the author's formula, written out: t = start + (c − c0)·T/(c_n − c0)
    + delay, T the last tick (s)."""
    c = np.array([1000.0, 1011.0, 1019.0, 1030.0, 1040.0, 1049.0, 1060.0])
    tag = _tag_obj(5e8, 61)
    with pytest.warns(UserWarning, match="ppm apart"):
        t = R.imu_times(c, tag, delay=-0.125, regular=False)
    expected = [5e8 + (ci - 1000.0) * 0.061 / 60.0 - 0.125 for ci in c]
    np.testing.assert_allclose(t, expected, rtol=0, atol=1e-7)
    assert t[-1] - t[0] == pytest.approx(0.061)


def test_imu_times_regular_removes_the_counter_jitter():
    """A 100 Hz record whose counter is read with ±1 ms of jitter: with regular=True the times
    are uniform and still end on the last tick."""
    rng = np.random.default_rng(36)
    n = 2001
    c = 5000.0 + 10.0 * np.arange(n) + np.round(rng.uniform(-1, 1, n))
    tag = _tag_obj(1.75e9, int(round(c[-1] - c[0])))
    t = R.imu_times(c, tag)
    d = np.diff(t)
    assert d.max() - d.min() < 1e-6                           # uniform to float rounding
    assert d.mean() == pytest.approx(0.01, rel=1e-3)
    assert t[0] == pytest.approx(1.75e9, abs=2e-3)
    assert t[-1] - t[0] == pytest.approx(tag.duration, abs=1e-6)
    raw = np.diff(R.imu_times(c, tag, regular=False))
    assert raw.max() - raw.min() > 1e-3                       # the jitter it removes


def test_imu_times_scales_a_drifting_clock_and_says_so():
    c = 10.0 * np.arange(1001)                                 # 10 s by the IMU's counter
    with pytest.warns(UserWarning, match="ppm apart"):
        t = R.imu_times(c, _tag_obj(0.0, 10030))               # 3000 ppm slower logger
    assert t[-1] == pytest.approx(10.03)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        R.imu_times(c, _tag_obj(0.0, 10001))                   # 100 ppm: a crystal, no word


@pytest.mark.parametrize("counter, tag_ms, kw, msg", [
    (10.0 * np.arange(1001), 20000, {}, r"spans 20 s but counter_ms spans 10 s: the tag "
                                        r"belongs to another record"),
    (10.0 * np.arange(60001), 540000, {}, "belongs to another record"),   # 600 s vs 540 s
    (np.r_[10.0 * np.arange(100), 1000.0 + 10.0 * np.arange(100) + 500], 2490, {},
     "departs from a regular clock .* samples lost"),
    (np.array([0.0, 10.0, 10.0]), 20, {}, "counter_ms must increase: sample 2"),
    (np.array([0.0]), 20, {}, "at least 2 samples"),
    (10.0 * np.arange(11), 100, dict(delay=float("nan")), "delay must be a finite number"),
])
def test_imu_times_refusals(counter, tag_ms, kw, msg):
    with pytest.raises(ImunavError, match=msg):
        R.imu_times(counter, _tag_obj(0.0, tag_ms), **kw)


def test_imu_times_short_log_tolerates_start_up_latency():
    """A 20 s log whose first sample came 0.4 s after the tag's start: within the 1 s slack."""
    c = 10.0 * np.arange(2001)
    with pytest.warns(UserWarning, match="20000 ppm apart"):
        t = R.imu_times(c, _tag_obj(0.0, 20400))
    assert t[-1] == pytest.approx(20.4)


def test_module_examples():
    result = doctest.testmod(R, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 3 and result.failed == 0
