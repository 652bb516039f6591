"""Fuzzing the command line, round 2 (issue 25, deliverable 5): every command's numeric
arguments and the file formats round 1 did not reach (pose CSVs, waypoint routes, IMU TOMLs,
allan logs). Whatever comes in: exit 0 or 2, one line on stderr for 2, never a traceback, no
output left behind on failure, no input modified, no temporary file left."""

import hashlib
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from imunav.cli import main
from imunav.sensors.terms import TRIADS, parameters

FUZZ = settings(max_examples=30, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])

MOTION = 'duration = 1.0\n[position]\nx = "0.5*t**2"\n[attitude]\nyaw = "0.3*t"\n'
OUTPUTS = ("o.csv", "tr.csv", "n.csv", "v.json", "fit.toml", "p.png")

#: Numbers a user or an adversary types: edges, non-numbers, spellings.
NUMBER = st.sampled_from(["0", "-1", "1", "3.5", "20", "100", "1e7", "1e300", "1e-300", "nan",
                          "inf", "-inf", "1e999", "abc", "", "0x10", " 5", "5e", "-0", "2"])
FLOAT_CELL = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr),
    st.sampled_from(["1e300", "-1e300", "1e-300", "0", "1", "", "nan", "x", "1e999"]))


def _digests(folder: Path) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in folder.iterdir() if p.is_file()}


def _run(args, capsys, folder: Path, inputs) -> int:
    for name in OUTPUTS:
        (folder / name).unlink(missing_ok=True)
    before = {n: d for n, d in _digests(folder).items() if n in inputs}
    code = main(args)
    out = capsys.readouterr()
    err = out.err
    assert code in (0, 2), (args, err)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("imunav: error: "), (args, err)
        left = [n for n in OUTPUTS if (folder / n).exists()]
        assert not left, (args, left, err)                   # nothing written on failure
    assert "Traceback" not in err + out.out
    after = _digests(folder)
    assert {n: after.get(n) for n in before} == before       # inputs untouched
    assert not list(folder.glob(".*imunav-tmp"))
    return code


@FUZZ
@given(command=st.sampled_from(["simulate", "assess", "design", "navigate"]),
       rate=NUMBER, tolerance=NUMBER, runs=NUMBER | st.none(), seed=NUMBER | st.none())
def test_fuzzed_numeric_arguments(tmp_path, monkeypatch, capsys, command, rate, tolerance,
                                  runs, seed):
    monkeypatch.chdir(tmp_path)
    Path("m.toml").write_text(MOTION)
    Path("s.csv").write_text("t,gx,gy,gz,ax,ay,az\n" + "".join(
        f"{i / 10!r},0,0,0,0,0,-9.80665\n" for i in range(11)))
    Path("i.csv").write_text("t,x,y,z,vx,vy,vz,qw,qx,qy,qz\n0,0,0,0,0,0,0,1,0,0,0\n")
    if command == "simulate":
        args = ["simulate", "m.toml", "--rate", rate, "--out", "o.csv", "--truth", "tr.csv"]
        if seed is not None:
            args += ["--imu", "BMI088", "--seed", seed]
    elif command == "navigate":
        args = ["navigate", "s.csv", "--initial", "i.csv", "--out", "n.csv"]
    else:
        args = [command, "m.toml", "--imu", "BMI088", "--rate", rate, "--tolerance", tolerance,
                "--json", "v.json"]
        if command == "assess" and runs is not None:
            args += ["--runs", runs] + (["--seed", seed] if seed is not None else [])
    _run(args, capsys, tmp_path, {"m.toml", "s.csv", "i.csv"})


@FUZZ
@given(n=st.sampled_from([0, 3, 6, 8, 12, 12, 12]),
       cells=st.lists(st.lists(FLOAT_CELL | st.sampled_from(["0.5", "1", "0"]), min_size=8,
                               max_size=8), max_size=2),
       where=st.lists(st.integers(0, 11), max_size=2), smoothing=st.sampled_from(
           [None, "1e-3", "1e-9", "1e300"]))
