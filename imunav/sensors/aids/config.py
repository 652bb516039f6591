"""``AIDING.toml`` as a whole, the readings of every aid, their simulation, and the aids the
filter takes built from them.

An ``AIDING.toml`` has one optional table per registered aid (:data:`~imunav.sensors.aids.base.AIDS`:
``[gnss]``, ``[baro]``, ``[heading]``, ``[nhc]``, ``[zupt]``, ``[odometer]``; every value SI,
an angle may also be a string with its unit, ``"2 deg"``) and two tables of the set-up:

    [initial]   position_sigma (m), velocity_sigma (m/s), attitude_sigma (rad): the filter's
                initial uncertainty (default 0: the initial state is known, as from a truth file)
    [mounting]  rpy_deg = [roll, pitch, yaw] (°): the IMU's axes against the vehicle's
                (``v_vehicle = C(rpy) v_imu``, Z-Y-X), time_offset (s): added to the IMU's
                time stamps

A sensor's ``rate`` and ``sigma`` (``position_sigma`` for GNSS) are required; everything else is
optional. Each aid's keys, units and physical ranges are its configuration class's
(:mod:`imunav.sensors.aids`).

The simulation (:func:`simulate_aiding`) draws each sensor's own errors from the exact motion,
each sensor from its own random stream (``SeedSequence(seed, spawn_key=(AIDING_STREAM, run,
stream))``, the aid's ``stream``) apart from the IMU's, so a run is reproducible and adding a
sensor changes no other. On the rotating Earth (an
:class:`~imunav.motion.geodetic.EarthMotion`) the errors are drawn in the local NED frame: GNSS
``[lat, lon, h]`` of the antenna with its NED position errors, its velocity relative to the
Earth in local NED; the barometer the height above the ellipsoid; the heading the yaw relative
to local north.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from imunav.core.constants import DEG
from imunav.core.validation import ImunavError, read_toml
from imunav.sensors.aids.base import AIDS, Aid, Key, Measurement, Readings, TableConfig, check_keys

__all__ = ["AIDING_STREAM", "SECTIONS", "AidingConfig", "AidingData", "InitialConfig",
           "MountingConfig", "aid_stream", "aiding_streams", "aids_from", "build_measurements",
           "simulate_aiding"]

#: The spawn key that separates the aiding sensors' random streams from the IMU's.
AIDING_STREAM = 0xA1D


@dataclass(frozen=True)
class InitialConfig(TableConfig):
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

    TABLE = "initial"
    FIELDS = (Key("position_sigma", "m", "initial position σ", default=0.0, positive=False,
                  hi=1e7),
              Key("velocity_sigma", "m/s", "initial velocity σ", default=0.0, positive=False,
                  hi=1e3),
              Key("attitude_sigma", "rad", "initial attitude σ", kind="angle", default=0.0,
                  positive=False, hi=np.pi))


@dataclass(frozen=True)
class MountingConfig(TableConfig):
    """How the IMU sits in the vehicle.

    Attributes
    ----------
    rpy_deg : tuple of float
        Roll, pitch, yaw (°) of the IMU's axes against the vehicle's (Z-Y-X): a vector
        measured by the IMU is ``C(rpy) v`` in the vehicle's axes.
    time_offset : float
        Seconds added to the IMU's time stamps (to bring them onto the aids' time axis).
    """

    rpy_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
    time_offset: float = 0.0

    TABLE = "mounting"
    FIELDS = (Key("rpy_deg", "°", "mounting angle", kind="vector", default=(0.0, 0.0, 0.0),
                  hi=360.0),
              Key("time_offset", "s", "IMU time offset (signed)", default=0.0))

    @classmethod
    def from_dict(cls, d: dict) -> MountingConfig:
        """Parse the ``[mounting]`` table (``time_offset`` is a signed number of seconds).

        Parameters
        ----------
        d : dict

        Returns
        -------
        MountingConfig

        Raises
        ------
        ImunavError
            For an unknown key, angles that are not three numbers within ±360°, or an offset
            that is not a finite number within ±1e6 s.
        """
        d = check_keys(d, cls.TABLE, cls.KEYS)
        rpy = cls.FIELDS[0].read(d, cls.TABLE)
        off = d.get("time_offset", 0.0)
        if isinstance(off, bool) or not isinstance(off, (int, float)) or not abs(off) <= 1e6:
            raise ImunavError(f"[mounting] time_offset must be a finite number of seconds "
                              f"within ±1e6, got {off!r}")
        return cls(rpy, float(off))

    @property
    def rotation(self) -> np.ndarray:
        """``C`` (3, 3): IMU axes → vehicle axes.

        Returns
        -------
        ndarray
        """
        r, p, y = (a * DEG for a in self.rpy_deg)
        cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
        Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1.0]])
        Ry = np.array([[cp, 0, sp], [0, 1.0, 0], [-sp, 0, cp]])
        Rx = np.array([[1.0, 0, 0], [0, cr, -sr], [0, sr, cr]])
        return Rz @ Ry @ Rx


#: The set-up tables of an ``AIDING.toml`` beside the aids' own.
SETUP = {"initial": InitialConfig, "mounting": MountingConfig}


class _Sections(dict):
    """The tables of an ``AIDING.toml`` and their parsers: every registered aid's, then the
    set-up's (read live from the registry)."""

    def _all(self):
        return {**{n: s.config for n, s in AIDS.items()}, **SETUP}

    def __iter__(self):
        return iter(self._all())

    def __len__(self):
        return len(self._all())

    def __getitem__(self, k):
        return self._all()[k]

    def __contains__(self, k):
        return k in self._all()

    def items(self):
        return self._all().items()

    def keys(self):
        return self._all().keys()

    def values(self):
        return self._all().values()


