"""Readers of real recordings (shipped data) and the CLI formats."""

import hashlib

import numpy as np
import pytest

from imunav import ImunavError
from imunav.cli import main
from imunav.io import realdata as R


def test_ximu3_reader_units_and_rate():
    rec = R.read_ximu3()
    s = rec.signals
    assert len(s) == 500 and s.rate == pytest.approx(49.915, rel=1e-3)
    # at rest: |f| ≈ g (file stores g), gyro small (file stores deg/s)
    assert np.linalg.norm(s.accel[:50].mean(0)) == pytest.approx(9.80665, rel=0.01)
    assert np.abs(s.gyro[:50]).max() < np.radians(2)
    assert rec.device_q.shape == (500, 4)


def test_ximu_reader():
    rec = R.read_ximu()
    assert len(rec.signals) == 12626 and rec.signals.rate == 256
    assert np.all(np.diff(rec.device_t) > 0)


def test_device_quaternion_conventions():
    from imunav.analysis import recordings as A

    c3 = A.device_quaternion_convention(R.read_ximu3())
    assert min(c3, key=c3.get) == "wxyz/q_nb" and c3["wxyz/q_nb"] < 5
    c1 = A.device_quaternion_convention(R.read_ximu())
    assert min(c1, key=c1.get) == "wxyz/q_bn" and c1["wxyz/q_bn"] < 10


def test_generic_reader_matches_ximu3():
    f = R.data_path("real_imu", "xio_ximu3", "Inertial.csv")
    g = R.read_generic(f, gyro_columns=["Gyroscope X (deg/s)", "Gyroscope Y (deg/s)",
                                        "Gyroscope Z (deg/s)"],
                       accel_columns=["Accelerometer X (g)", "Accelerometer Y (g)",
                                      "Accelerometer Z (g)"],
                       gyro_units="deg/s", accel_units="g", time_column="Timestamp (us)",
                       time_units="us")
    x = R.read_ximu3()
    np.testing.assert_allclose(g.signals.gyro, x.signals.gyro, rtol=1e-15)
    np.testing.assert_allclose(g.signals.accel, x.signals.accel, rtol=1e-15)


@pytest.mark.parametrize("kw, msg", [
    (dict(gyro_units="furlong/s"), "unknown gyro units"),
    (dict(accel_units="gee"), "unknown accel units"),
    (dict(time_units="fortnight"), "unknown time units"),
    (dict(gyro_columns=["a", "b", "c"]), "no column 'a'"),
])
def test_generic_reader_errors(kw, msg):
    f = R.data_path("real_imu", "xio_ximu3", "Inertial.csv")
    base = dict(gyro_columns=["Gyroscope X (deg/s)", "Gyroscope Y (deg/s)", "Gyroscope Z (deg/s)"],
                accel_columns=["Accelerometer X (g)", "Accelerometer Y (g)", "Accelerometer Z (g)"],
                time_column="Timestamp (us)", time_units="us")
    base.update(kw)
    with pytest.raises(ImunavError, match=msg):
        R.read_generic(f, **base)


def test_generic_reader_non_increasing_time(tmp_path):
    p = tmp_path / "r.csv"
    p.write_text("t,a,b,c,d,e,f\n0,0,0,0,0,0,1\n0.1,0,0,0,0,0,1\n0.1,0,0,0,0,0,1\n")
    with pytest.raises(ImunavError, match="strictly increasing"):
        R.read_generic(p, gyro_columns="abc", accel_columns="def", time_column="t")


def test_cli_formats(tmp_path, capsys):
    folder = R.data_path("real_imu", "xio_ximu3")
    digest = hashlib.sha256((folder / "Inertial.csv").read_bytes()).hexdigest()
    out = tmp_path / "nav.csv"
    assert main(["navigate", str(folder), "--format", "ximu3", "--out", str(out)]) == 0
    assert out.read_text().splitlines()[0] == "t,x,y,z,vx,vy,vz,qw,qx,qy,qz"
    assert len(out.read_text().splitlines()) == 501
    assert hashlib.sha256((folder / "Inertial.csv").read_bytes()).hexdigest() == digest
    assert main(["navigate", str(folder / "Inertial.csv"), "--format", "generic",
                 "--gyro-units", "parsecs", "--out", str(out)]) == 2
    assert "unknown gyro units" in capsys.readouterr().err
    assert main(["navigate", str(folder / "Inertial.csv"), "--out", str(out)]) == 2
    assert "--initial" in capsys.readouterr().err


