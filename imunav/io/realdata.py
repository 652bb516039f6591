"""Readers for real IMU recordings: x-io x-IMU3, x-io x-IMU, and generic CSV files (with or
without a header, timed by an RTKLIB time-tag file if there is one).

Every reader converts to imunav's SI units at the boundary (rad/s, m/s², s) and returns a
:class:`Recording` whose ``signals`` are ordinary rate :class:`~imunav.ImuSignals`. The
device's onboard orientation, where present, is returned raw (``device_t``, ``device_q``):
its convention is checked against the gyro by
:func:`imunav.analysis.recordings.device_quaternion_convention` (and in
``notebooks/07_real_imu_data.ipynb``). The analyses of recordings live in
:mod:`imunav.analysis.recordings`: this module only reads.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.io.csvio``, ``imunav.io.rtklib``.
"""

from __future__ import annotations

import csv
import warnings
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from imunav.core import units as U
from imunav.core.constants import DEG, G0
from imunav.core.rotations import FloatArray
from imunav.core.units import factor
from imunav.core.validation import ImunavError, check_positive
from imunav.io.csvio import read_chunks, read_header
from imunav.io.rtklib import TimeTag, imu_times, read_tag
from imunav.sensors.signals import ImuSignals


@dataclass
class Recording:
    """A real recording: its IMU signals (rates, SI) and the device's own output.

    Attributes
    ----------
    signals : ImuSignals
        Rate samples (rad/s, m/s²) at the recording's rate.
    device_t : ndarray, shape (M,), optional
        Times (s) of the device's onboard orientation, on the signals' clock.
    device_q : ndarray, shape (M, 4), optional
        That orientation as stored by the device (its element order and meaning are the
        reader's to state; see :func:`~imunav.analysis.recordings.device_as_q_nb`).
    meta : dict
        The device name, the path, packet numbers.
    """

    signals: ImuSignals
    device_t: FloatArray | None = None
    device_q: FloatArray | None = None   # raw, as stored by the device (see its reader)
    meta: dict = field(default_factory=dict)


def data_path(*parts: str) -> Path:
    """Path of a file shipped in ``imunav/data`` (e.g. ``data_path("real_imu", "xio_ximu3")``)."""
    return Path(str(resources.files("imunav") / "data" / Path(*parts)))


def _read_table(path: Path) -> tuple[list[str], np.ndarray]:
    """A numeric CSV with a header (every value a finite number; errors name line and column)."""
    header = read_header(Path(path), "recording")
    names = _first_line(Path(path))             # the header as CSV: quoted names unquoted
    header = tuple(names) if len(names) == len(header) else header
    parts = list(read_chunks(path, header, "recording"))
    data = np.concatenate(parts) if parts else np.empty((0, len(header)))
    if len(data) < 2:
        raise ImunavError(f"{path}: needs a header and at least 2 data rows")
    return list(header), data


def _uniform_rate(t: FloatArray, path, jitter: float = 0.05) -> float:
    d = np.diff(t)
    if np.any(d <= 0):
        i = int(np.argmax(d <= 0))
        raise ImunavError(f"{path}: time must be strictly increasing (row {i + 3})")
    med = float(np.median(d))
    if np.max(np.abs(d - med)) > jitter * med:
        raise ImunavError(f"{path}: sample times vary by more than {jitter:.0%} "
                          f"(median {med:.6g} s); resample first")
    return 1.0 / med


def _signals(t, gyro, accel, path) -> ImuSignals:
    for name, a in (("gyroscope", gyro), ("accelerometer", accel)):
        if not np.all(np.isfinite(a)):
            raise ImunavError(f"{path}: {name} columns contain NaN or inf")
    return ImuSignals(t, gyro, accel, "rates", _uniform_rate(t, path))


#: Largest RMS gyro reading (rad/s) while the accelerometer is still before the gyro units are
#: refused: 20 °/s, the largest turn-on bias of a MEMS gyro in :data:`imunav.sensors.presets`
#: (MPU-6050, ±20 °/s); a gyro in °/s read as rad/s reads 57× its bias and noise.
GYRO_AT_REST_LIMIT = 20 * DEG
#: Above this (rad/s, 5.7 °/s) at rest, a warning: large for a calibrated gyro.
GYRO_AT_REST_WARN = 0.1
#: Largest plausible gyro reading (rad/s): 4000 °/s, beyond the range of MEMS gyros.
GYRO_RANGE_LIMIT = 4000 * DEG
#: The band of the median specific-force magnitude, in g, that fits a recording on the Earth.
ACCEL_BAND = (0.8, 1.25)


