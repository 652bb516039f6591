"""The command line: exact CSV formats, full precision, and clean errors (exit 2, one line)."""

import hashlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from imunav import Motion
from imunav.cli import main
from imunav.io import read_signals, read_states

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "figure_eight.toml"
MOTION_TOML = """duration = 4.0
[position]
x = "t**2"
y = "t*sin(t)**2"
z = "2*t"
[attitude]
yaw = "0.3*sin(t)"
pitch = "0.2*sin(0.5*t)"
roll = "0.1*t"
"""


@pytest.fixture
def motion_file(tmp_path):
    p = tmp_path / "motion.toml"
    p.write_text(MOTION_TOML)
    return p


def _digest(p):
    return hashlib.sha256(Path(p).read_bytes()).hexdigest()


@pytest.mark.parametrize("output, header, rows", [
    ("rates", "t,gx,gy,gz,ax,ay,az", 201),
    ("increments", "t,dthx,dthy,dthz,dvx,dvy,dvz", 200),
])
def test_simulate_navigate_round_trip(tmp_path, motion_file, output, header, rows):
    sig, truth, nav = tmp_path / "s.csv", tmp_path / "truth.csv", tmp_path / "nav.csv"
    before = _digest(motion_file)
    assert main(["simulate", str(motion_file), "--rate", "50", "--out", str(sig),
                 "--output", output, "--truth", str(truth)]) == 0
    lines = sig.read_text().splitlines()
    assert lines[0] == header and len(lines) == rows + 1
    assert truth.read_text().splitlines()[0] == "t,x,y,z,vx,vy,vz,qw,qx,qy,qz"
    assert len(truth.read_text().splitlines()) == 202
    sig_digest = _digest(sig)
    assert main(["navigate", str(sig), "--initial", str(truth), "--out", str(nav)]) == 0
    assert _digest(sig) == sig_digest and _digest(motion_file) == before
    st = read_states(nav)
    assert st.t.size == 201 and st.t[0] == 0.0
    m = Motion(x="t**2", y="t*sin(t)**2", z="2*t", yaw="0.3*sin(t)", pitch="0.2*sin(0.5*t)",
               roll="0.1*t")
    # against the analytic truth, not the truth file; the default algorithms at 50 Hz over 4 s
    # reach 2.2e-10 m (rates, magnus6) and 4.9e-14 m (increments, poly8_m6): the bound guards a
    # CSV round trip that loses digits or a CLI that navigates with another algorithm
    assert np.abs(st.position - m.position(st.t)).max() < (1e-9 if output == "rates" else 1e-12)


def test_csv_keeps_full_double_precision(tmp_path, motion_file):
    out = tmp_path / "s.csv"
    main(["simulate", str(motion_file), "--rate", "30", "--out", str(out),
          "--output", "increments"])
    from imunav import simulate_imu
    from imunav.io import load_motion_toml

    m, dur, _ = load_motion_toml(motion_file)
    ref = simulate_imu(m, 30, dur, kind="increments")
    back = read_signals(out)
    assert back.kind == "increments" and back.rate == pytest.approx(30)
    assert np.array_equal(back.gyro, ref.gyro) and np.array_equal(back.accel, ref.accel)
    assert np.array_equal(back.t, ref.t)


def test_g_option_and_toml_g(tmp_path, motion_file):
    out = tmp_path / "s.csv"
    main(["simulate", str(motion_file), "--rate", "10", "--out", str(out), "--g", "9.81"])
    s1 = read_signals(out)
    m = Motion(x="t**2", y="t*sin(t)**2", z="2*t", yaw="0.3*sin(t)", pitch="0.2*sin(0.5*t)",
               roll="0.1*t")
    np.testing.assert_allclose(s1.accel, m.specific_force(s1.t, 9.81), atol=1e-12)
    motion_file.write_text("g = 1.62\n" + MOTION_TOML)
    main(["simulate", str(motion_file), "--rate", "10", "--out", str(out)])
    np.testing.assert_allclose(read_signals(out).accel, m.specific_force(s1.t, 1.62), atol=1e-12)


def test_algorithm_option(tmp_path, motion_file):
    sig, truth, nav = tmp_path / "s.csv", tmp_path / "t.csv", tmp_path / "n.csv"
    main(["simulate", str(motion_file), "--rate", "50", "--out", str(sig), "--truth", str(truth)])
    assert main(["navigate", str(sig), "--initial", str(truth), "--out", str(nav),
                 "--algorithm", "first_order"]) == 0
    assert main(["navigate", str(sig), "--initial", str(truth), "--out", str(nav),
                 "--algorithm", "coning2"]) == 2


