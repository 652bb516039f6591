"""RTKLIB files: a position solution (``.pos``), the time tags of a logged stream (``.tag``),
and the IMU sample times a tag gives (:func:`imu_times`).

**One time axis.** Every time here is *GPST seconds since 1970-01-01 00:00:00*, counted as
calendar seconds without leap seconds: RTKLIB's own ``gtime_t`` (``epoch2time`` of the GPST
calendar date and time), which is what a ``.tag`` file stores. An IMU record timed by its tag
and the GNSS epochs of a ``.pos`` solution therefore share one axis, and a difference of two
times is a plain duration. (It is not UTC: GPST runs ahead of UTC by the leap seconds since
1980, 18 s since 2017. A solution written in UTC or JST is refused rather than shifted by a
leap-second table.) At ~1.75e9 s a float64 resolves 0.24 µs.

**Frames and units** (imunav's, converted at this boundary): latitude and longitude in radians,
heights above the WGS-84 ellipsoid in metres, velocity north/east/**down** (RTKLIB writes
north/east/up), covariances in the NED frame.

May import: ``imunav.core``, ``imunav.earth``.
"""

from __future__ import annotations

import datetime as _dt
import math
import re
import struct
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, as_float_array
from imunav.earth import ecef_to_ned, geodetic_to_ecef
from imunav.sensors.aids import Readings

__all__ = ["GPST_EPOCH", "PosSolution", "TAG_HEADER", "TimeTag", "gnss_readings", "imu_times",
           "velocity_lag", "read_pos",
           "read_tag"]

#: The GPS time origin, 1980-01-06 00:00:00 GPST, in seconds since 1970-01-01 (calendar).
GPST_EPOCH = 315964800.0

#: What every RTKLIB time-tag file starts with.
TAG_HEADER = b"TIMETAG RTKLIB"

#: Bytes of a tag file's header: 60 of text, the uint32 start tick, the uint32 integer seconds
#: and the float64 fraction of the start time.
TAG_PREFIX = 60 + 4 + 4 + 8

#: The columns of a lat/lon/height solution after the time, in RTKLIB's order (degrees).
POS_COLUMNS = ("latitude(deg)", "longitude(deg)", "height(m)", "Q", "ns", "sdn(m)", "sde(m)",
               "sdu(m)", "sdne(m)", "sdeu(m)", "sdun(m)", "age(s)", "ratio")
#: The velocity columns RTKLIB appends with ``out-outvel = on`` (north, east, up).
VEL_COLUMNS = ("vn(m/s)", "ve(m/s)", "vu(m/s)", "sdvn", "sdve", "sdvu", "sdvne", "sdveu",
               "sdvun")

#: Headers of the solution formats imunav does not read, and what to ask RTKLIB for instead.
_OTHER_FORMATS = {
    "x-ecef(m)": "ECEF x/y/z",
    "e-baseline(m)": "an east/north/up baseline",
    "latitude(d'\")": "latitude/longitude in degrees-minutes-seconds",
}


