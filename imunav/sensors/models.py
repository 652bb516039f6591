"""Sensor error models from datasheets, and their application to ideal rates or increments.

One :class:`TriadModel` per sensor triad (gyro, accel) holds the values of the error terms of
:mod:`imunav.sensors.terms` (every term optional; 0/None = absent); an :class:`ImuModel` pairs
two. :class:`TriadStream` runs one triad's terms on ideal samples fed in chunks: the pipeline of
:data:`~imunav.sensors.terms.STAGES`, each term doing its own step.

Randomness: each run draws from its own stream ``SeedSequence(seed).spawn(runs)[r]``, so a run
is reproducible bit for bit whatever the chunking, and runs are independent.

May import: ``imunav.core``, ``imunav.sensors.allan``, ``imunav.sensors.presets``,
``imunav.sensors.terms``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from imunav.core.deprecation import renamed
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, check_positive, read_toml
from imunav.sensors.presets import PRESETS
from imunav.sensors.terms import DRAW_ORDER, TERMS, TRIADS, parameters, parse

__all__ = ["ImuModel", "MeasureStream", "TriadModel", "TriadStream", "apply_triad", "measure"]


def _known() -> dict[str, object]:
    """Every parameter key of every registered term (either triad) → its default."""
    return {key: p.default for triad in TRIADS for key, (_, p) in parameters(triad).items()}


class TriadModel:
    """Error parameters of one triad, in SI: one value per parameter of the registered terms
    (:data:`~imunav.sensors.terms.TERMS`), absent ones at their default (0 or None).

    ``TriadModel(noise_density=2e-4, bias=1e-3)``; attributes read the values
    (``m.noise_density``). Immutable, hashable, compared by value.

    Parameters
    ----------
    **values : float or None
        SI values keyed by parameter (``noise_density``, ``bias_correlation_time``, …).

    Raises
    ------
    TypeError
        For a keyword that is no parameter of any registered term.
    """

    __slots__ = ("_values",)

    def __init__(self, **values):
        known = _known()
        bad = sorted(set(values) - set(known))
        if bad:
            raise TypeError(f"TriadModel got unexpected keyword argument(s) {', '.join(bad)}; "
                            f"parameters are {', '.join(known)}")
        object.__setattr__(self, "_values", dict(values))

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        known = _known()
        if name not in known:
            raise AttributeError(f"TriadModel has no parameter {name!r}")
        return self._values.get(name, known[name])

    def __setattr__(self, name, value):
        raise AttributeError("TriadModel is immutable: build a new one")

    def _key(self) -> tuple:
        return tuple((k, getattr(self, k)) for k in sorted(_known()))

    def __eq__(self, other):
        return isinstance(other, TriadModel) and self._key() == other._key()

    def __hash__(self):
        return hash(self._key())

    def __reduce__(self):
        return (_triad_model, (tuple(self._values.items()),))

    def __repr__(self):
        known = _known()
        shown = ", ".join(f"{k}={v!r}" for k, v in self._values.items() if v != known[k])
        return f"TriadModel({shown})"

    def replace(self, **changes) -> TriadModel:
        """A copy with some parameters changed (the model itself is immutable).

        Parameters
        ----------
        **changes : float or None
            SI values keyed by parameter, as for the constructor.

        Returns
        -------
        TriadModel

        Raises
        ------
        TypeError
            If a key is not a parameter of the registered terms.

        Examples
        --------
        >>> TriadModel(bias=1e-3).replace(bias=2e-3).bias
        0.002
        """
        return TriadModel(**{**self._values, **changes})

    __replace__ = replace            # copy.replace (Python 3.13)

    def values(self) -> dict[str, float | None]:
        """Every parameter and its value (defaults included), in registry order.

        Returns
        -------
        dict
        """
        return {k: getattr(self, k) for k in _known()}

    @classmethod
    def from_dict(cls, d: Mapping, triad: str) -> TriadModel:
        """Parse ``{"noise_density": "0.014 deg/s/sqrt(Hz)", …}`` (numbers are SI).

        Parameters
        ----------
        d : dict
            The ``[gyro]`` or ``[accel]`` table of an ``IMU.toml``.
        triad : {"gyro", "accel"}

        Returns
        -------
        TriadModel

        Raises
        ------
        ImunavError
            For a table that is not a table, an unknown key, or a value
            :func:`~imunav.sensors.terms.parse` refuses.
        """
        if not isinstance(d, dict):
            raise ImunavError(f"[{triad}] must be a table")
        allowed = set(parameters(triad))
        bad = sorted(set(d) - allowed)
        if bad:
            raise ImunavError(f"unknown key(s) in [{triad}]: {', '.join(bad)}; expected "
                              f"{', '.join(sorted(allowed))}")
        return cls(**{k: parse(v, f"{triad}.{k}") for k, v in d.items()})

    def active(self) -> list[str]:
        """The error terms present, in registry order.

        Settings such as the internal rate, which are no error of their own, are not listed.

        Returns
        -------
        list of str
        """
        return [t.name for t in TERMS.values() if t.is_error and t.present(self)]

    def only(self, term: str | None) -> TriadModel:
        """A copy keeping only ``term``.

        With the qualifiers such as its correlation time, and the settings such as the internal
        rate: what the error budget of one term needs.

        Parameters
        ----------
        term : str or None
            A term name (``"bias"``); None → ideal.

        Returns
        -------
        TriadModel

        Examples
        --------
        >>> TriadModel(bias=1e-3, noise_density=1e-4).only("bias").active()
        ['bias']
        """
        keep = {p.key for t in TERMS.values() for p in t.parameters_
                if p.qualifier or not t.is_error} | ({term} if term else set())
        return TriadModel(**{k: v for k, v in self._values.items() if k in keep})


def _triad_model(items) -> TriadModel:
    return TriadModel(**dict(items))


@dataclass(frozen=True)
class ImuModel:
    """A 6-axis IMU: gyro and accelerometer triads.

    Build one from a preset or a file with :meth:`load`, from a parsed ``IMU.toml`` with
    :meth:`from_dict`, or directly from two :class:`TriadModel`. Frozen: compared by value.

    Attributes
    ----------
    gyro : TriadModel
        The gyro triad's errors (SI: rad/s, rad/√s …); default ideal.
    accel : TriadModel
        The accelerometer triad's errors (SI: m/s², m/s/√s …); default ideal.
    name : str, default "custom"
        A label for reports (a preset's name, a file's stem).

    Examples
    --------
    >>> m = ImuModel(TriadModel(bias=1e-3), TriadModel(noise_density=2e-4), "demo")
    >>> m.terms()
    ['gyro.bias', 'accel.noise_density']
    """

    gyro: TriadModel = field(default_factory=TriadModel)
    accel: TriadModel = field(default_factory=TriadModel)
    name: str = "custom"

    @classmethod
    def from_dict(cls, d: dict, name: str = "custom") -> ImuModel:
        """Parse the tables of an ``IMU.toml`` (strings with units, or SI numbers).

        Parameters
        ----------
        d : dict
            ``{"gyro": {...}, "accel": {...}, "name": ...}``; every key optional, a missing
            triad is ideal.
        name : str, default "custom"
            The model's name when ``d`` has no ``"name"``.

        Returns
        -------
        ImuModel

        Raises
        ------
        ImunavError
            For a key other than ``gyro``, ``accel`` and ``name``, or a triad table
            :meth:`TriadModel.from_dict` refuses.

        Examples
        --------
        >>> m = ImuModel.from_dict({"gyro": {"bias": "1 deg/s", "internal_rate": 1000}})
        >>> round(m.gyro.bias, 6), m.internal_rate
        (0.017453, 1000.0)
        """
        bad = sorted(set(d) - {"gyro", "accel", "name"})
        if bad:
            raise ImunavError(f"unknown table(s) in IMU file: {', '.join(bad)}; expected "
                              "[gyro] and [accel]")
        return cls(TriadModel.from_dict(d.get("gyro", {}), "gyro"),
                   TriadModel.from_dict(d.get("accel", {}), "accel"), d.get("name", name))

    @classmethod
    def from_toml(cls, path: str | Path) -> ImuModel:
        """Read an ``IMU.toml`` file (``[gyro]`` and ``[accel]`` tables, values with units).

        Parameters
        ----------
        path : str or Path
            The file; its stem names the model unless it sets ``name``.

        Returns
        -------
        ImuModel

        Raises
        ------
        ImunavError
            If the file cannot be read or is not valid TOML, or for the reasons of
            :meth:`from_dict`.
        """
        path = Path(path)
        d = read_toml(path, "IMU file")
        return cls.from_dict(d, path.stem)

    @classmethod
    def load(cls, spec: str) -> ImuModel:
        """A preset name or a path to ``IMU.toml``.

        Parameters
        ----------
        spec : str
            A key of :data:`~imunav.sensors.presets.PRESETS` or a path.

        Returns
        -------
        ImuModel

        Raises
        ------
        ImunavError
            If ``spec`` is neither (the message names the argument ``imu``), or the file is not
            a valid IMU model.
        """
        if isinstance(spec, Path):
            spec = str(spec)
        if spec in PRESETS:
            return cls.from_dict(PRESETS[spec], spec)
        if spec.endswith(".toml") or Path(spec).is_file():
            return cls.from_toml(spec)
        raise ImunavError(f"imu {spec!r} is neither a preset ({', '.join(PRESETS)}) nor a "
                          "TOML file", argument="imu")

    def terms(self) -> list[str]:
        """Active terms as ``gyro.noise_density`` etc.

        Returns
        -------
        list of str
            The gyro's, then the accelerometer's, in registry order.
        """
        return [f"gyro.{t}" for t in self.gyro.active()] + \
               [f"accel.{t}" for t in self.accel.active()]

    def only(self, term: str | None) -> ImuModel:
        """A copy keeping only one term, for error budgets.

        The term's qualifiers (e.g. a correlation time) and the settings such as the internal
        rate are kept too (see :meth:`TriadModel.only`).

        Parameters
        ----------
        term : str or None
            ``"triad.term"`` as listed by :meth:`terms` (``"gyro.bias"``); None → ideal.

        Returns
        -------
        ImuModel
            Named ``"<name>:<term>"``.

        Examples
        --------
        >>> m = ImuModel(TriadModel(bias=1e-3, noise_density=1e-4), name="demo")
        >>> m.only("gyro.bias").terms()
        ['gyro.bias']
        """
        tri, _, name = (term or "").partition(".")
        return ImuModel(self.gyro.only(name if tri == "gyro" else None),
                        self.accel.only(name if tri == "accel" else None), f"{self.name}:{term}")

    def missing_term_warnings(self) -> list[str]:
        """The warning an answer about this IMU carries when a triad with errors (of the linear
        error model: not only a range, a filter or a rate) has no bias instability: the in-run
        drift that a filter cannot estimate away, and that decides how long an outage is
        bridged. A term the datasheet is silent on is not zero — without it the turn-on bias,
        once estimated, never moves again and the answer is optimistic.

        The one check every assessment and outage answer calls
        (:func:`~imunav.analysis.assessment.assess`,
        :func:`~imunav.analysis.outage.aided_covariance` and through it ``assess_aided``,
        ``find_outage``, ``design_aided``).

        Returns
        -------
        list of str
            Empty, or one warning naming the triads without "bias instability".

        Examples
        --------
        >>> ImuModel(TriadModel(bias=1e-3), TriadModel(), "demo").missing_term_warnings()[0][:58]
        'demo: the gyro has no bias instability (in-run bias drift)'
        >>> ImuModel.load("ADIS16470").missing_term_warnings()
        []
        """
        names = {"gyro": "gyro", "accel": "accelerometer"}
        # a triad with errors of the linear model (not only a range, a filter, a rate)
        lacking = [names[t] for t in TRIADS
                   if any(term.is_error and term.linear and term.present(getattr(self, t))
                          for term in TERMS.values())
                   and not getattr(self, t).bias_instability]
        if not lacking:
            return []
        return [f"{self.name}: the {' and the '.join(lacking)} "
                f"{'has' if len(lacking) == 1 else 'have'} no bias instability (in-run bias "
                "drift): a term the datasheet is silent on is not zero — without it a turn-on "
                "bias, once estimated, never moves again and the answer is optimistic; give "
                f"{' and '.join(t + '.bias_instability' for t in TRIADS if names[t] in lacking)}"
                " (an Allan-variance value of the part)"]

    @property
    def internal_rate(self) -> float | None:
        """The sensor's internal sample rate (Hz): the larger of the triads', or None."""
        r = [x for x in (self.gyro.internal_rate, self.accel.internal_rate) if x]
        return max(r) if r else None

    def decimation(self, rate: float) -> int:
        """How many internal samples make one output sample at ``rate``.

        Parameters
        ----------
        rate : float
            Output rate (Hz), > 0.

        Returns
        -------
        int
            ``round(internal_rate / rate)``, at least 1 (1 without an internal rate).

        Raises
        ------
        ImunavError
            If ``rate`` is not a finite number > 0.

        Examples
        --------
        >>> ImuModel(TriadModel(internal_rate=1000.0)).decimation(100)
        10
        """
        rate = check_positive(rate, "rate")
        return max(1, int(round((self.internal_rate or rate) / rate)))


class TriadStream:
    """One run of one triad's errors, applied to ideal samples fed in consecutive chunks.

    When the stream is created every present term draws what its run needs
    (:meth:`~imunav.sensors.terms.Term.start`, in :data:`~imunav.sensors.terms.DRAW_ORDER`:
    the constants — turn-on bias, scale factor and misalignment matrix, g-sensitivity — from
    ``rng``, then each time-varying process its own child generator); the filters carry their
    state, so the output of a run does not depend on how it is chunked. Chunk lengths must be
    multiples of ``decimate`` (but the last).

    Parameters
    ----------
    m : TriadModel
    kind : {"rates", "increments"}
        Samples in rate units, or integrals over each ``1/rate`` interval.
    rate : float
        The rate of the ideal samples fed (Hz): the sensor's internal rate.
    rng : numpy.random.Generator
    decimate : int
        Internal samples per output sample; the output is at ``rate/decimate``.
    """

    def __init__(self, m: TriadModel, kind: str, rate: float, rng: np.random.Generator,
                 decimate: int = 1):
        self.m, self.kind, self.k = m, kind, int(decimate)
        self.rate = check_positive(rate, "rate")
        self.dt = 1.0 / self.rate
        present = [t for t in TERMS.values() if t.present(m)]
        self.state = {}
        for stage in DRAW_ORDER + tuple(sorted({t.stage for t in present} - set(DRAW_ORDER))):
            for t in present:
                if t.stage == stage:
                    self.state[t.name] = t.start(m, self, rng)
        self.by_stage = {}
        for t in present:
            self.by_stage.setdefault(t.stage, []).append((t, self.state[t.name]))
        M = np.eye(3)
        for t, st in self.by_stage.get("gain", ()):
            M = M + t.gain(m, st)
        self.matrix = M
        self.offset = np.zeros(3)
        for t, st in self.by_stage.get("offset", ()):
            self.offset = self.offset + t.offset(m, st)

    def process(self, ideal: FloatArray, other: FloatArray | None = None
                ) -> tuple[FloatArray, np.ndarray]:
        """Ideal samples (n, 3) → measured samples (n/decimate, 3) and the saturation flag of
        each output sample.

        Parameters
        ----------
        ideal : ndarray, shape (n, 3)
            The next ideal samples (rates or increments, as the stream's kind).
        other : ndarray, shape (n, 3), optional
            The ideal accelerometer samples of the same instants (the gyro's g-sensitivity).

        Returns
        -------
        measured : ndarray, shape (n // decimate, 3)
        flags : ndarray of bool
            True where an output sample was clipped at the range.
        """
        m, k, dt = self.m, self.k, self.dt
        stages = self.by_stage
        n = ideal.shape[0]
        x = ideal / dt if self.kind == "increments" else ideal          # rate units
        # in place, in the order of y = x Mᵀ + offset + drift + G f + noise (the same roundings);
        # a run without drift terms adds no zeros (y + 0 is y: no −0 survives "+ offset")
        y = x @ self.matrix.T
        y += self.offset
        drifting = stages.get("drift", ())
        if drifting:
            drift = np.zeros((n, 3))
            for t, st in drifting:
                t.add_drift(m, st, self, drift)
            y += drift
        for t, st in stages.get("coupling", ()):
            y = t.couple(m, st, self, y, other)
        for t, st in stages.get("white", ()):
            y = t.add_white(m, st, self, y)
        for t, st in stages.get("filter", ()):
            y = t.filter(m, st, self, y)
        flags = np.zeros(n, dtype=bool)
        for t, _ in stages.get("saturation", ()):
            y, clipped = t.saturate(m, y)
            flags |= clipped
        if k > 1:
            nn = n // k
            if self.kind == "increments":
                y = y[: nn * k].reshape(nn, k, 3).mean(axis=1)     # Σ increments / (k·dt)
                flags = flags[: nn * k].reshape(nn, k).any(axis=1)
            else:
                y, flags = y[::k], flags[::k]                      # the output instants
        if self.kind == "increments":
            y *= dt * k
        for t, st in stages.get("quantisation", ()):
            y = t.quantise(m, st, self, y)
        return y, flags


def apply_triad(m: TriadModel, ideal: FloatArray, kind: str, rate: float, rng,
                other: FloatArray | None = None, decimate: int = 1
                ) -> tuple[FloatArray, np.ndarray]:
    """One run of one triad's errors on a whole signal (a :class:`TriadStream` fed once).

    Parameters
    ----------
    m : TriadModel
        The triad's errors.
    ideal : ndarray, shape (n, 3)
        Ideal samples at ``rate``: ω_b (rad/s) or f_b (m/s²) for rates, Δθ (rad) or Δv (m/s)
        for increments.
    kind : {"rates", "increments"}
        What ``ideal`` holds.
    rate : float
        The rate of ``ideal`` (Hz): the sensor's internal rate.
    rng : numpy.random.Generator
        The run's random generator.
    other : ndarray, shape (n, 3), optional
        The ideal accelerometer signal (same kind) for a gyro's g-sensitivity.
    decimate : int, default 1
        Internal samples per output sample; the output is at ``rate / decimate``.

    Returns
    -------
    measured : ndarray, shape (n // decimate, 3)
        The measured signal, same kind and units as ``ideal``.
    flags : ndarray of bool, shape (n // decimate,)
        True where an output sample was clipped at the range.

    Raises
    ------
    ImunavError
        If ``rate`` is not a finite number > 0.

    Examples
    --------
    >>> import numpy as np
    >>> y, clipped = apply_triad(TriadModel(range=1.0), np.full((2, 3), 2.0), "rates", 100,
    ...                          np.random.default_rng(0))
    >>> y, clipped
    (array([[1., 1., 1.],
           [1., 1., 1.]]), array([ True,  True]))
    """
    return TriadStream(m, kind, rate, rng, decimate).process(ideal, other)


class MeasureStream:
    """One run of a 6-axis IMU: ideal gyro and accel chunks → measured chunks and flags.

    Parameters
    ----------
    imu : ImuModel
    kind : {"rates", "increments"}
    rate : float
        Rate of the ideal samples (Hz).
    rng : numpy.random.Generator
        The run's generator (the gyro's own generator is seeded from it first).
    decimate : int
        Internal samples per output sample.
    """

    @renamed(model="imu")
    def __init__(self, imu: ImuModel, kind: str, rate: float, rng: np.random.Generator,
                 decimate: int = 1):
        g2 = np.random.default_rng(rng.integers(2**63))
        self.gyro = TriadStream(imu.gyro, kind, rate, g2, decimate)
        self.accel = TriadStream(imu.accel, kind, rate, rng, decimate)

    def process(self, gyro: FloatArray, accel: FloatArray
                ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """Apply the run's errors to the next ideal chunks.

        Parameters
        ----------
        gyro : ndarray, shape (n, 3)
            Ideal ω_b (rad/s) or Δθ (rad), as the stream's kind.
        accel : ndarray, shape (n, 3)
            Ideal f_b (m/s²) or Δv (m/s) of the same instants.

        Returns
        -------
        gyro : ndarray, shape (n // decimate, 3)
            Measured gyro output.
        accel : ndarray, shape (n // decimate, 3)
            Measured accelerometer output.
        clipped : ndarray of bool, shape (n // decimate,)
            True where either triad clipped an output sample at its range.
        """
        gm, fg = self.gyro.process(gyro, other=accel)
        am, fa = self.accel.process(accel)
        return gm, am, fg | fa


@renamed(model="imu")
def measure(imu: ImuModel, gyro: FloatArray, accel: FloatArray, kind: str, rate: float,
            rng, decimate: int = 1) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """One run of a 6-axis IMU's errors on whole ideal signals (a :class:`MeasureStream` fed
    once).

    Parameters
    ----------
    imu : ImuModel
        The sensor's errors.
    gyro : ndarray, shape (n, 3)
        Ideal ω_b (rad/s) or Δθ (rad).
    accel : ndarray, shape (n, 3)
        Ideal f_b (m/s²) or Δv (m/s) of the same instants.
    kind : {"rates", "increments"}
        What the signals hold.
    rate : float
        Their rate (Hz): the sensor's internal rate.
    rng : numpy.random.Generator
        The run's random generator.
    decimate : int, default 1
        Internal samples per output sample.

    Returns
    -------
    gyro : ndarray, shape (n // decimate, 3)
        Measured gyro output.
    accel : ndarray, shape (n // decimate, 3)
        Measured accelerometer output.
    clipped : ndarray of bool, shape (n // decimate,)
        True where an output sample was clipped at a range.

    Raises
    ------
    ImunavError
        If ``rate`` is not a finite number > 0.

    Examples
    --------
    A turn-on bias is one constant per axis for the whole run:

    >>> import numpy as np
    >>> g, a, clipped = measure(ImuModel(TriadModel(bias=0.01)), np.zeros((3, 3)),
    ...                         np.zeros((3, 3)), "rates", 100, np.random.default_rng(0))
    >>> bool((g == g[0]).all()), bool(a.any()), bool(clipped.any())
    (True, False, False)
    """
    return MeasureStream(imu, kind, rate, rng, decimate).process(gyro, accel)
