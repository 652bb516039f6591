"""What a newcomer reads (issue 25, round 2): one spelling of each datasheet unit in every
report (typographic, as the notebooks print it: ``°/√h``, ``µg``), what ``allan --fit`` writes
loads back, and the aided TOML and measurement messages say what is true — ``%`` is no angle,
a measurement file without its table is named, ``[zupt]`` in ``assess`` is named, a path is
printed once, no empty unit ``()``, "positive" for > 0 and "non-negative" for ≥ 0, and a file
given for the measurements folder is called a file."""

import re
from pathlib import Path

import pytest

from imunav.cli import main
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS

STILL = 'name = "still"\nduration = 60.0\n'
DRIVE = """name = "drive"
orientation = "follow"
[[waypoint]]
t = 0
x = 0
y = 0
z = 0
[[waypoint]]
t = 20
x = 200
y = 20
z = 0
"""
AIDING = """[gnss]
rate = 1
position_sigma = 1.5
velocity_sigma = 0.1
[baro]
rate = 2
sigma = 0.5
[nhc]
sigma = 0.1
"""


def _run(capsys, *argv):
    code = main([str(x) for x in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _error(capsys, *argv) -> str:
    """The one error line of a refused command (exit 2, nothing on stdout)."""
    code, out, err = _run(capsys, *argv)
    assert code == 2, (code, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("imunav: error: "), err
    return lines[0]


@pytest.fixture(scope="module")
def still(tmp_path_factory):
    d = tmp_path_factory.mktemp("still")
    (d / "still.toml").write_text(STILL)
    assert main(["simulate", str(d / "still.toml"), "--rate", "50", "--imu", "ADIS16470",
                 "--out", str(d / "log.csv")]) == 0
    return d


@pytest.fixture(scope="module")
def sim(tmp_path_factory):
    d = tmp_path_factory.mktemp("aided")
    (d / "drive.toml").write_text(DRIVE)
    (d / "aiding.toml").write_text(AIDING)
    assert main(["simulate", str(d / "drive.toml"), "--rate", "50", "--output", "increments",
                 "--out", str(d / "imu.csv"), "--truth", str(d / "truth.csv"),
                 "--aiding", str(d / "aiding.toml"), "--aiding-out", str(d / "meas")]) == 0
    return d


def _units(text: str, term: str) -> list[str]:
    """The unit after each value of ``term`` on its report line (``0.34 °/√h``)."""
    line = next(ln for ln in text.splitlines() if ln.strip().startswith(term + " "))
    return re.findall(r"(?<![\w.])[-+]?\d[\d.]*(?:e[-+]?\d+)? ([^\s()]+)", line)


def test_design_and_allan_print_one_spelling_of_each_unit(still, capsys):
    code, allan, _ = _run(capsys, "allan", still / "log.csv", "--fit", still / "fit.toml")
    assert code == 0
    code, design, _ = _run(capsys, "design", still / "still.toml", "--imu", "ADIS16470",
                           "--rate", 20, "--tolerance", 5)
    assert code == 0
    for term, unit in (("gyro.noise_density", "°/√h"), ("accel.noise_density", "µg/√Hz")):
        assert _units(allan, term)[0] == unit, allan
        assert _units(design, term) == [unit, unit], design      # the limit and this IMU's
    assert _units(design, "gyro.bias_instability") == ["°/h", "°/h"]
    assert _units(design, "accel.bias_instability") == ["µg", "µg"]
    for spelt in ("deg/", "sqrt", " ug"):                        # the file spellings
        assert spelt not in allan and spelt not in design


def test_what_allan_fit_writes_loads_back(still, capsys):
    fit = still / "fitted.toml"
    assert _run(capsys, "allan", still / "log.csv", "--fit", fit)[0] == 0
    model = ImuModel.load(str(fit))
    truth = ImuModel.from_dict(PRESETS["ADIS16470"])         # the IMU the log was drawn from
    for triad in ("gyro", "accel"):
        got = getattr(model, triad).noise_density
        want = getattr(truth, triad).noise_density
        assert got == pytest.approx(want, rel=0.05)


@pytest.mark.parametrize("table, key", [("heading", "sigma"), ("initial", "attitude_sigma")])
def test_percent_is_no_angle(sim, tmp_path, capsys, table, key):
    a = tmp_path / "a.toml"
    a.write_text(f'[{table}]\nrate = 1\n{key} = "2 %"\n' if table == "heading"
                 else f'[gnss]\nrate = 1\nposition_sigma = 1\n[{table}]\n{key} = "2 %"\n')
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out",
                 tmp_path / "s.csv", "--aiding", a, "--aiding-out", tmp_path / "m")
    assert f"[{table}] {key} = '2 %'" in msg and "not an angle unit" in msg
    assert "rad, mrad, deg" in msg


def test_a_measurement_file_without_its_table_is_named(sim, tmp_path, capsys):
    a = tmp_path / "gnss_only.toml"
    a.write_text("[gnss]\nrate = 1\nposition_sigma = 1.5\nvelocity_sigma = 0.1\n")
    code, _, err = _run(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv",
                        "--aiding", a, "--measurements", sim / "meas", "--out", tmp_path / "n.csv")
    assert code == 0
    warned = [ln for ln in err.splitlines() if "warning:" in ln]
    assert len(warned) == 2, err                                  # baro.csv and nhc.csv
    for fname, table in (("baro.csv", "[baro]"), ("nhc.csv", "[nhc]")):
        assert any(str(sim / "meas" / fname) in ln and table in ln for ln in warned), err


def test_zupt_in_assess_answers_for_a_motion_that_starts_at_rest(capsys, tmp_path):
    """``assess --aiding`` with ``[zupt]`` used to refuse every motion standing still at its
    start (every foot walk): the zero-velocity updates at the very start now act on the
    initial covariance, and the walk gets a verdict (exit 0 or 1 under --check)."""
    walk = Path(__file__).resolve().parents[2] / "examples" / "walk.toml"
    a = tmp_path / "z.toml"
    a.write_text("[zupt]\nsigma = 0.01\n")
    code, out, err = _run(capsys, "assess", walk, "--imu", "ADIS16470", "--rate", 100,
                          "--tolerance", 1, "--aiding", a, "--check")
    assert code in (0, 1), err
    assert "with zupt" in out and ("SUITABLE" in out)


def test_a_path_is_printed_once(sim, capsys):
    meas = sim / "meas"
    for extra in (["--out", meas / "nhc.csv"], ["--out", sim / "x.csv", "--truth", meas / "gnss.csv"]):
        msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, *extra,
                     "--aiding", sim / "aiding.toml", "--aiding-out", meas)
        path = str(extra[-1])
        assert msg.count(path) == 1, msg
        assert f"--aiding-out {path} is the same file as --" in msg
    msg = _error(capsys, "simulate", meas / "nhc.csv", "--rate", 50, "--out", sim / "x.csv",
                 "--aiding", sim / "aiding.toml", "--aiding-out", meas)
    assert msg.count(str(meas / "nhc.csv")) == 1 and "would overwrite the input file" in msg


def test_no_empty_unit(tmp_path, sim, capsys):
    a = tmp_path / "z.toml"
    a.write_text("[zupt]\nsigma = 0.01\nthreshold = -1\n")
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out",
                 tmp_path / "s.csv", "--aiding", a, "--aiding-out", tmp_path / "m")
    assert "[zupt] threshold must be a positive number, got -1" in msg and "()" not in msg


