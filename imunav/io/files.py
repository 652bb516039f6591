"""Files: MOTION.toml, the signal / truth / navigation CSV formats, and result JSON.

CSV headers (exactly):

- rates:       ``t,gx,gy,gz,ax,ay,az``        (s, rad/s, m/s²), one row per t_k, k = 0..N
- increments:  ``t,dthx,dthy,dthz,dvx,dvy,dvz`` (s, rad, m/s), one row per interval end, k = 1..N
- truth / nav: ``t,x,y,z,vx,vy,vz,qw,qx,qy,qz`` (s, m, m/s, scalar-first q_nb)
- on the WGS-84 Earth: ``t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz`` (s, degrees, degrees, m above the
  ellipsoid, NED m/s relative to the Earth, q_nb relative to the local NED frame); read back in
  radians (:attr:`~imunav.core.states.States.frame` ``"wgs84"``)
- poses:       ``t,x,y,z,qw,qx,qy,qz``          (s, m, scalar-first q_nb) — a motion from data;
  a truth CSV is accepted as poses too (its velocities are ignored)

Motions: ``MOTION.toml`` (analytic laws), a pose CSV, a waypoints TOML (``[[waypoint]]``
tables), or a catalog TOML (``catalog = "foot_walk"`` and the motion's parameters) —
:func:`load_motion` tells them apart by extension and content.

Numbers are written as the shortest decimal that reads back as the same double, so every value
survives a write and a read exactly. Files of any length are read and written in chunks
(:class:`SignalFile`, :class:`~imunav.io.csvio.CsvWriter`); input files are only ever read,
and outputs appear only when complete.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.io.csvio``.
"""

from __future__ import annotations

import json
import math
import numbers
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from imunav.core import units as U
from imunav.core.constants import G0
from imunav.core.resources import check_memory
from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import (
    ImunavError,
    check_gravity,
    check_positive,
    read_toml,
    show,
    unit_quaternions,
)
from imunav.io.csvio import (
    CsvWriter,
    OutputFile,
    atomic_write_text,
    first_row,
    read_chunks,
    read_header,
)
from imunav.motion.analytic import Motion
from imunav.motion.base import BaseMotion
from imunav.motion.catalog import CATALOG
from imunav.motion.trajectory import ORIENTATIONS, PoseMotion, WaypointMotion
from imunav.sensors.signals import ImuSignals

RATES_HEADER = ("t", "gx", "gy", "gz", "ax", "ay", "az")
INCREMENTS_HEADER = ("t", "dthx", "dthy", "dthz", "dvx", "dvy", "dvz")
STATE_HEADER = ("t", "x", "y", "z", "vx", "vy", "vz", "qw", "qx", "qy", "qz")
WGS84_STATE_HEADER = ("t", "lat", "lon", "alt", "vn", "ve", "vd", "qw", "qx", "qy", "qz")
#: The truth/navigation header of each navigation frame.
STATE_HEADERS = {"flat": STATE_HEADER, "wgs84": WGS84_STATE_HEADER}
POSE_HEADER = ("t", "x", "y", "z", "qw", "qx", "qy", "qz")
HEADERS = {"rates": RATES_HEADER, "increments": INCREMENTS_HEADER}

#: Approximate bytes per written row (disk-space checks before long runs).
ROW_BYTES = {"signals": 170, "states": 260}

#: Largest relative departure of a sample interval from the file's mean interval.
SPACING_TOLERANCE = 1e-6


