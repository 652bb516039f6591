"""Files: MOTION.toml, and the signal / truth / navigation CSV formats.

CSV headers (exactly):

- rates:       ``t,gx,gy,gz,ax,ay,az``        (s, rad/s, m/s²), one row per t_k, k = 0..N
- increments:  ``t,dthx,dthy,dthz,dvx,dvy,dvz`` (s, rad, m/s), one row per interval end, k = 1..N
- truth / nav: ``t,x,y,z,vx,vy,vz,qw,qx,qy,qz`` (s, m, m/s, scalar-first q_nb)

Numbers are written with 17 significant digits so a double survives the round trip exactly.
Input files are only ever read.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import ImunavError, check_positive, check_time, read_toml
from imunav.motion.analytic import Motion
from imunav.sensors.signals import ImuSignals

RATES_HEADER = ("t", "gx", "gy", "gz", "ax", "ay", "az")
INCREMENTS_HEADER = ("t", "dthx", "dthy", "dthz", "dvx", "dvy", "dvz")
STATE_HEADER = ("t", "x", "y", "z", "vx", "vy", "vz", "qw", "qx", "qy", "qz")
HEADERS = {"rates": RATES_HEADER, "increments": INCREMENTS_HEADER}


def load_motion_toml(path: str | Path) -> tuple[Motion, float, float | None]:
    """Read ``MOTION.toml`` → ``(motion, duration, g or None)``.

    Top-level ``duration`` (s, required, > 0) and optional ``g`` (m/s²); tables
    ``[position]`` (``x``, ``y``, ``z``) and ``[attitude]`` (``yaw``, ``pitch``, ``roll``),
    each a SymPy expression string in ``t``; missing entries are 0.
    """
    path = Path(path)
    spec = read_toml(path, "motion file")
    if "duration" not in spec:
        raise ImunavError(f"{path}: top-level 'duration' (s) is required")
    duration = check_positive(spec["duration"], "duration")
    g = spec.get("g")
    if g is not None:
        g = check_positive(g, "g")
    motion = Motion.from_dict(spec, name=path.stem)
    return motion, duration, g


def _write(path: str | Path, header, columns: list[FloatArray]) -> None:
    data = np.column_stack(columns)
    path = Path(path)
    with path.open("w", newline="") as fh:
        fh.write(",".join(header) + "\n")
        # '%.17g' round-trips every double exactly.
        np.savetxt(fh, data, fmt="%.17g", delimiter=",")


def write_signals(path: str | Path, sig: ImuSignals) -> None:
    """Write rates or increments with the exact header of their kind."""
    _write(path, HEADERS[sig.kind], [sig.t, sig.gyro, sig.accel])


def write_states(path: str | Path, states: States) -> None:
    """Write a truth or navigation file ``t,x,y,z,vx,vy,vz,qw,qx,qy,qz``."""
    _write(path, STATE_HEADER, [states.t, states.position, states.velocity, states.quaternion])


def _read_csv(path: str | Path, what: str) -> tuple[tuple[str, ...], FloatArray]:
    path = Path(path)
    if not path.is_file():
        raise ImunavError(f"{what} file not found: {path}")
    with path.open(newline="") as fh:
        reader = csv.reader(fh)
        try:
            header = tuple(h.strip() for h in next(reader))
        except StopIteration:
            raise ImunavError(f"{what} file {path} is empty") from None
        rows = []
        for i, row in enumerate(reader, start=2):
            if not row or all(not c.strip() for c in row):
                continue
            if len(row) != len(header):
                raise ImunavError(
                    f"{path}, line {i}: expected {len(header)} columns, got {len(row)}"
                )
            try:
                rows.append([float(c) for c in row])
            except ValueError:
                raise ImunavError(f"{path}, line {i}: non-numeric value in {row}") from None
    if not rows:
        raise ImunavError(f"{what} file {path} has a header but no data rows")
    data = np.array(rows, dtype=np.float64)
    if not np.all(np.isfinite(data)):
        r, c = np.argwhere(~np.isfinite(data))[0]
        raise ImunavError(f"{path}, line {r + 2}, column '{header[c]}': NaN or inf")
    return header, data


def read_signals(path: str | Path, g: float | None = None) -> ImuSignals:
    """Read a rates or increments CSV; the kind is read from the header.

    The sample rate is inferred from the time column, which must be strictly increasing and
    uniformly spaced (to 1e-6 relative).
    """
    header, data = _read_csv(path, "signals")
    kind = next((k for k, h in HEADERS.items() if header == h), None)
    if kind is None:
        raise ImunavError(
            f"{path}: unrecognised header {','.join(header)!r}; expected "
            f"{','.join(RATES_HEADER)!r} (rates) or {','.join(INCREMENTS_HEADER)!r} (increments)"
        )
    t = check_time(data[:, 0], f"{path}: column t")
    if t.size < 2:
        raise ImunavError(f"{path}: need at least 2 rows to infer the sample rate")
    d = np.diff(t)
    dt = (t[-1] - t[0]) / (t.size - 1)
    if np.max(np.abs(d - dt)) > 1e-6 * dt:
        raise ImunavError(f"{path}: time column is not uniformly spaced (needed to infer the rate)")
    return ImuSignals(t, data[:, 1:4], data[:, 4:7], kind, 1.0 / dt, G0 if g is None else g)


def read_states(path: str | Path) -> States:
    """Read a truth/navigation CSV."""
    header, data = _read_csv(path, "state")
    if header != STATE_HEADER:
        raise ImunavError(
            f"{path}: unrecognised header {','.join(header)!r}; expected {','.join(STATE_HEADER)!r}"
        )
    t = check_time(data[:, 0], f"{path}: column t")
    q = data[:, 7:11]
    if np.any(np.linalg.norm(q, axis=1) < 1e-12):
        raise ImunavError(f"{path}: quaternion columns qw,qx,qy,qz must not be all zero")
    return States(t, data[:, 1:4], data[:, 4:7], q)


def write_json(r: dict, path: str | Path) -> None:
    """Write a result dictionary (``imunav assess --json``) as indented JSON."""
    with open(path, "w") as fh:
        json.dump(r, fh, indent=1)
        fh.write("\n")
