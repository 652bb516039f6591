"""Aiding sensors: their description (``AIDING.toml``), their simulation from the motion, and
the SHOE zero-velocity detector on IMU data.

An ``AIDING.toml`` has one optional table per aid (every value SI; an angle may also be a string
with its unit, ``"2 deg"``: rad, mrad or deg — not ``%``, a scale factor's unit)::

    [gnss]      rate (Hz), position_sigma (m, white), velocity_sigma (m/s, white; no velocity
                without it), correlated_sigma (m) and correlation_time (s) of a first-order
                Gauss–Markov position error, correlated_model = "state" | "white" (how the
                filter treats it: three states of its own, the default, or as white noise of
                variance position_sigma² + correlated_sigma², a common simplification whose
                cost imunav assess measures), lever_arm (m, body frame, default [0, 0, 0]),
                outages = [[t0, t1], …] (s: no fix with t0 ≤ t ≤ t1)
    [baro]      rate (Hz), sigma (m, white), bias_drift (m/√s: a random walk from 0)
    [heading]   rate (Hz), sigma (rad): a magnetometer-like yaw reference
    [nhc]       sigma (m/s): a wheeled vehicle's zero lateral and vertical body velocity;
                rate (Hz, default 10): how often the filter applies the constraint
    [zupt]      sigma (m/s), detector = "truth" | "shoe", window (samples, default 3) and
                threshold (default 3e4) of the SHOE detector (Skog et al. 2010, as OpenShoe)
    [initial]   position_sigma (m), velocity_sigma (m/s), attitude_sigma (rad): the filter's
                initial uncertainty (default 0: the initial state is known, as from a truth file)

A sensor's ``rate`` and ``sigma`` (``position_sigma`` for GNSS) are required; everything else is
optional. The simulation (:func:`simulate_aiding`) draws each sensor's own errors from the exact
motion: GNSS at the antenna (``p + C_nb l``, ``v + C_nb (ω_b × l)``) plus white and
Gauss–Markov errors (exact discrete recursion across any gap), the barometric altitude ``−z``
plus a random-walk bias and white noise, the true yaw plus white noise, the constraint readings
of NHC (0 plus the slip the constraint's sigma stands for), and the true stance intervals
(zero velocity) for ZUPT with the ``truth`` detector. Each sensor takes its own random stream
(``SeedSequence(seed, spawn_key=(AIDING_STREAM, run)).spawn(5)``: GNSS, baro, heading, NHC,
ZUPT), apart from the IMU's, so a run is reproducible and adding a sensor changes no other.

On the rotating Earth (an :class:`~imunav.motion.geodetic.EarthMotion`) the same errors are
drawn in the local NED frame: GNSS ``[lat, lon, h]`` (rad, rad, m) of the antenna with its NED
position errors, its velocity relative to the Earth in local NED; the barometer the height above
the ellipsoid; the heading the yaw relative to local north.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors.signals``.
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from imunav.core import units as U
from imunav.core.constants import DEG, G0
from imunav.core.kernels import FloatArray, cross, quat_conj, quat_rotate, quat_to_dcm
from imunav.core.validation import ImunavError, read_toml, show
from imunav.earth import dcm_ned_to_ecef, earth_rate_ned, ecef_to_geodetic, geodetic_to_ecef
from imunav.motion.base import BaseMotion

__all__ = ["AIDING_STREAM", "ANGLE_UNITS", "SECTIONS", "SHOE_SIGMA_A", "SHOE_SIGMA_G", "AidingConfig",
           "AidingData", "BaroConfig", "GnssConfig", "HeadingConfig", "InitialConfig",
           "NhcConfig", "Readings", "ZuptConfig", "aiding_streams", "intervals_of",
           "shoe_intervals", "shoe_statistic", "simulate_aiding", "true_stance", "wrap_angle"]

#: The spawn key that separates the aiding sensors' random streams from the IMU's.
AIDING_STREAM = 0xA1D

#: The SHOE detector's noise levels (OpenShoe's defaults, Skog et al. 2010): accelerometer
#: 0.01 m/s², gyro 0.1 °/s.
SHOE_SIGMA_A = 0.01
SHOE_SIGMA_G = 0.1 * DEG


def wrap_angle(a):
    """An angle (array) wrapped to [−π, π).

    Parameters
    ----------
    a : array_like
        Radians.

    Returns
    -------
    ndarray or float
    """
    return (np.asarray(a, dtype=float) + np.pi) % (2 * np.pi) - np.pi


# ----------------------------------------------------------------------------- configuration

#: The units an angle of an ``AIDING.toml`` may be written in: those of
#: :data:`imunav.core.units.ANGLE` less ``%`` (a cross-axis coupling, not an angle of its own).
ANGLE_UNITS = {u: f for u, f in U.ANGLE.items() if u != "%"}


def _number(table: dict, key: str, where: str, unit: str, *, positive: bool = True,
            required: bool = False, default=None, angle: bool = False):
    """``table[key]`` as a finite number, > 0 (``positive``) or ≥ 0; an angle may be a string
    with its unit (of :data:`ANGLE_UNITS`). Each message names ``[where] key`` and, unless
    ``unit`` is empty (a plain number), its unit."""
    in_unit = f" ({unit})" if unit else ""
    if key not in table:
        if required:
            raise ImunavError(f"[{where}] {key}{in_unit} is required")
        return default
    v = raw = table[key]
    if angle and isinstance(v, str):
        v = _angle(v, f"[{where}] {key}")
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
        raise ImunavError(f"[{where}] {key} must be a finite number{in_unit}, got {show(raw)}")
    v = float(v)
    if positive and not v > 0:
        raise ImunavError(f"[{where}] {key} must be a positive number{in_unit}, got {show(raw)}")
    if not positive and v < 0:
        raise ImunavError(f"[{where}] {key} must be a non-negative number{in_unit}, got "
                          f"{show(raw)}")
    return v


def _angle(text: str, name: str) -> float:
    """An angle written with its unit (``"2 deg"``) in radians, its sign kept (the caller checks
    the range, so that its message says what the check is)."""
    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", text)
    if not m:
        raise ImunavError(f"{name} = {text!r}: expected a number or '<number> <unit>' (an "
                          f"angle: {', '.join(ANGLE_UNITS)})")
    unit = U.normalise(m.group(2))
    if unit not in ANGLE_UNITS:
        why = " (% is for scale factors)" if unit == "%" else ""
        got = f"unit {m.group(2)!r} is not an angle unit{why}" if unit else "no unit"
        raise ImunavError(f"{name} = {text!r}: {got}; accepted: {', '.join(ANGLE_UNITS)}")
    return float(m.group(1)) * ANGLE_UNITS[unit]


def _keys(table, where: str, allowed: tuple[str, ...]) -> dict:
    if not isinstance(table, dict):
        raise ImunavError(f"[{where}] must be a table")
    bad = sorted(set(table) - set(allowed))
    if bad:
        raise ImunavError(f"unknown key(s) in [{where}]: {', '.join(bad)}; expected "
                          f"{', '.join(allowed)}")
    return table


@dataclass(frozen=True)
class GnssConfig:
    """A GNSS receiver: position fixes (and velocity) at ``rate``.

    Attributes
    ----------
    rate : float
        Hz.
    position_sigma : float
        White position noise (m, per axis).
    velocity_sigma : float or None
        White velocity noise (m/s, per axis); None: no velocity.
    correlated_sigma : float
        Stationary σ of a first-order Gauss–Markov position error (m, per axis); 0: none.
    correlation_time : float or None
        Its correlation time (s).
    lever_arm : tuple of float
        The antenna in the body frame (m).
    outages : tuple of (float, float)
        Intervals (s) without fixes, ends included.
    correlated_model : {"state", "white"}
        How the filter treats the correlated error: as three Gauss–Markov states of its own, or
        as white noise (its variance added to ``position_sigma²``) — the simulation draws it
        correlated either way.
    """

    rate: float
    position_sigma: float
    velocity_sigma: float | None = None
    correlated_sigma: float = 0.0
    correlation_time: float | None = None
    lever_arm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    outages: tuple[tuple[float, float], ...] = ()
    correlated_model: str = "state"

    KEYS = ("rate", "position_sigma", "velocity_sigma", "correlated_sigma", "correlation_time",
            "lever_arm", "outages", "correlated_model")

    #: How the filter may treat the correlated error.
    CORRELATED_MODELS = ("state", "white")

    @classmethod
    def from_dict(cls, d: dict) -> GnssConfig:
        """Parse the ``[gnss]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        GnssConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing ``rate`` or ``position_sigma``, a non-positive sigma
            or rate, a correlated error without its correlation time, a lever arm that is not
            3 numbers, an outage that is not ``[t0, t1]`` with ``0 ≤ t0 < t1``, or a
            ``correlated_model`` other than ``"state"`` or ``"white"``.
        """
        d = _keys(d, "gnss", cls.KEYS)
        rate = _number(d, "rate", "gnss", "Hz", required=True)
        ps = _number(d, "position_sigma", "gnss", "m", required=True)
        vs = _number(d, "velocity_sigma", "gnss", "m/s")
        cs = _number(d, "correlated_sigma", "gnss", "m", positive=False, default=0.0)
        tau = _number(d, "correlation_time", "gnss", "s")
        if cs > 0 and tau is None:
            raise ImunavError("[gnss] correlated_sigma needs correlation_time (s)")
        lever = d.get("lever_arm", [0.0, 0.0, 0.0])
        if (not isinstance(lever, list) or len(lever) != 3 or
                not all(isinstance(x, numbers.Real) and not isinstance(x, bool)
                        and math.isfinite(x) for x in lever)):
            raise ImunavError(f"[gnss] lever_arm must be 3 finite numbers (m, body frame), got "
                              f"{show(lever)}")
        outages = d.get("outages", [])
        if not isinstance(outages, list):
            raise ImunavError(f"[gnss] outages must be a list of [t0, t1] (s), got "
                              f"{show(outages)}")
        if outages and all(isinstance(o, numbers.Real) for o in outages):
            hint = f": write [{show(outages)}] for one outage" if len(outages) == 2 else ""
            raise ImunavError(f"[gnss] outages must be a list of [t0, t1] (s), got "
                              f"{show(outages)}{hint}")
        out = []
        for i, o in enumerate(outages):
            if (not isinstance(o, list) or len(o) != 2 or
                    not all(isinstance(x, numbers.Real) and not isinstance(x, bool)
                            and math.isfinite(x) for x in o) or not 0 <= o[0] < o[1]):
                raise ImunavError(f"[gnss] outages[{i}] must be [t0, t1] with 0 ≤ t0 < t1 (s), "
                                  f"got {show(o)}")
            if out and o[0] <= out[-1][1]:
                raise ImunavError(f"[gnss] outages[{i}] = {show(o)} must start after "
                                  f"outages[{i - 1}] ends ({out[-1][1]:g} s): list them in "
                                  "time order, without overlaps")
            out.append((float(o[0]), float(o[1])))
        model = d.get("correlated_model", "state")
        if model not in cls.CORRELATED_MODELS:
            raise ImunavError(f"[gnss] correlated_model must be \"state\" or \"white\", got "
                              f"{show(model)}")
        return cls(rate, ps, vs, cs, tau if cs > 0 else None,
                   tuple(float(x) for x in lever), tuple(out), model)

    def check_within(self, start: float, end: float) -> None:
        """Refuse an outage that lies wholly outside the record ``[start, end]`` (s).

        An outage running past the end is kept (GNSS lost until the end); one that starts at or
        after the end, or ends before the start, would silently change nothing.

        Parameters
        ----------
        start, end : float
            The record's first and last time (s).

        Raises
        ------
        ImunavError
            Naming ``[gnss] outages[i]`` and the record's span.
        """
        for i, (t0, t1) in enumerate(self.outages):
            if t0 >= end or t1 <= start:
                raise ImunavError(f"[gnss] outages[{i}] = [{t0:g}, {t1:g}] s lies outside the "
                                  f"record ({start:g} … {end:g} s)", argument="aiding")

    def in_outage(self, t: FloatArray) -> np.ndarray:
        """Whether each time lies in an outage.

        Parameters
        ----------
        t : ndarray
            Times (s).

        Returns
        -------
        ndarray of bool
        """
        t = np.asarray(t, dtype=float)
        bad = np.zeros(t.shape, dtype=bool)
        for t0, t1 in self.outages:
            bad |= (t >= t0) & (t <= t1)
        return bad


@dataclass(frozen=True)
class BaroConfig:
    """A barometric altimeter.

    Attributes
    ----------
    rate : float
        Hz.
    sigma : float
        White altitude noise (m).
    bias_drift : float
        Random-walk density of its bias (m/√s), from 0.
    """

    rate: float
    sigma: float
    bias_drift: float = 0.0

    KEYS = ("rate", "sigma", "bias_drift")

    @classmethod
    def from_dict(cls, d: dict) -> BaroConfig:
        """Parse the ``[baro]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        BaroConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing or non-positive rate or sigma, a negative drift.
        """
        d = _keys(d, "baro", cls.KEYS)
        return cls(_number(d, "rate", "baro", "Hz", required=True),
                   _number(d, "sigma", "baro", "m", required=True),
                   _number(d, "bias_drift", "baro", "m/√s", positive=False, default=0.0))


@dataclass(frozen=True)
class HeadingConfig:
    """A yaw reference (magnetometer-like).

    Attributes
    ----------
    rate : float
        Hz.
    sigma : float
        White yaw noise (rad).
    """

    rate: float
    sigma: float

    KEYS = ("rate", "sigma")

    @classmethod
    def from_dict(cls, d: dict) -> HeadingConfig:
        """Parse the ``[heading]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        HeadingConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing or non-positive rate or sigma.
        """
        d = _keys(d, "heading", cls.KEYS)
        return cls(_number(d, "rate", "heading", "Hz", required=True),
                   _number(d, "sigma", "heading", "rad", required=True, angle=True))


@dataclass(frozen=True)
class NhcConfig:
    """The non-holonomic constraint of a wheeled vehicle: zero lateral and vertical body velocity.

    Attributes
    ----------
    sigma : float
        How well the constraint holds (m/s): the slip, per component.
    rate : float
        How often it is applied (Hz).
    """

    sigma: float
    rate: float = 10.0

    KEYS = ("sigma", "rate")

    @classmethod
    def from_dict(cls, d: dict) -> NhcConfig:
        """Parse the ``[nhc]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        NhcConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing or non-positive sigma, a non-positive rate.
        """
        d = _keys(d, "nhc", cls.KEYS)
        return cls(_number(d, "sigma", "nhc", "m/s", required=True),
                   _number(d, "rate", "nhc", "Hz", default=10.0))


@dataclass(frozen=True)
class ZuptConfig:
    """Zero-velocity updates during stance.

    Attributes
    ----------
    sigma : float
        Velocity noise of the update (m/s, per axis).
    detector : {"truth", "shoe"}
        The stance intervals of the motion (``zupt.csv``), or the SHOE detector on the IMU data.
    window : int
        SHOE window (samples).
    threshold : float
        SHOE threshold: stance where the statistic is below it.
    """

    sigma: float
    detector: str = "truth"
    window: int = 3
    threshold: float = 3e4

    KEYS = ("sigma", "detector", "window", "threshold")

    @classmethod
    def from_dict(cls, d: dict) -> ZuptConfig:
        """Parse the ``[zupt]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        ZuptConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing or non-positive sigma, an unknown detector, a window
            that is not a whole number ≥ 1, a non-positive threshold.
        """
        d = _keys(d, "zupt", cls.KEYS)
        sigma = _number(d, "sigma", "zupt", "m/s", required=True)
        det = d.get("detector", "truth")
        if det not in ("truth", "shoe"):
            raise ImunavError(f"[zupt] detector must be \"truth\" or \"shoe\", got {show(det)}")
        w = d.get("window", 3)
        if isinstance(w, bool) or not isinstance(w, numbers.Integral) or w < 1:
            raise ImunavError(f"[zupt] window must be a whole number of samples ≥ 1, got "
                              f"{show(w)}")
        return cls(sigma, det, int(w), _number(d, "threshold", "zupt", "", default=3e4))


@dataclass(frozen=True)
class InitialConfig:
    """The filter's initial uncertainty (1σ per axis).

    Attributes
    ----------
    position_sigma : float
        m.
    velocity_sigma : float
        m/s.
    attitude_sigma : float
        rad (each of the three small rotation angles).
    """

    position_sigma: float = 0.0
    velocity_sigma: float = 0.0
    attitude_sigma: float = 0.0

    KEYS = ("position_sigma", "velocity_sigma", "attitude_sigma")

    @classmethod
    def from_dict(cls, d: dict) -> InitialConfig:
        """Parse the ``[initial]`` table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        InitialConfig

        Raises
        ------
        ImunavError
            For an unknown key or a negative value.
        """
        d = _keys(d, "initial", cls.KEYS)
        return cls(_number(d, "position_sigma", "initial", "m", positive=False, default=0.0),
                   _number(d, "velocity_sigma", "initial", "m/s", positive=False, default=0.0),
                   _number(d, "attitude_sigma", "initial", "rad", positive=False, default=0.0,
                           angle=True))


#: The tables of an ``AIDING.toml`` and their parsers.
SECTIONS = {"gnss": GnssConfig, "baro": BaroConfig, "heading": HeadingConfig, "nhc": NhcConfig,
            "zupt": ZuptConfig, "initial": InitialConfig}


@dataclass(frozen=True)
class AidingConfig:
    """Every aid of an ``AIDING.toml`` (None where absent).

    Attributes
    ----------
    gnss : GnssConfig or None
    baro : BaroConfig or None
    heading : HeadingConfig or None
    nhc : NhcConfig or None
    zupt : ZuptConfig or None
    initial : InitialConfig
    """

    gnss: GnssConfig | None = None
    baro: BaroConfig | None = None
    heading: HeadingConfig | None = None
    nhc: NhcConfig | None = None
    zupt: ZuptConfig | None = None
    initial: InitialConfig = field(default_factory=InitialConfig)

    @classmethod
    def from_dict(cls, d: dict) -> AidingConfig:
        """Parse the tables of an ``AIDING.toml``.

        Parameters
        ----------
        d : dict

        Returns
        -------
        AidingConfig

        Raises
        ------
        ImunavError
            For an unknown table or a table its parser refuses.
        """
        bad = sorted(set(d) - set(SECTIONS))
        if bad:
            raise ImunavError(f"unknown table(s) in AIDING file: {', '.join(bad)}; expected "
                              f"{', '.join(f'[{s}]' for s in SECTIONS)}")
        parsed = {k: SECTIONS[k].from_dict(v) for k, v in d.items()}
        return cls(**parsed)

    @classmethod
    def from_toml(cls, path: str | Path) -> AidingConfig:
        """Read an ``AIDING.toml``.

        Parameters
        ----------
        path : str or Path

        Returns
        -------
        AidingConfig

        Raises
        ------
        ImunavError
            For a missing or malformed file, or contents :meth:`from_dict` refuses (the message
            starts with the file name).
        """
        path = Path(path)
        d = read_toml(path, "aiding file")
        try:
            return cls.from_dict(d)
        except ImunavError as exc:
            raise ImunavError(f"{path}: {exc}") from None

    @property
    def sensors(self) -> list[str]:
        """The aids present, in file order (``gnss``, ``baro``, ``heading``, ``nhc``, ``zupt``).

        Returns
        -------
        list of str
        """
        return [s for s in ("gnss", "baro", "heading", "nhc", "zupt") if getattr(self, s)]


# ----------------------------------------------------------------------------- measurements

@dataclass
class Readings:
    """One sensor's readings: times and values.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s), strictly increasing.
    values : ndarray, shape (n, m)
        The readings (SI): GNSS ``x, y, z[, vx, vy, vz]``, baro ``alt``, heading ``yaw``,
        NHC ``vy, vz``.
    """

    t: FloatArray
    values: FloatArray

    def __len__(self) -> int:
        return int(self.t.shape[0])


@dataclass
class AidingData:
    """What the aiding sensors measured over a record.

    Attributes
    ----------
    gnss, baro, heading, nhc : Readings or None
    zupt : ndarray, shape (k, 2), or None
        Stance intervals ``[t0, t1]`` (s).
    """

    gnss: Readings | None = None
    baro: Readings | None = None
    heading: Readings | None = None
    nhc: Readings | None = None
    zupt: FloatArray | None = None


def aiding_streams(seed: int = 0, run: int = 0) -> list[np.random.Generator]:
    """The random generators of one run's aiding sensors (GNSS, baro, heading, NHC, ZUPT).

    Parameters
    ----------
    seed : int
    run : int
        The Monte Carlo run.

    Returns
    -------
    list of numpy.random.Generator
    """
    ss = np.random.SeedSequence(seed, spawn_key=(AIDING_STREAM, run))
    return [np.random.default_rng(s) for s in ss.spawn(5)]


def _times(rate: float, duration: float, t0: float) -> FloatArray:
    n = int(np.floor(duration * rate * (1 + 1e-12)))
    return t0 + np.arange(1, n + 1) / rate


def simulate_aiding(motion: BaseMotion, config: AidingConfig, duration: float, *,
                    seed: int = 0, run: int = 0, imu_rate: float | None = None, t0: float = 0.0
                    ) -> AidingData:
    """The aiding sensors' readings on ``motion``, each with its own errors.

    Parameters
    ----------
    motion : BaseMotion
    config : AidingConfig
    duration : float
        Seconds: readings at ``t0 + k/rate ≤ t0 + duration``, k ≥ 1.
    seed : int
        Random seed (the aiding streams of :func:`aiding_streams`).
    run : int
        Monte Carlo run (its own streams).
    imu_rate : float, optional
        The IMU rate (Hz): where the true stance intervals of ZUPT are found (default 100).
    t0 : float
        Start time (s).

    Returns
    -------
    AidingData
        In the flat frame: GNSS ``x, y, z`` (m, NED) and velocity; baro altitude ``−z``. On
        the Earth (``motion.frame == "wgs84"``): GNSS ``lat, lon, h`` (rad, rad, m) and NED
        velocity relative to the Earth; baro the height above the ellipsoid.
    """
    earth = getattr(motion, "frame", "flat") == "wgs84"
    rg, rb, rh, rn, _ = aiding_streams(seed, run)
    out = AidingData()
    if config.gnss is not None:
        c = config.gnss
        c.check_within(t0, t0 + duration)
        t = _times(c.rate, duration, t0)
        q = motion.attitude(t)
        lever = np.asarray(c.lever_arm)
        arm = quat_rotate(q, np.broadcast_to(lever, (t.size, 3)))         # NED
        pos = motion.position(t)
        if not earth:
            pos = pos + arm
        white = rg.normal(0.0, c.position_sigma, (t.size, 3))
        corr = np.zeros((t.size, 3))
        if c.correlated_sigma > 0 and t.size:
            e = rg.normal(0.0, c.correlated_sigma, 3)             # stationary start
            dts = np.diff(np.concatenate([[t0], t]))
            for i, dt in enumerate(dts):
                a = math.exp(-dt / c.correlation_time)
                e = a * e + math.sqrt(1 - a * a) * c.correlated_sigma * rg.normal(0.0, 1.0, 3)
                corr[i] = e
        if earth:                     # the antenna and its NED errors, exactly on the ellipsoid
            C_en = dcm_ned_to_ecef(pos[:, 0], pos[:, 1])
            r = geodetic_to_ecef(pos[:, 0], pos[:, 1], pos[:, 2])
            r = r + np.einsum("nij,nj->ni", C_en, arm + white + corr)
            vals = [np.stack(ecef_to_geodetic(r), axis=-1)]
        else:
            vals = [pos + white + corr]
        if c.velocity_sigma is not None:
            w = motion.angular_rate(t)
            if earth:                 # the body rate relative to the Earth
                w = w - quat_rotate(quat_conj(q), earth_rate_ned(pos[:, 0]))
            vel = motion.velocity(t) + quat_rotate(q, cross(w, np.broadcast_to(lever, w.shape)))
            vals.append(vel + rg.normal(0.0, c.velocity_sigma, (t.size, 3)))
        keep = ~c.in_outage(t)
        out.gnss = Readings(t[keep], np.concatenate(vals, axis=1)[keep])
    if config.baro is not None:
        c = config.baro
        t = _times(c.rate, duration, t0)
        dts = np.diff(np.concatenate([[t0], t]))
        bias = np.cumsum(rb.normal(0.0, 1.0, t.size) * c.bias_drift * np.sqrt(dts))
        alt = ((motion.position(t)[:, 2] if earth else -motion.position(t)[:, 2]) + bias
               + rb.normal(0.0, c.sigma, t.size))
        out.baro = Readings(t, alt[:, None])
    if config.heading is not None:
        c = config.heading
        t = _times(c.rate, duration, t0)
        C = quat_to_dcm(motion.attitude(t))
        yaw = np.arctan2(C[:, 1, 0], C[:, 0, 0])
        out.heading = Readings(t, wrap_angle(yaw + rh.normal(0.0, c.sigma, t.size))[:, None])
    if config.nhc is not None:
        c = config.nhc
        t = _times(c.rate, duration, t0)
        out.nhc = Readings(t, rn.normal(0.0, c.sigma, (t.size, 2)))
    if config.zupt is not None and config.zupt.detector == "truth":
        out.zupt = true_stance(motion, imu_rate or 100.0, duration, t0)
    return out


def intervals_of(flags: np.ndarray, t: FloatArray) -> FloatArray:
    """The runs of True in ``flags`` as ``[t_first, t_last]`` intervals.

    Parameters
    ----------
    flags : ndarray of bool, shape (n,)
    t : ndarray, shape (n,)
        The times of the flags.

    Returns
    -------
    ndarray, shape (k, 2)
    """
    f = np.concatenate([[False], np.asarray(flags, dtype=bool), [False]])
    d = np.diff(f.astype(int))
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1
    return np.stack([t[starts], t[ends]], axis=1) if starts.size else np.zeros((0, 2))


#: Speed (m/s) below which the true motion counts as standing still.
STANCE_SPEED = 1e-9


def true_stance(motion: BaseMotion, rate: float, duration: float, t0: float = 0.0
                ) -> FloatArray:
    """The intervals where the motion stands still (zero velocity), sampled at ``rate``.

    Parameters
    ----------
    motion : BaseMotion
    rate : float
        Hz.
    duration : float
        s.
    t0 : float
        Start time (s).

    Returns
    -------
    ndarray, shape (k, 2)
        ``[t0, t1]`` of each run of samples with ``|v| ≤`` :data:`STANCE_SPEED`.
    """
    n = int(round(duration * rate))
    t = t0 + np.arange(n + 1) / rate
    still = np.linalg.norm(motion.velocity(t), axis=1) <= STANCE_SPEED
    return intervals_of(still, t)


def shoe_statistic(gyro: FloatArray, accel: FloatArray, *, g: float = G0, window: int = 3,
                   sigma_a: float = SHOE_SIGMA_A, sigma_g: float = SHOE_SIGMA_G) -> FloatArray:
    """The SHOE (stance hypothesis optimal estimation) test statistic of Skog et al. (2010).

    ``T_k = (1/W) Σ_{l ∈ W_k} ( |a_l − g ā/|ā||² / σ_a² + |ω_l|² / σ_g² )`` over a centred
    window of ``W`` samples (ā its mean specific force); stance where ``T_k`` is below the
    threshold.

    Parameters
    ----------
    gyro, accel : ndarray, shape (n, 3)
        Rate samples: ``ω_b`` (rad/s) and ``f_b`` (m/s²).
    g : float
        Gravity (m/s²).
    window : int
        ``W`` (samples).
    sigma_a, sigma_g : float
        The noise levels the statistic is normalised by.

    Returns
    -------
    ndarray, shape (n,)
        ``T`` at each sample (the window's ends padded with the edge values).
    """
    n = gyro.shape[0]
    W = max(1, min(int(window), n))
    aw = sliding_window_view(np.asarray(accel, float), W, axis=0)     # (m, 3, W)
    ww = sliding_window_view(np.asarray(gyro, float), W, axis=0)
    am = aw.mean(axis=2)
    u = am / np.linalg.norm(am, axis=1, keepdims=True)
    acc_term = ((aw - g * u[:, :, None]) ** 2).sum(axis=(1, 2)) / W
    T = acc_term / sigma_a**2 + (ww ** 2).sum(axis=(1, 2)) / W / sigma_g**2
    m = T.size
    lo = (W - 1) // 2
    out = np.empty(n)
    out[lo:lo + m] = T
    out[:lo] = T[0]
    out[lo + m:] = T[-1]
    return out


def shoe_intervals(t: FloatArray, gyro: FloatArray, accel: FloatArray, *, g: float = G0,
                   window: int = 3, threshold: float = 3e4) -> FloatArray:
    """Stance intervals by the SHOE detector.

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times (s).
    gyro, accel : ndarray, shape (n, 3)
        Rate samples (rad/s, m/s²).
    g : float
        Gravity (m/s²).
    window : int
        Samples.
    threshold : float
        Stance where the statistic is below it.

    Returns
    -------
    ndarray, shape (k, 2)
    """
    T = shoe_statistic(gyro, accel, g=g, window=window)
    return intervals_of(T < threshold, t)
