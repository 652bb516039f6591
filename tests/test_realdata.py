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
    c3 = R.device_quaternion_convention(R.read_ximu3())
    assert min(c3, key=c3.get) == "wxyz/q_nb" and c3["wxyz/q_nb"] < 5
    c1 = R.device_quaternion_convention(R.read_ximu())
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
    from imunav.io import realdata as R

    s = R.read_ximu3().signals
    a, b = R.static_segments(s)[0]
    for split in (a + 20, (a + b) // 2):
        h = R.holdout_bias(s, a, b, split)
        # measured: 9.3 → 1.0 mm (split at 0.4 s) and 4.8 → 0.5 mm (at 0.66 s)
        assert h["out_of_sample"]["final"] < 0.3 * h["raw"]["final"]
    with pytest.raises(R.ImunavError, match="split"):
        R.holdout_bias(s, a, b, b)


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
    segs = R.static_segments(sig, window=0.1)
    assert segs == [(0, 50), (80, 150)]
    for a, b in segs:
        assert np.all(sig.gyro[a:b] == 0.0)
