"""Command line: ``imunav simulate | navigate | filter | assess | design | allan | reproduce``
(also ``python -m imunav``).

Exit status: 0 done; 1 a failed ``--check`` (``assess``: the IMU NOT SUITABLE; ``filter``: a health
warning fired); 2 a usage or input error,
with one line ``imunav: error: …`` naming the argument, file, row or law and what was expected;
70 an internal error (a bug: one line, ``IMUNAV_DEBUG=1`` shows the traceback); 130/143
interrupted or terminated. Numeric warnings never reach the terminal. No output
path may be an input (checked before anything runs), outputs are written to a temporary file
renamed at the end, and signals and states are streamed in chunks: a run of any length needs no
more memory than a short one.

May import: anything in imunav (a face of the package).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import os
import re
import signal
import sys
import warnings
from pathlib import Path

import numpy as np

from imunav.analysis.aided_assessment import assess_aided, format_aided_verdict
from imunav.analysis.aided_design import design_aided, format_outage_design
from imunav.analysis.assessment import assess, format_verdict
from imunav.analysis.design import design, format_design
from imunav.core.constants import G0
from imunav.core.resources import check_disk
from imunav.core.validation import ImunavError, check_positive
from imunav.earth import check_origin
from imunav.estimation.alignment import ALIGNMENTS, WINDOW
from imunav.estimation.filters import SD_COLUMNS, run_filter
from imunav.estimation.health import assess_health
from imunav.estimation.logs import filter_log, unknown_imu
from imunav.io import realdata
from imunav.io.aiding import (
    check_span,
    read_aiding,
    unused_files,
    write_aiding,
)
from imunav.io.csvio import CsvWriter
from imunav.io.files import (
    ROW_BYTES,
    STATE_HEADERS,
    SignalFile,
    figure_format,
    load_motion,
    read_initial_state,
    read_signals,
    save_figure,
    signals_writer,
    state_columns,
    states_writer,
    write_json,
    write_text,
)
from imunav.io.paths import check_outputs
from imunav.io.rtklib import gnss_readings, read_pos
from imunav.motion.geodetic import EarthMotion
from imunav.plotting import plot_allan
from imunav.reproduce import format_table, reproduce_all
from imunav.sensors.aids import AIDS, AidingConfig, AidingData, simulate_aiding
from imunav.sensors.allan import allan_fits
from imunav.sensors.allan_report import format_allan, imu_toml
from imunav.sensors.models import ImuModel
from imunav.sensors.presets import PRESETS
from imunav.sensors.simulate import interval_count, signal_chunks, truth_chunks
from imunav.strapdown.initial import level_attitude
from imunav.strapdown.registry import ALGORITHMS, navigate, navigate_chunks, resolve


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own usage errors: same one-line form, status 2
        """argparse's own usage errors: the same one-line form, status 2."""
        self.exit(2, f"imunav: error: {message}\n")


def _positive(name):
    def conv(text):
        """Convert the option's text, or an argparse error naming it."""
        try:
            return check_positive(float(text), name)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a positive number, got "
                                             f"{text!r}") from None
        except ImunavError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return conv


def _nonnegative(name):
    def conv(text):
        """Convert the option's text, or an argparse error naming it."""
        try:
            v = float(text)
        except ValueError:
            v = float("nan")
        if not (np.isfinite(v) and v >= 0):
            raise argparse.ArgumentTypeError(f"{name} must be a non-negative number, got "
                                             f"{text!r}")
        return v

    return conv


def _probability(name):
    def conv(text):
        """Convert the option's text, or an argparse error naming it."""
        try:
            v = float(text)
        except ValueError:
            v = float("nan")
        if not 0 < v <= 1:
            raise argparse.ArgumentTypeError(f"{name} must be a probability in (0, 1], got "
                                             f"{text!r}")
        return v

    return conv