def _bad(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD_RATES = "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.1,0,0,0,0,0,-9.8\n"


@pytest.mark.parametrize("case, fragment", [
    ("missing_motion", "not found"),
    ("malformed_toml", "malformed TOML"),
    ("bad_expression", "cannot be parsed"),
    ("other_symbol", "only 't'"),
    ("zero_rate", "--rate"),
    ("negative_duration", "duration"),
    ("wrong_header", "unrecognised header"),
    ("nan_value", "NaN or inf"),
    ("non_increasing_time", "strictly increasing"),
    ("unknown_table_key", "unknown key"),
])
def test_errors_exit_2_with_one_line(tmp_path, capsys, case, fragment):
    sig_out = str(tmp_path / "out.csv")
    init = _bad(tmp_path, "init.csv", "t,x,y,z,vx,vy,vz,qw,qx,qy,qz\n0,0,0,0,0,0,0,1,0,0,0\n")
    args = {
        "missing_motion": lambda: ["simulate", str(tmp_path / "nope.toml"), "--rate", "10", "--out",
                           sig_out],
        "malformed_toml": lambda: ["simulate", str(_bad(tmp_path, "m.toml", "duration = = 3")),
                           "--rate", "10", "--out", sig_out],
        "bad_expression": lambda: ["simulate", str(_bad(tmp_path, "m.toml",
                           'duration = 1\n[position]\nx = "sin(t"\n')), "--rate", "10",
                           "--out", sig_out],
        "other_symbol": lambda: ["simulate", str(_bad(tmp_path, "m.toml",
                         'duration = 1\n[attitude]\nyaw = "w*t"\n')), "--rate", "10",
                         "--out", sig_out],
        "zero_rate": lambda: ["simulate", str(EXAMPLE), "--rate", "0", "--out", sig_out],
        "negative_duration": lambda: ["simulate", str(_bad(tmp_path, "m.toml", "duration = -2\n")),
                              "--rate", "10", "--out", sig_out],
        "wrong_header": lambda: ["navigate", str(_bad(tmp_path, "s.csv", GOOD_RATES.replace("gx", "wx"))),
                         "--initial", str(init), "--out", sig_out],
        "nan_value": lambda: ["navigate", str(_bad(tmp_path, "s.csv", GOOD_RATES.replace("-9.8\n0.1",
                      "nan\n0.1"))), "--initial", str(init), "--out", sig_out],
        "non_increasing_time": lambda: ["navigate", str(_bad(tmp_path, "s.csv",
                                GOOD_RATES.replace("0.1,", "0,"))), "--initial", str(init),
                                "--out", sig_out],
        "unknown_table_key": lambda: ["simulate", str(_bad(tmp_path, "m.toml",
                              'duration = 1\n[position]\nw = "t"\n')), "--rate", "10",
                              "--out", sig_out],
    }[case]()
    inputs = [a for a in args if Path(a).is_file()]
    digests = {a: _digest(a) for a in inputs}
    code = main(args)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("imunav: error: ") and fragment in err[0], err
    assert {a: _digest(a) for a in inputs} == digests


def test_module_entry_point_no_traceback(tmp_path):
    r = subprocess.run([sys.executable, "-m", "imunav", "simulate", str(tmp_path / "x.toml"),
                        "--rate", "10", "--out", str(tmp_path / "o.csv")],
                       capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr.startswith("imunav: error: motion file not found")
    assert "Traceback" not in r.stderr


def test_example_motion_runs(tmp_path):
    assert main(["simulate", str(EXAMPLE), "--rate", "20", "--out", str(tmp_path / "s.csv"),
                 "--output", "increments"]) == 0


def test_library_errors_name_library_arguments_and_the_cli_maps_them_to_flags(capsys):
    """The library speaks of its own arguments (``imu``, ``smoothing``); only the command line
    speaks of flags (issue 24)."""
    from imunav import ImunavError
    from imunav.io.files import load_motion
    from imunav.sensors.models import ImuModel

    with pytest.raises(ImunavError) as e:
        ImuModel.load("nope")
    assert str(e.value).startswith("imu 'nope' is neither a preset") and "--" not in str(e.value)
    with pytest.raises(ImunavError) as e:
        load_motion("examples/figure_eight.toml", smoothing=0.1)
    assert str(e.value) == "smoothing and attitude_smoothing apply to pose CSV files only"
    assert main(["assess", "examples/figure_eight.toml", "--imu", "nope", "--rate", "10",
                 "--tolerance", "1"]) == 2
    assert capsys.readouterr().err.startswith("imunav: error: --imu 'nope' is neither a preset")
    assert main(["assess", "examples/figure_eight.toml", "--imu", "ideal", "--rate", "10",
                 "--tolerance", "1", "--smoothing", "0.1"]) == 2
    assert capsys.readouterr().err == ("imunav: error: --smoothing and --attitude-smoothing "
                                       "apply to pose CSV files only\n")