def _quiet_windows(accel: FloatArray, rate: float) -> tuple[list[slice], FloatArray]:
    """The tenth of the record's 0.1 s windows (at least 3 samples each) where the
    accelerometer's magnitude varies least, and every window's standard deviation of it."""
    W = max(3, int(round(0.1 * rate)))
    norm = np.linalg.norm(accel, axis=1)
    k = norm.size // W
    if k == 0:
        return [], np.zeros(0)
    sd = norm[:k * W].reshape(k, W).std(axis=1)
    quiet = np.nonzero(sd <= np.percentile(sd, 10))[0]
    return [slice(int(i) * W, (int(i) + 1) * W) for i in quiet], sd


def check_imu_units(gyro: FloatArray, accel: FloatArray, rate: float, *,
                    gyro_argument: str = "gyro_units", accel_argument: str = "accel_units",
                    accel_units: str | None = None) -> None:
    """Refuse (or warn about) IMU samples whose magnitudes do not fit their stated units.

    Where an accelerometer on the Earth is quietest it reads 1 g, and a gyro at rest reads its
    bias and noise. So: the specific-force magnitude in the tenth of the record's 0.1 s
    windows where it varies least must lie within 0.8–1.25 g (else, if the values fit another
    unit — g read as m/s² or the reverse — refused naming it, else a warning); a gyro reading
    more than 4000 °/s, or more than 20 °/s RMS (the largest MEMS turn-on bias on a datasheet
    here) in the quietest of those windows where the accelerometer is still (within 10 % of g,
    varying by less than 5 %), is refused as a gyro in °/s read as rad/s; 5.7–20 °/s there is
    a warning, and so is a gyro that never exceeds 1.1 °/s while the accelerometer shows
    motion (rad/s read as °/s). What this cannot see: a quiet gyro in °/s read as rad/s that
    never turns faster than 4000 °/s and reads less than 5.7 °/s at rest (57 × its bias and
    noise); a record that starts at rest with a bias above 0.1 °/s is caught.

    Parameters
    ----------
    gyro, accel : ndarray, shape (n, 3)
        Rate samples converted to SI (rad/s, m/s²).
    rate : float
        Sample rate (Hz).
    gyro_argument, accel_argument : str
        How the caller's units are named in the messages (``"gyro_units"``, ``"--gyro-units"``).
    accel_units : str, optional
        The accelerometer unit the samples were converted from (to say which unit the raw
        values fit).

    Raises
    ------
    ImunavError
        For an accelerometer whose values fit another unit, or a gyro whose values are too large
        for rad/s (the message names the argument and the unit the values look like).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.tile([0.0, 0.0, -1.0], (100, 1))          # 1 g, but read as m/s²
    >>> try:
    ...     check_imu_units(np.zeros((100, 3)), f, 100.0, accel_units="m/s^2")
    ... except ImunavError as exc:
    ...     print(str(exc).split(": ")[-1])
    the values look like 'g'
    """
    norm = np.linalg.norm(accel, axis=1)
    quiet, sd = _quiet_windows(accel, rate)
    # the magnitude where the accelerometer is quietest: gravity alone (a run's median is 1.5 g)
    m = float(np.median([norm[w].mean() for w in quiet])) if quiet else \
        float(np.median(norm)) if norm.size else G0
    lo, hi = ACCEL_BAND
    if not lo <= m / G0 <= hi:
        given = factor(accel_units, "accel", "accel units") if accel_units else 1.0
        fits = [u for u in ("g", "m/s^2", "mg") if lo <= m / given * U.ACCEL[u] / G0 <= hi]
        told = f" with {accel_argument} = {accel_units!r}" if accel_units else ""
        if fits:
            raise ImunavError(f"accelerometer: |f| = {m:.3g} m/s²{told} where it is quietest "
                              f"(gravity is 9.81 m/s²): the values look like {fits[0]!r}",
                              argument=accel_argument)
        warnings.warn(f"accelerometer: |f| = {m:.3g} m/s² where it is quietest, not about 9.81: "
                      f"check {accel_argument} and the accelerometer columns", stacklevel=3)
    peak = float(np.max(np.abs(gyro))) if gyro.size else 0.0
    if peak > GYRO_RANGE_LIMIT:
        raise ImunavError(f"gyro: a reading of {peak:.4g} rad/s is beyond any MEMS gyro's range "
                          f"(4000 °/s = {GYRO_RANGE_LIMIT:.3g} rad/s): the values look like "
                          f"deg/s; check {gyro_argument}", argument=gyro_argument)
    still = [w for w in quiet if abs(norm[w].mean() - G0) < 0.1 * G0 and
             norm[w].std() < 0.05 * G0]
    if still:
        # the quietest still window: a slow turn can keep the accelerometer's magnitude still
        rms = float(np.min([np.sqrt(np.mean(np.sum(gyro[w] ** 2, axis=1))) for w in still]))
        if rms > GYRO_AT_REST_LIMIT:
            raise ImunavError(f"gyro: {rms:.3g} rad/s RMS ({rms / DEG:.3g} °/s) while the "
                              "accelerometer is still, more than any MEMS gyro's bias: the "
                              f"values look like deg/s; check {gyro_argument}",
                              argument=gyro_argument)
        if rms > GYRO_AT_REST_WARN:
            warnings.warn(f"gyro: {rms:.3g} rad/s RMS ({rms / DEG:.3g} °/s) while the "
                          "accelerometer is still: large for a gyro at rest (deg/s read as "
                          f"rad/s?); check {gyro_argument}", stacklevel=3)
    moving = sd.size > 0 and float(sd.max()) > 1.0
    if moving and peak < 0.02:
        warnings.warn(f"gyro: at most {peak:.3g} rad/s ({peak / DEG:.3g} °/s) while the "
                      f"accelerometer shows motion: the values look like rad/s read as deg/s; "
                      f"check {gyro_argument}", stacklevel=3)