@pytest.mark.parametrize("toml, words", [
    ('[baro]\nrate = 1\nsigma = 1\nbias_drift = -1\n',                  # ≥ 0
     "[baro] bias_drift must be a non-negative number"),
    ('[gnss]\nrate = 1\nposition_sigma = 1\n[initial]\nattitude_sigma = "-1 deg"\n',
     "[initial] attitude_sigma must be a non-negative number"),
    ('[baro]\nrate = 1\nsigma = -1\n', "[baro] sigma must be a positive number"),   # > 0
    ('[heading]\nrate = 1\nsigma = "-2 deg"\n', "[heading] sigma must be a positive number"),
])
def test_positive_and_non_negative_say_what_is_checked(sim, tmp_path, capsys, toml, words):
    a = tmp_path / "a.toml"
    a.write_text(toml)
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out",
                 tmp_path / "s.csv", "--aiding", a, "--aiding-out", tmp_path / "m")
    assert words in msg
    assert ("non-negative" in msg) == ("non-negative" in words)


def test_outage_start_is_non_negative(sim, capsys):
    msg = _error(capsys, "design", sim / "drive.toml", "--imu", "ADIS16470", "--rate", 50,
                 "--tolerance", 5, "--aiding", sim / "aiding.toml", "--find", "outage",
                 "--outage-start", -1)
    assert "--outage-start must be a non-negative number" in msg