def _integer(name, minimum):
    def conv(text):
        """Convert the option's text, or an argparse error naming it."""
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer ≥ {minimum}, got "
                                             f"{text!r}") from None
        if v < minimum:
            raise argparse.ArgumentTypeError(f"{name} must be an integer ≥ {minimum}, got {v}")
        return v

    return conv


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command (``imunav --help``)."""
    p = _Parser(prog="imunav", description=__doc__.splitlines()[0],
                epilog="exit status: 0 done, 1 a failed --check (assess: NOT SUITABLE; "
                       "filter: a health warning), 2 usage or input error, 70 internal error")
    p.add_argument("--version", action="version",
                   version=f"imunav {importlib.metadata.version('imunav')}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    presets = ", ".join(PRESETS)

    s = sub.add_parser("simulate", help="IMU signals from MOTION.toml (ideal, or with --imu)")
    s.add_argument("motion", metavar="MOTION", help=MOTION_HELP)
    _smoothing_options(s)
    s.add_argument("--rate", required=True, type=_positive("--rate"), metavar="HZ")
    s.add_argument("--out", required=True, metavar="SIGNALS.csv")
    s.add_argument("--output", choices=("rates", "increments"), default="rates")
    s.add_argument("--truth", metavar="TRUTH.csv", help="also write the true states at t_k")
    s.add_argument("--g", type=_positive("--g"), metavar="G",
                   help="gravity (m/s²); default the motion file's g or 9.80665")
    s.add_argument("--imu", metavar="PRESET|IMU.toml",
                   help=f"add sensor errors: a preset ({presets}) or an IMU.toml with [gyro] "
                        "and [accel] tables")
    s.add_argument("--seed", type=_integer("--seed", 0), default=0,
                   help="random seed for --imu and --aiding (default 0)")
    s.add_argument("--aiding", metavar="AIDING.toml",
                   help="also simulate the aiding sensors of AIDING.toml (with --aiding-out)")
    s.add_argument("--aiding-out", metavar="DIR",
                   help="folder for gnss.csv, baro.csv, heading.csv, nhc.csv, zupt.csv "
                        "(created if absent)")
    _earth_options(s)

    names = sorted({n for table in ALGORITHMS.values() for n in table})
    n = sub.add_parser("navigate", help="integrate SIGNALS.csv from the initial state")
    n.add_argument("signals", metavar="SIGNALS.csv")
    n.add_argument("--initial", metavar="TRUTH.csv",
                   help="its first row is the initial state (required for imunav CSV signals; "
                        "for recordings, default: roll/pitch from the resting accelerometer, "
                        "yaw 0, at rest at the origin)")
    n.add_argument("--format", choices=("imunav", "ximu3", "ximu", "generic"), default="imunav",
                   help="signal file format (ximu3/ximu: the folder or its inertial CSV)")
    n.add_argument("--gyro-units", default="rad/s", help="generic: rad/s or deg/s")
    n.add_argument("--accel-units", default="m/s^2", help="generic: m/s^2 or g")
    n.add_argument("--gyro-columns", default="gx,gy,gz", help="generic: three column names")
    n.add_argument("--accel-columns", default="ax,ay,az", help="generic: three column names")
    n.add_argument("--time-column", help="generic: time column name (else --rate)")
    n.add_argument("--time-units", default="s", help="generic: s, ms or us")
    n.add_argument("--rate", type=_positive("--rate"), metavar="HZ",
                   help="generic without a time column: sample rate")
    n.add_argument("--imu-tag", metavar="FILE.tag",
                   help="generic: RTKLIB time tags of the log (times in GPST seconds)")
    n.add_argument("--imu-time-offset", type=float, default=0.0, metavar="S",
                   help="generic: seconds added to the time stamps")
    n.add_argument("--rest-window", type=_positive("--rest-window"), default=0.5, metavar="S",
                   help="recordings without --initial: seconds at rest used for the attitude")
    n.add_argument("--out", required=True, metavar="NAV.csv")
    n.add_argument("--algorithm", choices=names, metavar="NAME",
                   help="one of " + ", ".join(names) + "; default the most accurate for the kind")
    n.add_argument("--g", type=_positive("--g"), metavar="G", help="gravity (m/s²), 9.80665")
    n.add_argument("--earth", choices=EARTHS, default="flat",
                   help="navigation frame: flat (non-rotating NED, the default) or wgs84 (the "
                        "rotating Earth; --initial is then a t,lat,lon,alt,vn,ve,vd,… truth CSV)")

    f = sub.add_parser("filter", help="aided navigation: the error-state Kalman filter (and "
                                      "RTS smoother) of an IMU record with its aids — a "
                                      "simulated record with its truth, or a real log")
    f.add_argument("signals", metavar="SIGNALS.csv",
                   help="an imunav signals CSV, or a log with --format generic")
    f.add_argument("--format", choices=("imunav", "generic"), default="imunav",
                   help="generic: a CSV of any layout (with or without a header), read with the "
                        "flags below")
    f.add_argument("--gyro-columns", default="gx,gy,gz",
                   help="generic: three column names or 0-based indices")
    f.add_argument("--accel-columns", default="ax,ay,az",
                   help="generic: three column names or 0-based indices")
    f.add_argument("--gyro-units", default="rad/s", help="generic: rad/s or deg/s")
    f.add_argument("--accel-units", default="m/s^2", help="generic: m/s^2 or g")
    f.add_argument("--time-column", help="generic: time column (name or index; with --imu-tag "
                                         "the IMU's counter); else --rate")
    f.add_argument("--time-units", default="s", help="generic: s, ms or us")
    f.add_argument("--rate", type=_positive("--rate"), metavar="HZ",
                   help="generic without a time column: sample rate")
    f.add_argument("--imu-tag", metavar="FILE.tag",
                   help="RTKLIB time tags of the IMU log: its times become GPST seconds, the "
                        "axis of an RTKLIB .pos solution")
    f.add_argument("--imu-time-offset", metavar="S|auto",
                   help="seconds added to the IMU's time stamps (after [mounting] "
                        "time_offset); auto: the lag that lines the IMU's yaw rate up with the "
                        "GNSS course rate")
    f.add_argument("--initial", metavar="TRUTH.csv",
                   help="start from the first row of a truth CSV (a simulated record); or "
                        "--align")
    f.add_argument("--align", choices=("static", "gnss"),
                   help="start from what a log gives: static (levelled on the still start, "
                        "heading 0, position 0 — a foot) or gnss (levelled, then the heading "
                        "from the GNSS velocity once moving — a vehicle)")
    f.add_argument("--still", type=_positive("--still"), metavar="S",
                   help="with --align: the still start (s; default: until 2 s before the GNSS "
                        "speed first exceeds 0.1 m/s with gnss, 1 s with static)")
    f.add_argument("--noise", choices=("model", "rest"), default="model",
                   help="with --align: the IMU model's white noise, or at least the noise "
                        "measured on the still start (rest: a vehicle's vibration)")
    f.add_argument("--imu", metavar="PRESET|IMU.toml",
                   help="the IMU model the filter assumes (default: a stated model of an "
                        "unknown IMU; 'ideal': no sensor-error states)")
    f.add_argument("--aiding", required=True, metavar="AIDING.toml",
                   help="the aids' noise models, the set-up ([mounting]) and the [initial] "
                        "uncertainty")
    f.add_argument("--measurements", metavar="DIR",
                   help="folder with the aids' files (gnss.csv, baro.csv, …); not needed when "
                        "no aid needs one")
    f.add_argument("--gnss", metavar="FILE.pos",
                   help="GNSS from an RTKLIB solution (instead of [gnss] file / gnss.csv)")
    f.add_argument("--out", required=True, metavar="NAV.csv",
                   help="navigation CSV plus " + ",".join(SD_COLUMNS))
    f.add_argument("--smooth", action="store_true",
                   help="write the RTS smoother's states and standard deviations instead")
    f.add_argument("--algorithm", choices=names, metavar="NAME",
                   help="strapdown algorithm; default the most accurate for the kind")
    f.add_argument("--gate", type=_probability("--gate"), default=0.9999, metavar="P",
                   help="χ² innovation gate probability: a reading whose innovation is less "
                        "likely than this is not used (default 0.9999; 1: no gate)")
    f.add_argument("--recover", type=_integer("--recover", 0), default=5, metavar="N",
                   help="after N consecutive readings of one aid rejected by the gate, use the "
                        "next one with the covariance inflated until it is plausible, and warn "
                        "(default 5; 0: never)")
    f.add_argument("--report", metavar="FILE.json",
                   help="write each aid's health (readings used and gated, the longest run of "
                        "rejections, re-admissions, NIS and autocorrelation against their "
                        "bands) and the warnings")
    f.add_argument("--check", action="store_true",
                   help="exit 1 when any health warning fires")
    f.add_argument("--covariance-step", type=_positive("--covariance-step"), default=0.1,
                   metavar="S", help="longest covariance step (s, default 0.1)")
    f.add_argument("--g", type=_positive("--g"), metavar="G", help="gravity (m/s²), 9.80665")
    f.add_argument("--earth", choices=EARTHS, default="flat",
                   help="navigation frame: flat (the default) or wgs84 (the rotating Earth: "
                        "--initial a t,lat,lon,alt,vn,ve,vd,… truth, gnss.csv "
                        "t,lat,lon,alt[,vn,ve,vd], baro.csv heights above the ellipsoid; --out "
                        "t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz plus the σ in metres)")

    a = sub.add_parser("assess", help="can this IMU track this motion? (the verdict)")
    a.add_argument("motion", metavar="MOTION", help=MOTION_HELP)
    _smoothing_options(a)
    a.add_argument("--imu", required=True, metavar="PRESET|IMU.toml")
    a.add_argument("--rate", required=True, type=_positive("--rate"), metavar="HZ")
    a.add_argument("--tolerance", required=True, type=_positive("--tolerance"), metavar="POS_M")
    a.add_argument("--method", choices=("covariance", "montecarlo", "auto"),
                   help="covariance (linear covariance analysis: fast, the default without "
                        "--runs), montecarlo (the default when --runs is given), or auto (the "
                        "covariance, and a Monte Carlo of --runs (default 200) when the "
                        "covariance's own linearisation check fails)")
    a.add_argument("--runs", type=_integer("--runs", 1), metavar="N",
                   help="Monte Carlo runs (--method montecarlo)")
    a.add_argument("--seed", type=_integer("--seed", 0), help="Monte Carlo seed (default 0)")
    a.add_argument("--json", metavar="OUT.json")
    _alignment_options(a)
    a.add_argument("--check", action="store_true",
                   help="exit with status 1 when the verdict is NOT SUITABLE (for scripts; "
                        "without it the status is 0 whatever the verdict)")
    a.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the Monte Carlo on a Dask cluster (imunav[dask])")
    a.add_argument("--aiding", metavar="AIDING.toml",
                   help="aided: the error-state filter with these aids (GNSS with its outages, "
                        "baro, heading, NHC, ZUPT) — its covariance along the true motion, or "
                        "with --runs a Monte Carlo of the filter; the verdict through every "
                        "GNSS outage")
    a.add_argument("--covariance-step", type=_positive("--covariance-step"), default=0.1,
                   metavar="S", help="with --aiding: the filter's longest covariance step "
                                     "(s, default 0.1)")
    _earth_options(a, vertical=True)

    d = sub.add_parser("design", help="the worst IMU that still meets a tolerance on a motion")
    d.add_argument("motion", metavar="MOTION", help=MOTION_HELP)
    _smoothing_options(d)
    d.add_argument("--imu", required=True, metavar="BASE",
                   help="the IMU whose terms are varied: a preset or an IMU.toml")
    d.add_argument("--rate", required=True, type=_positive("--rate"), metavar="HZ")
    d.add_argument("--tolerance", required=True, type=_positive("--tolerance"), metavar="M")
    d.add_argument("--json", metavar="OUT.json")
    _alignment_options(d)
    d.add_argument("--aiding", metavar="AIDING.toml",
                   help="aided: the filter with these aids (the file's GNSS outages kept for "
                        "the IMU limits; replaced by the one searched with --find outage)")
    d.add_argument("--find", choices=("outage",),
                   help="with --aiding: outage — the longest GNSS outage (max_outage_s: from "
                        "the last fix used to the next) through which the position error "
                        "stays within the tolerance at every epoch with a probability of at "
                        "least 95 %%")
    d.add_argument("--outage-start", type=_nonnegative("--outage-start"), metavar="S",
                   help="with --find outage: the outage starts here (s; default where it "
                        "hurts most)")
    _earth_options(d, vertical=True)

    al = sub.add_parser("allan", help="fit an IMU model (N, B, K) to a static recording's "
                                      "Allan deviation")
    al.add_argument("log", metavar="LOG.csv",
                    help="a static recording: an imunav rates CSV, or --format generic")
    al.add_argument("--fit", required=True, metavar="IMU.toml", help="write the fitted model")
    al.add_argument("--plot", metavar="ADEV.png", help="also plot the Allan deviations and fits")
    al.add_argument("--format", choices=("imunav", "generic"), default="imunav")
    for opt, default, what in (("--gyro-units", "rad/s", "rad/s or deg/s"),
                               ("--accel-units", "m/s^2", "m/s^2 or g"),
                               ("--gyro-columns", "gx,gy,gz", "three column names"),
                               ("--accel-columns", "ax,ay,az", "three column names"),
                               ("--time-units", "s", "s, ms or us")):
        al.add_argument(opt, default=default, help=f"generic: {what}")
    al.add_argument("--time-column", help="generic: time column name (else --rate)")
    al.add_argument("--rate", type=_positive("--rate"), metavar="HZ",
                    help="generic without a time column: sample rate")

    r = sub.add_parser("reproduce", help="regenerate every reproduction figure and record")
    r.add_argument("--out", default="figures", metavar="DIR")
    return p


MOTION_HELP = ("the motion: MOTION.toml (analytic laws), a pose CSV (t,x,y,z,qw,qx,qy,qz, or a "
               "truth CSV) or a waypoints TOML ([[waypoint]] tables)")


#: The navigation frames of the command line.
EARTHS = ("flat", "wgs84")


def _alignment_options(p) -> None:
    p.add_argument("--alignment", choices=ALIGNMENTS, default="truth",
                   help="the initial attitude: truth (default), or level — roll and pitch "
                        "levelled from the accelerometer at rest before the motion, which "
                        "absorbs its horizontal bias into the initial tilt (flat frame)")
    p.add_argument("--align-window", type=_positive("--align-window"), metavar="S",
                   help=f"with --alignment level: seconds at rest averaged (default {WINDOW:g})")


def _alignment(args, motion) -> dict:
    """The library's alignment arguments from ``--alignment``/``--align-window``."""
    if args.alignment == "truth":
        if args.align_window is not None:
            raise ImunavError("--align-window applies to --alignment level only")
        return {}
    if motion.frame != "flat":
        raise ImunavError("--alignment level works on --earth flat only (levelling on the "
                          "rotating Earth is not modelled)")
    return {"alignment": "level", "align_window": args.align_window or WINDOW}