@dataclass
class PosSolution:
    """An RTKLIB position solution (lat/lon/height), converted to imunav's units and frames.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Epoch times: GPST seconds since 1970-01-01 (see the module docstring).
    llh : ndarray, shape (n, 3)
        Latitude, longitude (rad) and height above the ellipsoid (m) of the antenna.
    quality : ndarray of int, shape (n,)
        RTKLIB's Q: 1 fixed, 2 float, 3 SBAS, 4 DGPS, 5 single, 6 PPP.
    satellites : ndarray of int, shape (n,)
        Satellites used (``ns``).
    position_cov : ndarray, shape (n, 3, 3)
        Position covariance (m²), NED.
    age : ndarray, shape (n,)
        Age of the differential corrections (s).
    ratio : ndarray, shape (n,)
        The ambiguity-validation ratio.
    velocity : ndarray, shape (n, 3), optional
        Velocity north, east, down (m/s); None when the file has no velocity columns.
    velocity_cov : ndarray, shape (n, 3, 3), optional
        Its covariance ((m/s)²), NED.
    path : str
        The file read.
    """

    t: FloatArray
    llh: FloatArray
    quality: np.ndarray
    satellites: np.ndarray
    position_cov: FloatArray
    age: FloatArray
    ratio: FloatArray
    velocity: FloatArray | None = None
    velocity_cov: FloatArray | None = None
    path: str = ""

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def position_sd(self) -> FloatArray:
        """σ north, east, down of each fix (m), shape (n, 3).

        Returns
        -------
        ndarray
        """
        return np.sqrt(np.diagonal(self.position_cov, axis1=1, axis2=2))

    @property
    def velocity_sd(self) -> FloatArray | None:
        """σ of the velocity north, east, down (m/s), shape (n, 3); None without velocity.

        Returns
        -------
        ndarray or None
        """
        if self.velocity_cov is None:
            return None
        return np.sqrt(np.diagonal(self.velocity_cov, axis1=1, axis2=2))

    def ned(self, origin: npt.ArrayLike | None = None) -> FloatArray:
        """The fixes as north, east, down offsets (m) in the tangent frame at ``origin``.

        Parameters
        ----------
        origin : array_like, shape (3,), optional
            ``(lat, lon, h)`` (rad, rad, m); default the first fix.

        Returns
        -------
        ndarray, shape (n, 3)
            Exact on the ellipsoid (through ECEF); the tangent plane departs from the
            ellipsoid's surface by about ``d²/2R``: 8 cm at 1 km from the origin.

        Raises
        ------
        ImunavError
            If ``origin`` is not three finite numbers or lies off the Earth.
        """
        o = self.llh[0] if origin is None else as_float_array(origin, "origin", ndim=1, last=3)
        r = geodetic_to_ecef(self.llh[:, 0], self.llh[:, 1], self.llh[:, 2])
        return ecef_to_ned(r, (float(o[0]), float(o[1]), float(o[2])))

    def select(self, keep: npt.ArrayLike) -> PosSolution:
        """The epochs where ``keep`` is True (a boolean mask or indices).

        Parameters
        ----------
        keep : array_like
            Boolean mask of shape (n,) or integer indices.

        Returns
        -------
        PosSolution
        """
        k = np.asarray(keep)

        def pick(a):
            return None if a is None else a[k]

        return PosSolution(self.t[k], self.llh[k], self.quality[k], self.satellites[k],
                           self.position_cov[k], self.age[k], self.ratio[k],
                           pick(self.velocity), pick(self.velocity_cov), self.path)


def _signed_square(s: FloatArray) -> FloatArray:
    """RTKLIB writes a covariance ``c`` as ``sign(c)·√|c|`` (its ``sqvar``): undo it."""
    return s * np.abs(s)


def _neu_cov_to_ned(sn, se, su, sne, seu, sun) -> FloatArray:
    """The NED covariance from RTKLIB's six columns (σ north, east, up; signed roots of the
    north-east, east-up and up-north covariances); down = −up flips the signs of the
    covariances with the vertical."""
    n = sn.shape[0]
    C = np.empty((n, 3, 3))
    C[:, 0, 0], C[:, 1, 1], C[:, 2, 2] = sn ** 2, se ** 2, su ** 2
    ne, ed, nd = _signed_square(sne), -_signed_square(seu), -_signed_square(sun)
    C[:, 0, 1] = C[:, 1, 0] = ne
    C[:, 1, 2] = C[:, 2, 1] = ed
    C[:, 0, 2] = C[:, 2, 0] = nd
    return C


_DATE = re.compile(r"(\d{4})/(\d{1,2})/(\d{1,2})")
_TIME = re.compile(r"(\d{1,2}):(\d{1,2}):(\d{1,2}(?:\.\d*)?)")


