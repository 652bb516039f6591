"""The aiding sensors' measurement files: one CSV per sensor in a folder.

========== ============================================ =============================
file       header (exactly)                             units
========== ============================================ =============================
gnss.csv   ``t,x,y,z,vx,vy,vz`` or ``t,x,y,z`` (flat)   s, m (NED), m/s
gnss.csv   ``t,lat,lon,alt,vn,ve,vd`` or ``t,lat,lon,alt``  s, deg, deg, m, m/s (wgs84)
baro.csv   ``t,alt``                                    s, m (altitude: ``−z``, or the
                                                        height above the ellipsoid)
heading.csv ``t,yaw``                                   s, rad
nhc.csv    ``t,vy,vz``                                  s, m/s (the constraint readings)
zupt.csv   ``t0,t1``                                    s (stance intervals)
========== ============================================ =============================

On the WGS-84 Earth latitude and longitude are in degrees in the file (radians in
:class:`~imunav.sensors.aiding.Readings`), the velocity relative to the Earth in local NED. A
file without velocity (``t,x,y,z``) is written when the GNSS has no ``velocity_sigma``. On
reading, every value must be a finite number, times strictly increasing (stance intervals with
``t0 ≤ t1``, in order, not overlapping); a bad file is one :class:`ImunavError` naming the file
and its line (a file with a header and no rows has no readings: a record inside an outage).
Files are written through a temporary file renamed at the end.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.io.csvio``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from imunav.core.validation import ImunavError
from imunav.io.csvio import CsvWriter, read_chunks, read_header
from imunav.sensors.aiding import AidingData, Readings

__all__ = ["AIDING_FILES", "GNSS_HEADERS", "check_span", "read_aiding", "unused_files",
           "write_aiding"]

#: The headers of ``gnss.csv``: with and without velocity (flat frame).
GNSS_HEADERS = {"flat": (("t", "x", "y", "z", "vx", "vy", "vz"), ("t", "x", "y", "z")),
                "wgs84": (("t", "lat", "lon", "alt", "vn", "ve", "vd"),
                          ("t", "lat", "lon", "alt"))}

#: Each file and its header (GNSS: see :data:`GNSS_HEADERS`).
AIDING_FILES = {"gnss": ("gnss.csv", None), "baro": ("baro.csv", ("t", "alt")),
                "heading": ("heading.csv", ("t", "yaw")), "nhc": ("nhc.csv", ("t", "vy", "vz")),
                "zupt": ("zupt.csv", ("t0", "t1"))}


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


def read_aiding(folder: str | Path, sensors, frame: str = "flat") -> AidingData:
    """Read the measurement files of ``sensors`` from ``folder``.

    Parameters
    ----------
    folder : str or Path
    sensors : iterable of str
        The aids to read (``gnss``, ``baro``, ``heading``, ``zupt``; ``nhc`` is read only if its
        file exists, else the filter applies the constraint itself).
    frame : {"flat", "wgs84"}
        The frame of the GNSS file (wgs84: latitude and longitude in degrees, converted to
        radians).

    Returns
    -------
    AidingData

    Raises
    ------
    ImunavError
        For a missing folder or file, a file given as the folder, a wrong header, a value that
        is not a finite number, times not strictly increasing, stance intervals with
        ``t1 < t0`` or overlapping, or (wgs84) a latitude outside ±90° or a longitude outside ±180°.
    """
    if frame not in GNSS_HEADERS:
        raise ImunavError(f"frame must be one of {tuple(GNSS_HEADERS)}, got {frame!r}",
                          argument="frame")
    folder = Path(folder)
    if folder.is_file():
        raise ImunavError(f"measurements {folder} is a file; give the folder that holds "
                          f"{', '.join(f for f, _ in AIDING_FILES.values())}",
                          argument="measurements")
    if not folder.is_dir():
        raise ImunavError(f"measurements folder not found: {folder}", argument="measurements")
    out = AidingData()
    for name in sensors:
        fname, header = AIDING_FILES[name]
        path = folder / fname
        if name == "nhc" and not path.exists():
            continue
        if name == "zupt" and not path.exists():
            continue                   # the shoe detector needs no file; truth is checked later
        if not path.exists():
            raise ImunavError(f"{path} not found (the [{name}] readings)")
        got = read_header(path, name)
        if name == "gnss":
            allowed = GNSS_HEADERS[frame]
            if got not in allowed:
                other = [f for f, hs in GNSS_HEADERS.items() if got in hs]
                hint = (f" (a {other[0]} file: the filter's frame is {frame})" if other else "")
                raise ImunavError(f"{path}: unrecognised header {','.join(got)!r}; expected "
                                  + " or ".join(repr(",".join(h)) for h in allowed) + hint)
            header = got
        elif got != header:
            raise ImunavError(f"{path}: unrecognised header {','.join(got)!r}; expected "
                              f"{','.join(header)!r}")
        data = _read(path, header, name)
        if name == "zupt":
            bad = data[:, 1] < data[:, 0]
            if bad.any():
                i = int(np.argmax(bad))
                raise ImunavError(f"{path}, line {_line_of(path, i)}: t1 = {data[i, 1]:.9g} s "
                                  f"is before t0 = {data[i, 0]:.9g} s")
            over = data[1:, 0] <= data[:-1, 1]
            if over.any():
                i = int(np.argmax(over)) + 1
                raise ImunavError(f"{path}, line {_line_of(path, i)}: the stance interval starts "
                                  f"at {data[i, 0]:.9g} s, not after the previous one ends "
                                  f"({data[i - 1, 1]:.9g} s): intervals must be in order and "
                                  "not overlap")
            out.zupt = data
        else:
            _check_times(path, data[:, 0])
            values = data[:, 1:]
            if name == "gnss" and frame == "wgs84":
                bad = np.abs(values[:, 0]) > 90.0
                if bad.any():
                    i = int(np.argmax(bad))
                    raise ImunavError(f"{path}, line {_line_of(path, i)}: lat = "
                                      f"{values[i, 0]:.9g}° is outside ±90°")
                bad = np.abs(values[:, 1]) > 180.0
                if bad.any():
                    i = int(np.argmax(bad))
                    raise ImunavError(f"{path}, line {_line_of(path, i)}: lon = "
                                      f"{values[i, 1]:.9g}° is outside ±180°")
                values = values.copy()
                values[:, :2] = np.radians(values[:, :2])
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
    out = [f"{folder / fname} is not used: the aiding file has no [{name}] table"
           for name, (fname, _) in AIDING_FILES.items()
           if name not in sensors and (folder / fname).is_file()]
    if "zupt" in sensors and detector == "shoe" and (folder / "zupt.csv").is_file():
        out.append(f"{folder / 'zupt.csv'} is not used: [zupt] detector = \"shoe\" finds the "
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
    for name in ("gnss", "baro", "heading", "nhc", "zupt"):
        r = getattr(data, name)
        if r is None:
            continue
        t = r.ravel() if name == "zupt" else r.t
        bad = (t < t_start - tol) | (t > t_end + tol)
        if bad.any():
            i = int(np.argmax(bad))
            row = i // 2 if name == "zupt" else i
            path = Path(folder) / AIDING_FILES[name][0]
            raise ImunavError(f"{path}, line {_line_of(path, row)}: t = {t[i]:.9g} s lies "
                              f"outside the IMU record ({t_start:.9g} … {t_end:.9g} s)")


def write_aiding(folder: str | Path, data: AidingData, frame: str = "flat") -> list[Path]:
    """Write each sensor's readings of ``data`` to its file in ``folder`` (created if absent).

    Parameters
    ----------
    folder : str or Path
    data : AidingData
    frame : {"flat", "wgs84"}
        The frame of the GNSS readings (wgs84: latitude and longitude written in degrees).

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ImunavError
        For another ``frame``.
    """
    if frame not in GNSS_HEADERS:
        raise ImunavError(f"frame must be one of {tuple(GNSS_HEADERS)}, got {frame!r}",
                          argument="frame")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, (fname, header) in AIDING_FILES.items():
        r = getattr(data, name)
        if r is None:
            continue
        if name == "zupt":
            cols = [r[:, 0], r[:, 1]]
        else:
            vals = r.values
            if name == "gnss":
                header = GNSS_HEADERS[frame][0 if vals.shape[1] == 6 else 1]
                if frame == "wgs84":
                    vals = vals.copy()
                    vals[:, :2] = np.degrees(vals[:, :2])
            cols = [r.t] + [vals[:, j] for j in range(vals.shape[1])]
        path = folder / fname
        with CsvWriter(path, header) as w:
            w.write(cols)
        written.append(path)
    return written