def _origin(text: str) -> tuple[float, float, float]:
    """``--origin LAT,LON,ALT`` (degrees, degrees, metres) → radians, radians, metres."""
    parts = text.split(",")
    try:
        if len(parts) != 3:
            raise ValueError
        lat, lon, alt = (float(x) for x in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--origin must be LAT,LON,ALT (degrees, degrees, metres above the ellipsoid), got "
            f"{text!r}") from None
    try:
        return check_origin(np.radians(lat), np.radians(lon), alt, "--origin")
    except ImunavError as exc:                           # argparse names the option itself
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--origin: ")) from None


def _earth_options(p, vertical: bool = False) -> None:
    p.add_argument("--earth", choices=EARTHS, default="flat",
                   help="flat (non-rotating NED with constant gravity, the default) or wgs84 (the "
                        "rotating WGS-84 Earth: Earth rate, transport rate, normal gravity)")
    p.add_argument("--origin", type=_origin, metavar="LAT,LON,ALT",
                   help="with --earth wgs84 (required): the Earth-fixed origin of the motion's "
                        "NED frame, degrees, degrees, metres above the ellipsoid")
    if vertical:
        p.add_argument("--vertical", choices=("free", "hold"), default="free",
                       help="with --earth wgs84: the vertical channel free (unstable, the "
                            "default) or held at the true height (a perfect height aid)")


