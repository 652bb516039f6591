"""What every aid is made of: its keys in ``AIDING.toml`` (with units and physical limits), its
readings, its measurement model for the filter, and the registry that lists the aids.

An aid (GNSS, a barometer, an odometer, …) is one :class:`AidSpec` registered in :data:`AIDS`
— as an IMU error term is one :class:`~imunav.sensors.terms.Term` of ``TERMS``. The spec holds
everything the rest of imunav asks of the aid:

- its ``AIDING.toml`` table: a configuration class whose :class:`Key` declarations give each
  key's unit, default and physical range (``from_dict`` reads and checks them all);
- its reading file (``file``, the accepted headers per frame, columns in degrees on the Earth)
  and the units of its innovation components (``units``);
- its simulation from the true motion (``simulate``, from its own random stream ``stream``);
- its measurement model for the filter (``measurement``: a :class:`Measurement` — prediction
  from the navigation state, Jacobian, noise, own error states) and the readings the filter
  uses (``readings``: a GNSS outage left out, a constraint applied at its rate, …);
- when it reads along a motion (``times``), for the covariance analysis.

Every list of aid names in imunav derives from :data:`AIDS` (in registration order, which is
also the order the filter uses the readings of one epoch). A new aid is one module with its
configuration, its measurement and its spec, plus one import in :mod:`imunav.sensors.aids`.

The measurement contract (:class:`Measurement`, :class:`NavPoint`) is what the filter calls;
:mod:`imunav.estimation.measurements` re-exports it. A measurement written by a user (a
subclass with ``name``, ``columns``, ``predict``, ``jacobian``, ``noise``) needs no spec: it is
given to the filter with its readings as an :class:`Aid`.

Error conventions (those of :mod:`imunav.estimation.error_model`): ``φ`` with
``C_est = (I − [φ×]) C_nb``, ``δv = v_est − v``, ``δp = p_est − p`` (indices
:data:`~imunav.core.layout.PHI`, :data:`~imunav.core.layout.DV`, :data:`~imunav.core.layout.DP`);
a sensor or aid error state ``x = s − ŝ`` (the true error minus its estimate). A measurement's
``jacobian`` is ``H`` with ``predicted(estimate) − predicted(truth) ≈ H e``; the filter forms
``z = predicted − measured ≈ H e − noise``.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors.signals``.
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass, field

import numpy as np

from imunav.core import units as U
from imunav.core.kernels import FloatArray, quat_to_dcm
from imunav.core.validation import ImunavError, show

__all__ = ["AIDS", "ANGLE_UNITS", "Aid", "AidSpec", "AidStates", "Key", "Measurement",
           "NavPoint", "Readings", "TableConfig", "check_keys", "euler_jacobian", "reading_times", "register",
           "wrap_angle", "yaw_of"]


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


def reading_times(rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """When a sensor at ``rate`` reads over ``duration`` from ``t0``: ``t0 + k/rate`` for
    ``k ≥ 1`` up to ``t0 + duration`` (the one schedule of the simulation, the filter's
    constraints and the covariance analysis).

    Parameters
    ----------
    rate : float
        Hz.
    duration : float
        Seconds.
    t0 : float
        Start (s).

    Returns
    -------
    ndarray, shape (k,)
    """
    n = int(np.floor(duration * rate * (1 + 1e-12)))
    return t0 + np.arange(1, n + 1) / rate


# ----------------------------------------------------------------------------- configuration

#: The units an angle of an ``AIDING.toml`` may be written in: those of
#: :data:`imunav.core.units.ANGLE` less ``%`` (a cross-axis coupling, not an angle of its own).
ANGLE_UNITS = {u: f for u, f in U.ANGLE.items() if u != "%"}


def _angle(text: str, name: str) -> float:
    """An angle written with its unit (``"2 deg"``) in radians, its sign kept."""
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


def _real(x) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x)


@dataclass(frozen=True)
class Key:
    """One key of an ``AIDING.toml`` table: its unit, default and physical range.

    Parameters
    ----------
    name : str
    unit : str
        The SI unit it is written in (``""``: a plain number).
    doc : str
        What it is (one line: the file-format page is generated from these).
    kind : {"number", "angle", "integer", "vector", "intervals", "choice", "path", "delay"}
        A finite number; an angle (a number in rad, or a string with its unit, ``"2 deg"``);
        a whole number; a list of three numbers; a list of ``[t0, t1]``; one of ``choices``;
        a file name; a signed number of seconds or ``"auto"``.
    required : bool
    default : object
        When absent (and not required).
    positive : bool
        A number must be > 0 (else ≥ 0; a vector's components may have any sign).
    hi : float, optional
        The largest physical value (a vector: of each component's magnitude).
    choices : tuple of str
    """

    name: str
    unit: str
    doc: str
    kind: str = "number"
    required: bool = False
    default: object = None
    positive: bool = True
    hi: float | None = None
    choices: tuple[str, ...] = ()

    def read(self, table: dict, where: str):
        """The key's value in ``table`` (the ``[where]`` table), checked.

        Parameters
        ----------
        table : dict
        where : str
            The table's name (for messages).

        Returns
        -------
        object
            A float, an int, a tuple, a string, or the default.

        Raises
        ------
        ImunavError
            Naming ``[where] key``, what was expected (its unit and range) and what came.
        """
        name, unit = f"[{where}] {self.name}", self.unit
        in_unit = f" ({unit})" if unit else ""
        if self.name not in table:
            if self.required:
                raise ImunavError(f"{name}{in_unit} is required")
            return self.default
        raw = table[self.name]
        if self.kind == "choice":
            if raw not in self.choices:
                raise ImunavError(f"{name} must be " + " or ".join(f'"{c}"' for c in self.choices)
                                  + f", got {show(raw)}")
            return raw
        if self.kind == "integer":
            top = "" if self.hi is None else f" and ≤ {self.hi:g}"
            if (isinstance(raw, bool) or not isinstance(raw, numbers.Integral) or raw < 1
                    or (self.hi is not None and raw > self.hi)):
                raise ImunavError(f"{name} must be a whole number of {unit} ≥ 1{top}, got "
                                  f"{show(raw)}")
            return int(raw)
        if self.kind == "vector":
            if not isinstance(raw, list) or len(raw) != 3 or not all(_real(x) for x in raw):
                raise ImunavError(f"{name} must be 3 finite numbers{in_unit}, got {show(raw)}")
            if self.hi is not None and max(abs(x) for x in raw) > self.hi:
                raise ImunavError(f"{name} must be 3 numbers within ±{self.hi:g}{in_unit} (a "
                                  f"physical {self.doc}), got {show(raw)}")
            return tuple(float(x) for x in raw)
        if self.kind == "intervals":
            return _intervals(raw, name, self.hi)
        if self.kind == "path":
            if not isinstance(raw, str) or not raw.strip() or "\x00" in raw:
                raise ImunavError(f"{name} must be a file name (a string), got {show(raw)}")
            return raw
        if self.kind == "delay":
            if raw == "auto":
                return raw
            if not _real(raw) or not abs(raw) <= 10.0:
                raise ImunavError(f'{name} must be a number of seconds within ±10 or "auto", '
                                  f"got {show(raw)}")
            return float(raw)
        v = raw
        if self.kind == "angle" and isinstance(v, str):
            v = _angle(v, name)
        if not _real(v):
            raise ImunavError(f"{name} must be a finite number{in_unit}, got {show(raw)}")
        v = float(v)
        if self.positive and not v > 0:
            raise ImunavError(f"{name} must be a positive number{in_unit}, got {show(raw)}")
        if not self.positive and v < 0:
            raise ImunavError(f"{name} must be a non-negative number{in_unit}, got {show(raw)}")
        if self.hi is not None and v > self.hi:
            lo = "(0" if self.positive else "[0"
            raise ImunavError(f"{name} must be in {lo}, {self.hi:g}]{in_unit} (a physical "
                              f"{self.doc}), got {show(raw)}")
        return v


def _intervals(raw, name: str, hi: float | None) -> tuple[tuple[float, float], ...]:
    """A list of ``[t0, t1]`` with ``0 ≤ t0 < t1``, in time order, not overlapping."""
    if not isinstance(raw, list):
        raise ImunavError(f"{name} must be a list of [t0, t1] (s), got {show(raw)}")
    if raw and all(isinstance(o, numbers.Real) for o in raw):
        hint = f": write [{show(raw)}] for one outage" if len(raw) == 2 else ""
        raise ImunavError(f"{name} must be a list of [t0, t1] (s), got {show(raw)}{hint}")
    out: list[tuple[float, float]] = []
    for i, o in enumerate(raw):
        if (not isinstance(o, list) or len(o) != 2 or not all(_real(x) for x in o)
                or not 0 <= o[0] < o[1] or (hi is not None and o[1] > hi)):
            top = "" if hi is None else f" ≤ {hi:g}"
            raise ImunavError(f"{name}[{i}] must be [t0, t1] with 0 ≤ t0 < t1{top} (s), got "
                              f"{show(o)}")
        if out and o[0] <= out[-1][1]:
            raise ImunavError(f"{name}[{i}] = {show(o)} must start after {name.split()[-1]}"
                              f"[{i - 1}] ends ({out[-1][1]:g} s): list them in time order, "
                              "without overlaps")
        out.append((float(o[0]), float(o[1])))
    return tuple(out)


def check_keys(table, where: str, allowed) -> dict:
    """``table`` as a dict holding only ``allowed`` keys.

    Parameters
    ----------
    table : object
    where : str
        The table's name.
    allowed : iterable of str

    Returns
    -------
    dict

    Raises
    ------
    ImunavError
        If it is not a table or holds another key.
    """
    if not isinstance(table, dict):
        raise ImunavError(f"[{where}] must be a table")
    allowed = tuple(allowed)
    bad = sorted(set(table) - set(allowed))
    if bad:
        raise ImunavError(f"unknown key(s) in [{where}]: {', '.join(bad)}; expected "
                          f"{', '.join(allowed)}")
    return table


class TableConfig:
    """A table of ``AIDING.toml`` as a frozen dataclass read from its :class:`Key` list.

    Subclasses are dataclasses whose fields are, in order, the keys of :attr:`FIELDS`, and set
    :attr:`TABLE`; :meth:`from_dict` reads and checks every key, then :meth:`checked` checks
    what involves several keys.
    """

    TABLE = ""
    FIELDS: tuple[Key, ...] = ()
    #: The table's keys, in order (set from :attr:`FIELDS`).
    KEYS: tuple[str, ...] = ()

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        cls.KEYS = tuple(k.name for k in cls.FIELDS)

    @classmethod
    def from_dict(cls, d: dict):
        """Parse the table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        TableConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing required key, or a value out of its type or range
            (the message names ``[table] key``).
        """
        d = check_keys(d, cls.TABLE, cls.KEYS)
        return cls(*(k.read(d, cls.TABLE) for k in cls.FIELDS)).checked()

    def checked(self):
        """What involves several keys (none by default).

        Returns
        -------
        TableConfig
            Itself (or a normalised copy).
        """
        return self

# ----------------------------------------------------------------------------- readings

@dataclass
class Readings:
    """One sensor's readings: times and values.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s), strictly increasing.
    values : ndarray, shape (n, m)
        The readings (SI): GNSS ``x, y, z[, vx, vy, vz]``, baro ``alt``, heading ``yaw``,
        NHC ``vy, vz``, odometer ``speed``.
    sigma : ndarray, shape (n, m), optional
        Each reading's own standard deviations (an RTKLIB solution gives them); None: the
        aid's configured noise.
    """

    t: FloatArray
    values: FloatArray
    sigma: FloatArray | None = None

    def __len__(self) -> int:
        return int(self.t.shape[0])


# ----------------------------------------------------------------------------- the measurement

@dataclass
class NavPoint:
    """The navigation state a measurement is predicted from.

    In a batch of ``R`` runs every array has a leading run axis (``q`` (R, 4), …); a
    measurement whose :attr:`Measurement.batched` is True handles that, any other is called
    once per run.

    Attributes
    ----------
    q : ndarray, shape ([R,] 4)
        ``q_nb``.
    v, p : ndarray, shape ([R,] 3)
        Velocity (m/s) and position (m), navigation frame (on the Earth: local NED, the
        position the offset from the ellipsoid below the estimate, so ``-p_z`` is the height).
    omega : ndarray, shape ([R,] 3)
        Body rate ``ω_b`` (rad/s), compensated (on the Earth: relative to the Earth).
    dt : float
        Reading time minus the state's time (s).
    estimates : ndarray, shape ([R,] n)
        The filter's estimates of the sensor and aid error states (``ŝ``; zeros in the
        navigation entries).
    gyro_input : ndarray, shape ([R,] 3, n)
        ``δω = gyro_input @ x``: how the sensor states enter the gyro's error.
    """

    q: FloatArray
    v: FloatArray
    p: FloatArray
    omega: FloatArray
    dt: float
    estimates: FloatArray
    gyro_input: FloatArray

    @property
    def C(self) -> FloatArray:
        """``C_nb`` ([R,] 3, 3).

        Returns
        -------
        ndarray
        """
        return quat_to_dcm(self.q)

    def run(self, r: int) -> NavPoint:
        """Run ``r`` of a batch.

        Parameters
        ----------
        r : int

        Returns
        -------
        NavPoint
        """
        return NavPoint(self.q[r], self.v[r], self.p[r], self.omega[r], self.dt,
                        self.estimates[r], self.gyro_input[r])


@dataclass
class AidStates:
    """Error states of an aid itself: ``ẋ = diag(D) x + w``, ``E[w wᵀ] = diag(Qs) δ``.

    Attributes
    ----------
    name : str
        ``"gnss.correlated"``, ``"baro.bias"``, ``"odometer.scale"``.
    D, Qs : ndarray, shape (k,)
        Decay rates (1/s) and driving PSD.
    P0 : ndarray, shape (k, k)
        Initial covariance.
    """

    name: str
    D: FloatArray
    P0: FloatArray
    Qs: FloatArray

    @property
    def size(self) -> int:
        """Number of states.

        Returns
        -------
        int
        """
        return int(self.D.size)


def yaw_of(C: FloatArray) -> FloatArray:
    """Yaw ``atan2(C₁₀, C₀₀)`` of ``C_nb`` (…, 3, 3).

    Parameters
    ----------
    C : ndarray, shape (..., 3, 3)

    Returns
    -------
    ndarray
    """
    return np.arctan2(C[..., 1, 0], C[..., 0, 0])


def euler_jacobian(C: FloatArray) -> FloatArray:
    """``∂[yaw, pitch, roll]/∂φ`` of ``C_est = (I − [φ×]) C`` at ``φ = 0``.

    A rotation ``ε`` in the navigation frame changes the Z-Y-X angles by ``E⁻¹ ε`` with
    ``E = [e_z, R_z(ψ) e_y, R_z(ψ) R_y(θ) e_x]``; the error ``φ`` is the rotation ``−φ``.

    Parameters
    ----------
    C : ndarray, shape (..., 3, 3)
        ``C_nb``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Rows yaw, pitch, roll (singular at pitch ±90°).
    """
    psi = np.arctan2(C[..., 1, 0], C[..., 0, 0])
    theta = -np.arcsin(np.clip(C[..., 2, 0], -1.0, 1.0))
    cp, sp, ct, st = np.cos(psi), np.sin(psi), np.cos(theta), np.sin(theta)
    E = np.zeros(C.shape)
    E[..., 2, 0] = 1.0
    E[..., 0, 1], E[..., 1, 1] = -sp, cp
    E[..., 0, 2], E[..., 1, 2], E[..., 2, 2] = cp * ct, sp * ct, -st
    return -np.linalg.inv(E)


class Measurement:
    """One aid's measurement model: prediction, Jacobian, noise.

    Subclasses set :attr:`name`, :attr:`columns` and implement :meth:`predict`,
    :meth:`jacobian` and :meth:`noise`; an aid with error states of its own lists them in
    :attr:`states` and is told where they sit in the filter's state by :meth:`bind`. That is
    the whole contract: the filter (:func:`~imunav.estimation.filters.run_filter`), its
    smoother, the aided covariance analysis and the aided Monte Carlo take any subclass.

    Attributes
    ----------
    name : str
        ``"gnss"``, ``"baro"``, … (a user's own: any name not already used in one run).
    columns : tuple of str
        The reading's components.
    states : list of AidStates
        The aid's own error states.
    angular : bool
        Whether the innovation is an angle (wrapped to [−π, π)).
    gated : bool
        Whether the filter's χ² gate applies to its readings (False: a constraint a detector
        has already decided on, as a zero-velocity update: rejecting it would leave the drift
        it exists to stop unbounded).
    batched : bool
        Whether :meth:`predict` and :meth:`jacobian` take a :class:`NavPoint` of ``R`` runs
        (arrays with a leading run axis) and return ``(R, m)`` and ``(R, m, n)``; False (a
        user's class, by default): the filter calls them run by run.
    """

    name = ""
    columns: tuple[str, ...] = ()
    angular = False
    gated = True
    batched = False

    def __init__(self):
        self.states: list[AidStates] = []
        self.offsets: dict[str, slice] = {}

    @property
    def size(self) -> int:
        """Components of a reading.

        Returns
        -------
        int
        """
        return len(self.columns)

    def bind(self, offsets: dict[str, slice]) -> None:
        """Where the aid's own states sit in the filter's error state.

        Parameters
        ----------
        offsets : dict
            ``{state name: slice}`` of the filter's layout.
        """
        self.offsets = {s.name: offsets[s.name] for s in self.states}

    def predict(self, nav: NavPoint) -> FloatArray:
        """The reading predicted from the navigation state.

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray, shape (m,)
        """
        raise NotImplementedError

    def jacobian(self, nav: NavPoint) -> FloatArray:
        """``H``: ``predicted(est) − predicted(true) ≈ H e``.

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray, shape (m, n)
        """
        raise NotImplementedError

    def noise(self) -> FloatArray:
        """``R`` (m, m).

        Returns
        -------
        ndarray
        """
        raise NotImplementedError

    def residual(self, predicted: FloatArray, reading: FloatArray) -> FloatArray:
        """``predicted − reading`` (angles wrapped).

        Parameters
        ----------
        predicted, reading : ndarray, shape (..., m)

        Returns
        -------
        ndarray, shape (..., m)
        """
        d = np.asarray(predicted, float) - np.asarray(reading, float)
        return (d + np.pi) % (2 * np.pi) - np.pi if self.angular else d

    def localise(self, values: FloatArray, lla: FloatArray) -> FloatArray:
        """A reading made on the WGS-84 Earth in the coordinates :meth:`predict` uses there
        (local NED at the estimate, its origin on the ellipsoid below it): the identity,
        unless the reading holds a geodetic position (GNSS).

        Parameters
        ----------
        values : ndarray, shape ([R,] m)
        lla : ndarray, shape ([R,] 3)
            The estimate's ``[lat, lon, h]`` (rad, rad, m).

        Returns
        -------
        ndarray, shape ([R,] m)
        """
        return values

    def zeros_H(self, nav: NavPoint) -> FloatArray:
        """A zero Jacobian of the right shape for ``nav`` (``(m, n)``, or ``(R, m, n)``).

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray
        """
        return np.zeros(nav.estimates.shape[:-1] + (self.size, nav.estimates.shape[-1]))


@dataclass
class Aid:
    """An aid as the filter takes it: a measurement model and its readings.

    Parameters
    ----------
    measurement : Measurement
        The model (any subclass: imunav's own or a user's).
    t : array_like, shape (N,)
        Reading times (s), non-decreasing.
    values : array_like, shape (N, m)
        The readings (``m = measurement.size``).
    sigma : array_like, shape (N, m), optional
        Each reading's own standard deviations (uncorrelated components); None: the
        measurement's ``noise()``.

    Raises
    ------
    ImunavError
        For a measurement that is not a :class:`Measurement`, shapes that do not fit,
        non-finite values, times out of order, or a non-positive σ.
    """

    measurement: Measurement
    t: FloatArray
    values: FloatArray
    sigma: FloatArray | None = None
    name: str = field(init=False)

    def __post_init__(self):
        m = self.measurement
        if not isinstance(m, Measurement):
            raise ImunavError(f"measurement must be a Measurement (imunav.estimation."
                              f"measurements), got {type(m).__name__}", argument="measurements")
        self.name = m.name or type(m).__name__
        t = np.asarray(self.t, dtype=float).reshape(-1)
        v = np.asarray(self.values, dtype=float)
        if v.ndim == 1 and m.size == 1:
            v = v[:, None]
        if v.shape != (t.size, m.size):
            raise ImunavError(f"aid {self.name}: values must have shape ({t.size}, {m.size}) "
                              f"(one row per reading time, columns {', '.join(m.columns)}), "
                              f"got {v.shape}", argument="measurements")
        if not (np.isfinite(t).all() and np.isfinite(v).all()):
            raise ImunavError(f"aid {self.name}: times and values must be finite",
                              argument="measurements")
        if np.any(np.diff(t) < 0):
            raise ImunavError(f"aid {self.name}: reading times must be in order",
                              argument="measurements")
        if self.sigma is not None:
            s = np.asarray(self.sigma, dtype=float)
            if s.shape != v.shape or not np.isfinite(s).all() or np.any(s <= 0):
                raise ImunavError(f"aid {self.name}: sigma must be positive and finite, shape "
                                  f"{v.shape}", argument="measurements")
            self.sigma = s
        self.t, self.values = t, v

    def __len__(self) -> int:
        return int(self.t.size)


# ----------------------------------------------------------------------------- the registry

class AidSpec:
    """One kind of aid, everything imunav asks of it (see the module docstring).

    Subclasses set the class attributes and implement :meth:`measurement` and
    :meth:`simulate`; the defaults of the other methods fit an aid that reads at ``rate``
    from a file of its own.

    Attributes
    ----------
    name : str
        Its table in ``AIDING.toml``, its file's stem, its name in every report.
    summary : str
        What it measures (one line).
    config : type
        Its :class:`TableConfig`.
    file : str
        Its reading file (``gnss.csv``).
    headers : dict
        ``{frame: (header, …)}``: the headers its file may have, the full one first.
    degrees : tuple of str
        Columns written in degrees on the Earth (converted to rad on reading).
    intervals : bool
        The file holds ``[t0, t1]`` intervals (stance), not readings.
    stream : int
        Its random stream among the aiding sensors' (fixed: adding an aid changes no other).
    """

    name = ""
    summary = ""
    config: type = TableConfig
    file = ""
    headers: dict[str, tuple[tuple[str, ...], ...]] = {}
    degrees: tuple[str, ...] = ()
    intervals = False
    stream = 0

    def units(self, config) -> tuple[str, ...]:
        """The units of its innovation components (for the statistics table).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        tuple of str
        """
        return ()

    def measurement(self, config, *, truth: bool = False) -> Measurement:
        """Its measurement model.

        Parameters
        ----------
        config : TableConfig
        truth : bool
            As the simulation makes the readings (a correlated error always as states),
            rather than as the filter assumes them.

        Returns
        -------
        Measurement
        """
        raise NotImplementedError

    def simulate(self, motion, config, t0: float, duration: float, rng: np.random.Generator,
                 imu_rate: float):
        """Its readings on the true motion, with its own errors.

        Parameters
        ----------
        motion : BaseMotion
        config : TableConfig
        t0, duration : float
            The record (s).
        rng : numpy.random.Generator
            Its own stream.
        imu_rate : float
            The IMU rate (Hz).

        Returns
        -------
        Readings or ndarray or None
            Readings; an ``(k, 2)`` array of intervals (:attr:`intervals`); None when the
            aid needs no file (found from the IMU data).
        """
        raise NotImplementedError

    def file_needed(self, config) -> bool:
        """Whether the filter needs its file (else it works without one).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        bool
        """
        return True

    def rate(self, config) -> float | None:
        """How often it reads (Hz), if at a fixed rate.

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        float or None
        """
        return getattr(config, "rate", None)

    def readings(self, config, data, signals) -> Readings:
        """The readings the filter uses, from the data read or simulated.

        Parameters
        ----------
        config : TableConfig
        data : AidingData
        signals : ImuSignals
            The IMU record (an aid found from the IMU data, a constraint applied at the
            IMU's nodes).

        Returns
        -------
        Readings

        Raises
        ------
        ImunavError
            When its readings are missing.
        """
        r = data.get(self.name)
        if r is None:
            raise ImunavError(f"aiding has [{self.name}] but no {self.name} readings were "
                              "given", argument="data")
        return r

    def times(self, config, motion, rate: float, duration: float) -> FloatArray:
        """When it reads along a motion (the covariance analysis's schedule).

        Parameters
        ----------
        config : TableConfig
        motion : BaseMotion
        rate : float
            IMU rate (Hz).
        duration : float
            Seconds.

        Returns
        -------
        ndarray
        """
        return reading_times(config.rate, duration)

    def analysis_warnings(self, config) -> list[str]:
        """What the covariance analysis cannot model of this aid (none by default).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        list of str
        """
        return []


#: The aids, in the order the filter uses the readings of one epoch.
AIDS: dict[str, AidSpec] = {}


def register(spec: AidSpec) -> AidSpec:
    """Add an aid to :data:`AIDS`.

    Parameters
    ----------
    spec : AidSpec

    Returns
    -------
    AidSpec

    Raises
    ------
    ValueError
        For a name or a random stream already taken.
    """
    if spec.name in AIDS or any(s.stream == spec.stream for s in AIDS.values()):
        raise ValueError(f"aid {spec.name!r} (stream {spec.stream}) is registered already")
    AIDS[spec.name] = spec
    return spec
