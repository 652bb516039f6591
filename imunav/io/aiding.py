"""The aiding sensors' measurement files: one CSV per aid in a folder, its name and headers
those of the aid's spec (:data:`~imunav.sensors.aids.AIDS`):

============= ================================================ =============================
file          header (exactly)                                 units
============= ================================================ =============================
gnss.csv      ``t,x,y,z,vx,vy,vz`` or ``t,x,y,z`` (flat)         s, m (NED), m/s
gnss.csv      ``t,lat,lon,alt,vn,ve,vd`` or ``t,lat,lon,alt``    s, deg, deg, m, m/s (wgs84)
baro.csv      ``t,alt``                                        s, m (altitude: ``−z``, or the
                                                               height above the ellipsoid)
heading.csv   ``t,yaw``                                        s, rad
nhc.csv       ``t,vy,vz``                                      s, m/s (the constraint readings)
zupt.csv      ``t0,t1``                                        s (stance intervals)
odometer.csv  ``t,speed``                                      s, m/s
============= ================================================ =============================

On the WGS-84 Earth the columns an aid writes in degrees (GNSS latitude and longitude) are in
degrees in the file (radians in :class:`~imunav.sensors.aids.Readings`), the velocity relative
to the Earth in local NED. A GNSS file without velocity (``t,x,y,z``) is written when the GNSS
has no ``velocity_sigma``. On reading, every value must be a finite number, times strictly
increasing (intervals with ``t0 ≤ t1``, in order, not overlapping); a bad file is one
:class:`ImunavError` naming the file and its line (a file with a header and no rows has no
readings: a record inside an outage). Files are written through a temporary file renamed at the
end.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.io.csvio``.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from imunav.core.validation import ImunavError
from imunav.io.csvio import CsvWriter, read_chunks, read_header
from imunav.sensors.aids import AIDS, AidingData, Readings

__all__ = ["FRAMES", "aid_files", "check_span", "read_aiding", "unused_files", "write_aiding"]

#: The frames an aid's file may be written in.
FRAMES = ("flat", "wgs84")

#: Latitude and longitude limits (°) of a column written in degrees.
_DEGREE_LIMITS = {"lat": 90.0, "lon": 180.0}


#: Angle columns read in radians (a value beyond 2π suggests a file in degrees).
_RADIAN_ANGLES = frozenset({"yaw", "pitch", "roll", "heading"})


def aid_files() -> dict[str, str]:
    """``{aid: file name}`` of every registered aid.

    Returns
    -------
    dict
    """
    return {n: s.file for n, s in AIDS.items()}


def _line_of(path: Path, row: int) -> int:
    """The line number (1-based) of data row ``row`` (0-based; blank lines are skipped)."""
    with path.open("rb") as fh:
        fh.readline()
        r = 0
        for line_no, raw in enumerate(fh, start=2):
            if not raw.strip():
                continue
            if r == row:
                return line_no
            r += 1
    return row + 2


def _read(path: Path, header: tuple[str, ...], what: str) -> np.ndarray:
    parts = list(read_chunks(path, header, what))
    return np.concatenate(parts) if parts else np.zeros((0, len(header)))


def _check_times(path: Path, t: np.ndarray, column: str = "t") -> None:
    d = np.diff(t)
    if np.any(d <= 0):
        i = int(np.argmax(d <= 0)) + 1
        what = "repeated" if d[i - 1] == 0 else "out of order"
        raise ImunavError(f"{path}, line {_line_of(path, i)}: column {column} must be strictly "
                          f"increasing; t = {t[i]:.9g} s is {what} (after {t[i - 1]:.9g} s)")


def read_aiding(folder: str | Path, sensors, frame: str = "flat", aiding=None) -> AidingData:
    """Read the measurement files of ``sensors`` from ``folder``.

    Parameters
    ----------
    folder : str or Path
    sensors : iterable of str
        The aids to read (a file an aid can do without — NHC applied by the filter itself, a
        stance found by the SHOE detector — is read only if it exists).
    frame : {"flat", "wgs84"}
        The frame of the files (wgs84: the columns in degrees converted to radians).
    aiding : AidingConfig, optional
        The aids' configuration (which files are optional; default: NHC's and ZUPT's).

    Returns
    -------
    AidingData

    Raises
    ------
    ImunavError
        For a missing folder or file, a file given as the folder, a wrong header, a value that
        is not a finite number, times not strictly increasing, intervals with ``t1 < t0`` or
        overlapping, or (wgs84) a latitude outside ±90° or a longitude outside ±180°.
    """
    if frame not in FRAMES:
        raise ImunavError(f"frame must be one of {FRAMES}, got {frame!r}", argument="frame")
    folder = Path(folder)
    if folder.is_file():
        raise ImunavError(f"measurements {folder} is a file; give the folder that holds "
                          f"{', '.join(aid_files().values())}", argument="measurements")
    if not folder.is_dir():
        raise ImunavError(f"measurements folder not found: {folder}", argument="measurements")
    out = AidingData()
    for name in sensors:
        spec = AIDS[name]
        path = folder / spec.file
        if not path.exists():
            optional = (not spec.file_needed(aiding.get(name)) if aiding is not None
                        else name in ("nhc", "zupt"))
            if optional:
                continue
            raise ImunavError(f"{path} not found (the [{name}] readings)")
        got = read_header(path, name)
        allowed = spec.headers[frame]
        if got not in allowed:
            other = [f for f, hs in spec.headers.items() if got in hs and f != frame]
            hint = f" (a {other[0]} file: the filter's frame is {frame})" if other else ""
            raise ImunavError(f"{path}: unrecognised header {','.join(got)!r}; expected "
                              + " or ".join(repr(",".join(h)) for h in allowed) + hint)
        data = _read(path, got, name)
        if spec.intervals:
            bad = data[:, 1] < data[:, 0]
            if bad.any():
                i = int(np.argmax(bad))
                raise ImunavError(f"{path}, line {_line_of(path, i)}: t1 = {data[i, 1]:.9g} s "
                                  f"is before t0 = {data[i, 0]:.9g} s")
            over = data[1:, 0] <= data[:-1, 1]
            if over.any():
                i = int(np.argmax(over)) + 1
                raise ImunavError(f"{path}, line {_line_of(path, i)}: the interval starts "
                                  f"at {data[i, 0]:.9g} s, not after the previous one ends "
                                  f"({data[i - 1, 1]:.9g} s): intervals must be in order and "
                                  "not overlap")
            setattr(out, name, data)
            continue
        _check_times(path, data[:, 0])
        values = data[:, 1:]
        if frame == "wgs84":
            for j, col in enumerate(got[1:]):
                if col not in spec.degrees:
                    continue
                lim = _DEGREE_LIMITS.get(col, 360.0)
                bad = np.abs(values[:, j]) > lim
                if bad.any():
                    i = int(np.argmax(bad))
                    raise ImunavError(f"{path}, line {_line_of(path, i)}: {col} = "
                                      f"{values[i, j]:.9g}° is outside ±{lim:g}°")
                values = values.copy() if values.base is data else values
                values[:, j] = np.radians(values[:, j])
        for j, col in enumerate(got[1:]):
            if col in _RADIAN_ANGLES:                 # radians here, whatever the file had
                peak = float(np.max(np.abs(values[:, j]))) if len(values) else 0.0
                if peak > 2 * np.pi + 1e-9:
                    warnings.warn(f"{path}: {col} reaches {peak:.4g}, beyond 2π: the file is "
                                  "read in radians — are its angles in degrees?", stacklevel=2)
        setattr(out, name, Readings(data[:, 0], values))
    return out


def unused_files(folder: str | Path, sensors, detector: str | None = None) -> list[str]:
    """The measurement files in ``folder`` that no aid of ``sensors`` reads, as warnings: such
    a file would be ignored silently.

    Parameters
    ----------
    folder : str or Path
    sensors : iterable of str
        The aids of the aiding file (``AidingConfig.sensors``).
    detector : {"truth", "shoe"}, optional
        The ``[zupt]`` detector: ``"shoe"`` finds the stance in the IMU data and reads no
        ``zupt.csv``.

    Returns
    -------
    list of str
        One warning per file: ``"meas/baro.csv is not used: the aiding file has no [baro]
        table"``.
    """
    folder, sensors = Path(folder), set(sensors)
    out = [f"{folder / spec.file} is not used: the aiding file has no [{name}] table"
           for name, spec in AIDS.items()
           if name not in sensors and (folder / spec.file).is_file()]
    z = AIDS["zupt"].file
    if "zupt" in sensors and detector == "shoe" and (folder / z).is_file():
        out.append(f"{folder / z} is not used: [zupt] detector = \"shoe\" finds the "
                   "stance in the IMU data")
    return out


def check_span(folder: str | Path, data: AidingData, t_start: float, t_end: float) -> None:
    """Refuse readings outside the IMU record ``[t_start, t_end]``.

    Parameters
    ----------
    folder : str or Path
        Where the files are (for the message).
    data : AidingData
    t_start, t_end : float
        The record's first and last state times (s).

    Raises
    ------
    ImunavError
        Naming the file, its line and the record's span.
    """
    tol = 1e-9 * max(1.0, abs(t_end))
    for name, r in data.items():
        spec = AIDS[name]
        t = np.asarray(r).ravel() if spec.intervals else r.t
        bad = (t < t_start - tol) | (t > t_end + tol)
        if bad.any():
            i = int(np.argmax(bad))
            row = i // 2 if spec.intervals else i
            path = Path(folder) / spec.file
            raise ImunavError(f"{path}, line {_line_of(path, row)}: t = {t[i]:.9g} s lies "
                              f"outside the IMU record ({t_start:.9g} … {t_end:.9g} s)")


def write_aiding(folder: str | Path, data: AidingData, frame: str = "flat") -> list[Path]:
    """Write each aid's readings of ``data`` to its file in ``folder`` (created if absent).

    Parameters
    ----------
    folder : str or Path
    data : AidingData
    frame : {"flat", "wgs84"}
        The frame of the readings (wgs84: the aid's degree columns written in degrees).

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ImunavError
        For another ``frame``, or a value that is not finite.
    """
    if frame not in FRAMES:
        raise ImunavError(f"frame must be one of {FRAMES}, got {frame!r}", argument="frame")
    folder = Path(folder)
    cols_of = []
    for name, r in data.items():
        spec = AIDS[name]
        if spec.intervals:
            header, cols = spec.headers[frame][0], [r[:, 0], r[:, 1]]
        else:
            vals = r.values
            header = next(h for h in spec.headers[frame] if len(h) == vals.shape[1] + 1)
            if frame == "wgs84" and spec.degrees:
                vals = vals.copy()
                for j, col in enumerate(header[1:]):
                    if col in spec.degrees:
                        vals[:, j] = np.degrees(vals[:, j])
            cols = [r.t] + [vals[:, j] for j in range(vals.shape[1])]
        if not all(np.isfinite(c).all() for c in cols):
            raise ImunavError(f"the {name} readings are not all finite numbers: nothing "
                              f"written to {folder / spec.file}", argument="aiding")
        cols_of.append((folder / spec.file, header, cols))
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for path, header, cols in cols_of:
        with CsvWriter(path, header) as w:
            w.write(cols)
        written.append(path)
    return written


def __getattr__(name):
    # the names of 0.2, kept one release (derived from the registry)
    if name in ("AIDING_FILES", "GNSS_HEADERS"):
        import warnings
        warnings.warn(f"imunav.io.aiding.{name} is deprecated and will be removed in imunav 0.3; "
                      "use imunav.sensors.aids.AIDS (each aid's file and headers)",
                      DeprecationWarning, stacklevel=2)
        if name == "AIDING_FILES":
            return {n: (s.file, None if n == "gnss" else s.headers["flat"][0])
                    for n, s in AIDS.items()}
        return dict(AIDS["gnss"].headers)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