def test_measurements_given_a_file_says_a_folder_is_expected(sim, tmp_path, capsys):
    msg = _error(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv",
                 "--aiding", sim / "aiding.toml", "--measurements", sim / "meas" / "gnss.csv",
                 "--out", tmp_path / "n.csv")
    assert f"--measurements {sim / 'meas' / 'gnss.csv'} is a file" in msg
    assert "folder" in msg and "not found" not in msg


# ------------------------------------------------------------- round 2's second attack

def test_a_file_shoe_does_not_read_is_named_and_warnings_do_not_precede_an_error(sim, tmp_path,
                                                                                 capsys):
    meas = tmp_path / "meas"
    meas.mkdir()
    for f in ("gnss.csv", "baro.csv"):
        (meas / f).write_bytes((sim / "meas" / f).read_bytes())
    (meas / "zupt.csv").write_text("t0,t1\n1,2\n")
    a = tmp_path / "a.toml"
    a.write_text("[gnss]\nrate = 1\nposition_sigma = 1.5\nvelocity_sigma = 0.1\n"
                 "[zupt]\nsigma = 0.01\ndetector = \"shoe\"\n")
    code, _, err = _run(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv",
                        "--aiding", a, "--measurements", meas, "--out", tmp_path / "n.csv")
    assert code == 0
    warned = [ln for ln in err.splitlines() if "warning:" in ln]
    assert any(str(meas / "zupt.csv") in ln and "shoe" in ln for ln in warned), err
    assert any(str(meas / "baro.csv") in ln and "[baro]" in ln for ln in warned), err
    # a refused run prints its one error line only, not the warnings before it
    (meas / "gnss.csv").write_text("t,x,y,z\n")
    msg = _error(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv",
                 "--aiding", a, "--measurements", meas, "--out", tmp_path / "n.csv")
    assert f"{meas / 'gnss.csv'} has no velocity columns" in msg and "velocity_sigma" in msg


@pytest.mark.parametrize("toml, words", [
    ("[initial]\nposition_sigma = 1\n", "has no aiding sensor"),
    ("", "has no aiding sensor"),
    ("[gnss]\nrate = 1\nposition_sigma = 1\noutages = [5, 8]\n",
     "[gnss] outages must be a list of [t0, t1] (s), got [5, 8]: write [[5, 8]]"),
])
def test_simulate_refuses_an_aiding_file_it_cannot_use(sim, tmp_path, capsys, toml, words):
    a = tmp_path / "a.toml"
    a.write_text(toml)
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out",
                 tmp_path / "s.csv", "--aiding", a, "--aiding-out", tmp_path / "m")
    assert words in msg
    assert not (tmp_path / "m").exists()


def test_simulate_names_files_left_from_an_earlier_run(sim, tmp_path, capsys):
    out = tmp_path / "meas"
    argv = ["simulate", sim / "drive.toml", "--rate", 50, "--out", tmp_path / "s.csv",
            "--aiding-out", out, "--aiding"]
    assert _run(capsys, *argv, sim / "aiding.toml")[0] == 0          # gnss, baro, nhc
    a = tmp_path / "gnss.toml"
    a.write_text("[gnss]\nrate = 1\nposition_sigma = 1.5\n")
    code, _, err = _run(capsys, *argv, a)
    assert code == 0
    warned = [ln for ln in err.splitlines() if "warning:" in ln]
    assert len(warned) == 2, err
    for fname, table in (("baro.csv", "[baro]"), ("nhc.csv", "[nhc]")):
        assert any(str(out / fname) in ln and table in ln for ln in warned), err
    shoe = tmp_path / "shoe.toml"
    shoe.write_text('[zupt]\nsigma = 0.01\ndetector = "shoe"\n')
    code, text, _ = _run(capsys, *argv[:-3], "--aiding-out", tmp_path / "none", "--aiding", shoe)
    assert code == 0 and "wrote no aiding file" in text and "wrote  to" not in text