def test_bias_calibration_judged_out_of_sample():
    from imunav.analysis import recordings as A

    s = R.read_ximu3().signals
    a, b = A.static_segments(s)[0]
    for split in (a + 20, (a + b) // 2):
        h = A.holdout_bias(s, a, b, split)
        # measured: 9.3 → 1.0 mm (split at 0.4 s) and 4.8 → 0.5 mm (at 0.66 s)
        assert h["out_of_sample"]["final"] < 0.3 * h["raw"]["final"]
    with pytest.raises(ImunavError, match="split"):
        A.holdout_bias(s, a, b, b)


def test_static_segments_end_with_the_last_quiet_sample():
    """A hand-built record at 100 Hz: at rest for samples 0–49, turning ever faster (0.5 to
    2 rad/s) and accelerating (|f| = 1.2 g) for 50–79, at rest again for 80–149. With 0.1 s
    windows (10 samples) the quiet stretches are exactly [0, 50) and [80, 150): the first
    turning sample (50) must not be in a "static" segment, and the last segment must not run
    past the record."""

    from imunav.sensors.signals import ImuSignals

    n, rate, g = 150, 100.0, 9.80665
    gyro = np.zeros((n, 3))
    gyro[50:80, 2] = np.linspace(0.5, 2.0, 30)
    accel = np.tile([0.0, 0.0, -g], (n, 1))
    accel[50:80, 2] *= 1.2
    sig = ImuSignals(np.arange(n) / rate, gyro, accel, "rates", rate, g)
    from imunav.analysis import recordings as A

    segs = A.static_segments(sig, window=0.1)
    assert segs == [(0, 50), (80, 150)]
    for a, b in segs:
        assert np.all(sig.gyro[a:b] == 0.0)


# ----------------------------------------------------------------------------- issue 36
# Logs as they come: files without a header, names with spaces and parentheses, RTKLIB time
# tags, and magnitudes that do not fit the units. Every file is written by the test.

import struct  # noqa: E402
import warnings  # noqa: E402

from imunav.io import rtklib  # noqa: E402

DEG = np.pi / 180
G = 9.80665


def _log(n=600, rate=100.0, seed=36):
    """A 6-s IMU log in g and °/s: at rest for 2 s (bias 0.5, −0.3, 0.2 °/s), then turning at
    30 °/s about z and shaking (0.3 g)."""
    rng = np.random.default_rng(seed)
    gyro = np.array([0.5, -0.3, 0.2]) + rng.normal(0, 0.05, (n, 3))
    accel = np.array([0.0, 0.0, -1.0]) + rng.normal(0, 0.002, (n, 3))
    still = int(2 * rate)
    gyro[still:, 2] += 30.0
    accel[still:] += rng.normal(0, 0.3, (n - still, 3))
    return gyro, accel


def _csv(path, cols, header=None):
    lines = [] if header is None else [header]
    lines += [",".join(f"{v:.6f}" for v in row) for row in np.column_stack(cols)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_generic_headerless_by_index(tmp_path):
    gyro, accel = _log()
    p = _csv(tmp_path / "log.csv", [accel, gyro])
    rec = R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                         accel_units="g", rate=100)
    s = rec.signals
    assert len(s) == 600 and s.rate == pytest.approx(100.0) and s.t[0] == 0.0
    np.testing.assert_allclose(s.gyro, np.round(gyro, 6) * DEG, rtol=1e-12)
    np.testing.assert_allclose(s.accel, np.round(accel, 6) * G, rtol=1e-12)
    # the command line passes strings: digits that are not a header's names are indices
    rec2 = R.read_generic(p, gyro_columns=["3", "4", "5"], accel_columns=["0", "1", "2"],
                          gyro_units="deg/s", accel_units="g", rate=100)
    np.testing.assert_array_equal(rec2.signals.gyro, s.gyro)


@pytest.mark.parametrize("kw, msg", [
    (dict(gyro_columns=["gx", "gy", "gz"]), "has no header line .* give gyro_columns by 0-based"),
    (dict(accel_columns=[0, 1, 6]), "accel_columns index 6 is out of range .* 6 columns"),
    (dict(gyro_columns=[3, 4]), "must each name 3 columns"),
    (dict(rate=None), "give either time_column or rate"),
])
def test_generic_headerless_refusals(tmp_path, kw, msg):
    gyro, accel = _log()
    p = _csv(tmp_path / "log.csv", [accel, gyro])
    args = dict(gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                accel_units="g", rate=100)
    args.update(kw)
    with pytest.raises(ImunavError, match=msg):
        R.read_generic(p, **args)


def test_generic_headerless_bad_row_names_its_line(tmp_path):
    p = tmp_path / "log.csv"
    p.write_text("0,0,-1,0,0,0\n0,0,-1,0,0,0\n0,0,x,0,0,0\n")
    with pytest.raises(ImunavError, match=r"line 3, column 2: 'x' is not a finite number"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], accel_units="g",
                       rate=100)
    p.write_text("0,0,-1,0,0,0\n0,0,-1,0,0\n")
    with pytest.raises(ImunavError, match=r"line 2: expected 6 columns .* got 5"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], accel_units="g",
                       rate=100)