def load_motion_toml(path: str | Path) -> tuple[Motion, float, float | None]:
    """Read a ``MOTION.toml`` of analytic laws.

    Top-level ``duration`` (s, required, a number > 0) and optional ``g`` (m/s², > 0); tables
    ``[position]`` (``x``, ``y``, ``z``: m, NED) and ``[attitude]`` (``yaw``, ``pitch``,
    ``roll``: rad, Z-Y-X), each a law in ``t`` (see :mod:`imunav.motion.laws`); missing entries
    are 0.

    Parameters
    ----------
    path : str or Path
        The TOML file; its stem names the motion.

    Returns
    -------
    motion : Motion
        The analytic motion.
    duration : float
        Its duration (s).
    g : float or None
        The gravity magnitude (m/s²) the file sets, or None.

    Raises
    ------
    ImunavError
        If the file cannot be read or is not TOML, ``duration`` is missing or not a finite
        number > 0, ``g`` is not a finite number > 0, or a table, key or law is refused by
        :meth:`Motion.from_dict <imunav.motion.analytic.Motion.from_dict>`; the message starts
        with the path.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "turn.toml"
    >>> _ = path.write_text('duration = 2.0\\n[attitude]\\nyaw = "0.5*t"\\n')
    >>> motion, duration, g = load_motion_toml(path)
    >>> duration, g, motion.name
    (2.0, None, 'turn')
    >>> tmp.cleanup()
    """
    path = Path(path)
    spec = read_toml(path, "motion file")
    if "duration" not in spec:
        raise ImunavError(f"{path}: top-level 'duration' (s) is required")
    duration = check_positive(spec["duration"], f"{path}: duration")
    g = spec.get("g")
    if g is not None:
        g = check_positive(g, f"{path}: g")
    return Motion.from_dict(spec, name=path.stem), duration, g


def load_motion(path: str | Path, *, smoothing: float | None = None,
                attitude_smoothing: float | None = None) -> tuple[BaseMotion, float, float | None]:
    """Read any motion file, telling the formats apart by extension and content.

    ``*.csv``: poses (header ``t,x,y,z,qw,qx,qy,qz``, or a truth CSV) → a
    :class:`~imunav.motion.trajectory.PoseMotion` (:func:`load_poses`). ``*.toml`` with
    ``[[waypoint]]`` tables → a :class:`~imunav.motion.trajectory.WaypointMotion`
    (:func:`load_waypoints`); a TOML with
    ``catalog = "<name>"`` → that motion of :data:`imunav.motion.catalog.CATALOG`
    (:func:`load_catalog`); any other TOML → analytic laws (:func:`load_motion_toml`). Times
    of data motions start at the first pose or waypoint (the motion's t = 0 is that time).

    Parameters
    ----------
    path : str or Path
        The motion file.
    smoothing : float, optional
        Pose CSVs only: the position noise level (m) of a smoothing spline; default
        interpolating.
    attitude_smoothing : float, optional
        Pose CSVs only: the attitude noise level (rad) of a smoothing spline.

    Returns
    -------
    motion : BaseMotion
        The motion.
    duration : float
        Its duration (s).
    g : float or None
        The gravity magnitude (m/s²) the file sets (never for a pose CSV), or None.

    Raises
    ------
    ImunavError
        If ``smoothing`` or ``attitude_smoothing`` is given for a TOML file, or for the
        reasons of the reader the file goes to.
    """
    path = Path(path)
    if path.suffix.lower() == ".csv":
        return load_poses(path, smoothing=smoothing, attitude_smoothing=attitude_smoothing)
    if smoothing is not None or attitude_smoothing is not None:
        raise ImunavError("smoothing and attitude_smoothing apply to pose CSV files only",
                          argument=("smoothing", "attitude_smoothing"))
    spec = read_toml(path, "motion file")
    if "waypoint" in spec:
        return load_waypoints(path, spec)
    if "catalog" in spec:
        return load_catalog(path, spec)
    return load_motion_toml(path)


#: Keys of a catalog motion file besides the motion's own parameters.
CATALOG_TOP = ("catalog", "duration", "g", "name")


