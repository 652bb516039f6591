"""Fuzzing the command line in-process (issue 12): generated motion laws, TOML, CSVs and random
bytes. Whatever comes in, the exit status is 0 or 2 with one line on stderr, never a traceback;
no input file changes; the canary file an injected law would create never appears; a run never
leaves a temporary file behind."""

import hashlib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from imunav.cli import main

FUZZ = settings(max_examples=60, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])

CANARY = "canary"
EVIL = [
    f"__import__('os').system('touch {CANARY}')", f"open('{CANARY}', 'w')", "exec('1')",
    "eval('t')", "().__class__.__bases__", "t.real", "lambda: t", "'t'", "globals()",
    "[t]", "{t: 1}", "t if t else 1", "9**9**9", "1e999", "t^2", "t % 2", "Abs(t)", "f(t)",
    "Heaviside(t)", "sqrt(-1)", "log(-2)", "x", "__builtins__", "t;t", "t\n1", "",
]
ATOMS = st.sampled_from(["t", "pi", "E", "0", "1", "2.5", "1e-3", "-t", "0.1*t"] + EVIL)
FUNCS = st.sampled_from(["sin", "cos", "tan", "exp", "log", "sqrt", "asin", "atan", "tanh",
                         "cosh", "Abs", "sign", "__import__", "getattr"])


def _law():
    return st.recursive(
        ATOMS,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**", "^", "%", ".", ","]),
                      inner).map(lambda x: f"({x[0]}{x[1]}{x[2]})"),
            st.tuples(FUNCS, inner).map(lambda x: f"{x[0]}({x[1]})"),
        ),
        max_leaves=8,
    ) | st.text(max_size=40)


def _digests(folder: Path) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in folder.iterdir() if p.is_file()}


def _run(args, capsys, folder: Path, inputs):
    before = {n: d for n, d in _digests(folder).items() if n in inputs}
    code = main(args)
    err = capsys.readouterr().err
    assert code in (0, 2), err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("imunav: error: "), err
    assert "Traceback" not in err
    after = _digests(folder)
    assert {n: after.get(n) for n in before} == before
    assert not (folder / CANARY).exists()
    assert not list(folder.glob(".*imunav-tmp"))
    return code


def _toml_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


@FUZZ
@given(x=_law(), yaw=_law(), duration=st.sampled_from(["0.5", "1", "0", "-1", "true", '"2"',
                                                      "1e999", "nan"]),
       output=st.sampled_from(["rates", "increments"]))
def test_fuzzed_laws(tmp_path, monkeypatch, capsys, x, yaw, duration, output):
    monkeypatch.chdir(tmp_path)
    Path("m.toml").write_text(f"duration = {duration}\n[position]\nx = {_toml_string(x)}\n"
                              f"[attitude]\nyaw = {_toml_string(yaw)}\n")
    _run(["simulate", "m.toml", "--rate", "8", "--output", output, "--out", "s.csv", "--truth",
          "tr.csv"], capsys, tmp_path, {"m.toml"})


@FUZZ
@given(text=st.text(max_size=200) | st.binary(max_size=200))
def test_fuzzed_toml(tmp_path, monkeypatch, capsys, text):
    monkeypatch.chdir(tmp_path)
    p = Path("m.toml")
    p.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass"))
    _run(["simulate", "m.toml", "--rate", "5", "--out", "s.csv"], capsys, tmp_path, {"m.toml"})


CELL = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr),
                 st.integers(-10, 10).map(str), st.sampled_from(["", "abc", "1e400", "0x10",
                                                                 " 1 ", "nan", "-0"]))
HEADERS = ["t,gx,gy,gz,ax,ay,az", "t,dthx,dthy,dthz,dvx,dvy,dvz", "t,gx,gy", "x,y", ""]


@FUZZ
@given(header=st.sampled_from(HEADERS),
       rows=st.lists(st.lists(CELL, min_size=0, max_size=8), max_size=6),
       monotone=st.booleans())
def test_fuzzed_signal_csv(tmp_path, monkeypatch, capsys, header, rows, monotone):
    monkeypatch.chdir(tmp_path)
    if monotone:          # mostly valid files: increasing times, seven columns
        rows = [[str(0.1 * (i + 1))] + (r + ["0"] * 6)[:6] for i, r in enumerate(rows)]
    Path("s.csv").write_text(header + "\n" + "\n".join(",".join(r) for r in rows) + "\n")
    Path("i.csv").write_text("t,x,y,z,vx,vy,vz,qw,qx,qy,qz\n0,0,0,0,0,0,0,1,0,0,0\n")
    _run(["navigate", "s.csv", "--initial", "i.csv", "--out", "n.csv"], capsys, tmp_path,
         {"s.csv", "i.csv"})


@FUZZ
@given(data=st.binary(max_size=300),
       which=st.sampled_from(["signals", "initial", "imu", "generic"]))
def test_random_bytes_as_any_input(tmp_path, monkeypatch, capsys, data, which):
    monkeypatch.chdir(tmp_path)
    Path("s.csv").write_text("t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,-9.8\n0.1,0,0,0,0,0,-9.8\n")
    Path("i.csv").write_text("t,x,y,z,vx,vy,vz,qw,qx,qy,qz\n0,0,0,0,0,0,0,1,0,0,0\n")
    Path("m.toml").write_text('duration = 1\n[position]\nx = "t"\n')
    Path("bad").write_bytes(data)
    if which == "imu":
        args = ["simulate", "m.toml", "--rate", "10", "--imu", "bad", "--out", "o.csv"]
    elif which == "generic":
        args = ["navigate", "bad", "--format", "generic", "--rate", "10", "--out", "o.csv"]
    else:
        s, i = ("bad", "i.csv") if which == "signals" else ("s.csv", "bad")
        args = ["navigate", s, "--initial", i, "--out", "o.csv"]
    _run(args, capsys, tmp_path, {"s.csv", "i.csv", "m.toml", "bad"})


def test_the_fuzz_harness_catches_a_traceback(tmp_path, monkeypatch, capsys):
    """The harness itself: an internal error (exit 1) must fail the property."""
    import imunav.cli as cli

    monkeypatch.chdir(tmp_path)
    Path("m.toml").write_text('duration = 1\n[position]\nx = "t"\n')

    def boom(args):
        raise ZeroDivisionError("planted")

    monkeypatch.setitem(cli.build_parser.__globals__, "cmd_simulate", boom)
    with pytest.raises(AssertionError):
        _run(["simulate", "m.toml", "--rate", "5", "--out", "s.csv"], capsys, tmp_path,
             {"m.toml"})