def _cells(line: str) -> list[str]:
    return [c.strip() for c in next(csv.reader([line], skipinitialspace=True))] if line.strip() else []


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _first_line(path: Path) -> list[str]:
    if not path.is_file():
        raise ImunavError(f"recording file not found: {path}")
    with path.open("rb") as fh:
        for raw in fh:
            try:
                text = raw.decode("utf-8-sig")
            except UnicodeDecodeError as exc:
                raise ImunavError(f"{path}, line 1: not UTF-8 text (byte {exc.start})") from None
            if text.strip():
                return _cells(text)
    raise ImunavError(f"{path}: the file is empty")


def _read_headerless(path: Path, ncols: int) -> np.ndarray:
    """Every row of a CSV without a header (float64; errors name the line and column)."""
    import pyarrow as pa
    import pyarrow.csv as pc

    names = [f"c{i}" for i in range(ncols)]
    try:
        table = pc.read_csv(path, read_options=pc.ReadOptions(column_names=names),
                            parse_options=pc.ParseOptions(ignore_empty_lines=True),
                            convert_options=pc.ConvertOptions(
                                column_types={c: pa.float64() for c in names},
                                strings_can_be_null=False))
        data = np.column_stack([table.column(i).to_numpy(zero_copy_only=False)
                                for i in range(ncols)]).astype(np.float64, copy=False)
    except pa.ArrowInvalid:
        data = None
    if data is None or not np.isfinite(data).all():
        with path.open("rb") as fh:
            for line_no, raw in enumerate(fh, start=1):
                text = raw.decode("utf-8-sig", "replace")
                if not text.strip():
                    continue
                cells = _cells(text)
                if len(cells) != ncols:
                    raise ImunavError(f"{path}, line {line_no}: expected {ncols} columns (as "
                                      f"on line 1), got {len(cells)}")
                for j, c in enumerate(cells):
                    if not _is_number(c) or not np.isfinite(float(c)):
                        raise ImunavError(f"{path}, line {line_no}, column {j}: {c!r} is not "
                                          "a finite number")
        raise ImunavError(f"{path}: unreadable CSV")
    return data