def _on_earth(args, motion, g_file):
    """The motion in the frame of ``--earth``: on wgs84 wrapped at ``--origin`` (required), and
    ``--g`` refused (gravity comes from the model); a motion file's own ``g`` is not used."""
    if getattr(args, "earth", "flat") == "flat":
        if getattr(args, "origin", None) is not None:
            raise ImunavError("--origin applies to --earth wgs84 only")
        if getattr(args, "vertical", "free") != "free":
            raise ImunavError("--vertical applies to --earth wgs84 only (the flat frame has no "
                              "vertical instability)")
        return motion
    if getattr(args, "g", None) is not None:
        raise ImunavError("--g belongs to the flat frame: with --earth wgs84 gravity comes from "
                          "the normal gravity model")
    if args.origin is None:
        raise ImunavError("--earth wgs84 needs --origin LAT,LON,ALT (degrees, degrees, metres)")
    if g_file is not None:
        print(f"imunav: warning: the motion file's g = {g_file:g} is not used with --earth wgs84 "
              "(normal gravity)", file=sys.stderr)
    return EarthMotion(motion, args.origin)


def _smoothing_options(p) -> None:
    p.add_argument("--smoothing", type=_positive("--smoothing"), metavar="M",
                   help="pose CSV: position noise level (m) for a smoothing spline")
    p.add_argument("--attitude-smoothing", type=_positive("--attitude-smoothing"),
                   metavar="RAD", help="pose CSV: attitude noise level (rad)")


def _motion(args):
    """The motion file of any kind → (motion, duration, g or None)."""
    return load_motion(args.motion, smoothing=args.smoothing,
                       attitude_smoothing=args.attitude_smoothing)


def _imu(spec: str | None) -> tuple[ImuModel | None, list]:
    """The --imu model and, if it is a file, that file as an input."""
    if spec is None:
        return None, []
    return ImuModel.load(spec), ([] if spec in PRESETS else [spec])


def cmd_simulate(args) -> int:
    """``imunav simulate``: stream the signals (and ``--truth``) of a motion to CSV."""
    model, imu_files = _imu(args.imu)
    if (args.aiding is None) != (args.aiding_out is None):
        raise ImunavError("--aiding and --aiding-out go together")
    aiding = AidingConfig.from_toml(args.aiding) if args.aiding else None
    if aiding is not None and not aiding.sensors:
        raise ImunavError(f"--aiding {args.aiding} has no aiding sensor to simulate "
                          f"({_tables()})")
    inputs = [args.motion, *imu_files] + ([args.aiding] if args.aiding else [])
    out = check_outputs({"--out": args.out, "--truth": args.truth}, inputs)
    if args.aiding_out:
        _check_aiding_out(Path(args.aiding_out), aiding, inputs, out)
    motion, duration, g_file = _motion(args)
    motion = _on_earth(args, motion, g_file)
    g = args.g if args.g is not None else (g_file if g_file is not None else G0)
    n = interval_count(args.rate, duration)
    check_disk(out["--out"], (n + 1) * ROW_BYTES["signals"], "this simulation")
    if args.truth:
        check_disk(out["--truth"], (n + 1) * ROW_BYTES["states"], "--truth")
    data = None
    if aiding is not None:            # every check of the aids before anything is written
        data = simulate_aiding(motion, aiding, n / args.rate, seed=args.seed,
                               imu_rate=args.rate)
        _check_aids_rate(aiding, args.rate)
    clipped = [0]
    chunks = signal_chunks(motion, args.rate, duration, kind=args.output, g=g, imu=model,
                           seed=args.seed,
                           on_clip=lambda c: clipped.__setitem__(0, clipped[0] + c))
    rows = 0
    with signals_writer(out["--out"], args.output) as w:
        for t, gyro, accel in chunks:
            w.write([t, gyro, accel])
            rows += t.size
        if args.truth:
            with states_writer(out["--truth"], motion.frame) as tw:
                for st in truth_chunks(motion, args.rate, duration):
                    tw.write(state_columns(st))
    if clipped[0]:
        print(f"imunav: warning: {clipped[0]} samples clipped at the sensor range",
              file=sys.stderr)
    if aiding is not None:
        files = write_aiding(args.aiding_out, data, motion.frame)
        counts = ", ".join(f"{p.name} ({_rows(data, p.stem)} rows)" for p in files)
        print(f"wrote {counts} to {args.aiding_out}" if files else
              f"wrote no aiding file to {args.aiding_out} (the [zupt] detector \"shoe\" finds "
              "the stance in the IMU data)")
        for name, spec in AIDS.items():                     # a filter would read them as new
            stale = Path(args.aiding_out) / spec.file
            if stale.is_file() and stale not in files:
                print(f"imunav: warning: {stale} is left from before: --aiding {args.aiding} "
                      f"simulates no [{name}]" + (" readings (detector = \"shoe\")"
                                                  if name == "zupt" and aiding.zupt else ""),
                      file=sys.stderr)
    offset = motion.time_offset
    note = (f" (t = 0 is the first pose or waypoint, t = {offset:g} s in {args.motion})"
            if offset else "")
    print(f"wrote {rows} {args.output} rows at {args.rate:g} Hz to {args.out}{note}",
          file=_report(out))
    return 0


def _rows(data, name: str) -> int:
    r = getattr(data, name)
    return int(r.shape[0]) if name == "zupt" else len(r)


def _check_aids_rate(aiding, imu_rate: float) -> None:
    """An aid may not read faster than the IMU samples (the filter updates at IMU nodes)."""
    for name in aiding.sensors:
        r = AIDS[name].rate(aiding.get(name))
        if r is not None and r > imu_rate * (1 + 1e-12):
            raise ImunavError(f"[{name}] rate = {r:g} Hz is above the IMU rate of {imu_rate:g} "
                              f"Hz: expected at most {imu_rate:g} Hz (the filter updates at IMU "
                              "samples)")


def _check_aiding_out(folder: Path, aiding, inputs, outputs) -> None:
    """--aiding-out: not a file, and none of its sensor files an input or another output."""
    if folder.exists() and not folder.is_dir():
        raise ImunavError(f"--aiding-out {folder} is a file; give a folder")
    if not folder.resolve().parent.is_dir():
        raise ImunavError(f"--aiding-out {folder}: the folder {folder.resolve().parent} does "
                          "not exist")
    where = folder if folder.is_dir() else folder.resolve().parent
    if not os.access(where, os.W_OK | os.X_OK):
        raise ImunavError(f"--aiding-out {folder}: {where} is not writable")
    names = {f"--aiding-out {folder / fname}": folder / fname
             for fname in (spec.file for spec in AIDS.values())}
    check_outputs({**outputs, **names} if folder.is_dir() else dict(outputs), inputs)