def load_catalog(path: str | Path, spec: dict | None = None
                 ) -> tuple[BaseMotion, float, float | None]:
    """A catalog motion file: ``catalog = "<name>"`` (one of
    :data:`imunav.motion.catalog.CATALOG`, e.g. ``"foot_walk"``), ``duration`` (s, required),
    optional ``g`` (m/s²) and ``name``, and any of the motion's own parameters (numbers in
    their units; an angle in radians or as a string with its unit, ``"90 deg"``).

    Parameters
    ----------
    path : str or Path
    spec : dict, optional
        The file's table, if already read.

    Returns
    -------
    tuple
        ``(motion, duration, g or None)``.

    Raises
    ------
    ImunavError
        For an unknown catalog name or key, a missing or non-positive duration, a value of the
        wrong type, or one the motion refuses (each message starts with the file name).
    """
    path = Path(path)
    spec = read_toml(path, "motion file") if spec is None else spec
    name = spec["catalog"]
    if not isinstance(name, str) or name not in CATALOG:
        raise ImunavError(f"{path}: catalog must be one of {', '.join(CATALOG)}, got {show(name)}")
    factory, params = CATALOG[name]
    bad = sorted(set(spec) - set(CATALOG_TOP) - set(params))
    if bad:
        allowed = ", ".join(list(CATALOG_TOP) + list(params))
        raise ImunavError(f"{path}: unknown key(s) {', '.join(bad)} for catalog = {name!r}; "
                          f"expected {allowed}")
    if "duration" not in spec:
        raise ImunavError(f"{path}: top-level 'duration' (s) is required")
    duration = check_positive(spec["duration"], f"{path}: duration")
    g = spec.get("g")
    if g is not None:
        g = check_positive(g, f"{path}: g")
    kwargs = {key: _catalog_value(path, key, spec[key], unit)
              for key, unit in params.items() if key in spec}
    try:
        motion = factory(duration=duration, **kwargs)
    except ImunavError as exc:
        raise ImunavError(f"{path}: {exc}") from None
    label = spec.get("name", path.stem)
    if not isinstance(label, str):
        raise ImunavError(f"{path}: name must be a string, got {show(label)}")
    motion.name = label
    return motion, duration, g


def _catalog_value(path: Path, key: str, value, unit: str):
    """One parameter of a catalog motion file in the factory's units."""
    if unit == "count":
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise ImunavError(f"{path}: {key} must be a whole number, got {show(value)}")
        return int(value)
    if unit == "angle" and isinstance(value, str):
        text = value.strip()
        sign = -1.0 if text.startswith("-") else 1.0
        return sign * U.convert(text.lstrip("+-"), U.ANGLE, f"{path}: {key}", "angle")
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        what = "radians, or a string with its unit (\"90 deg\")" if unit == "angle" else unit
        raise ImunavError(f"{path}: {key} must be a finite number ({what}), got {show(value)}")
    return float(value)