def _gpst_seconds(a: str, b: str, where: str) -> float:
    """``yyyy/mm/dd hh:mm:ss.sss`` (or GPS week and seconds of week) as GPST seconds since
    1970-01-01 (calendar seconds, no leap seconds)."""
    d, t = _DATE.fullmatch(a), _TIME.fullmatch(b)
    if d and t:
        try:
            day = _dt.date(int(d[1]), int(d[2]), int(d[3])).toordinal() - 719163  # 1970-01-01
        except ValueError:
            raise ImunavError(f"{where}: {a!r} is not a date") from None
        h, m, s = int(t[1]), int(t[2]), float(t[3])
        if h > 23 or m > 59 or s >= 61:
            raise ImunavError(f"{where}: {b!r} is not a time of day")
        return day * 86400.0 + h * 3600.0 + m * 60.0 + s
    try:
        week, tow = int(a), float(b)
    except ValueError:
        raise ImunavError(f"{where}: expected a GPST date and time (yyyy/mm/dd hh:mm:ss.sss) "
                          f"or a GPS week and seconds, got {a!r} {b!r}") from None
    if week < 0 or not 0 <= tow < 604800:
        raise ImunavError(f"{where}: GPS week {week} and seconds {tow:g} out of range")
    return GPST_EPOCH + week * 604800.0 + tow


def _header(lines: list[tuple[int, str]], path: Path) -> list[str]:
    """The column names of the header comment (the time label first)."""
    for _, text in lines:
        if re.search(r"lat/lon/height=\S+/geodetic", text):
            raise ImunavError(f"{path}: heights are geodetic (above the geoid); imunav needs "
                              "heights above the ellipsoid (RTKLIB: out-height = ellipsoidal)")
    for line_no, text in lines:
        names = [c for c in re.split(r"[\s,]+", text.lstrip("%").strip()) if c]
        for other, what in _OTHER_FORMATS.items():
            if other in names:
                raise ImunavError(f"{path}, line {line_no}: a solution in {what}; imunav reads "
                                  "latitude/longitude/height in degrees (RTKLIB: out-solformat "
                                  "= llh, out-degform = deg)")
        if "latitude(deg)" in names:
            return names
    raise ImunavError(f"{path}: no RTKLIB column header (a '%' comment line naming "
                      "latitude(deg) longitude(deg) height(m) …)")


