"""Issue 12, case by case: every hostile or careless input gets exit 2 and one line (or works,
where it is valid), no input is ever modified, and every output appears whole or not at all."""

import hashlib
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from imunav import ImuModel, ImunavError, ImuSignals, Motion, monte_carlo, navigate, simulate_imu
from imunav.cli import main
from imunav.io.realdata import data_path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _digests(folder: Path) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and "imunav-tmp" not in p.name}


@pytest.fixture
def work(tmp_path, monkeypatch):
    for f in ("figure_eight.toml", "my_imu.toml"):
        shutil.copy(EXAMPLES / f, tmp_path / f)
    shutil.copytree(data_path("real_imu", "xio_ximu3"), tmp_path / "rec3")
    shutil.copytree(data_path("real_imu", "xio_ximu"), tmp_path / "rec1")
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "figure_eight.toml", "--rate", "20", "--output", "increments",
                 "--out", "sig.csv", "--truth", "truth.csv"]) == 0
    os.link("sig.csv", "hard.csv")
    return tmp_path


def _write(name, content):
    Path(name).write_bytes(content if isinstance(content, bytes) else content.encode())
    return name


def _one_line_exit_2(capsys, args, fragment):
    before = _digests(Path.cwd())
    code = main(args)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1 and err[0].startswith("imunav: error: "), err
    assert fragment in err[0], err
    assert "np.float64" not in err[0]
    after = _digests(Path.cwd())
    assert {k: v for k, v in after.items() if k in before} == before   # inputs untouched
    assert set(after) <= set(before) | {"out.csv", "out.json"}
    assert not list(Path.cwd().glob(".*imunav-tmp"))                    # no half file left


INJECT = "duration = 2\n[position]\nx = \"t + 0*__import__('os').system('touch canary')\"\n"