def load_poses(path: str | Path, *, smoothing: float | None = None,
               attitude_smoothing: float | None = None) -> tuple[BaseMotion, float, None]:
    """Read a pose CSV into a motion from data.

    Parameters
    ----------
    path : str or Path
        A CSV with header ``t,x,y,z,qw,qx,qy,qz`` (s, m NED, scalar-first ``q_nb``), or a
        truth CSV (``t,x,y,z,vx,vy,vz,qw,qx,qy,qz``) whose velocities are ignored.
    smoothing : float, optional
        Position noise level (m) for a smoothing spline; default interpolating.
    attitude_smoothing : float, optional
        Attitude noise level (rad) for a smoothing spline; default interpolating.

    Returns
    -------
    motion : PoseMotion
        The motion (:class:`~imunav.motion.trajectory.PoseMotion`), t = 0 at the first pose.
    duration : float
        Its duration (s).
    g : None
        A pose file sets no gravity.

    Raises
    ------
    ImunavError
        If the file is missing, not UTF-8 or empty; its header is neither of the two; a row
        is malformed or not finite (with its line); the data would not fit in memory; or
        :class:`~imunav.motion.trajectory.PoseMotion` refuses the poses (too few for a
        quintic spline, times not increasing, a quaternion not of unit norm, a smoothing level
        that is not a positive number). Every message starts with the path.
    """
    path = Path(path)
    header = read_header(path, "pose")
    if header not in (POSE_HEADER, STATE_HEADER):
        raise ImunavError(f"{path}: unrecognised header {','.join(header)!r}; expected "
                          f"{','.join(POSE_HEADER)!r} (poses) or {','.join(STATE_HEADER)!r} "
                          "(a truth CSV)")
    check_memory(8 * 4 * len(header) * max(path.stat().st_size // 40, 1), "the pose file")
    rows = [b for b in read_chunks(path, header, "pose")]
    data = np.concatenate(rows) if rows else np.zeros((0, len(header)))
    q = data[:, -4:]
    try:
        motion = PoseMotion(data[:, 0], data[:, 1:4], q, smoothing=smoothing,
                            attitude_smoothing=attitude_smoothing, name=path.stem,
                            row_name=f"{path}, line", first_row=2)
    except ImunavError as exc:
        msg = str(exc)
        raise ImunavError(msg if msg.startswith(str(path)) else f"{path}: {msg}",
                          argument=exc.argument) from None
    return motion, motion.duration, None


#: Keys of a waypoints TOML: top level, and each ``[[waypoint]]``.
WAYPOINT_TOP = {"waypoint", "orientation", "name", "g"}
WAYPOINT_KEYS = {"t", "x", "y", "z", "yaw", "pitch", "roll"}
WAYPOINT_UNITS = {"t": "s", "x": "m", "y": "m", "z": "m", "yaw": "rad", "pitch": "rad",
                  "roll": "rad"}


def load_waypoints(path: str | Path, spec: dict | None = None
                   ) -> tuple[BaseMotion, float, float | None]:
    """Read a waypoints TOML into a route through the waypoints.

    ``[[waypoint]]`` tables with ``t``, ``x``, ``y``, ``z`` (s, m, NED) and optional ``yaw``,
    ``pitch``, ``roll`` (rad), plus top-level ``orientation = "given" | "follow"`` (default
    given) and optional ``g`` (m/s²) and ``name``.

    Parameters
    ----------
    path : str or Path
        The TOML file (named in messages; its stem names the motion unless ``name`` is set).
    spec : dict, optional
        The file's parsed table, if already read; default read ``path``.

    Returns
    -------
    motion : WaypointMotion
        The route (:class:`~imunav.motion.trajectory.WaypointMotion`), t = 0 at the first
        waypoint.
    duration : float
        Its duration (s).
    g : float or None
        The gravity magnitude (m/s²) the file sets, or None.

    Raises
    ------
    ImunavError
        If the file cannot be read; it has an unknown top-level key, an ``orientation`` other
        than ``"given"`` or ``"follow"``, fewer than 2 waypoints, or a ``g`` that is not a
        finite number > 0; a waypoint has an unknown or missing key, a value that is not a
        finite number, attitude with ``orientation = "follow"``, or a time not after the
        previous one; or the route cannot be built. Messages start with the path.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "route.toml"
    >>> _ = path.write_text("[[waypoint]]\\nt = 0\\nx = 0\\ny = 0\\nz = 0\\n"
    ...                     "[[waypoint]]\\nt = 10\\nx = 50\\ny = 0\\nz = 0\\n")
    >>> motion, duration, g = load_waypoints(path)
    >>> duration, g
    (10.0, None)
    >>> tmp.cleanup()
    """
    path = Path(path)
    spec = read_toml(path, "waypoints file") if spec is None else spec
    bad = sorted(set(spec) - WAYPOINT_TOP)
    if bad:
        raise ImunavError(f"{path}: unknown top-level key(s) {', '.join(bad)}; expected "
                          f"{', '.join(sorted(WAYPOINT_TOP))}")
    orientation = spec.get("orientation", "given")
    if orientation not in ORIENTATIONS:
        raise ImunavError(f"{path}: orientation must be \"given\" or \"follow\", got "
                          f"{orientation!r}")
    wps = spec["waypoint"]
    if not isinstance(wps, list) or not all(isinstance(w, dict) for w in wps):
        raise ImunavError(f"{path}: 'waypoint' must be [[waypoint]] tables")
    if len(wps) < 2:
        raise ImunavError(f"{path}: {len(wps)} waypoint(s); a route needs at least 2")
    t, p, a = [], [], []
    for n, w in enumerate(wps, start=1):
        bad = sorted(set(w) - WAYPOINT_KEYS)
        if bad:
            raise ImunavError(f"{path}: waypoint {n}: unknown key(s) {', '.join(bad)}; expected "
                              f"{', '.join(sorted(WAYPOINT_KEYS))}")
        for key in ("t", "x", "y", "z"):
            if key not in w:
                raise ImunavError(f"{path}: waypoint {n}: missing {key!r}")
        if orientation == "follow" and set(w) & {"yaw", "pitch", "roll"}:
            raise ImunavError(f"{path}: waypoint {n}: orientation = \"follow\" derives yaw, "
                              "pitch and roll from the path; remove them or use \"given\"")
        vals = {}
        for key in WAYPOINT_KEYS & set(w):
            v = w[key]
            if isinstance(v, bool) or not isinstance(v, int | float) or not np.isfinite(v):
                raise ImunavError(f"{path}: waypoint {n}: {key} must be a finite number "
                                  f"({WAYPOINT_UNITS[key]}), got {v!r}")
            vals[key] = float(v)
        if n > 1 and vals["t"] <= t[-1]:
            raise ImunavError(f"{path}: waypoint {n}: t = {vals['t']:g} is not after waypoint "
                              f"{n - 1}'s t = {t[-1]:g} (times must strictly increase)")
        t.append(vals["t"])
        p.append([vals["x"], vals["y"], vals["z"]])
        a.append([vals.get("yaw", 0.0), vals.get("pitch", 0.0), vals.get("roll", 0.0)])
    g = spec.get("g")
    g = None if g is None else check_positive(g, f"{path}: g")
    try:
        motion = WaypointMotion(t, p, a if orientation == "given" else None,
                                orientation=orientation, g=g or G0,
                                name=str(spec.get("name", path.stem)))
    except ImunavError as exc:
        raise ImunavError(f"{path}: {exc}") from None
    return motion, motion.duration, g


class SignalFile:
    """A rates or increments CSV, read chunk by chunk.

    The kind comes from the header; the sample rate from the time column of the first chunk
    (at least two rows); every later row is checked as it is read: strictly increasing times,
    uniformly spaced (to 1e-6 of the interval). :meth:`chunks` yields ``(t, gyro, accel)``.

    Parameters
    ----------
    path : str or Path
        A CSV with header ``t,gx,gy,gz,ax,ay,az`` (s, rad/s, m/s²) or
        ``t,dthx,dthy,dthz,dvx,dvy,dvz`` (s, rad, m/s).
    g : float, optional
        Gravity magnitude (m/s²) the signals were made with; default G0.

    Attributes
    ----------
    kind : {"rates", "increments"}
        From the header.
    rate : float
        Sample rate (Hz), inferred from the first rows (to 12 significant digits).
    dt : float
        ``1/rate`` (s).
    t_first : float
        Time of the first row (s).
    rows : int
        Data rows read so far.

    Raises
    ------
    ImunavError
        If the file is missing, not UTF-8 or empty; its header is neither; it has fewer than
        2 data rows; the first times do not increase; or ``g`` is not a valid gravity.
        :meth:`chunks` raises later for a malformed row or times not uniformly spaced, naming
        the path and the row.
    """

    def __init__(self, path: str | Path, g: float | None = None):
        self.path = Path(path)
        header = read_header(self.path, "signals")
        self.kind = next((k for k, h in HEADERS.items() if header == h), None)
        if self.kind is None:
            raise ImunavError(
                f"{self.path}: unrecognised header {','.join(header)!r}; expected "
                f"{','.join(RATES_HEADER)!r} (rates) or {','.join(INCREMENTS_HEADER)!r} "
                "(increments)")
        self.g = G0 if g is None else check_gravity(g)
        self._it = read_chunks(self.path, header, "signals")
        first = []
        n = 0
        for data in self._it:
            first.append(data)
            n += len(data)
            if n >= 2:
                break
        if n == 0:
            raise ImunavError(f"signals file {self.path} has a header but no data rows")
        if n < 2:
            raise ImunavError(f"{self.path}: need at least 2 rows to infer the sample rate")
        self._first = np.concatenate(first)
        t = self._first[:, 0]
        self.t_first = float(t[0])
        # the interval of the first rows: the median of their first thousand steps, then the
        # mean over the leading run that keeps it (a gap later in the first chunk must not
        # enter the estimate: a 100 s gap at row 10 000 was reported at row 2)
        d = np.diff(t[:1001])
        med = float(np.median(d))
        off = np.nonzero(~(np.abs(d - med) <= 1e-3 * abs(med)))[0]
        m = int(off[0]) if off.size else d.size
        dt = (t[m] - t[0]) / m if m else med
        if not dt > 0:
            raise ImunavError(f"{self.path}: column t must be strictly increasing")
        # the times of a file imunav wrote are t0 + k/rate: the estimate carries rounding that
        # 12 significant digits remove (0.05 s, not 0.05000000000000000694)
        self.rate = float(f"{1.0 / dt:.12g}")
        self.dt = 1.0 / self.rate
        self._last_t = None
        self.rows = 0

    @property
    def t0(self) -> float:
        """Start time (s) of the navigation: the first sample, or for increments the start of
        the first interval."""
        return self.t_first if self.kind == "rates" else self.t_first - self.dt

    def _check(self, t: FloatArray) -> None:
        prev = self._last_t
        tt = t if prev is None else np.concatenate([[prev], t])
        d = np.diff(tt)
        bad = (d <= 0) | (np.abs(d - self.dt) > SPACING_TOLERANCE * self.dt)
        if bad.any():
            i = int(np.argmax(bad))
            row = self.rows + i + (2 if prev is None else 1)          # 1-based data row
            what = ("strictly increasing" if d[i] <= 0 else
                    f"uniformly spaced (every {self.dt:.9g} s, as in the first rows)")
            raise ImunavError(f"{self.path}: column t must be {what}; data row {row} has "
                              f"t = {tt[i + 1]:.9g} s after {tt[i]:.9g} s")

    def chunks(self) -> Iterator[tuple[FloatArray, FloatArray, FloatArray]]:
        """The whole file in chunks, checked as they are read.

        Yields
        ------
        t : ndarray, shape (n,)
            Sample times (s); interval ends for increments.
        gyro : ndarray, shape (n, 3)
            ω_b (rad/s) or Δθ (rad).
        accel : ndarray, shape (n, 3)
            f_b (m/s²) or Δv (m/s).

        Raises
        ------
        ImunavError
            For a malformed or non-finite row, or times not strictly increasing or not
            uniformly spaced (the message names the path and the row).
        """
        for data in self._data():
            yield data[:, 0], data[:, 1:4], data[:, 4:7]

    def _data(self) -> Iterator[np.ndarray]:
        first, self._first = self._first, None
        for data in ([first] if first is not None else []):
            self._check(data[:, 0])
            self._last_t, self.rows = data[-1, 0], self.rows + len(data)
            yield data
        for data in self._it:
            self._check(data[:, 0])
            self._last_t, self.rows = data[-1, 0], self.rows + len(data)
            yield data


def read_signals(path: str | Path, g: float | None = None) -> ImuSignals:
    """Read a whole rates or increments CSV into memory.

    Parameters
    ----------
    path : str or Path
        The CSV (see :class:`SignalFile` for the headers and checks).
    g : float, optional
        Gravity magnitude (m/s²) the signals were made with; default G0.

    Returns
    -------
    ImuSignals
        The signals, their kind from the header and their rate from the times.

    Raises
    ------
    ImunavError
        For the reasons of :class:`SignalFile`, or if the file would not fit in memory
        (``imunav navigate`` streams files of any length).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> from imunav.sensors.signals import ImuSignals
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "imu.csv"
    >>> sig = ImuSignals(t=np.arange(3) / 100, gyro=np.zeros((3, 3)),
    ...                  accel=np.tile([0.0, 0.0, -9.80665], (3, 1)), kind="rates", rate=100)
    >>> write_signals(path, sig)
    >>> back = read_signals(path)
    >>> back.kind, back.rate, bool((back.accel == sig.accel).all())
    ('rates', 100.0, True)
    >>> tmp.cleanup()
    """
    f = SignalFile(path, g)
    check_memory(4 * Path(path).stat().st_size, f"reading {path} into memory",
                 "imunav navigate streams files of any length")
    parts = list(f.chunks())
    t, gyro, accel = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return ImuSignals(t, gyro, accel, f.kind, f.rate, f.g)


def _states_header(path: Path) -> tuple[tuple[str, ...], str]:
    header = read_header(path, "state")
    for frame, h in STATE_HEADERS.items():
        if header == h:
            return header, frame
    raise ImunavError(f"{path}: unrecognised header {','.join(header)!r}; expected "
                      f"{','.join(STATE_HEADER)!r} (flat frame) or {','.join(WGS84_STATE_HEADER)!r} "
                      "(WGS-84)")


def _states(path: Path, data: np.ndarray, frame: str = "flat") -> States:
    q = unit_quaternions(data[:, 7:11], f"{path}, line", 2)
    t = data[:, 0]
    if t.size > 1 and np.any(np.diff(t) <= 0):
        i = int(np.argmax(np.diff(t) <= 0))
        raise ImunavError(f"{path}: column t must be strictly increasing (data row {i + 2})")
    p = data[:, 1:4]
    if frame == "wgs84":
        bad = np.abs(p[:, 0]) > 90
        if bad.any():
            i = int(np.argmax(bad))
            raise ImunavError(f"{path}: column lat must be within ±90° (degrees), got "
                              f"{p[i, 0]:.10g} in data row {i + 1}")
        p = np.column_stack([np.radians(p[:, 0]), np.radians(p[:, 1]), p[:, 2]])
    return States(t, p, data[:, 4:7], q, frame=frame)


def read_initial_state(path: str | Path) -> States:
    """The first data row of a truth/navigation CSV (the rest of the file is not read).

    Parameters
    ----------
    path : str or Path
        A CSV with header ``t,x,y,z,vx,vy,vz,qw,qx,qy,qz`` (flat frame: s, m, m/s NED,
        ``q_nb``) or ``t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz`` (WGS-84: degrees, m, m/s).

    Returns
    -------
    States
        One state, its ``frame`` from the header (WGS-84 latitude and longitude returned in
        radians).

    Raises
    ------
    ImunavError
        If the file is missing or empty, its header is neither, it has no data rows, the row
        is malformed or not finite, the quaternion is zero, or a latitude is beyond ±90°.
    """
    path = Path(path)
    header, frame = _states_header(path)
    row = first_row(path, header, "state")
    if row is None:
        raise ImunavError(f"state file {path} has a header but no data rows")
    return _states(path, row[None], frame)


def read_states(path: str | Path) -> States:
    """Read a whole truth/navigation CSV (either frame, see :func:`read_initial_state`).

    Parameters
    ----------
    path : str or Path
        The CSV.

    Returns
    -------
    States
        Every row, positions in m (flat) or ``[lat, lon, h]`` in rad, rad, m (WGS-84).

    Raises
    ------
    ImunavError
        For the reasons of :func:`read_initial_state`, or if the times do not strictly
        increase (with the row).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from imunav.motion import Motion
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "truth.csv"
    >>> write_states(path, Motion(x="2*t").states([0.0, 0.5, 1.0]))
    >>> read_states(path).position[:, 0]
    array([0., 1., 2.])
    >>> tmp.cleanup()
    """
    path = Path(path)
    header, frame = _states_header(path)
    parts = list(read_chunks(path, header, "state"))
    if not parts:
        raise ImunavError(f"state file {path} has a header but no data rows")
    return _states(path, np.concatenate(parts), frame)


def signals_writer(path: str | Path, kind: str) -> CsvWriter:
    """A :class:`CsvWriter` for ``kind`` signals; write ``[t, gyro, accel]`` chunks."""
    return CsvWriter(path, HEADERS[kind])


def states_writer(path: str | Path, frame: str = "flat") -> CsvWriter:
    """A :class:`CsvWriter` for states of ``frame``; write :func:`state_columns` chunks
    (``[t, position, velocity, quaternion]`` in the flat frame)."""
    return CsvWriter(path, STATE_HEADERS[frame])


def state_columns(states: States) -> list[FloatArray]:
    """The columns of a truth/navigation CSV for ``states``, in the file's units: latitude and
    longitude in degrees on the WGS-84 Earth (written to the last bit, as every double: up to
    17 significant digits, a nanometre of latitude).

    Parameters
    ----------
    states : States

    Returns
    -------
    list of ndarray
        ``[t, position, velocity, quaternion]`` for :meth:`CsvWriter.write`.
    """
    p = states.position
    if states.frame == "wgs84":
        p = np.column_stack([np.degrees(p[:, 0]), np.degrees(p[:, 1]), p[:, 2]])
    return [states.t, p, states.velocity, states.quaternion]


def write_signals(path: str | Path, sig: ImuSignals) -> None:
    """Write rates or increments with the exact header of their kind.

    The file appears only when complete (a temporary file renamed at the end); every number
    is the shortest decimal that reads back as the same double.

    Parameters
    ----------
    path : str or Path
        The output CSV (its directory must exist).
    sig : ImuSignals
        The signals: ``t,gx,gy,gz,ax,ay,az`` for rates, ``t,dthx,dthy,dthz,dvx,dvy,dvz`` for
        increments.
    """
    with signals_writer(path, sig.kind) as w:
        w.write([sig.t, sig.gyro, sig.accel])


def write_states(path: str | Path, states: States) -> None:
    """Write a truth or navigation CSV, the header of its frame.

    ``t,x,y,z,vx,vy,vz,qw,qx,qy,qz`` (s, m, m/s, NED, ``q_nb``), or on the WGS-84 Earth
    ``t,lat,lon,alt,vn,ve,vd,qw,qx,qy,qz`` (latitude and longitude written in degrees). The
    file appears only when complete.

    Parameters
    ----------
    path : str or Path
        The output CSV (its directory must exist).
    states : States
        The states to write.
    """
    with states_writer(path, states.frame) as w:
        w.write(state_columns(states))


def write_json(r: dict, path: str | Path) -> None:
    """Write a result dictionary (``imunav assess --json``) as indented JSON.

    The file appears only when complete (a temporary file renamed at the end).

    Parameters
    ----------
    r : dict
        JSON-serialisable results (numbers, strings, lists, dicts).
    path : str or Path
        The output file (its directory must exist).
    """
    atomic_write_text(path, json.dumps(r, indent=1) + "\n")


def write_text(path: str | Path, text: str) -> None:
    """Write a text file through a temporary file renamed at the end."""
    atomic_write_text(path, text)


#: The metadata keys matplotlib fills with a date or its version, emptied per format.
NEUTRAL_METADATA = {
    "png": {"Software": None},
    "pdf": {"Creator": None, "Producer": None, "CreationDate": None},
    "svg": {"Creator": None, "Date": None},
    "eps": {"Creator": None, "CreationDate": None},
    "ps": {"Creator": None, "CreationDate": None},
}


def save_figure(fig, path: str | Path, **kw) -> None:
    """``fig.savefig`` as :class:`~imunav.io.csvio.OutputFile` writes (a regular file through a
    temporary file renamed at the end; a device or FIFO directly); the format from the suffix
    (:func:`figure_format`). The file carries no date and no software version
    (:data:`NEUTRAL_METADATA`): the same figure gives the same bytes on every run."""
    fmt = figure_format(path)
    kw.setdefault("metadata", NEUTRAL_METADATA.get(fmt))
    import matplotlib

    out = OutputFile(path)
    try:
        with matplotlib.rc_context({"svg.hashsalt": "imunav"}):   # SVG ids: fixed, not random
            fig.savefig(out.fh, format=fmt, **kw)
    except BaseException:
        out.abort()
        raise
    out.commit()


def figure_format(path: str | Path, what: str = "figure") -> str:
    """The image format of a figure path, from its suffix (``png`` without one), or an
    ImunavError naming the formats matplotlib writes — checked before any work is done.

    Parameters
    ----------
    path : str or Path
    what : str
        The option that names it, for the message.

    Returns
    -------
    str
    """
    from matplotlib.backend_bases import FigureCanvasBase

    fmt = Path(path).suffix.lower().lstrip(".") or "png"
    known = FigureCanvasBase.get_supported_filetypes()
    if fmt not in known:
        raise ImunavError(f"{what} {path}: unknown image format {fmt!r}; use one of "
                          + ", ".join(sorted(known)))
    return fmt