def cmd_filter(args) -> int:
    """``imunav filter``: the aided filter (or smoother) of an IMU record and its aids."""
    model, imu_files = _imu(args.imu)
    if (args.initial is None) == (args.align is None):
        raise ImunavError("give --initial TRUTH.csv (a simulated record) or --align static|gnss "
                          "(a log), one of them")
    if args.align is None:
        for opt, val in (("--still", args.still), ("--imu-time-offset", args.imu_time_offset),
                         ("--gnss", args.gnss)):
            if val is not None:
                raise ImunavError(f"{opt} applies with --align (a log) only")
        if args.noise != "model":
            raise ImunavError("--noise applies with --align (a log) only")
    if args.format == "imunav" and args.imu_tag:
        raise ImunavError("--imu-tag applies with --format generic")
    inputs = [args.signals, args.initial, args.aiding, args.measurements, args.imu_tag,
              args.gnss, *imu_files]
    out = check_outputs({"--out": args.out, "--report": args.report}, inputs)
    aiding = AidingConfig.from_toml(args.aiding)
    if not aiding.sensors:
        raise ImunavError(f"--aiding {args.aiding} has no aiding sensor ({_tables()})")
    if args.earth == "wgs84" and args.g is not None:
        raise ImunavError("--g belongs to the flat frame: with --earth wgs84 gravity comes from "
                          "the normal gravity model")
    if args.align is not None and args.earth != "flat":
        raise ImunavError("--align runs the flat frame (a log's own tangent frame): drop "
                          "--earth wgs84")
    if model is None:
        model = unknown_imu(aiding)
        print(f"filter: no --imu given: the filter assumes the {model.name} (give --imu, or "
              "--imu ideal for no sensor-error states)")
    if args.format == "generic":
        sig = _read_log(args)
    else:
        sig = read_signals(args.signals, g=args.g)
    _check_algorithm(sig.kind, args.algorithm)
    init = None
    if args.initial is not None:
        init = read_initial_state(args.initial)
        _check_initial_frame(args, init)
    data, origin = _log_data(args, aiding, sig)
    n_rows = len(sig) + (1 if sig.kind == "increments" else 0)
    check_disk(out["--out"], n_rows * (ROW_BYTES["states"] + 9 * 24), "this filter's output")
    gate = None if args.gate >= 1 else args.gate
    if args.align is not None:
        offset = args.imu_time_offset
        if offset is not None and offset != "auto":
            try:
                offset = float(offset)
            except ValueError:
                raise ImunavError(f"--imu-time-offset must be a number of seconds or auto, got "
                                  f"{offset!r}") from None
        lr = filter_log(sig, aiding, data, imu=model, align=args.align,
                        still_seconds=args.still if args.still is not None else "auto",
                        noise=args.noise, time_offset=offset, smooth=args.smooth, gate=gate,
                        recover=args.recover or None, covariance_step=args.covariance_step,
                        algorithm=args.algorithm)
        res = lr.result
        for note in lr.notes + ([f"flat frame: NED from the first GNSS epoch used, "
                                 f"{np.degrees(origin[0]):.8f}°, {np.degrees(origin[1]):.8f}°, "
                                 f"{origin[2]:.3f} m"] if origin is not None else []):
            print(f"filter: {note}")
    else:
        t_start = float(sig.state_times()[0])
        if abs(init.t[0] - t_start) > 1e-6 / sig.rate + 1e-12 * abs(t_start):
            raise ImunavError(f"--initial {args.initial} starts at t = {init.t[0]:.9g} s but "
                              f"the signals start at t = {t_start:.9g} s")
        q0, v0, p0 = init.initial()
        res = run_filter(sig, q0, v0, p0, aiding, data, imu=model, algorithm=args.algorithm,
                         covariance_step=args.covariance_step, gate=gate, smooth=args.smooth,
                         earth=args.earth, recover=args.recover or None)
    r = res.smoothed if args.smooth else res
    st = r.states
    with CsvWriter(out["--out"], STATE_HEADERS[args.earth] + SD_COLUMNS) as w:
        w.write(state_columns(st) + [r.sd])
    for msg in res.warnings:
        print(f"imunav: warning: {msg}", file=sys.stderr)
    what = "smoothed " if args.smooth else ""
    print(f"wrote {len(st.t)} {what}navigation rows ({st.algorithm}, {len(res.layout)} state "
          f"blocks, {res.estimates.shape[1] + 9} error states) to {args.out}")
    print(format_innovations(res.innovations, res.health))
    if args.report:
        write_json({**res.health.as_dict(), "warnings": list(res.warnings),
                    "gate": gate, "recover": args.recover}, out["--report"])
    return 1 if args.check and res.health.warnings else 0


def _read_log(args):
    """--format generic (with --imu-tag): the log's IMU samples."""
    cols = [c.strip() for c in args.gyro_columns.split(",")], \
           [c.strip() for c in args.accel_columns.split(",")]
    rec = realdata.read_generic(args.signals, gyro_columns=cols[0], accel_columns=cols[1],
                                gyro_units=args.gyro_units, accel_units=args.accel_units,
                                time_column=args.time_column, time_units=args.time_units,
                                rate=args.rate, tag=args.imu_tag)
    for w in getattr(rec, "warnings", []) or []:
        print(f"imunav: warning: {w}", file=sys.stderr)
    sig = rec.signals
    if args.g is not None:
        sig.g = args.g
    return sig


