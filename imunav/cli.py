"""Command line: ``imunav simulate | navigate | reproduce`` (also ``python -m imunav``).

User errors exit with status 2 and a single line ``imunav: error: …`` (no traceback).

May import: anything in imunav (a face of the package).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from imunav.analysis.assessment import assess, format_verdict
from imunav.core.constants import G0
from imunav.core.validation import ImunavError, check_positive
from imunav.io import realdata
from imunav.io.files import (
    load_motion_toml,
    read_signals,
    read_states,
    write_json,
    write_signals,
    write_states,
)
from imunav.reproduce import format_table, reproduce_all
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import simulate_imu, truth_states
from imunav.strapdown.alignment import level_attitude
from imunav.strapdown.registry import ALGORITHMS, navigate


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own usage errors: same one-line form, status 2
        self.exit(2, f"imunav: error: {message}\n")


def _positive(name):
    def conv(text):
        try:
            return check_positive(float(text), name)
        except (ValueError, ImunavError) as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return conv


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="imunav", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("simulate", help="ideal IMU signals from MOTION.toml")
    s.add_argument("motion", metavar="MOTION.toml")
    s.add_argument("--rate", required=True, type=_positive("--rate"), metavar="HZ")
    s.add_argument("--out", required=True, metavar="SIGNALS.csv")
    s.add_argument("--output", choices=("rates", "increments"), default="rates")
    s.add_argument("--truth", metavar="TRUTH.csv", help="also write the true states at t_k")
    s.add_argument("--g", type=_positive("--g"), metavar="G",
                   help="gravity (m/s²); default the motion file's g or 9.80665")
    s.add_argument("--imu", metavar="PRESET|IMU.toml",
                   help="add sensor errors: a preset (ideal, BNO055, MPU-6050, BMI088, "
                        "ADIS16470, tactical) or an IMU.toml with [gyro] and [accel] tables")
    s.add_argument("--seed", type=int, default=0, help="random seed for --imu (default 0)")

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
    n.add_argument("--rest-window", type=_positive("--rest-window"), default=0.5, metavar="S",
                   help="recordings without --initial: seconds at rest used for the attitude")
    n.add_argument("--out", required=True, metavar="NAV.csv")
    n.add_argument("--algorithm", choices=names, metavar="NAME",
                   help="one of " + ", ".join(names) + "; default the most accurate for the kind")
    n.add_argument("--g", type=_positive("--g"), metavar="G", help="gravity (m/s²), 9.80665")

    a = sub.add_parser("assess", help="can this IMU track this motion? (Monte Carlo verdict)")
    a.add_argument("motion", metavar="MOTION.toml")
    a.add_argument("--imu", required=True, metavar="PRESET|IMU.toml")
    a.add_argument("--rate", required=True, type=_positive("--rate"), metavar="HZ")
    a.add_argument("--runs", required=True, type=int, metavar="N")
    a.add_argument("--tolerance", required=True, type=_positive("--tolerance"), metavar="POS_M")
    a.add_argument("--seed", type=int, default=0)
    a.add_argument("--json", metavar="OUT.json")
    a.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask cluster (imunav[dask])")

    r = sub.add_parser("reproduce", help="regenerate every reproduction figure and record")
    r.add_argument("--out", default="figures", metavar="DIR")
    return p


def _same_file(a: str, b: str) -> bool:
    try:
        return Path(a).resolve() == Path(b).resolve()
    except OSError:
        return False


def cmd_simulate(args) -> int:
    if _same_file(args.out, args.motion) or (args.truth and _same_file(args.truth, args.motion)):
        raise ImunavError("output file would overwrite the motion file")
    motion, duration, g_file = load_motion_toml(args.motion)
    g = args.g if args.g is not None else (g_file if g_file is not None else G0)
    if args.imu:
        model = ImuModel.load(args.imu)
        sig = _simulate_with_errors(motion, model, args.rate, duration, args.output, g, args.seed)
    else:
        sig = simulate_imu(motion, args.rate, duration, output=args.output, g=g)
    write_signals(args.out, sig)
    if args.truth:
        t = np.arange(int(round(duration * args.rate)) + 1) / args.rate
        write_states(args.truth, truth_states(motion, t))
    print(f"wrote {len(sig)} {sig.kind} rows at {args.rate:g} Hz to {args.out}")
    return 0


def _simulate_with_errors(motion, model, rate, duration, output, g, seed):
    k = model.decimation(rate)
    sim = simulate_imu(motion, rate * k, duration, output=output, g=g)
    rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(1)[0])
    gm, am, flags = measure(model, sim.gyro, sim.accel, output, rate * k, rng, k)
    t = sim.t[::k] if output == "rates" else sim.t[k - 1::k][: gm.shape[0]]
    if flags.any():
        print(f"warning: {int(flags.sum())} samples clipped at the sensor range", file=sys.stderr)
    return ImuSignals(t, gm, am, output, rate, g)


def cmd_assess(args) -> int:
    if args.runs < 1:
        raise ImunavError(f"--runs must be a positive integer, got {args.runs}")
    motion, duration, g_file = load_motion_toml(args.motion)
    model = ImuModel.load(args.imu)
    r = assess(motion, model, args.rate, args.runs, args.tolerance, seed=args.seed,
               duration=duration, scheduler=args.scheduler)
    print(format_verdict(r))
    if args.json:
        write_json(r, args.json)
    return 0


def cmd_navigate(args) -> int:
    for other in (args.signals, args.initial):
        if other and _same_file(args.out, other):
            raise ImunavError(f"--out {args.out} would overwrite an input file")
    if args.format == "imunav":
        if not args.initial:
            raise ImunavError("--initial TRUTH.csv is required for imunav signal files")
        sig = read_signals(args.signals, g=args.g)
    else:
        sig = _read_recording(args)
    if args.initial:
        st = read_states(args.initial)
        init = {"quaternion": st.quaternion, "velocity": st.velocity, "position": st.position}
    else:
        n = max(1, int(args.rest_window * sig.rate))
        init = {"quaternion": [level_attitude(sig.accel[:n], sig.g, tol=0.1)],
                "velocity": [np.zeros(3)], "position": [np.zeros(3)]}
    if args.algorithm and args.algorithm not in ALGORITHMS[sig.kind]:
        raise ImunavError(
            f"algorithm {args.algorithm!r} does not take {sig.kind}; choose one of "
            f"{', '.join(sorted(ALGORITHMS[sig.kind]))}"
        )
    res = navigate(sig, init["quaternion"][0], init["velocity"][0], init["position"][0],
                   algorithm=args.algorithm)
    write_states(args.out, res)
    print(f"wrote {len(res.t)} navigation rows ({res.algorithm}) to {args.out}")
    return 0


def _read_recording(args):
    path = Path(args.signals)
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
                                    rate=args.rate)
    if args.g is not None:
        rec.signals.g = args.g
    return rec.signals


def cmd_reproduce(args) -> int:
    records = reproduce_all(args.out)
    print(format_table(records))
    return 0


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return {"simulate": cmd_simulate, "navigate": cmd_navigate, "assess": cmd_assess,
                "reproduce": cmd_reproduce}[args.command](args)
    except ImunavError as exc:
        print(f"imunav: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # unreadable/unwritable paths
        print(f"imunav: error: {exc.strerror or exc}: {exc.filename}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