def _column(spec, header: list[str] | None, ncols: int, path: Path, what: str) -> int:
    """The 0-based index of a column given by name (a header's) or by index."""
    if isinstance(spec, str):
        name = spec.strip()
        if header is not None and name in header:
            return header.index(name)
        if not name.isdigit():
            if header is None:
                raise ImunavError(f"{path} has no header line (its first line is numbers): give "
                                  f"{what} by 0-based index, not {spec!r}", argument=what)
            raise ImunavError(f"{path}: no column {spec!r}; columns are {header}",
                              argument=what)
        spec = int(name)
    if isinstance(spec, bool) or not isinstance(spec, int | np.integer):
        raise ImunavError(f"{what} must name columns (str) or give their 0-based index (int), "
                          f"got {spec!r}", argument=what)
    if not 0 <= spec < ncols:
        raise ImunavError(f"{path}: {what} index {spec} is out of range (the file has {ncols} "
                          f"columns: 0 … {ncols - 1})", argument=what)
    return int(spec)


def _check_tag_size(tag: TimeTag, path: Path, rows: int) -> None:
    """The tag's last file position against the file's size: the same record (one byte a line
    may have been lost to a CRLF → LF conversion)."""
    size = path.stat().st_size
    last = int(tag.fpos[-1])
    if not 0.95 * size <= last <= 1.05 * (size + rows + 1):
        raise ImunavError(f"tag {tag.path}: its last file position is {last} bytes but {path} "
                          f"has {size}: the tag belongs to another record", argument="tag")