def read_pos(path: str | Path) -> PosSolution:
    """Read an RTKLIB position solution (``.pos``) in latitude/longitude/height.

    Comment lines start with ``%``; the one naming the columns (``GPST latitude(deg)
    longitude(deg) height(m) Q ns sdn(m) sde(m) sdu(m) sdne(m) sdeu(m) sdun(m) age(s) ratio``,
    then optionally ``vn(m/s) ve(m/s) vu(m/s) sdvn sdve sdvu sdvne sdveu sdvun``) is checked
    column by column. Values may be separated by spaces or commas.

    Parameters
    ----------
    path : str or Path
        The solution file.

    Returns
    -------
    PosSolution
        Times in GPST seconds since 1970-01-01 (the time base of :func:`read_tag`), positions
        in radians and metres, velocity and covariances converted from north/east/up to
        north/east/down. RTKLIB's covariance columns hold ``sign(c)·√|c|``; they are squared
        back with their sign.

    Raises
    ------
    ImunavError
        If the file is missing or not text; it has no column header, or its columns are not
        those above (an ECEF, east/north/up or degrees-minutes-seconds solution, or a column
        imunav does not know); its times are not GPST (UTC, JST); its heights are geodetic;
        a row has the wrong number of values, a value is not a finite number, or the times do
        not increase (each naming the file and line); or it holds no epoch.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> p = pathlib.Path(tmp.name) / "x.pos"
    >>> _ = p.write_text("%  GPST  latitude(deg) longitude(deg) height(m) Q ns sdn(m) sde(m) "
    ...                  "sdu(m) sdne(m) sdeu(m) sdun(m) age(s) ratio\\n"
    ...                  "1980/01/06 00:00:01.500 45.0 7.0 100.0 1 9 0.01 0.02 0.03 0 0 0 0 9\\n")
    >>> sol = read_pos(p)
    >>> float(sol.t[0] - GPST_EPOCH), sol.llh[0].round(6).tolist(), sol.position_sd[0].tolist()
    (1.5, [0.785398, 0.122173, 100.0], [0.01, 0.02, 0.03])
    >>> tmp.cleanup()
    """
    path = Path(path)
    if not path.is_file():
        raise ImunavError(f"GNSS solution file not found: {path}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ImunavError(f"{path}: not a text file (byte {exc.start} is not UTF-8)") from None
    comments, rows = [], []
    for line_no, line in enumerate(text.splitlines(), start=1):
        s = line.strip()
        if not s:
            continue
        (comments if s.startswith("%") else rows).append((line_no, s))
    names = _header(comments, path)
    label, cols = names[0], names[1:]
    if label != "GPST":
        raise ImunavError(f"{path}: times are {label}; imunav needs GPST (RTKLIB: out-timesys "
                          "= gpst), the time base of the IMU's tag file")
    if tuple(cols) not in (POS_COLUMNS, POS_COLUMNS + VEL_COLUMNS):
        want = " ".join(POS_COLUMNS) + " [" + " ".join(VEL_COLUMNS) + "]"
        unknown = [c for c in cols if c not in POS_COLUMNS + VEL_COLUMNS]
        why = f"unknown column(s) {', '.join(unknown)}" if unknown else "columns out of order"
        raise ImunavError(f"{path}: {why}; expected GPST {want}")
    if not rows:
        raise ImunavError(f"{path}: no solution epochs (only comments)")
    k = len(cols)
    t = np.empty(len(rows))
    vals = np.empty((len(rows), k))
    for i, (line_no, s) in enumerate(rows):
        cells = [c for c in re.split(r"[\s,]+", s) if c]
        where = f"{path}, line {line_no}"
        if len(cells) != k + 2:
            raise ImunavError(f"{where}: expected {k + 2} values (date, time and {k} columns), "
                              f"got {len(cells)}")
        t[i] = _gpst_seconds(cells[0], cells[1], where)
        for j, c in enumerate(cells[2:]):
            try:
                vals[i, j] = float(c)
            except ValueError:
                raise ImunavError(f"{where}, column {cols[j]}: {c!r} is not a number") from None
            if not math.isfinite(vals[i, j]):
                raise ImunavError(f"{where}, column {cols[j]}: NaN or inf")
        if i and t[i] <= t[i - 1]:
            raise ImunavError(f"{where}: time {cells[0]} {cells[1]} does not follow the "
                              "previous epoch's")
    llh = np.column_stack([np.radians(vals[:, 0]), np.radians(vals[:, 1]), vals[:, 2]])
    if np.any(np.abs(vals[:, 0]) > 90):
        i = int(np.argmax(np.abs(vals[:, 0]) > 90))
        raise ImunavError(f"{path}, line {rows[i][0]}: latitude {vals[i, 0]:g}° is not in "
                          "[−90°, 90°]")
    pos_cov = _neu_cov_to_ned(*(vals[:, j] for j in range(5, 11)))
    vel = vel_cov = None
    if k == len(POS_COLUMNS) + len(VEL_COLUMNS):
        v = vals[:, 13:16]
        vel = np.column_stack([v[:, 0], v[:, 1], -v[:, 2]])
        vel_cov = _neu_cov_to_ned(*(vals[:, j] for j in range(16, 22)))
    return PosSolution(t, llh, vals[:, 3].astype(int), vals[:, 4].astype(int), pos_cov,
                       vals[:, 11].copy(), vals[:, 12].copy(), vel, vel_cov, str(path))


@dataclass
class TimeTag:
    """An RTKLIB time-tag file: when each block of a logged stream was written.

    Attributes
    ----------
    start : float
        The log's start: GPST seconds since 1970-01-01.
    tick : ndarray of int64, shape (k,)
        Milliseconds since the start at which each block was written.
    fpos : ndarray of int64, shape (k,)
        The position in the logged file after that block (bytes).
    header : str
        The header text (``"TIMETAG RTKLIB demo5"``).
    tick_start : int
        The logger's millisecond tick at the start (the uint32 after the header text).
    path : str
        The file read.
    """

    start: float
    tick: np.ndarray
    fpos: np.ndarray
    header: str
    tick_start: int = 0
    path: str = ""

    @property
    def duration(self) -> float:
        """Seconds from the start to the last block.

        Returns
        -------
        float
        """
        return float(self.tick[-1]) / 1000.0 if self.tick.size else 0.0


def read_tag(path: str | Path) -> TimeTag:
    """Read an RTKLIB time-tag file (``FILE.tag`` beside a stream logged as ``FILE``).

    Little-endian: a 60-byte header starting ``TIMETAG RTKLIB``, a uint32 (the logger's tick at
    the start; not needed), the start time as a uint32 of integer GPST seconds since 1970-01-01
    and a float64 fraction, then 8-byte records of a uint32 tick (ms since the start) and a
    uint32 file position.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    TimeTag

    Raises
    ------
    ImunavError
        If the file is missing, does not start with ``TIMETAG RTKLIB``, is shorter than its
        header, has a partial record, a fraction of a second outside [0, 1), no record, or
        ticks or file positions that go backwards.

    Examples
    --------
    >>> import struct, tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> p = pathlib.Path(tmp.name) / "imu.csv.tag"
    >>> head = b"TIMETAG RTKLIB demo5".ljust(60, b"\\0") + struct.pack("<IId", 7, 1752003261, 0.5)
    >>> _ = p.write_bytes(head + struct.pack("<IIII", 100, 40, 1100, 480))
    >>> tag = read_tag(p)
    >>> tag.start - 1752003261, tag.tick.tolist(), tag.fpos.tolist(), tag.duration
    (0.5, [100, 1100], [40, 480], 1.1)
    >>> tmp.cleanup()
    """
    path = Path(path)
    if not path.is_file():
        raise ImunavError(f"time-tag file not found: {path}")
    raw = path.read_bytes()
    if not raw.startswith(TAG_HEADER):
        raise ImunavError(f"{path}: not an RTKLIB time-tag file (it does not start with "
                          f"{TAG_HEADER.decode()!r})")
    if len(raw) < TAG_PREFIX:
        raise ImunavError(f"{path}: {len(raw)} bytes, shorter than a tag file's {TAG_PREFIX}-byte "
                          "header")
    rest = len(raw) - TAG_PREFIX
    if rest % 8:
        raise ImunavError(f"{path}: {rest} bytes of records is not a whole number of 8-byte "
                          "records (truncated?)")
    if rest == 0:
        raise ImunavError(f"{path}: no time-tag records")
    tick0, sec, frac = struct.unpack("<IId", raw[60:TAG_PREFIX])
    if not 0.0 <= frac < 1.0:
        raise ImunavError(f"{path}: start time fraction {frac!r} is not in [0, 1)")
    rec = np.frombuffer(raw, dtype="<u4", offset=TAG_PREFIX).reshape(-1, 2).astype(np.int64)
    tick, fpos = rec[:, 0], rec[:, 1]
    for name, a in (("tick", tick), ("file position", fpos)):
        back = np.diff(a) < 0
        if back.any():
            i = int(np.argmax(back)) + 1
            raise ImunavError(f"{path}: record {i}: the {name} goes backwards ({a[i - 1]} → "
                              f"{a[i]})")
    head = raw[:60].split(b"\0", 1)[0].decode("ascii", "replace").strip()
    return TimeTag(float(sec) + frac, tick, fpos, head, int(tick0), str(path))


#: Largest relative difference between the counter's span and the tag's before a tag is refused
#: as belonging to another record (a crystal is off by ~1e-4; 1 % is another file).
TAG_SPAN_TOLERANCE = 0.01
#: … and the absolute part of that tolerance (s): start-up latency of a short log.
TAG_SPAN_SLACK = 1.0


def imu_times(counter_ms: npt.ArrayLike, tag: TimeTag, delay: float = 0.0, *,
              regular: bool = True) -> FloatArray:
    """Sample times of an IMU record logged through RTKLIB: its millisecond counter on the
    tag's GPST axis.

    The timing of rtklibexplorer's GNSS_IMU (``convert_imu_file.py``): the counter shifted to
    start at 0 and scaled so that the last sample falls on the last tag's tick, added to the
    tag's start time; then ``delay`` added.

    Parameters
    ----------
    counter_ms : array_like, shape (n,)
        The IMU's millisecond counter, one value per sample (strictly increasing).
    tag : TimeTag
        The tag file of the IMU log (:func:`read_tag`).
    delay : float, default 0.0
        Seconds added to every time: the logging delay. rtklibexplorer's configuration of his
        drive (``drive_config.py``, ``imu_t_off``) uses −0.125 s for his logger; imunav assumes
        none unless told.
    regular : bool, default True
        Fit a straight line to the counter first: the samples come from the IMU's own regular
        clock, and a counter read when each sample arrives jitters by a millisecond or two
        (8–11 ms steps at 100 Hz), which no strapdown integration should see as motion. False
        keeps the counter's values as they are (the author's exact times).

    Returns
    -------
    ndarray, shape (n,)
        GPST seconds since 1970-01-01.

    Raises
    ------
    ImunavError
        If ``counter_ms`` is not a 1-D finite array of at least 2 increasing values; ``delay``
        is not a finite number; the tag's span and the counter's differ by more than 1 %
        (and 1 s): the tag is another record's; or, with ``regular``, the counter departs from
        a straight line by more than half a sample interval (samples lost or the clock
        jumped: use ``regular=False``).

    Examples
    --------
    >>> import numpy as np
    >>> tag = TimeTag(start=1000.0, tick=np.array([50, 2000]), fpos=np.array([10, 900]),
    ...               header="TIMETAG RTKLIB")
    >>> imu_times([5000, 6000, 7000], tag, delay=-0.125).tolist()
    [999.875, 1000.875, 1001.875]
    """
    c = as_float_array(counter_ms, "counter_ms", ndim=1)
    if c.size < 2:
        raise ImunavError(f"counter_ms needs at least 2 samples, got {c.size}")
    d = np.diff(c)
    if np.any(d <= 0):
        i = int(np.argmax(d <= 0)) + 1
        raise ImunavError(f"counter_ms must increase: sample {i} reads {c[i]:.9g} ms after "
                          f"{c[i - 1]:.9g} ms")
    if isinstance(delay, bool) or not isinstance(delay, int | float | np.floating) or \
            not math.isfinite(delay):
        raise ImunavError(f"delay must be a finite number of seconds, got {delay!r}")
    if regular:
        k = np.arange(c.size, dtype=float)
        slope, icpt = np.polyfit(k, c, 1)
        fit = icpt + slope * k
        worst = float(np.max(np.abs(c - fit)))
        if worst > 0.5 * slope:
            i = int(np.argmax(np.abs(c - fit)))
            raise ImunavError(f"counter_ms departs from a regular clock by {worst:.6g} ms at "
                              f"sample {i} (more than half a sample interval of {slope:.6g} ms: "
                              "samples lost?); use regular=False to keep the counter as it is")
        c = fit
    span = (c[-1] - c[0]) / 1000.0
    tag_span = tag.duration
    if abs(tag_span - span) > max(TAG_SPAN_TOLERANCE * span, TAG_SPAN_SLACK):
        name = f"tag {tag.path}" if tag.path else "tag"
        raise ImunavError(f"{name} spans {tag_span:.6g} s but counter_ms spans {span:.6g} s: "
                          "the tag belongs to another record")
    if abs(tag_span - span) > 1e-3 * span:
        warnings.warn(f"the tag spans {tag_span:.6g} s and the IMU counter {span:.6g} s "
                      f"({(tag_span / span - 1) * 1e6:.0f} ppm apart): the counter is scaled "
                      "to the tag", stacklevel=2)
    return tag.start + (c - c[0]) * (tag_span / span) / 1000.0 + float(delay)


def velocity_lag(t: FloatArray, position: FloatArray, velocity: FloatArray,
                 max_lag: float = 0.5) -> float:
    """How late a GNSS receiver stamps its velocity: the lag ``L`` that best matches the velocity
    read at ``t + L`` with the central differences of its own positions (least squares on a
    grid of 1 ms, horizontal components).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Epochs (s).
    position, velocity : ndarray, shape (n, 3)
        NED (m, m/s).
    max_lag : float
        The lags searched: ±max_lag (s).

    Returns
    -------
    float
        Seconds (positive: the velocity is stamped late).
    """
    t = np.asarray(t, float)
    dt = t[2:] - t[:-2]
    ok = (dt > 0) & (dt < 4 * np.median(dt))
    vfd = (position[2:, :2] - position[:-2, :2]) / dt[:, None]
    tm = t[1:-1]
    lags = np.arange(-max_lag, max_lag + 5e-4, 1e-3)
    cost = []
    for L in lags:
        v = np.column_stack([np.interp(tm + L, t, velocity[:, j]) for j in range(2)])
        inside = ok & (tm + L >= t[0]) & (tm + L <= t[-1])
        cost.append(np.mean((v[inside] - vfd[inside]) ** 2))
    return float(lags[int(np.argmin(cost))])


def gnss_readings(sol: PosSolution, config, *, frame: str = "flat", origin=None
                  ) -> tuple[Readings, list[str]]:
    """The readings of ``[gnss]`` from an RTKLIB solution: the epochs of quality up to
    ``min_quality``, each with its own σ (north, east, down from its covariance, times
    ``float_scale`` for a float solution and ``single_scale`` for a single, DGPS or SBAS one;
    never below ``position_sigma``/``velocity_sigma`` when those are given), the velocity read
    ``velocity_delay`` later (``"auto"``: :func:`velocity_lag`).

    Parameters
    ----------
    sol : PosSolution
    config : GnssConfig
    frame : {"flat", "wgs84"}
        Positions as NED metres from ``origin`` (flat), or ``[lat, lon, h]`` (rad, rad, m).
    origin : array_like, shape (3,), optional
        ``(lat, lon, h)`` of the flat frame's origin (default the first epoch used).

    Returns
    -------
    readings : Readings
        ``x, y, z[, vx, vy, vz]`` with ``sigma``.
    notes : list of str
        What was dropped and estimated.

    Raises
    ------
    ImunavError
        For velocity asked of a solution without it, or no epoch of a usable quality.
    """
    notes = []
    keep = sol.quality <= config.min_quality
    if not keep.all():
        notes.append(f"{int((~keep).sum())} of {len(sol)} epochs of quality above "
                     f"{config.min_quality} not used")
    if not keep.any():
        raise ImunavError(f"{sol.path}: no epoch of quality up to min_quality = "
                          f"{config.min_quality}", argument="gnss")
    full = sol
    sol = sol.select(keep)
    scale = np.where(sol.quality == 1, 1.0, np.where(sol.quality == 2, config.float_scale,
                                                     config.single_scale))
    scale = np.where(sol.quality == 6, 1.0, scale)
    pos = sol.ned(origin if origin is not None else sol.llh[0]) if frame == "flat" else sol.llh
    sd = sol.position_sd * scale[:, None]
    if config.position_sigma is not None:
        sd = np.maximum(sd, config.position_sigma)
    vals, sds = [pos], [sd]
    if config.velocity_sigma is not None:
        if sol.velocity is None:
            raise ImunavError(f"{sol.path}: [gnss] velocity_sigma is set but the solution has "
                              "no velocity columns", argument="gnss")
        delay = config.velocity_delay
        if delay == "auto":
            delay = velocity_lag(full.t, full.ned(full.llh[0]), full.velocity)
            notes.append(f"the receiver stamps its velocity {1000 * delay:.0f} ms late "
                         "(from its own positions): read that much later")
        vel = sol.velocity
        if delay:
            vel = np.column_stack([np.interp(sol.t + delay, full.t, full.velocity[:, j])
                                   for j in range(3)])
        vsd = sol.velocity_sd * scale[:, None]
        vsd = np.maximum(vsd, config.velocity_sigma)
        vals.append(vel)
        sds.append(vsd)
    return Readings(sol.t, np.concatenate(vals, axis=1), np.concatenate(sds, axis=1)), notes