@pytest.mark.parametrize("files, args, fragment", [
    # laws never run code, and cannot hang the parser
    ({"m.toml": INJECT}, ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"],
     "is not a function name"),
    ({"m.toml": 'duration = 2\n[position]\nx = "9**9**9"\n'},
     ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"], "exceeds the limit"),
    ({"m.toml": 'duration = 2\n[position]\nx = "Abs(t-1)**3"\n'},
     ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"], "not smooth"),
    ({"m.toml": 'duration = 2\n[position]\nx = "sqrt(t-5)"\n'},
     ["simulate", "m.toml", "--rate", "10", "--out", "out.csv", "--truth", "t2.csv"],
     "x = 'sqrt(t-5)') is not finite"),
    ({"m.toml": 'duration = 2\n[position]\nx = "1/t"\n'},
     ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"], "at t = 0 s"),
    # inputs never overwritten
    ({}, ["assess", "figure_eight.toml", "--imu", "my_imu.toml", "--rate", "20", "--runs", "2",
          "--tolerance", "1", "--json", "figure_eight.toml"], "would overwrite the input"),
    ({}, ["assess", "figure_eight.toml", "--imu", "my_imu.toml", "--rate", "20", "--runs", "2",
          "--tolerance", "1", "--json", "my_imu.toml"], "would overwrite the input"),
    ({}, ["simulate", "figure_eight.toml", "--rate", "10", "--imu", "my_imu.toml", "--out",
          "my_imu.toml"], "would overwrite the input"),
    ({}, ["navigate", "rec3", "--format", "ximu3", "--out", "rec3/Inertial.csv"],
     "would overwrite the input"),
    ({}, ["navigate", "rec3", "--format", "ximu3", "--out", "rec3/Quaternion.csv"],
     "would overwrite the input"),
    ({}, ["navigate", "rec1", "--format", "ximu", "--out", "rec1/00033_CalInertialAndMag.csv"],
     "would overwrite the input"),
    ({}, ["navigate", "sig.csv", "--initial", "truth.csv", "--out", "hard.csv"],
     "would overwrite the input file sig.csv"),
    ({}, ["navigate", "sig.csv", "--initial", "truth.csv", "--out", "./truth.csv"],
     "would overwrite the input"),
    ({}, ["simulate", "figure_eight.toml", "--rate", "10", "--out", "out.csv", "--truth",
          "./out.csv"], "outputs must differ"),
    ({}, ["simulate", "figure_eight.toml", "--rate", "10", "--out", "rec3"], "is a folder"),
    ({}, ["simulate", "figure_eight.toml", "--rate", "10", "--out", "nowhere/out.csv"],
     "does not exist"),
    # user errors that were tracebacks
    ({"m.toml": b"duration = 2\n\xff\xfe[position]\n"},
     ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"], "is not UTF-8"),
    ({"s.csv": b"t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.1,0,\xff,0,0,0,-9.8\n"},
     ["navigate", "s.csv", "--initial", "truth.csv", "--out", "out.csv"],
     "line 3: not UTF-8"),
    ({}, ["simulate", "figure_eight.toml", "--rate", "10", "--out", "out.csv", "--imu", "BMI088",
          "--seed", "-1"], "--seed must be an integer ≥ 0"),
    # impossible sizes refused before work starts
    ({"m.toml": "duration = 1e9\n"}, ["simulate", "m.toml", "--rate", "100", "--out", "out.csv"],
     "would write about"),
    ({"i.toml": '[gyro]\ninternal_rate = "1e9 Hz"\n'},
     ["simulate", "figure_eight.toml", "--rate", "10", "--out", "out.csv", "--imu", "i.toml"],
     "faster than 1 MHz"),
    ({}, ["assess", "figure_eight.toml", "--imu", "BMI088", "--rate", "100", "--runs",
          "1000000000", "--tolerance", "1"], "of memory"),
    ({}, ["assess", "figure_eight.toml", "--imu", "BMI088", "--rate", "100", "--runs", "1.7",
          "--tolerance", "1"], "--runs must be an integer"),
    # one line, naming the row / law and the time
    ({"s.csv": "t,dthx,dthy,dthz,dvx,dvy,dvz\n0.05,0,nan,0,0,0,-0.5\n0.1,0,0,0,0,0,-0.5\n"},
     ["navigate", "s.csv", "--initial", "truth.csv", "--out", "out.csv"],
     "line 2, column 'dthy': NaN or inf"),
    ({"s.csv": "t,gx,gy,gz,ax,ay,az\n0,0,1e300,0,0,0,-9.8\n0.05,0,1e300,0,0,0,-9.8\n"},
     ["navigate", "s.csv", "--initial", "truth.csv", "--out", "out.csv"], "non-finite at t ="),
    ({"s.csv": "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.05,0,abc,0,0,0,-9.8\n"},
     ["navigate", "s.csv", "--initial", "truth.csv", "--out", "out.csv"],
     "column 'gy': 'abc' is not a number"),
    ({"i.csv": "t,x,y,z,vx,vy,vz,qw,qx,qy,qz\n3,0,0,0,0,0,0,1,0,0,0\n"},
     ["navigate", "sig.csv", "--initial", "i.csv", "--out", "out.csv"],
     "starts at t = 3 s but the signals start at t = 0 s"),
    # lenient types
    ({"m.toml": "duration = true\n"}, ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"],
     "duration must be a positive number, got True"),
    ({"m.toml": 'duration = "10"\n'}, ["simulate", "m.toml", "--rate", "10", "--out", "out.csv"],
     "duration must be a positive number, got '10'"),
])
def test_cli_case(work, capsys, files, args, fragment):
    for name, content in files.items():
        _write(name, content)
    _one_line_exit_2(capsys, args, fragment)
    assert not Path("canary").exists()


def test_initial_file_is_read_only_to_its_first_row(work, capsys):
    # a broken second row would fail a full read; only the first row matters
    _write("i.csv", Path("truth.csv").read_text().splitlines()[0] + "\n"
           + Path("truth.csv").read_text().splitlines()[1] + "\nthis,is,not,a,row\n")
    assert main(["navigate", "sig.csv", "--initial", "i.csv", "--out", "out.csv"]) == 0


def test_interrupted_write_leaves_nothing(work, monkeypatch):
    from imunav.io import csvio

    calls = {"n": 0}
    real = csvio._format

    def flaky(cols):
        calls["n"] += 1
        if calls["n"] > 1:
            raise KeyboardInterrupt
        return real(cols)

    monkeypatch.setattr(csvio, "_format", flaky)
    monkeypatch.setattr(csvio, "BLOCK", 4096)
    # a long rate file so the writer is called more than once
    assert main(["simulate", "figure_eight.toml", "--rate", "3000", "--out", "out.csv"]) == 130
    assert not Path("out.csv").exists() and not list(Path.cwd().glob(".*imunav-tmp"))


@pytest.mark.parametrize("call, fragment", [
    (lambda: simulate_imu(Motion(x="t"), 10, 1.0, g=0.0), "g must be a positive"),
    (lambda: simulate_imu(Motion(x="t"), 10, 1.0, g=float("nan")), "g must be a positive"),
    (lambda: simulate_imu(Motion(x="t"), 10, True), "duration must be a positive number"),
    (lambda: ImuSignals([0.0, 0.1, 0.1], np.zeros((3, 3)), np.zeros((3, 3)), "rates", 10.0),
     "strictly increasing"),
    (lambda: ImuSignals([0.0, 0.1, 0.5], np.zeros((3, 3)), np.zeros((3, 3)), "rates", 10.0),
     "inconsistent with rate = 10 Hz"),
    (lambda: monte_carlo(Motion(x="t", duration=1.0), ImuModel.load("BMI088"), 10.0, runs=1.7),
     "runs must be an integer"),
    (lambda: monte_carlo(Motion(x="t", duration=1.0), ImuModel.load("BMI088"), 10.0, runs=2,
                         seed=-3), "seed must be an integer ≥ 0"),
    (lambda: navigate(ImuSignals([0.0, 0.1], np.full((2, 3), 1e300), np.zeros((2, 3)), "rates",
                                 10.0), [1, 0, 0, 0]), "non-finite at t = 0.1 s"),
])
def test_api_case(call, fragment):
    with pytest.raises(ImunavError, match=fragment):
        call()


def test_api_refuses_arrays_that_cannot_fit_in_memory():
    with pytest.raises(ImunavError, match=r"would need about .* of memory.*streams"):
        simulate_imu(Motion(x="t"), 1e6, 1e7)


def test_a_long_csv_is_read_with_a_progress_bar_and_the_same_rows(tmp_path, monkeypatch,
                                                                   capsys):
    """Above PROGRESS_BYTES a file is read with a progress bar in bytes (on stderr) that ends
    at the file's size; the rows are those of the plain read (blocks of 4 kB: many batches)."""
    from imunav.io import csvio

    rng = np.random.default_rng(0)
    data = np.column_stack([np.arange(3000) * 0.01, rng.standard_normal((3000, 3))])
    path = tmp_path / "g.csv"
    np.savetxt(path, data, delimiter=",", header="t,x,y,z", comments="", fmt="%.17g")
    monkeypatch.setattr(csvio, "BLOCK", 4096)
    plain = np.concatenate(list(csvio.read_chunks(path, ("t", "x", "y", "z"), "test")))
    assert "reading g.csv" not in capsys.readouterr().err
    import tqdm.auto

    seen = {}

    class Recorded(tqdm.auto.tqdm):
        def close(self):
            seen["n"], seen["total"] = self.n, self.total
            super().close()

    monkeypatch.setattr(tqdm.auto, "tqdm", Recorded)
    monkeypatch.setattr(csvio, "PROGRESS_BYTES", 1000)
    parts = list(csvio.read_chunks(path, ("t", "x", "y", "z"), "test"))
    assert len(parts) > 10 and np.array_equal(np.concatenate(parts), plain)
    np.testing.assert_array_equal(plain, data)               # exact: shortest round trip
    assert "reading g.csv" in capsys.readouterr().err
    assert seen == {"n": path.stat().st_size, "total": path.stat().st_size}   # ends at 100 %