def read_generic(path: str | Path, *, gyro_columns, accel_columns, gyro_units: str = "rad/s",
                 accel_units: str = "m/s^2", time_column: str | int | None = None,
                 time_units: str = "s", rate: float | None = None,
                 tag: str | Path | TimeTag | None = None, time_offset: float = 0.0,
                 check_units: bool = True) -> Recording:
    """Read a CSV recording, with or without a header, naming its columns and their units.

    A file whose first line is all numbers has no header: its columns are given by 0-based
    index. A header's names are matched whole after stripping spaces around them (``Time
    (s)``); a column may also be given by index in a file with a header, and a string of
    digits that is not a header name is an index (the command line passes strings).

    Times start at 0 at the first row (plus ``time_offset``). With ``tag`` (an RTKLIB time-tag
    file of the log) they are GPST seconds since 1970-01-01 instead
    (:func:`imunav.io.rtklib.imu_times`): ``time_column`` is then the IMU's counter (or, without
    it, samples are taken every ``1/rate`` s), mapped onto the tag's span, so the IMU shares
    the time axis of an RTKLIB ``.pos`` solution. The samples must be uniformly spaced (to 5 %).

    Parameters
    ----------
    path : str or Path
        The CSV.
    gyro_columns : sequence of str or int
        The three gyro columns (body x, y, z): names or 0-based indices.
    accel_columns : sequence of str or int
        The three accelerometer columns (body x, y, z): specific force, ``[0, 0, −g]`` level
        at rest in imunav's convention.
    gyro_units : str, default "rad/s"
        Their unit (e.g. ``"deg/s"``), converted to rad/s.
    accel_units : str, default "m/s^2"
        Their unit (e.g. ``"g"``), converted to m/s².
    time_column : str or int, optional
        The time column (with ``tag``: the IMU's counter); give it or ``rate``.
    time_units : str, default "s"
        Its unit (e.g. ``"ms"``, ``"us"``), converted to s.
    rate : float, optional
        Sample rate (Hz) when there is no time column.
    tag : str, Path or TimeTag, optional
        The RTKLIB time tags of this log (``FILE.csv.tag``): absolute GPST times.
    time_offset : float, default 0.0
        Seconds added to every time (a logging delay: rtklibexplorer's drive uses −0.125 s).
    check_units : bool, default True
        Check the magnitudes against the units (:func:`check_imu_units`).

    Returns
    -------
    Recording
        Rate signals in SI, ``meta={"path": ...}`` (and ``"tag"``, ``"time": "GPST"`` with a
        tag), no device orientation.

    Raises
    ------
    ImunavError
        If a unit is unknown or of the wrong kind; the file is missing, malformed, not finite
        or has fewer than 2 data rows; a named column is absent, a column index out of range,
        or a name given for a file without a header; ``gyro_columns`` or ``accel_columns``
        does not name 3 columns; neither ``time_column`` nor ``rate`` is given, or ``rate`` is
        not a finite number > 0; the times are not strictly increasing or vary by more than
        5 %; the tag is not a tag file or belongs to another record (its span or its file size
        differs); or the magnitudes do not fit the units (:func:`check_imu_units`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "rec.csv"
    >>> _ = path.write_text("ms,gx,gy,gz,ax,ay,az\\n0,0,0,90,0,0,-1\\n10,0,0,90,0,0,-1\\n")
    >>> rec = read_generic(path, gyro_columns=["gx", "gy", "gz"], accel_columns=["ax", "ay", "az"],
    ...                    gyro_units="deg/s", accel_units="g", time_column="ms", time_units="ms")
    >>> round(rec.signals.rate, 9), rec.signals.omega[0].round(6), rec.signals.specific_force[0]
    (100.0, array([0.      , 0.      , 1.570796]), array([ 0.     ,  0.     , -9.80665]))
    >>> _ = path.write_text("0,0,90,0,0,-1\\n0,0,90,0,0,-1\\n")          # no header: indices
    >>> rec = read_generic(path, gyro_columns=[0, 1, 2], accel_columns=[3, 4, 5],
    ...                    gyro_units="deg/s", accel_units="g", rate=100)
    >>> rec.signals.t.tolist()
    [0.0, 0.01]
    >>> tmp.cleanup()
    """
    path = Path(path)
    gs = factor(gyro_units, "rate", "gyro units")
    as_ = factor(accel_units, "accel", "accel units")
    ts = factor(time_units, "time", "time units")
    first = _first_line(path)
    if all(_is_number(c) for c in first):
        header, data = None, _read_headerless(path, len(first))
        if len(data) < 2:
            raise ImunavError(f"{path}: needs at least 2 data rows")
    else:
        header, data = _read_table(path)
    ncols = data.shape[1]
    gyro_columns, accel_columns = list(gyro_columns), list(accel_columns)
    if len(gyro_columns) != 3 or len(accel_columns) != 3:
        raise ImunavError("gyro_columns and accel_columns must each name 3 columns (x, y, z)")
    gi = [_column(c, header, ncols, path, "gyro_columns") for c in gyro_columns]
    ai = [_column(c, header, ncols, path, "accel_columns") for c in accel_columns]
    ti = None if time_column is None else _column(time_column, header, ncols, path,
                                                  "time_column")
    if isinstance(time_offset, bool) or not isinstance(time_offset, int | float) or \
            not np.isfinite(time_offset):
        raise ImunavError(f"time_offset must be a finite number of seconds, got {time_offset!r}",
                          argument="time_offset")
    meta = {"path": str(path)}
    if tag is not None:
        tag = tag if isinstance(tag, TimeTag) else read_tag(tag)
        _check_tag_size(tag, path, data.shape[0])
        if ti is not None:
            counter = data[:, ti] * ts * 1000.0
        elif rate is not None:
            counter = np.arange(data.shape[0]) * 1000.0 / check_positive(rate, "rate")
        else:
            raise ImunavError("with tag, give time_column (the IMU's counter) or rate")
        try:
            t = imu_times(counter, tag, float(time_offset))
        except ImunavError as exc:
            raise ImunavError(f"{path}: {exc}".replace("counter_ms", "the time column"),
                              argument="tag") from None
        meta.update(tag=tag.path, time="GPST")
    else:
        if ti is not None:
            t = data[:, ti] * ts
        elif rate is not None:
            t = np.arange(data.shape[0]) / check_positive(rate, "rate")
        else:
            raise ImunavError("give either time_column or rate")
        t = t - t[0] + float(time_offset)
    gyro = data[:, gi] * gs
    accel = data[:, ai] * as_
    rec = Recording(_signals(t, gyro, accel, path), meta=meta)
    if check_units:
        try:
            check_imu_units(gyro, accel, rec.signals.rate, accel_units=accel_units)
        except ImunavError as exc:
            raise ImunavError(f"{path}: {exc}", argument=exc.argument) from None
    return rec