#: The tables of an ``AIDING.toml`` and their parsers.
SECTIONS = _Sections()


class AidingConfig:
    """Every aid of an ``AIDING.toml`` (the attribute of an aid absent from it is None), and the
    set-up (``initial``, ``mounting``).

    Parameters
    ----------
    initial : InitialConfig, optional
    mounting : MountingConfig, optional
    **aids
        ``name=config`` for registered aids (``gnss=GnssConfig(…)``).

    Raises
    ------
    ImunavError
        For a name that is not a registered aid.
    """

    def __init__(self, initial: InitialConfig | None = None,
                 mounting: MountingConfig | None = None, **aids):
        bad = sorted(set(aids) - set(AIDS))
        if bad:
            raise ImunavError(f"unknown aid(s): {', '.join(bad)}; expected "
                              f"{', '.join(AIDS)}", argument="aiding")
        object.__setattr__(self, "_aids", {n: aids[n] for n in AIDS if aids.get(n) is not None})
        object.__setattr__(self, "initial", initial or InitialConfig())
        object.__setattr__(self, "mounting", mounting or MountingConfig())

    def __getattr__(self, name):
        if name in AIDS:
            return self._aids.get(name)
        raise AttributeError(name)

    def __setattr__(self, name, value):
        raise AttributeError("AidingConfig is immutable: use replace()")

    def __eq__(self, other):
        return (isinstance(other, AidingConfig) and self._aids == other._aids
                and self.initial == other.initial and self.mounting == other.mounting)

    def __hash__(self):
        return hash((tuple(self._aids.items()), self.initial, self.mounting))

    def __repr__(self):
        parts = [f"{n}={c!r}" for n, c in self._aids.items()]
        return f"AidingConfig({', '.join(parts + [f'initial={self.initial!r}'])})"

    def replace(self, **changes) -> AidingConfig:
        """A copy with some tables replaced (None removes an aid).

        Parameters
        ----------
        **changes
            ``name=config``.

        Returns
        -------
        AidingConfig
        """
        d = {**self._aids, "initial": self.initial, "mounting": self.mounting, **changes}
        return AidingConfig(**d)

    def get(self, name: str):
        """The configuration of aid ``name`` (None if absent).

        Parameters
        ----------
        name : str

        Returns
        -------
        TableConfig or None
        """
        return self._aids.get(name)

    @property
    def sensors(self) -> list[str]:
        """The aids present, in the registry's order.

        Returns
        -------
        list of str
        """
        return list(self._aids)

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
        return cls(**{k: SECTIONS[k].from_dict(v) for k, v in d.items()})

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