def test_fuzzed_pose_csv(tmp_path, monkeypatch, capsys, n, cells, where, smoothing):
    """Mostly valid poses with a few rows replaced by hostile ones (1e300 times, 1e-300
    intervals, non-unit quaternions, NaN)."""
    monkeypatch.chdir(tmp_path)
    rows = [[repr(0.2 * i), repr(0.1 * i), "0", "0", "1", "0", "0", "0"] for i in range(n)]
    for k, row in zip(where, cells, strict=False):
        if rows:
            rows[k % len(rows)] = row
    Path("poses.csv").write_text("t,x,y,z,qw,qx,qy,qz\n" + "".join(",".join(r) + "\n"
                                                                   for r in rows))
    args = ["simulate", "poses.csv", "--rate", "10", "--out", "o.csv"]
    if smoothing:
        args += ["--smoothing", smoothing]
    _run(args, capsys, tmp_path, {"poses.csv"})


@FUZZ
@given(k=st.integers(1, 4), hostile=st.none() | st.tuples(st.integers(0, 3), st.sampled_from(
           [0.0, 1e-300, 1e-7, 1e300, -1.0, float("nan"), 2.0])),
       x=st.sampled_from([0.0, 1.0, 1e300, -5.0, 3.0]),
       orientation=st.sampled_from(["follow", "follow", "given", "given", "sideways"]))
def test_fuzzed_waypoints(tmp_path, monkeypatch, capsys, k, hostile, x, orientation):
    """Routes of 1-4 waypoints, valid but for at most one hostile time."""
    monkeypatch.chdir(tmp_path)
    times = [0.0, 1.0, 2.0, 4.0][:k]
    if hostile is not None:
        times[hostile[0] % k] = hostile[1]
    body = f'orientation = "{orientation}"\n' + "".join(
        f"[[waypoint]]\nt = {t!r}\nx = {x * i!r}\ny = 0.0\nz = 0.0\n"
        for i, t in enumerate(times))
    Path("wp.toml").write_text(body)
    _run(["simulate", "wp.toml", "--rate", "10", "--out", "o.csv"], capsys, tmp_path,
         {"wp.toml"})


KEYS = [(t, k) for t in TRIADS for k in parameters(t)]
VALUE = st.sampled_from(["0", "-1", "1e300", "1e-300", "1e10", "nan", "inf", '"1 deg/h"',
                         '"1e300 deg/h"', '"5 furlongs"', '"10 Hz"', '"0.1 Hz"', "true",
                         '"abc"', "[1, 2]", "1e-3", "100"])


@FUZZ
@given(entries=st.lists(st.tuples(st.sampled_from(KEYS), VALUE), max_size=4),
       command=st.sampled_from(["simulate", "assess"]))
def test_fuzzed_imu_toml(tmp_path, monkeypatch, capsys, entries, command):
    monkeypatch.chdir(tmp_path)
    Path("m.toml").write_text(MOTION)
    tables: dict = {}
    for (triad, key), value in entries:
        tables.setdefault(triad, {})[key] = value
    Path("imu.toml").write_text("".join(
        f"[{triad}]\n" + "".join(f"{k} = {v}\n" for k, v in kv.items())
        for triad, kv in tables.items()))
    if command == "simulate":
        args = ["simulate", "m.toml", "--rate", "20", "--imu", "imu.toml", "--out", "o.csv"]
    else:
        args = ["assess", "m.toml", "--rate", "20", "--imu", "imu.toml", "--tolerance", "5",
                "--json", "v.json"]
    _run(args, capsys, tmp_path, {"m.toml", "imu.toml"})


@FUZZ
@given(n=st.sampled_from([0, 1, 3, 50, 1000, 1000]), value=FLOAT_CELL | st.none(),
       column=st.integers(0, 6), plot=st.sampled_from([None, "p.png", "p.xyz"]))
def test_fuzzed_allan_logs(tmp_path, monkeypatch, capsys, n, value, column, plot):
    monkeypatch.chdir(tmp_path)
    rng = np.random.default_rng(n)
    noise = rng.normal(0, 1e-3, (n, 6)) + [0, 0, 0, 0, 0, -9.8]
    rows = [[repr(i / 50)] + [repr(float(v)) for v in noise[i]] for i in range(n)]
    if rows and value is not None:
        rows[n // 2][column] = value
    Path("log.csv").write_text("t,gx,gy,gz,ax,ay,az\n" + "".join(",".join(r) + "\n"
                                                                 for r in rows))
    args = ["allan", "log.csv", "--fit", "fit.toml"] + (["--plot", plot] if plot else [])
    _run(args, capsys, tmp_path, {"log.csv"})
