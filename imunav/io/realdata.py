"""Readers for real IMU recordings: x-io x-IMU3, x-io x-IMU, and generic CSV files.

Every reader converts to imunav's SI units at the boundary (rad/s, m/s², s) and returns a
:class:`Recording` whose ``signals`` are ordinary rate :class:`~imunav.ImuSignals`. The
device's onboard orientation, where present, is returned raw (``device_t``, ``device_q``):
its convention is checked against the gyro by
:func:`imunav.analysis.recordings.device_quaternion_convention` (and in
``notebooks/07_real_imu_data.ipynb``). The analyses of recordings live in
:mod:`imunav.analysis.recordings`: this module only reads.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.io.csvio``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from imunav.core.constants import DEG, G0
from imunav.core.rotations import FloatArray
from imunav.core.units import factor
from imunav.core.validation import ImunavError, check_positive
from imunav.io.csvio import read_chunks, read_header
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


def read_generic(path: str | Path, *, gyro_columns, accel_columns, gyro_units: str = "rad/s",
                 accel_units: str = "m/s^2", time_column: str | None = None,
                 time_units: str = "s", rate: float | None = None) -> Recording:
    """Read a CSV recording with a header, naming its columns and their units.

    Times start at 0 at the first row; the samples must be uniformly spaced (to 5 %).

    Parameters
    ----------
    path : str or Path
        The CSV (a header line, then numeric rows).
    gyro_columns : sequence of str
        The three gyro columns (body x, y, z).
    accel_columns : sequence of str
        The three accelerometer columns (body x, y, z): specific force, ``[0, 0, −g]`` level
        at rest in imunav's convention.
    gyro_units : str, default "rad/s"
        Their unit (e.g. ``"deg/s"``), converted to rad/s.
    accel_units : str, default "m/s^2"
        Their unit (e.g. ``"g"``), converted to m/s².
    time_column : str, optional
        The time column; give it or ``rate``.
    time_units : str, default "s"
        Its unit (e.g. ``"ms"``, ``"us"``), converted to s.
    rate : float, optional
        Sample rate (Hz) when there is no time column.

    Returns
    -------
    Recording
        Rate signals in SI, ``meta={"path": ...}``, no device orientation.

    Raises
    ------
    ImunavError
        If a unit is unknown or of the wrong kind; the file is missing, malformed, not finite
        or has fewer than 2 data rows; a named column is absent; ``gyro_columns`` or
        ``accel_columns`` does not name 3 columns; neither ``time_column`` nor ``rate`` is
        given, or ``rate`` is not a finite number > 0; or the times are not strictly
        increasing or vary by more than 5 %.

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
    >>> tmp.cleanup()
    """
    path = Path(path)
    gs = factor(gyro_units, "rate", "gyro units")
    as_ = factor(accel_units, "accel", "accel units")
    ts = factor(time_units, "time", "time units")
    header, data = _read_table(path)
    cols = {}
    for name in list(gyro_columns) + list(accel_columns) + ([time_column] if time_column else []):
        if name not in header:
            raise ImunavError(f"{path}: no column {name!r}; columns are {header}")
        cols[name] = header.index(name)
    if len(gyro_columns) != 3 or len(accel_columns) != 3:
        raise ImunavError("gyro_columns and accel_columns must each name 3 columns (x, y, z)")
    if time_column:
        t = data[:, cols[time_column]] * ts
    elif rate is not None:
        t = np.arange(data.shape[0]) / check_positive(rate, "rate")
    else:
        raise ImunavError("give either time_column or rate")
    t = t - t[0]
    gyro = data[:, [cols[c] for c in gyro_columns]] * gs
    accel = data[:, [cols[c] for c in accel_columns]] * as_
    return Recording(_signals(t, gyro, accel, path), meta={"path": str(path)})


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