class AidingData:
    """What the aiding sensors measured over a record: per aid its :class:`Readings` (or, for
    an aid of intervals, an ``(k, 2)`` array of ``[t0, t1]``); an aid absent is None.

    Parameters
    ----------
    **readings
        ``name=Readings`` for registered aids.

    Raises
    ------
    ImunavError
        For a name that is not a registered aid.
    """

    def __init__(self, **readings):
        bad = sorted(set(readings) - set(AIDS))
        if bad:
            raise ImunavError(f"unknown aid(s): {', '.join(bad)}; expected {', '.join(AIDS)}",
                              argument="data")
        object.__setattr__(self, "_d", {k: v for k, v in readings.items() if v is not None})

    def __getattr__(self, name):
        if name in AIDS:
            return self._d.get(name)
        raise AttributeError(name)

    def __setattr__(self, name, value):
        if name not in AIDS:
            raise AttributeError(f"{name} is not a registered aid ({', '.join(AIDS)})")
        if value is None:
            self._d.pop(name, None)
        else:
            self._d[name] = value

    def get(self, name: str):
        """The readings of aid ``name`` (None if absent).

        Parameters
        ----------
        name : str

        Returns
        -------
        Readings or ndarray or None
        """
        return self._d.get(name)

    def items(self):
        """``(name, readings)`` of the aids present, in the registry's order.

        Returns
        -------
        list of tuple
        """
        return [(n, self._d[n]) for n in AIDS if n in self._d]

    def __repr__(self):
        return f"AidingData({', '.join(f'{n}={len(v)} rows' for n, v in self.items())})"


def aid_stream(seed: int, run: int, stream: int) -> np.random.Generator:
    """The random generator of one aiding sensor in one run.

    Parameters
    ----------
    seed, run : int
    stream : int
        The aid's stream (:attr:`~imunav.sensors.aids.base.AidSpec.stream`).

    Returns
    -------
    numpy.random.Generator
    """
    return np.random.default_rng(np.random.SeedSequence(seed,
                                                        spawn_key=(AIDING_STREAM, run, stream)))


def aiding_streams(seed: int = 0, run: int = 0) -> list[np.random.Generator]:
    """The random generators of one run's aiding sensors, in stream order.

    Parameters
    ----------
    seed : int
    run : int
        The Monte Carlo run.

    Returns
    -------
    list of numpy.random.Generator
    """
    n = 1 + max((s.stream for s in AIDS.values()), default=-1)
    return [aid_stream(seed, run, i) for i in range(n)]


def simulate_aiding(motion, config: AidingConfig, duration: float, *, seed: int = 0, run: int = 0,
                    imu_rate: float | None = None, t0: float = 0.0) -> AidingData:
    """The aiding sensors' readings on ``motion``, each with its own errors.

    Parameters
    ----------
    motion : BaseMotion
    config : AidingConfig
    duration : float
        Seconds: readings at ``t0 + k/rate ≤ t0 + duration``, k ≥ 1.
    seed : int
        Random seed (each aid its stream of :func:`aid_stream`).
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
    out = AidingData()
    for name in config.sensors:
        spec = AIDS[name]
        r = spec.simulate(motion, config.get(name), t0, duration,
                          aid_stream(seed, run, spec.stream), imu_rate)
        if r is not None:
            setattr(out, name, r)
    return out


def build_measurements(aiding: AidingConfig, *, truth: bool = False) -> dict[str, Measurement]:
    """The measurement models of the aids in ``aiding``.

    Parameters
    ----------
    aiding : AidingConfig
    truth : bool
        As the simulation makes the readings (``[gnss] correlated_model = "white"`` still
        carries the correlated error as states) rather than as the filter assumes them.

    Returns
    -------
    dict
        ``{"gnss": GnssFix, "baro": Baro, …}`` for the aids present.
    """
    return {n: AIDS[n].measurement(aiding.get(n), truth=truth) for n in aiding.sensors}


def aids_from(aiding: AidingConfig, data: AidingData, signals) -> list[Aid]:
    """The aids the filter takes, from a configuration and its readings.

    Parameters
    ----------
    aiding : AidingConfig
        The aids' models (what the filter assumes).
    data : AidingData
        Their readings: GNSS fixes inside ``[gnss] outages`` are left out; NHC without
        readings is applied at its rate; ZUPT over the stance intervals (SHOE: found in
        ``signals``).
    signals : ImuSignals
        The IMU record.

    Returns
    -------
    list of Aid
        In the registry's order.

    Raises
    ------
    ImunavError
        For readings an aid needs and does not have.
    """
    out = []
    for name in aiding.sensors:
        spec, cfg = AIDS[name], aiding.get(name)
        m = spec.measurement(cfg)
        r = spec.readings(cfg, data, signals)
        out.append(Aid(m, r.t, r.values, r.sigma))
    return out


def describe(spec_or_name) -> list[Key]:
    """The keys of an aid's table (for the file-format page).

    Parameters
    ----------
    spec_or_name : AidSpec or str

    Returns
    -------
    list of Key
    """
    spec = AIDS[spec_or_name] if isinstance(spec_or_name, str) else spec_or_name
    return list(spec.config.FIELDS)


__all__ += ["SETUP", "describe", "Readings"]