def _log_data(args, aiding, sig):
    """The aids' readings: --gnss / [gnss] file (an RTKLIB solution), and --measurements.

    Returns the data and, for an RTKLIB solution on the flat frame, its origin."""
    data, origin = AidingData(), None
    meas = Path(args.measurements) if args.measurements else None
    pos = args.gnss
    g = aiding.gnss
    if pos is None and g is not None and g.file is not None:
        pos = Path(args.aiding).parent / g.file
    if pos is not None and g is None:
        raise ImunavError(f"--gnss {pos} needs a [gnss] table in --aiding {args.aiding}")
    need = [n for n in aiding.sensors
            if AIDS[n].file_needed(aiding.get(n)) and not (n == "gnss" and pos is not None)]
    if need and meas is None:
        raise ImunavError(f"--aiding {args.aiding} has " + ", ".join(f"[{n}]" for n in need)
                          + ": give --measurements DIR with "
                          + ", ".join(AIDS[n].file for n in need))
    if meas is not None:
        names = [n for n in aiding.sensors if not (n == "gnss" and pos is not None)]
        data = read_aiding(meas, names, args.earth, aiding)
        t_start, t_end = float(sig.state_times()[0]), float(sig.state_times()[-1])
        check_span(meas, data, t_start, t_end)
        if aiding.zupt and aiding.zupt.detector == "truth" and data.zupt is None:
            raise ImunavError(f"[zupt] detector = \"truth\" needs {meas / 'zupt.csv'}"
                              " (the stance intervals)")
        if aiding.gnss and pos is None and aiding.gnss.velocity_sigma and \
                data.gnss.values.shape[1] == 3:
            raise ImunavError(f"{meas / 'gnss.csv'} has no velocity columns, but --aiding "
                              f"{args.aiding} sets [gnss] velocity_sigma: drop it, or give the "
                              f"header {','.join(AIDS['gnss'].headers[args.earth][0])}")
        detector = aiding.zupt.detector if aiding.zupt else None
        for msg in unused_files(meas, aiding.sensors, detector):
            print(f"imunav: warning: {msg} (--aiding {args.aiding})", file=sys.stderr)
    if pos is not None:
        sol = read_pos(pos)
        readings, notes = gnss_readings(sol, g, frame=args.earth)
        origin = sol.select(sol.quality <= g.min_quality).llh[0] if args.earth == "flat" \
            else None
        for n in notes:
            print(f"filter: {pos}: {n}")
        data.gnss = readings
    return data, origin


def format_innovations(innovations: dict, health=None) -> str:
    """Each aid's innovations and health, as ``imunav filter`` prints them.

    Parameters
    ----------
    innovations : dict
        ``{aid: Innovations}`` of a filter result.
    health : Health, optional
        Its health (:mod:`imunav.estimation.health`; default computed from the innovations).

    Returns
    -------
    str
    """
    health = health or assess_health(innovations)
    lines = ["innovations (predicted − measured) and each aid's health:",
             f"  {'aid':9} {'readings':>8} {'used':>7} {'gated':>7} {'longest':>8} "
             f"{'mean NIS':>9} {'band':>13} {'lag-1 ρ':>8} {'band':>7}  rms per component"]
    for name, inn in innovations.items():
        h = health.aids[name]
        if not h["readings"]:
            lines.append(f"  {name:9} {0:>8} {0:>7} {'–':>7} {'–':>8} {'–':>9} {'–':>13} "
                         f"{'–':>8} {'–':>7}  (no readings)")
            continue
        st = inn.stats()
        gated = f"{100 * h['gated_share']:.3g}%"
        longest = f"{h['longest_rejection_s']:.3g} s" if h["longest_rejection_run"] else "–"
        band = "[{:.3g}, {:.3g}]".format(*h["nis_band"])
        rho = [r for r in (h["lag1"] or []) if r is not None]
        worst = max(rho, key=abs) if rho else float("nan")
        lag_band = f"±{h['lag1_band']:.3g}" if h["lag1_band"] is not None else "–"
        units = inn.units or ("",) * st["dof"]
        rms = ", ".join(f"{v:.3g} {u}" for v, u in zip(st["rms"], units, strict=False))
        lines.append(f"  {name:9} {h['readings']:>8} {h['used']:>7} {gated:>7} {longest:>8} "
                     f"{_num(h['mean_nis']):>9} {band:>13} {worst:>8.3f} {lag_band:>7}  {rms}")
    return "\n".join(lines)


def _check_status(args, r: dict) -> int:
    """The exit status of ``assess [--check]``: 1 with --check unless the verdict is SUITABLE
    and the runs decide it (a Monte Carlo too short to is UNDECIDED)."""
    return 1 if args.check and not (r["suitable"] and r.get("conclusive", True)) else 0


def _num(x) -> str:
    """``x`` to 3 significant digits, "–" for None or NaN (a divergence's readings)."""
    return "–" if x is None or not np.isfinite(x) else f"{x:.3g}"


def cmd_assess(args) -> int:
    """``imunav assess``: the verdict, by covariance analysis or Monte Carlo."""
    model, imu_files = _imu(args.imu)
    out = check_outputs({"--json": args.json},
                        [args.motion, *imu_files] + ([args.aiding] if args.aiding else []))
    method = args.method or ("montecarlo" if args.runs is not None else "covariance")
    if method == "montecarlo" and args.runs is None:
        raise ImunavError("--method montecarlo needs --runs N")
    if method == "covariance":
        for opt, val in (("--runs", args.runs), ("--seed", args.seed),
                         ("--scheduler", args.scheduler)):
            if val is not None:
                raise ImunavError(f"{opt} applies to --method montecarlo only")
    motion, duration, g_file = _motion(args)
    motion = _on_earth(args, motion, g_file)
    if args.aiding is not None:
        return _assess_aided(args, model, motion, duration, out)
    if args.covariance_step != 0.1:
        raise ImunavError("--covariance-step applies with --aiding only")
    al = _alignment(args, motion)
    r = assess(motion, model, args.rate, args.runs, args.tolerance, seed=args.seed or 0,
               duration=duration, scheduler=args.scheduler, method=method,
               vertical=args.vertical, **al)
    print(format_verdict(r), file=_report(out))
    if args.json:
        write_json(r, out["--json"])
    return _check_status(args, r)


def _tables() -> str:
    """The aids' tables, for messages: "[gnss], [baro], … or [odometer]"."""
    names = [f"[{n}]" for n in AIDS]
    return ", ".join(names[:-1]) + " or " + names[-1]


def _aiding_file(args) -> AidingConfig:
    """--aiding: the aids of the aided analysis."""
    aiding = AidingConfig.from_toml(args.aiding)
    if not aiding.sensors:
        raise ImunavError(f"--aiding {args.aiding} has no aiding sensor ({_tables()})")
    return aiding


def _assess_aided(args, model, motion, duration, out) -> int:
    """``imunav assess --aiding``: the aided verdict through every GNSS outage."""
    if args.alignment != "truth" or args.align_window is not None:
        raise ImunavError("--alignment and --align-window apply without --aiding only (the "
                          "aided analysis starts from the true attitude)")
    aiding = _aiding_file(args)
    if args.method == "montecarlo" and args.runs is None:
        raise ImunavError("--method montecarlo needs --runs N")
    if args.method == "covariance" and args.runs is not None:
        raise ImunavError("--runs applies to --method montecarlo only")
    if args.runs is None:
        for opt, val in (("--seed", args.seed), ("--scheduler", args.scheduler)):
            if val is not None:
                raise ImunavError(f"{opt} applies to a Monte Carlo (--runs) only")
    r = assess_aided(motion, model, aiding, args.rate, args.tolerance, duration,
                     runs=args.runs, seed=args.seed or 0, scheduler=args.scheduler,
                     covariance_step=args.covariance_step, method=args.method)
    print(format_aided_verdict(r), file=_report(out))
    if args.json:
        write_json(r, out["--json"])
    return _check_status(args, r)