def read_ximu3(folder: str | Path | None = None) -> Recording:
    """Read an x-io x-IMU3 recording: ``Inertial.csv`` (+ ``Quaternion.csv`` if present).

    Timestamps in µs, gyro in deg/s and accelerometer in g are converted to s, rad/s and m/s²;
    times start at 0 at the first inertial sample.

    Parameters
    ----------
    folder : str or Path, optional
        The folder holding the files; default the recording shipped with imunav (BSD-3).

    Returns
    -------
    Recording
        Rate signals; ``device_t`` and ``device_q`` (``[W, X, Y, Z]`` as stored) when
        ``Quaternion.csv`` exists; ``meta={"device": "x-IMU3"}``.

    Raises
    ------
    ImunavError
        If ``Inertial.csv`` is missing, malformed or has fewer than 2 rows; its header is not
        an x-IMU3 inertial header; a value is not finite; or the times are not strictly
        increasing or vary by more than 5 %.

    Examples
    --------
    >>> rec = read_ximu3()
    >>> len(rec.signals), rec.device_q.shape, rec.meta
    (500, (500, 4), {'device': 'x-IMU3'})
    """
    folder = Path(folder) if folder else data_path("real_imu", "xio_ximu3")
    header, d = _read_table(folder / "Inertial.csv")
    want = ["Timestamp (us)", "Gyroscope X (deg/s)", "Gyroscope Y (deg/s)", "Gyroscope Z (deg/s)",
            "Accelerometer X (g)", "Accelerometer Y (g)", "Accelerometer Z (g)"]
    if header[:7] != want:
        raise ImunavError(f"{folder / 'Inertial.csv'}: not an x-IMU3 inertial file "
                          f"(header {header[:7]})")
    t = (d[:, 0] - d[0, 0]) * 1e-6
    rec = Recording(_signals(t, d[:, 1:4] * DEG, d[:, 4:7] * G0,
                             folder / "Inertial.csv"), meta={"device": "x-IMU3"})
    qf = folder / "Quaternion.csv"
    if qf.is_file():
        _, q = _read_table(qf)
        rec.device_t = (q[:, 0] - d[0, 0]) * 1e-6
        rec.device_q = q[:, 1:5]
    return rec


def read_ximu(folder: str | Path | None = None, rate: float = 256.0) -> Recording:
    """Read an x-io x-IMU recording: ``*_CalInertialAndMag.csv`` (+ ``*_Quaternion.csv``).

    Packet number, gyro in deg/s and accelerometer in g (magnetometer ignored) are converted
    to rad/s and m/s². Inertial samples are consecutive at ``rate``; the quaternion packets
    are timed by interpolating packet numbers.

    Parameters
    ----------
    folder : str or Path, optional
        The folder holding the files; default the recording shipped with imunav (BSD-3).
    rate : float, default 256.0
        The inertial sample rate (Hz): the device's register code 9 = 256 Hz.

    Returns
    -------
    Recording
        Rate signals from t = 0; ``device_t`` and ``device_q`` (the four "Element" columns as
        stored) when a quaternion file exists; ``meta`` with ``"device"`` and ``"packets"``.

    Raises
    ------
    ImunavError
        If no ``*_CalInertialAndMag.csv`` is in ``folder``; it is malformed, has fewer than 2
        rows or is not an x-IMU calibrated inertial file; a value is not finite; or ``rate``
        is not a finite number > 0.

    Examples
    --------
    >>> rec = read_ximu()
    >>> rec.signals.rate, len(rec.signals), rec.meta["device"]
    (256.0, 12626, 'x-IMU')
    """
    folder = Path(folder) if folder else data_path("real_imu", "xio_ximu")
    files = sorted(folder.glob("*_CalInertialAndMag.csv"))
    if not files:
        raise ImunavError(f"no *_CalInertialAndMag.csv in {folder}")
    header, d = _read_table(files[0])
    if not header[0].startswith("Packet number") or "Gyroscope X (deg/s)" not in header:
        raise ImunavError(f"{files[0]}: not an x-IMU calibrated inertial file")
    t = np.arange(d.shape[0]) / check_positive(rate, "rate")
    rec = Recording(_signals(t, d[:, 1:4] * DEG, d[:, 4:7] * G0, files[0]),
                    meta={"device": "x-IMU", "packets": d[:, 0]})
    qfiles = sorted(folder.glob("*_Quaternion.csv"))
    if qfiles:
        _, q = _read_table(qfiles[0])
        rec.device_t = np.interp(q[:, 0], d[:, 0], t)
        rec.device_q = q[:, 1:5]
    return rec


READERS = {"ximu3": read_ximu3, "ximu": read_ximu}