@pytest.mark.parametrize("header", [
    "Time (s),Gyro X (deg/s),Gyro Y (deg/s),Gyro Z (deg/s),Acc X (g),Acc Y (g),Acc Z (g)",
    '"Time (s)", "Gyro X (deg/s)","Gyro Y (deg/s)","Gyro Z (deg/s)","Acc X (g)","Acc Y (g)",'
    '"Acc Z (g)"',
])
def test_generic_names_with_spaces_and_parentheses(tmp_path, header):
    gyro, accel = _log()
    t = np.arange(600) / 100.0
    p = _csv(tmp_path / "log.csv", [t, gyro, accel], header=header)
    rec = R.read_generic(p, gyro_columns=["Gyro X (deg/s)", "Gyro Y (deg/s)", "Gyro Z (deg/s)"],
                         accel_columns=["Acc X (g)", "Acc Y (g)", "Acc Z (g)"],
                         time_column="Time (s)", gyro_units="deg/s", accel_units="g")
    assert rec.signals.rate == pytest.approx(100.0)
    np.testing.assert_allclose(rec.signals.gyro[:, 2], np.round(gyro[:, 2], 6) * DEG)
    # and by index in a file with a header
    rec2 = R.read_generic(p, gyro_columns=[1, 2, 3], accel_columns=[4, 5, 6], time_column=0,
                          gyro_units="deg/s", accel_units="g")
    np.testing.assert_array_equal(rec2.signals.accel, rec.signals.accel)


def _tag_file(path, start, last_tick, last_fpos):
    body = b"TIMETAG RTKLIB demo5".ljust(60, b"\0") + struct.pack("<IId", 0, int(start),
                                                                   start - int(start))
    body += struct.pack("<IIII", 130, 40, last_tick, last_fpos)
    path.write_bytes(body)
    return path


def _counter_log(tmp_path, n=600, seed=7):
    """A headerless log with a millisecond counter read with ±1 ms of jitter (last column)."""
    gyro, accel = _log(n)
    rng = np.random.default_rng(seed)
    counter = 261906 + 10 * np.arange(n) + np.round(rng.uniform(-1, 1, n))
    return _csv(tmp_path / "imu.csv", [accel, gyro, counter]), counter