def _design_aided(args, model, motion, duration, out) -> int:
    """``imunav design --aiding [--find outage]``."""
    if args.alignment != "truth" or args.align_window is not None:
        raise ImunavError("--alignment and --align-window apply without --aiding only (the "
                          "aided analysis starts from the true attitude)")
    aiding = _aiding_file(args)
    r = design_aided(motion, model, aiding, args.rate, args.tolerance, duration,
                     find=args.find, outage_start=args.outage_start)
    print(format_outage_design(r), file=_report(out))
    if args.json:
        write_json(r, out["--json"])
    return 0


def cmd_design(args) -> int:
    """``imunav design``: the worst IMU that still meets the tolerance."""
    model, imu_files = _imu(args.imu)
    out = check_outputs({"--json": args.json},
                        [args.motion, *imu_files] + ([args.aiding] if args.aiding else []))
    if args.aiding is None and (args.find or args.outage_start is not None):
        raise ImunavError("--find and --outage-start need --aiding AIDING.toml")
    if args.outage_start is not None and args.find != "outage":
        raise ImunavError("--outage-start applies to --find outage only")
    motion, duration, g_file = _motion(args)
    motion = _on_earth(args, motion, g_file)
    if args.aiding is not None:
        return _design_aided(args, model, motion, duration, out)
    r = design(motion, model, args.rate, args.tolerance, duration=duration,
               vertical=args.vertical, **_alignment(args, motion))
    print(format_design(r), file=_report(out))
    if args.json:
        write_json(r, out["--json"])
    return 0


def cmd_allan(args) -> int:
    """``imunav allan``: fit an IMU model to a static log's Allan deviation."""
    out = check_outputs({"--fit": args.fit, "--plot": args.plot}, [args.log])
    if args.plot:
        figure_format(args.plot, "--plot")                   # before anything is written
    if args.format == "imunav":
        f = SignalFile(args.log)
        if f.kind != "rates":
            raise ImunavError(f"{args.log}: allan needs rate samples (t,gx,…); these are "
                              f"{f.kind}")
        sig = read_signals(args.log)
    else:
        sig = _read_recording(args, args.log)
    fits = allan_fits(sig, Path(args.log).name)
    write_text(out["--fit"], imu_toml(fits, Path(args.log).name))
    print(format_allan(fits, args.fit), file=_report(out))
    if args.plot:
        save_figure(plot_allan(fits), out["--plot"])
    return 0


def _check_algorithm(kind: str, name: str | None) -> None:
    if name and name not in ALGORITHMS[kind]:
        raise ImunavError(f"--algorithm {name!r} does not take {kind}; choose one of "
                          f"{', '.join(sorted(ALGORITHMS[kind]))}")


def cmd_navigate(args) -> int:
    """``imunav navigate``: stream a signals CSV (or a recording) through a strapdown algorithm."""
    out = check_outputs({"--out": args.out}, [args.signals, args.initial])
    if args.format != "imunav":
        return _navigate_recording(args, out["--out"])
    if not Path(args.signals).exists():
        raise ImunavError(f"signal file not found: {args.signals}")
    if not args.initial:
        raise ImunavError("--initial TRUTH.csv is required for imunav signal files")
    if args.earth == "wgs84" and args.g is not None:
        raise ImunavError("--g belongs to the flat frame: with --earth wgs84 gravity comes from "
                          "the normal gravity model")
    f = SignalFile(args.signals, g=args.g)
    _check_algorithm(f.kind, args.algorithm)
    init = read_initial_state(args.initial)
    _check_initial_frame(args, init)
    if abs(init.t[0] - f.t0) > 1e-6 * f.dt + 1e-12 * abs(f.t0):
        raise ImunavError(f"--initial {args.initial} starts at t = {init.t[0]:.9g} s but the "
                          f"signals start at t = {f.t0:.9g} s")
    check_disk(out["--out"], 1.7 * Path(args.signals).stat().st_size, "this navigation")
    q0, v0, p0 = init.initial()
    rows, algo = 0, resolve(f.kind, args.algorithm).name
    try:
        with states_writer(out["--out"], args.earth) as w:
            for st in navigate_chunks(f.kind, f.rate, f.chunks(), q0, v0, p0, f.g,
                                      algorithm=algo, t0=f.t0, earth=args.earth):
                w.write(state_columns(st))
                rows += len(st)
    except ImunavError as exc:                   # the integration's errors: name the file
        msg = str(exc)
        if msg.startswith("navigation "):
            raise ImunavError(f"{args.signals}: {msg}", argument=exc.argument) from None
        raise
    print(f"wrote {rows} navigation rows ({algo}) to {args.out}", file=_report(out))
    return 0


def _check_initial_frame(args, init) -> None:
    """The ``--initial`` truth must be in the frame of ``--earth``."""
    if init.frame != args.earth:
        want = ("t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz" if args.earth == "wgs84"
                else "t,x,y,z,vx,vy,vz,qw,qx,qy,qz")
        raise ImunavError(f"--initial {args.initial} is a {init.frame} truth but --earth is "
                          f"{args.earth} (expected the header {want})")
    if init.frame == "wgs84":                  # where it starts must be on the Earth
        lat, lon, h = init.position[0]
        check_origin(float(lat), float(lon), float(h), f"--initial {args.initial}, its first row")


def _navigate_recording(args, out: Path) -> int:
    sig = _read_recording(args)
    _check_algorithm(sig.kind, args.algorithm)
    if args.earth == "wgs84" and not args.initial:
        raise ImunavError("--earth wgs84 needs --initial TRUTH.csv (t,lat,lon,alt,vn,ve,vd,…): "
                          "where the recording starts on the Earth")
    if args.initial:
        init = read_initial_state(args.initial)
        _check_initial_frame(args, init)
        q0, v0, p0 = init.initial()
    else:
        n = max(1, int(args.rest_window * sig.rate))
        q0, v0, p0 = level_attitude(sig.accel[:n], sig.g, tol=0.1), np.zeros(3), np.zeros(3)
    if args.earth == "wgs84" and args.g is not None:
        raise ImunavError("--g belongs to the flat frame: with --earth wgs84 gravity comes from "
                          "the normal gravity model")
    res = navigate(sig, q0, v0, p0, algorithm=args.algorithm, earth=args.earth)
    with states_writer(out, res.frame) as w:
        w.write(state_columns(res))
    print(f"wrote {len(res.t)} navigation rows ({res.algorithm}) to {args.out}",
          file=_report({"--out": out}))
    return 0