def test_a_folder_given_for_a_toml_file_is_called_a_folder(tmp_path, capsys):
    """`--aiding DIR` said 'aiding file not found' for a folder that exists."""
    from imunav.cli import main

    motion = tmp_path / "m.toml"
    motion.write_text('duration = 2\n[attitude]\nroll = "0.3*sin(t)"\n')
    (tmp_path / "aid_dir").mkdir()
    assert main(["assess", str(motion), "--imu", "ADIS16470", "--rate", "50", "--tolerance", "5",
                 "--aiding", str(tmp_path / "aid_dir")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a folder; expected a TOML file" in err


# ----------------------------------------------------------------------------- issue 37

@pytest.mark.parametrize("toml, words", [
    ("[gnss]\nrate = 1\nposition_sigma = 1e308\n", "[gnss] position_sigma must be in (0, 10000]"),
    ("[gnss]\nrate = 1e308\nposition_sigma = 1\n", "[gnss] rate must be in (0, 100]"),
    ("[gnss]\nrate = 1\nposition_sigma = 1\nlever_arm = [1e9, 0, 0]\n",
     "[gnss] lever_arm must be 3 numbers within ±100"),
    ("[gnss]\nrate = 1\nposition_sigma = 1\n[initial]\nposition_sigma = 1e308\n",
     "[initial] position_sigma must be in [0, 1e+07]"),
    ("[baro]\nrate = 1\nsigma = 1\nbias_drift = 1e308\n", "[baro] bias_drift must be in [0, 10]"),
])
def test_absurd_values_name_their_key_and_range(sim, tmp_path, capsys, toml, words):
    """A σ, rate, drift or lever arm beyond any physical sensor: one line naming the key and its
    range (exit 70 or inf/nan in the files before issue 37)."""
    a = tmp_path / "a.toml"
    a.write_text(toml)
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out", tmp_path / "s.csv",
                 "--aiding", a, "--aiding-out", tmp_path / "m")
    assert words in msg, msg
    assert not (tmp_path / "s.csv").exists() and not (tmp_path / "m").exists()


def test_covariance_step_has_a_physical_range(sim, tmp_path, capsys):
    msg = _error(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv", "--aiding",
                 sim / "aiding.toml", "--measurements", sim / "meas", "--out",
                 tmp_path / "n.csv", "--covariance-step", "1e308")
    assert "--covariance-step must be in (0, 10] s" in msg, msg


@pytest.mark.parametrize("toml, words", [
    ("[gnss]\nrate = 1\nposition_sigma = 1\noutages = [[400, 500]]\n", "lies outside the record"),
    ("[gnss]\nrate = 80\nposition_sigma = 1\n", "above the IMU rate of 50 Hz"),
])
def test_simulate_aiding_checks_everything_before_writing(sim, tmp_path, capsys, toml, words):
    """An outage outside the record or an aid faster than the IMU used to fail after the IMU
    and truth files were written (issue 37): now nothing is left."""
    a = tmp_path / "a.toml"
    a.write_text(toml)
    msg = _error(capsys, "simulate", sim / "drive.toml", "--rate", 50, "--out", tmp_path / "s.csv",
                 "--truth", tmp_path / "t.csv", "--aiding", a, "--aiding-out", tmp_path / "m")
    assert words in msg, msg
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.toml"]


def test_a_byte_order_mark_in_a_toml_is_read(sim, tmp_path, capsys):
    """A TOML saved with a BOM (Windows editors) was 'malformed TOML at line 1'."""
    a = tmp_path / "bom.toml"
    a.write_bytes(b"\xef\xbb\xbf" + AIDING.encode())
    code, _, err = _run(capsys, "filter", sim / "imu.csv", "--initial", sim / "truth.csv",
                        "--imu", "ADIS16470", "--aiding", a, "--measurements", sim / "meas",
                        "--out", tmp_path / "n.csv")
    assert code == 0, err


def test_an_absurd_initial_height_names_the_initial_file(tmp_path, capsys):
    """A truth file's first row 1e9 m above the ellipsoid was reported as 'p0: …'."""
    d = tmp_path
    (d / "drive.toml").write_text(DRIVE)
    assert main(["simulate", str(d / "drive.toml"), "--rate", "50", "--earth", "wgs84",
                 "--origin", "45,7,300", "--out", str(d / "s.csv"),
                 "--truth", str(d / "t.csv")]) == 0
    lines = (d / "t.csv").read_text().splitlines()
    cells = lines[1].split(",")
    cells[3] = "1e9"
    lines[1] = ",".join(cells)
    (d / "bad.csv").write_text("\n".join(lines) + "\n")
    (d / "a.toml").write_text("[baro]\nrate = 1\nsigma = 1\n")
    capsys.readouterr()
    msg = _error(capsys, "navigate", d / "s.csv", "--initial", d / "bad.csv", "--earth", "wgs84",
                 "--out", d / "n.csv")
    assert f"--initial {d / 'bad.csv'}" in msg and "height" in msg, msg