def test_generic_timed_by_an_rtklib_tag(tmp_path):
    p, counter = _counter_log(tmp_path)
    start = 1752003261.854
    span = int(counter[-1] - counter[0])
    tag = _tag_file(tmp_path / "imu.csv.tag", start, span, p.stat().st_size)
    kw = dict(gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
              accel_units="g", time_column=6, time_units="ms", tag=tag)
    s = R.read_generic(p, time_offset=-0.125, **kw).signals
    # GPST seconds on the tag's axis: the first sample at the start plus the offset, the last
    # on the last tick (the counter's jitter fitted away: uniform steps)
    assert s.t[0] == pytest.approx(start - 0.125, abs=2e-3)
    assert s.t[-1] - s.t[0] == pytest.approx(span / 1000.0, abs=1e-6)
    assert np.ptp(np.diff(s.t)) < 1e-6
    # a file converted from CRLF to LF is one byte a line shorter than the tag says
    tag2 = _tag_file(tmp_path / "crlf.tag", start, span, p.stat().st_size + 600)
    R.read_generic(p, **{**kw, "tag": tag2})
    # the tag with rate instead of a counter column
    s3 = R.read_generic(p, **{**kw, "time_column": None, "rate": 100.0}).signals
    assert s3.t[0] == pytest.approx(start) and s3.t[-1] - s3.t[0] == pytest.approx(span / 1e3)


@pytest.mark.parametrize("tick_factor, fpos_factor, msg", [
    (2.0, 1.0, r"spans 11.98 s but the time column spans 5.99\d* s: the tag belongs to another"),
    (1.0, 3.0, "last file position is .* the tag belongs to another record"),
    (1.0, 0.5, "last file position is .* the tag belongs to another record"),
])
def test_generic_refuses_a_tag_of_another_record(tmp_path, tick_factor, fpos_factor, msg):
    p, counter = _counter_log(tmp_path)
    span = int(counter[-1] - counter[0])
    tag = _tag_file(tmp_path / "other.tag", 1.7e9, int(span * tick_factor),
                    int(p.stat().st_size * fpos_factor))
    with pytest.raises(ImunavError, match=msg) as exc:
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                       accel_units="g", time_column=6, time_units="ms", tag=tag)
    assert "\n" not in str(exc.value)
    not_a_tag = tmp_path / "x.tag"
    not_a_tag.write_bytes(b"hello")
    with pytest.raises(ImunavError, match="not an RTKLIB time-tag file"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                       accel_units="g", time_column=6, time_units="ms", tag=not_a_tag)


@pytest.mark.parametrize("units, msg", [
    (dict(gyro_units="rad/s"), r"gyro: .* rad/s RMS .* while the accelerometer is still.*"
                               r"look like deg/s; check gyro_units"),
    (dict(accel_units="m/s^2"), r"accelerometer: \|f\| = 1 m/s² with accel_units = 'm/s\^2'.*"
                                r"look like 'g'"),
])
def test_generic_refuses_units_that_do_not_fit(tmp_path, units, msg):
    gyro, accel = _log()
    p = _csv(tmp_path / "log.csv", [accel, gyro])
    kw = dict(gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
              accel_units="g", rate=100)
    kw.update(units)
    with pytest.raises(ImunavError, match=msg) as exc:
        R.read_generic(p, **kw)
    assert "\n" not in str(exc.value)
    assert R.read_generic(p, check_units=False, **kw).signals.rate == pytest.approx(100.0)


def test_generic_unit_checks_in_motion(tmp_path):
    gyro, accel = _log()
    # accelerometer data in m/s² declared as g: 9.81 g where it is quietest
    p = _csv(tmp_path / "ms2.csv", [accel * G, gyro])
    with pytest.raises(ImunavError, match="look like 'm/s\\^2'"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                       accel_units="g", rate=100)
    # a gyro turning at 300 °/s read as rad/s: beyond any MEMS range
    fast = gyro.copy()
    fast[:, 2] *= 10
    p = _csv(tmp_path / "fast.csv", [accel, fast])
    with pytest.raises(ImunavError, match="beyond any MEMS gyro's range"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], accel_units="g",
                       rate=100)
    # rad/s read as deg/s: the gyro hardly moves while the accelerometer shakes
    p = _csv(tmp_path / "rad.csv", [accel, gyro * DEG])
    with pytest.warns(UserWarning, match="look like rad/s read as deg/s"):
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                       accel_units="g", rate=100)
    # the right units: no word
    p = _csv(tmp_path / "ok.csv", [accel, gyro])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        R.read_generic(p, gyro_columns=[3, 4, 5], accel_columns=[0, 1, 2], gyro_units="deg/s",
                       accel_units="g", rate=100)


def test_generic_reader_examples():
    import doctest

    result = doctest.testmod(R, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 5 and result.failed == 0
    assert rtklib.imu_times is R.imu_times