def _read_recording(args, path=None):
    path = Path(args.signals if path is None else path)
    if args.format in ("ximu3", "ximu"):
        folder = path if path.is_dir() else path.parent
        if not folder.exists():
            raise ImunavError(f"recording not found: {path}")
        rec = realdata.READERS[args.format](folder)
    else:
        cols = [c.strip() for c in args.gyro_columns.split(",")], \
               [c.strip() for c in args.accel_columns.split(",")]
        rec = realdata.read_generic(path, gyro_columns=cols[0], accel_columns=cols[1],
                                    gyro_units=args.gyro_units, accel_units=args.accel_units,
                                    time_column=args.time_column, time_units=args.time_units,
                                    rate=args.rate, tag=getattr(args, "imu_tag", None),
                                    time_offset=getattr(args, "imu_time_offset", 0.0) or 0.0)
    if getattr(args, "g", None) is not None:
        rec.signals.g = args.g
    return rec.signals


def cmd_reproduce(args) -> int:
    """``imunav reproduce``: every reproduction figure and record."""
    records = reproduce_all(args.out)
    print(format_table(records))
    return 0


#: Exit status of an internal error (``EX_SOFTWARE`` of sysexits.h): not the 1 of a failed
#: ``--check`` nor the 2 of a usage error.
INTERNAL_ERROR = 70


def _report(outputs: dict) -> object:
    """Where a command's report goes: stdout, or stderr when one of its outputs is stdout
    itself (``--out /dev/stdout``), so the data stream stays clean."""
    try:
        fd1 = os.fstat(sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        return sys.stdout
    for path in outputs.values():
        try:
            st = os.stat(path)
        except OSError:
            continue
        if (st.st_dev, st.st_ino) == (fd1.st_dev, fd1.st_ino):
            return sys.stderr
    return sys.stdout


class _Terminated(BaseException):
    """SIGTERM, raised in the main thread so that every output's temporary file is removed."""


def _terminate(signum, frame):
    raise _Terminated()


def _warning_line(message, category, filename, lineno, file=None, line=None):
    print(f"imunav: warning: {message}", file=sys.stderr)


def _joined_negative_origin(argv: list[str]) -> list[str]:
    """``--origin -33.9,18.4,10`` (a southern latitude) as ``--origin=-33.9,18.4,10``: argparse
    takes a value that starts with ``-`` and is not a plain number for an option of its own."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else ""
        if a == "--origin" and len(nxt) > 1 and nxt[0] == "-" and (nxt[1].isdigit()
                                                                    or nxt[1] == "."):
            out.append(f"--origin={nxt}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def main(argv: list[str] | None = None) -> int:
    """The command line: parse ``argv``, run the command, map errors to one line and an exit status."""
    try:
        args = build_parser().parse_args(_joined_negative_origin(
            sys.argv[1:] if argv is None else list(argv)))
    except SystemExit as exc:                                # usage errors (2), --help (0)
        return int(exc.code or 0)
    command = {"simulate": cmd_simulate, "navigate": cmd_navigate, "filter": cmd_filter,
               "assess": cmd_assess,
               "design": cmd_design, "allan": cmd_allan,
               "reproduce": cmd_reproduce}[args.command]
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:                                       # not the main thread
        previous = None
    try:
        return _run(command, args)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


#: The library's argument names and the options that set them: a library error names the
#: argument in the library's terms (``imu``), the command line shows its flag (``--imu``).
FLAGS = {"imu": "--imu", "smoothing": "--smoothing", "attitude_smoothing": "--attitude-smoothing",
         "scheduler": "--scheduler", "runs": "--runs", "seed": "--seed", "rate": "--rate",
         "tolerance": "--tolerance", "algorithm": "--algorithm", "initial": "--initial",
         "measurements": "--measurements", "covariance_step": "--covariance-step",
         "gate": "--gate", "origin": "--origin", "earth": "--earth", "g": "--g",
         "alignment": "--alignment", "align_window": "--align-window",
         "aiding": "--aiding", "outage_start": "--outage-start", "recover": "--recover",
         "align": "--align", "still_seconds": "--still", "noise": "--noise",
         "time_offset": "--imu-time-offset", "gnss": "--gnss", "gyro_units": "--gyro-units",
         "accel_units": "--accel-units", "gyro_columns": "--gyro-columns",
         "accel_columns": "--accel-columns", "time_column": "--time-column",
         "time_units": "--time-units", "tag": "--imu-tag"}


def flagged(exc: ImunavError) -> str:
    """The message of a library error with each argument it names (``exc.argument``) written
    as the command-line option that sets it (:data:`FLAGS`).

    Parameters
    ----------
    exc : ImunavError

    Returns
    -------
    str
    """
    message = str(exc)
    names = exc.argument if isinstance(exc.argument, tuple) else (exc.argument,)
    for name in names:
        if name in FLAGS:
            message = re.sub(rf"(?<![\w-]){re.escape(name)}(?![\w-])", FLAGS[name], message,
                             count=1)
    return message


def _run(command, args) -> int:
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)      # numeric noise: checked values
        warnings.showwarning = _warning_line                 # anything else: one line
        try:
            return command(args)
        except ImunavError as exc:
            message = flagged(exc)
            path = getattr(args, "aiding", None)      # an AIDING.toml's table: name the file
            if exc.argument == "aiding" and isinstance(path, str) and path not in message:
                message = f"{path}: {message}"
            print(f"imunav: error: {message}", file=sys.stderr)
            return 2
        except BrokenPipeError:                              # `imunav … | head`: not an error
            try:
                sys.stdout = open(os.devnull, "w")           # noqa: SIM115 — swallow the flush
            except OSError:
                pass
            return 0
        except OSError as exc:                               # unreadable/unwritable paths
            where = f": {exc.filename}" if exc.filename else ""
            print(f"imunav: error: {exc.strerror or exc}{where}", file=sys.stderr)
            return 2
        except MemoryError:
            runs = "fewer --runs, " if getattr(args, "runs", None) is not None else ""
            print(f"imunav: error: out of memory (try {runs}a lower --rate or a shorter "
                  "duration)", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            print("imunav: interrupted; no output was written", file=sys.stderr)
            return 130
        except _Terminated:
            print("imunav: terminated; no output was written", file=sys.stderr)
            return 143
        except Exception as exc:                             # a bug: one line, exit 70
            if os.environ.get("IMUNAV_DEBUG"):
                raise
            print(f"imunav: internal error (please report it; IMUNAV_DEBUG=1 shows the "
                  f"traceback): {type(exc).__name__}: {exc}", file=sys.stderr)
            return INTERNAL_ERROR


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
