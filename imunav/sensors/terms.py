"""The sensor error terms: one object per term, the one authority for everything about it.

Each term of :data:`TERMS` carries

- its **name** and the **parameters** a datasheet gives for it (``bias_instability`` and its
  ``bias_correlation_time``), with their **units** per triad: the spellings an ``IMU.toml``
  may use (:func:`parse`) and the unit it is **shown** in (:meth:`Term.show`: the limits of
  ``imunav design``, the fits of ``imunav allan``);
- its **realisation** in the simulation: the per-run draws (:meth:`Term.start`) and its step of
  the sensor pipeline (:data:`STAGES`), which :class:`~imunav.sensors.models.TriadStream` runs;
- its **linearisation** (:meth:`Term.linearise`): the sensor-error states it adds to the error
  state, as :class:`SensorErrorStates` — ``k`` states ``x`` with ``ẋ = diag(D) x + w``
  (``E[w wᵀ] = diag(Qs) δ(t − s)``, ``x(0) ~ N(0, P0)``) entering the triad's output as
  ``δu = M(t) x``, plus white noise on the output. :mod:`imunav.estimation` maps them into the
  navigation errors; terms without a linear model (range, the anti-alias filter, the internal
  rate) say so and what stands in for it.

A term realised in the simulation must have a linearisation: :meth:`Term.linearise` of the base
class raises, so a new term that forgets it fails in the covariance analysis instead of being
ignored (``tests/test_sensor_terms.py`` checks every registered term). Adding a term is one
subclass here and one :func:`register` call — nothing else in imunav changes.

The terms (every one optional; 0 or absent = no such error):

=====================  ==================================================================
noise_density N        white noise; Allan σ(τ) = N/√τ. Linear: PSD N² on the output (rate
                       samples decimated from an internal rate: × the folded power of the
                       filter, :func:`aliasing_gain`)
bias σ                 turn-on bias, 1σ per axis, drawn once per run; 3 random constants
bias_instability B     Allan-deviation floor B; Gauss–Markov with ``bias_correlation_time``,
                       else flicker (1/f) from a bank of Gauss–Markov processes (0.3–3000 s);
                       each component 3 states, decay 1/T, stationary variance s², driving
                       PSD 2s²/T (:func:`bias_instability_sigma`)
random_walk K          rate/acceleration random walk; Allan σ(τ) = K √(τ/3); 3 states of
                       integrated white noise of PSD K², starting at 0
scale_factor σ         1σ per axis, drawn once per run: δu = diag(u) s
misalignment σ         1σ cross-axis coupling (rad), 6 off-diagonal terms: δu_i = Σ_{j≠i} m_ij u_j
g_sensitivity σ        gyro only: ω += G f_b, G 1σ per axis pair (9 constants)
range                  saturation (clipped, flagged); not linear: a warning when the motion's
                       |ω_b| or |f_b| exceeds it
resolution q           quantisation step (rate units); increments carry the residual. Linear:
                       rate samples, white noise of variance q²/12 per sample (PSD q²h/12);
                       increments, the error of increment k is e_k − e_{k−1} with e white of
                       variance (q h)²/12 (the angle or velocity error stays bounded)
bandwidth              2nd-order Butterworth low-pass at the internal rate; no linear state:
                       increments keep unit gain at low frequency, and its effect on the
                       noise of decimated rate samples is in the white noise's aliasing gain
internal_rate          the sensor samples and filters internally at this rate, then decimates
                       (every k-th rate sample, or the sum of k increments); no error of its own
=====================  ==================================================================

Randomness: the constants of a run (offset, gain, coupling terms) are drawn from the run's
generator first, then each process (drift and white-noise terms) takes its own child
generator (:data:`DRAW_ORDER`), so a run is reproducible bit for bit whatever the chunking.

May import: ``imunav.core``, ``imunav.sensors.allan``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import butter, lfilter, sosfilt, sosfilt_zi, sosfreqz

from imunav.core import units as U
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, show
from imunav.sensors.allan import gauss_markov_allan_variance

__all__ = ["DRAW_ORDER", "STAGES", "TERMS", "TRIADS", "LinearisationContext", "Parameter",
           "SensorErrorStates", "Term", "aliasing_gain", "bias_instability_sigma",
           "flicker_bank", "parameters", "parse", "printed", "register", "terms_for",
           "unregister"]

#: The two triads of a 6-axis IMU.
TRIADS = ("gyro", "accel")

#: The sensor pipeline, in the order a sample goes through it: ``y = M x + offset + drift``
#: (gain, offset, drift), then the coupling to the other triad, white noise, the anti-alias
#: filter, saturation, decimation to the output rate, quantisation.
STAGES = ("gain", "offset", "drift", "coupling", "white", "filter", "saturation", "decimation",
          "quantisation")

#: The order in which the terms of a run take their random numbers: first the run's constants
#: (offset, gain, coupling) from its generator, then one child generator per process (drift,
#: white). Kept from imunav 0.2, so a seed gives the same runs as before.
DRAW_ORDER = ("offset", "gain", "coupling", "drift", "white")


@dataclass(frozen=True)
class Parameter:
    """One datasheet parameter of a term.

    Attributes
    ----------
    key : str
        Its key in ``[gyro]`` / ``[accel]`` of an ``IMU.toml`` and its attribute of
        :class:`~imunav.sensors.models.TriadModel`.
    units : dict
        ``{triad: {spelling: SI factor}}``: the accepted units (a table of :mod:`imunav.core.units`).
    description : dict
        ``{triad: text}``, used in error messages ("unit 'x' is not a unit of …").
    default : float or None
        The value when absent (0.0 for error magnitudes, None for settings such as the range).
    limits : tuple or None
        ``(low, high, why)`` in SI for values that size the work; outside is an error.
    qualifier : bool
        True for a parameter that only qualifies another (a correlation time): it is kept when
        a model is reduced to one term (:meth:`~imunav.sensors.models.TriadModel.only`).
    positive : bool
        True where 0 is not a value (a range: it would clip everything): it is refused.
    """

    key: str
    units: Mapping[str, Mapping[str, float]]
    description: Mapping[str, str]
    default: float | None = 0.0
    limits: tuple[float, float, str] | None = None
    qualifier: bool = False
    positive: bool = False


@dataclass
class LinearisationContext:
    """What a term needs to linearise itself along a motion.

    Attributes
    ----------
    triad : {"gyro", "accel"}
    h : float
        Output sample interval (s).
    output : {"increments", "rates"}
        The signal kind the analysis is for.
    decimate : int
        Internal samples per output sample.
    peak : float
        Largest ``|u|`` the triad measures over the motion (``|ω_b|`` or ``|f_b|``, SI).
    warnings : list of str
        Where a term without a linear model appends why the linear analysis may be wrong.
    """

    triad: str
    h: float
    output: str = "increments"
    decimate: int = 1
    peak: float = 0.0
    warnings: list[str] = field(default_factory=list)


def _no_input(u: FloatArray, f: FloatArray) -> FloatArray:
    return np.zeros(u.shape[:1] + (3, 0))


def _identity_input(u: FloatArray, f: FloatArray) -> FloatArray:
    return np.broadcast_to(np.eye(3), (u.shape[0], 3, 3))


@dataclass
class SensorErrorStates:
    """The linearisation of one error term of one triad, in the sensor's own terms.

    ``k`` states ``x`` with ``ẋ = diag(D) x + w``, ``E[w wᵀ] = diag(Qs) δ``, ``x(0) ~ N(0, P0)``,
    entering the triad's output (rate units: rad/s or m/s²) as ``δu = M(t) x`` with
    ``M = input_matrix(u, f)`` over the steps; plus white noise of PSD ``white_psd`` per axis
    on the output, and (quantisation of increments with a carried residual) a differenced white
    error ``δu_k = (e_k − e_{k−1})/h`` with ``e`` white of variance ``differenced_white``.

    Attributes
    ----------
    name : str
        ``"gyro.bias"`` etc.
    triad : {"gyro", "accel"}
    D, P0, Qs : ndarray, shapes (k,), (k, k), (k,)
    input_matrix : callable
        ``(u (n, 3), f_b (n, 3)) → M (n, 3, k)``: ``u`` what the triad measures over ``n``
        steps (``ω_b`` or ``f_b``), ``f_b`` the specific force (the gyro's g-sensitivity).
    white_psd : float
    differenced_white : float
    """

    name: str
    triad: str
    D: FloatArray = field(default_factory=lambda: np.zeros(0))
    P0: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    Qs: FloatArray = field(default_factory=lambda: np.zeros(0))
    input_matrix: Callable[[FloatArray, FloatArray], FloatArray] = _no_input
    white_psd: float = 0.0
    differenced_white: float = 0.0

    @property
    def size(self) -> int:
        """Number of sensor states ``k``."""
        return int(self.D.size)


class Term:
    """One sensor error term: its parameters and units, its realisation, its linearisation.

    Subclasses set :attr:`name`, :attr:`stage`, :attr:`parameters_` and implement the hook of
    their stage and :meth:`linearise`.

    Attributes
    ----------
    name : str
        The term's key (its main parameter), e.g. ``"noise_density"``.
    triads : tuple of str
        The triads it exists for.
    stage : str
        Its step of the pipeline, one of :data:`STAGES`.
    is_error : bool
        False for a setting that is not itself an error (the internal rate): it is not listed
        among a model's terms.
    linear : bool
        Whether it adds states or noise to the error model (False: :meth:`linearise` explains
        what stands in for it, or warns).
    parameters_ : tuple of Parameter
        The main parameter first.
    display : dict
        ``{triad: (unit, typographic unit, SI unit text)}``: the datasheet unit values are
        shown in (a spelling of the parameter's units), its printed form, and the SI unit.
    """

    name: str = ""
    triads: tuple[str, ...] = TRIADS
    stage: str = ""
    is_error: bool = True
    linear: bool = True
    parameters_: tuple[Parameter, ...] = ()
    display: Mapping[str, tuple[str, str, str]] = {}

    # ------------------------------------------------------------------ values and units
    def value(self, model) -> float | None:
        """The term's main value in ``model``.

        Parameters
        ----------
        model : TriadModel

        Returns
        -------
        float or None
            SI.
        """
        return getattr(model, self.name)

    def present(self, model) -> bool:
        """Whether ``model`` has this term (its value neither 0 nor None).

        Parameters
        ----------
        model : TriadModel

        Returns
        -------
        bool
        """
        return self.value(model) not in (None, 0.0)

    def show(self, si: float, triad: str, *, digits: int = 3, typographic: bool = False) -> str:
        """``"0.12 deg/sqrt(h)"``: an SI value in the term's datasheet unit for ``triad``.

        Parameters
        ----------
        si : float
            The value in SI units.
        triad : {"gyro", "accel"}
        digits : int
            Significant digits.
        typographic : bool
            Write the unit as printed for people (``°/√h``, ``µg``: every report of the command
            line and the notebooks) rather than as spelt in files (``deg/sqrt(h)``, ``ug``).

        Returns
        -------
        str

        Raises
        ------
        KeyError
            If the term has no display unit for ``triad``.
        """
        unit, pretty, _ = self.display[triad]
        factor = self.parameters_[0].units[triad][unit]
        return f"{si / factor:.{digits}g} {pretty if typographic else unit}"

    def si_unit(self, triad: str) -> str:
        """The SI unit of the main value, as written beside it in a fitted ``IMU.toml``.

        Parameters
        ----------
        triad : {"gyro", "accel"}

        Returns
        -------
        str
        """
        return self.display[triad][2]

    # ------------------------------------------------------------------ realisation
    def start(self, model, stream, rng: np.random.Generator):
        """Draw what one run of this term needs when its stream starts.

        Constants come from ``rng``; a process spawns its own child generator, so that the run does not
        depend on how it is chunked.

        Parameters
        ----------
        model : TriadModel
        stream : TriadStream
            Its ``rate``, ``dt``, ``kind`` and decimation ``k``.
        rng : numpy.random.Generator
            The run's generator.

        Returns
        -------
        object
            The term's run state, handed back to its stage hook (None if it needs none).
        """
        return None

    # ------------------------------------------------------------------ linearisation
    def linearise(self, model, ctx: LinearisationContext) -> list[SensorErrorStates]:
        """The sensor-error states of this term for ``model`` (a TriadModel) along a motion.

        Parameters
        ----------
        model : TriadModel
        ctx : LinearisationContext

        Returns
        -------
        list of SensorErrorStates
            Empty when the term is absent, or has no linear model (then it may append a
            warning to ``ctx.warnings``).

        Raises
        ------
        NotImplementedError
            Always, in the base class: every term realised in the simulation must say how it
            enters the error model.
        """
        raise NotImplementedError(f"sensor error term {self.name!r} has a realisation but no "
                                  "linearisation: implement Term.linearise")


def _tables(gyro: Mapping[str, float], accel: Mapping[str, float]) -> dict[str, Mapping]:
    return {"gyro": gyro, "accel": accel}


def _both(text: str) -> dict[str, str]:
    return {"gyro": text, "accel": text}


def _main(term_name: str, units, description, default: float | None = 0.0, limits=None
          ) -> Parameter:
    return Parameter(term_name, units, description, default, limits)


# ---------------------------------------------------------------------------- the terms


class WhiteNoise(Term):
    """White noise of density N: ``N·√rate`` per sample."""

    name, stage = "noise_density", "white"
    parameters_ = (_main("noise_density", _tables(U.DENSITY_RATE, U.DENSITY_ACCEL),
                         {"gyro": "rate noise density / angle random walk",
                          "accel": "acceleration noise density / velocity random walk"}),)
    display = {"gyro": ("deg/sqrt(h)", "°/√h", "rad/s/√Hz (= rad/√s)"),
               "accel": ("ug/sqrt(Hz)", "µg/√Hz", "m/s²/√Hz (= m/s/√s)")}

    def start(self, model, stream, rng):
        """A child generator for the noise."""
        return rng.spawn(1)[0]

    def add_white(self, model, state, stream, y: FloatArray) -> FloatArray:
        """``y`` plus this run's white noise (rate units)."""
        y += state.normal(0.0, model.noise_density * np.sqrt(stream.rate), y.shape)
        return y

    def linearise(self, model, ctx):
        """White noise of PSD ``(N · aliasing gain)²`` on the output."""
        if not self.present(model):
            return []
        gain = aliasing_gain(model, 1 / ctx.h, ctx.decimate, ctx.output)
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad,
                                  white_psd=(model.noise_density * gain) ** 2)]


class TurnOnBias(Term):
    """A constant offset per run, 1σ per axis."""

    name, stage = "bias", "offset"
    parameters_ = (_main("bias", _tables(U.RATE, U.ACCEL), _both("turn-on bias (1σ)")),)
    display = {"gyro": ("deg/h", "°/h", "rad/s"), "accel": ("mg", "mg", "m/s²")}

    def start(self, model, stream, rng):
        """The run's bias vector (3,)."""
        return rng.normal(0.0, model.bias, 3)

    def offset(self, model, state) -> FloatArray:
        """The term's part of the constant offset (rate units)."""
        return state

    def linearise(self, model, ctx):
        """Three random constants of variance σ²."""
        if not self.present(model):
            return []
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  model.bias ** 2 * np.eye(3), np.zeros(3), _identity_input)]


def flicker_bank(T: float | None) -> list[float]:
    """Correlation times (s) of the Gauss–Markov components of a bias instability: ``[T]`` if
    a correlation time is given, else the flicker bank (9 times from 0.3 to 3000 s)."""
    return [T] if T else list(np.logspace(np.log10(0.3), np.log10(3000.0), 9))


def bias_instability_sigma(B: float, T: float | None) -> float:
    """Std of each Gauss–Markov component so the Allan-deviation maximum equals ``B``.

    Parameters
    ----------
    B : float
        The bias instability (Allan-deviation floor), SI.
    T : float or None
        The correlation time (s), or None for the flicker bank.

    Returns
    -------
    float
    """
    taus = np.logspace(-3, 5, 4000)
    var = sum(gauss_markov_allan_variance(taus, 1.0, t) for t in flicker_bank(T))
    return B / float(np.sqrt(var.max()))


class BiasInstability(Term):
    """Gauss–Markov processes whose Allan maximum is the datasheet's bias instability."""

    name, stage = "bias_instability", "drift"
    parameters_ = (
        _main("bias_instability", _tables(U.RATE, U.ACCEL),
              _both("bias instability (Allan deviation floor)")),
        Parameter("bias_correlation_time", _tables(U.TIME, U.TIME),
                  _both("bias correlation time"), None,
                  (1e-3, 1e9, "a correlation time between 1 ms and 30 years"), qualifier=True),
    )
    display = {"gyro": ("deg/h", "°/h", "rad/s"), "accel": ("ug", "µg", "m/s²")}

    def start(self, model, stream, rng):
        """Per component: ``[child generator, a = e^{−dt/T}, innovation σ, previous value]``,
        the value before the first sample drawn from the stationary distribution."""
        sd = bias_instability_sigma(model.bias_instability, model.bias_correlation_time)
        out = []
        for T in flicker_bank(model.bias_correlation_time):
            child = rng.spawn(1)[0]
            a = float(np.exp(-stream.dt / T))
            out.append([child, a, sd * np.sqrt(1 - a * a), child.normal(0.0, sd, 3)])
        return out

    def add_drift(self, model, state, stream, drift: FloatArray) -> None:
        """Add the next ``len(drift)`` samples of each component to ``drift`` (in place)."""
        n = drift.shape[0]
        for st in state:
            child, a, sw, prev = st
            w = child.normal(0.0, sw, (n, 3))
            y, _ = lfilter([1.0], [1.0, -a], w, axis=0, zi=(a * prev)[None])
            drift += y
            st[3] = y[-1]

    def linearise(self, model, ctx):
        """3 states per component: decay 1/T, stationary variance s², driving PSD 2s²/T."""
        if not self.present(model):
            return []
        s = bias_instability_sigma(model.bias_instability, model.bias_correlation_time)
        bank = flicker_bank(model.bias_correlation_time)
        k = 3 * len(bank)
        D = np.repeat([-1.0 / T for T in bank], 3)
        Qs = np.repeat([2 * s * s / T for T in bank], 3)

        def each_component(u, f):
            """δ = Σ components: the identity once per component."""
            return np.tile(np.broadcast_to(np.eye(3), (u.shape[0], 3, 3)), (1, 1, len(bank)))

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, D, s * s * np.eye(k),
                                  Qs, each_component)]


class RandomWalk(Term):
    """Integrated white noise of density K."""

    name, stage = "random_walk", "drift"
    parameters_ = (_main("random_walk", _tables(U.RW_RATE, U.RW_ACCEL),
                         {"gyro": "rate random walk", "accel": "acceleration random walk"}),)
    display = {"gyro": ("deg/h/sqrt(h)", "°/h/√h", "rad/s/√s"),
               "accel": ("m/s/h/sqrt(h)", "m/s/h/√h", "m/s²/√s")}

    def start(self, model, stream, rng):
        """``[child generator, the walk's last value]``."""
        return [rng.spawn(1)[0], np.zeros(3)]

    def add_drift(self, model, state, stream, drift: FloatArray) -> None:
        """Add the next ``len(drift)`` samples of the walk to ``drift`` (in place)."""
        child, last = state
        walk = np.cumsum(child.normal(0.0, model.random_walk * np.sqrt(stream.dt),
                                      drift.shape), axis=0) + last
        state[1] = walk[-1]
        drift += walk

    def linearise(self, model, ctx):
        """3 states of integrated white noise (PSD K²), starting at 0."""
        if not self.present(model):
            return []
        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  np.zeros((3, 3)), np.full(3, model.random_walk ** 2),
                                  _identity_input)]


class ScaleFactor(Term):
    """``y = (I + diag(s)) x``, s drawn once per run."""

    name, stage = "scale_factor", "gain"
    parameters_ = (_main("scale_factor", _tables(U.FRACTION, U.FRACTION),
                         _both("scale-factor error (1σ)")),)
    display = {"gyro": ("ppm", "ppm", "1"), "accel": ("ppm", "ppm", "1")}

    def start(self, model, stream, rng):
        """The run's gain error, a diagonal 3×3 matrix."""
        return np.diag(rng.normal(0.0, model.scale_factor, 3))

    def gain(self, model, state) -> FloatArray:
        """The term's part of ``M − I``."""
        return state

    def linearise(self, model, ctx):
        """3 random constants: ``δu = diag(u) s``."""
        if not self.present(model):
            return []

        def diag_u(u, f):
            """``diag(u)`` at each step."""
            M = np.zeros((u.shape[0], 3, 3))
            M[:, [0, 1, 2], [0, 1, 2]] = u
            return M

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(3),
                                  model.scale_factor ** 2 * np.eye(3), np.zeros(3), diag_u)]


#: The six off-diagonal (row, column) pairs of a 3×3 matrix, in row order.
OFF_DIAGONAL = [(i, j) for i in range(3) for j in range(3) if i != j]


class Misalignment(Term):
    """Cross-axis coupling: 6 off-diagonal entries of ``M``, drawn once per run."""

    name, stage = "misalignment", "gain"
    parameters_ = (_main("misalignment", _tables(U.ANGLE, U.ANGLE),
                         _both("misalignment / cross-axis coupling (1σ)")),)
    display = {"gyro": ("mrad", "mrad", "rad"), "accel": ("mrad", "mrad", "rad")}

    def start(self, model, stream, rng):
        """The run's cross-axis matrix (zero diagonal)."""
        off = rng.normal(0.0, model.misalignment, (3, 3))
        np.fill_diagonal(off, 0.0)
        return off

    def gain(self, model, state) -> FloatArray:
        """The term's part of ``M − I``."""
        return state

    def linearise(self, model, ctx):
        """6 random constants: ``δu_i = Σ_{j≠i} m_ij u_j``."""
        if not self.present(model):
            return []

        def cross_axis(u, f):
            """The other axes' ``u`` in each off-diagonal column."""
            M = np.zeros((u.shape[0], 3, 6))
            for c, (i, j) in enumerate(OFF_DIAGONAL):
                M[:, i, c] = u[:, j]
            return M

        return [SensorErrorStates(f"{ctx.triad}.{self.name}", ctx.triad, np.zeros(6),
                                  model.misalignment ** 2 * np.eye(6), np.zeros(6), cross_axis)]


class GSensitivity(Term):
    """The gyro's response to specific force: ``ω += G f_b``."""

    name, stage, triads = "g_sensitivity", "coupling", ("gyro",)
    parameters_ = (_main("g_sensitivity", {"gyro": U.GSENS}, {"gyro": "g-sensitivity (1σ)"}),)
    display = {"gyro": ("deg/h/g", "°/h/g", "rad/s/(m/s²)")}

    def start(self, model, stream, rng):
        """The run's 3×3 g-sensitivity matrix."""
        return rng.normal(0.0, model.g_sensitivity, (3, 3))

    def couple(self, model, state, stream, y: FloatArray, other: FloatArray | None
               ) -> FloatArray:
        """``y + G f`` with ``f`` the ideal specific force of the same samples."""
        if other is None:
            return y
        f = other / stream.dt if stream.kind == "increments" else other
        y += f @ state.T
        return y

    def linearise(self, model, ctx):
        """9 random constants: ``δω_i = Σ_j G_ij f_j``."""
        if ctx.triad != "gyro" or not self.present(model):
            return []

        def by_force(u, f):
            """``f`` in the row block of each gyro axis."""
            M = np.zeros((u.shape[0], 3, 9))
            for i in range(3):
                M[:, i, 3 * i: 3 * i + 3] = f
            return M

        return [SensorErrorStates(f"gyro.{self.name}", "gyro", np.zeros(9),
                                  model.g_sensitivity ** 2 * np.eye(9), np.zeros(9), by_force)]


class Range(Term):
    """Saturation: outputs beyond ±range are clipped and flagged."""

    name, stage, linear = "range", "saturation", False
    parameters_ = (Parameter("range", _tables(U.RATE, U.ACCEL), _both("measurement range"), None,
                             positive=True),)
    display = {"gyro": ("deg/s", "°/s", "rad/s"), "accel": ("g", "g", "m/s²")}

    def saturate(self, model, y: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """``(clipped y, flag per sample)``."""
        over = np.abs(y) > model.range
        flags = over[:, 0] | over[:, 1] | over[:, 2]          # any axis (8× np.any's speed)
        np.clip(y, -model.range, model.range, out=y)
        return y, flags

    def linearise(self, model, ctx):
        """No linear model: a warning when the motion exceeds the range."""
        if self.present(model) and ctx.peak > model.range:
            what = "angular rate" if ctx.triad == "gyro" else "specific force"
            t = ctx.triad
            peak = self.show(ctx.peak, t, typographic=True)
            limit = self.show(model.range, t, typographic=True)
            ctx.warnings.append(f"the motion's {what} reaches {peak}, beyond the {t} range "
                                f"{limit}: clipping is not in the covariance; use Monte Carlo")
        return []


class Resolution(Term):
    """Quantisation to a step q; increments carry the rounding residual."""

    name, stage = "resolution", "quantisation"
    parameters_ = (_main("resolution", _tables(U.RATE, U.ACCEL), _both("quantisation step"),
                         None),)
    display = {"gyro": ("deg/s", "°/s", "rad/s"), "accel": ("mg", "mg", "m/s²")}

    def start(self, model, stream, rng):
        """Increments: ``[exact running sum, quantised running sum]``."""
        return [np.zeros(3), np.zeros(3)]

    def quantise(self, model, state, stream, y: FloatArray) -> FloatArray:
        """Output samples ``y`` (already in output units) rounded to the step."""
        if stream.kind == "increments":
            q = model.resolution * stream.dt * stream.k
            total = np.cumsum(y, axis=0)                             # residual carry: no loss
            total += state[0]
            qt = total / q
            np.round(qt, out=qt)
            qt *= q
            out = np.empty_like(qt)                                  # np.diff(qt, prepend=…)
            np.subtract(qt[:1], state[1], out=out[:1])
            np.subtract(qt[1:], qt[:-1], out=out[1:])
            state[0], state[1] = total[-1], qt[-1]
            return out
        return np.round(y / model.resolution) * model.resolution

    def linearise(self, model, ctx):
        """Rates: white noise of PSD q²h/12; increments: differenced white noise."""
        if not self.present(model):
            return []
        name = f"{ctx.triad}.{self.name}"
        if ctx.output == "rates":
            return [SensorErrorStates(name, ctx.triad, white_psd=model.resolution ** 2 * ctx.h / 12)]
        return [SensorErrorStates(name, ctx.triad, input_matrix=_identity_input,
                                  differenced_white=(model.resolution * ctx.h) ** 2 / 12)]


class Bandwidth(Term):
    """A 2nd-order Butterworth low-pass at the internal rate (steady state at the start)."""

    name, stage, linear = "bandwidth", "filter", False
    parameters_ = (_main("bandwidth", _tables(U.FREQ, U.FREQ),
                         _both("anti-alias / bandwidth filter corner"), None,
                         (1e-3, 1e6, "a filter corner between 1 mHz and 1 MHz")),)

    def start(self, model, stream, rng):
        """``[sos, filter state]`` if the corner is below the Nyquist rate, else None."""
        if model.bandwidth < 0.5 * stream.rate:
            return [butter(2, model.bandwidth, fs=stream.rate, output="sos"), None]
        return None

    def filter(self, model, state, stream, y: FloatArray) -> FloatArray:
        """``y`` through the filter, its state carried to the next chunk."""
        if state is None:
            return y
        sos, zi = state
        if zi is None:                # steady state for the first input (no start-up transient)
            zi = sosfilt_zi(sos)[:, :, None] * y[0]
        y, state[1] = sosfilt(sos, y, axis=0, zi=zi)
        return y

    def linearise(self, model, ctx):
        """No states: unit gain at low frequency; its effect on decimated rate noise is in
        :func:`aliasing_gain` (the white-noise term)."""
        return []


class InternalRate(Term):
    """The sensor's internal sample rate: the simulation runs there and decimates."""

    name, stage, is_error, linear = "internal_rate", "decimation", False, False
    parameters_ = (_main("internal_rate", _tables(U.FREQ, U.FREQ),
                         _both("internal sample rate"), None,
                         (1.0, 1e6, "no inertial sensor samples faster than 1 MHz internally")),)

    def linearise(self, model, ctx):
        """No error of its own: it sets the decimation the white noise's aliasing gain uses."""
        return []


def aliasing_gain(model, rate: float, decimate: int, output: str) -> float:
    """Factor on the white-noise density of ``output`` samples at ``rate`` taken every
    ``decimate``-th of the sensor's internal samples.

    Increments sum the internal ones, so the integrated noise is unchanged (1). Rate samples
    decimated by k keep every k-th sample: the noise above the output Nyquist folds onto low
    frequencies, and the density is multiplied by ``√(Σ_{m<k} |H(m·rate)|²)`` (H the anti-alias
    filter; 1 without one, so √k).

    Parameters
    ----------
    model : TriadModel
    rate : float
        Output rate (Hz).
    decimate : int
        Internal samples per output sample.
    output : {"increments", "rates"}

    Returns
    -------
    float
    """
    if output != "rates" or decimate <= 1:
        return 1.0
    fi = rate * decimate
    f = np.arange(decimate) * rate
    if model.bandwidth and model.bandwidth < 0.5 * fi:
        sos = butter(2, model.bandwidth, fs=fi, output="sos")
        h2 = np.abs(sosfreqz(sos, worN=f, fs=fi)[1]) ** 2
    else:
        h2 = np.ones(decimate)
    return float(np.sqrt(h2.sum()))


# ---------------------------------------------------------------------------- the registry

#: ``TERMS[name]`` → :class:`Term`, in the order models list their terms and the covariance
#: analysis propagates them.
TERMS: dict[str, Term] = {}


def register(term: Term) -> Term:
    """Add ``term`` to :data:`TERMS` (after the others).

    Parameters
    ----------
    term : Term

    Returns
    -------
    Term
        ``term`` itself.

    Raises
    ------
    ImunavError
        If a term of that name, or a parameter of that key, exists already, or its stage is
        not one of :data:`STAGES`.
    """
    if term.name in TERMS:
        raise ImunavError(f"a sensor error term {term.name!r} is registered already")
    if term.stage not in STAGES:
        raise ImunavError(f"term {term.name!r}: stage must be one of {STAGES}, got "
                          f"{term.stage!r}")
    keys = {p.key for t in TERMS.values() for p in t.parameters_}
    clash = sorted(keys & {p.key for p in term.parameters_})
    if clash:
        raise ImunavError(f"term {term.name!r}: parameter(s) {', '.join(clash)} exist already")
    TERMS[term.name] = term
    return term


def unregister(name: str) -> Term:
    """Remove the term ``name`` from :data:`TERMS` and return it (tests that add a toy term).

    Raises
    ------
    ImunavError
        If no term of that name is registered.
    """
    if name not in TERMS:
        raise ImunavError(f"no sensor error term {name!r} is registered")
    return TERMS.pop(name)


for _cls in (WhiteNoise, TurnOnBias, BiasInstability, RandomWalk, ScaleFactor, Misalignment,
             GSensitivity, Range, Resolution, Bandwidth, InternalRate):
    register(_cls())


def terms_for(triad: str) -> list[Term]:
    """The registered terms that exist for ``triad``, in registry order."""
    return [t for t in TERMS.values() if triad in t.triads]


def parameters(triad: str) -> dict[str, tuple[Term, Parameter]]:
    """``{key: (term, parameter)}`` of every parameter of ``triad``, in registry order."""
    return {p.key: (t, p) for t in terms_for(triad) for p in t.parameters_}


def parse(value, key: str) -> float:
    """Convert ``value`` for the parameter ``key`` (``"gyro.noise_density"``) to SI.

    ``parse("0.014 deg/s/sqrt(Hz)", "gyro.noise_density")`` → 2.443e-4 (rad/s/√Hz). A unit of
    another dimension (``"deg/s"`` for a noise density) or an unknown unit is an error naming
    the parameter and the accepted units; plain numbers are SI.

    Parameters
    ----------
    value : float or str
        A number in SI, or ``"<number> <unit>"``.
    key : str
        ``"<triad>.<parameter>"``.

    Returns
    -------
    float
        The value in SI, finite and ≥ 0.

    Raises
    ------
    ImunavError
        For an unknown key, a malformed value, a unit of another dimension, a negative or
        non-finite value, or one outside the parameter's limits.
    """
    triad, _, name = key.partition(".")
    table = parameters(triad) if triad in TRIADS else {}
    if name not in table:
        known = ", ".join(f"{t}.{k}" for t in TRIADS for k in parameters(t))
        raise ImunavError(f"unknown error parameter {key!r}; known: {known}")
    term, p = table[name]
    v = U.convert(value, p.units[triad], key, p.description[triad])
    if p.limits and not p.limits[0] <= v <= p.limits[1]:
        lo, hi, why = p.limits
        raise ImunavError(f"{key} = {show(value)} is outside {lo:g}–{hi:g} (SI): {why}")
    if v > MAX_VALUE:
        unit = (term.si_unit(triad) if p is term.parameters_[0] and term.display.get(triad)
                else "SI units")
        raise ImunavError(f"{key} = {show(value)} is beyond any sensor: at most {MAX_VALUE:g} "
                          f"{unit}")
    if p.positive and v == 0:
        raise ImunavError(f"{key} = {show(value)}: it must be > 0 (a {name} of 0 would clip every "
                          "sample); leave it out for none")
    return v


#: The largest value of any parameter in SI: far beyond every sensor (and its squares and
#: products along an analysis stay finite).
MAX_VALUE = 1e9


def printed(term: str, text: str) -> str:
    """A datasheet value as spelt in files and JSON (``"0.12 deg/sqrt(h)"``) with its unit as
    printed for people (``"0.12 °/√h"``), the one spelling of every report; a text in another
    unit (or a word such as ``"unbounded"``) is returned unchanged.

    Parameters
    ----------
    term : str
        ``"<triad>.<term>"``, e.g. ``"gyro.noise_density"``.
    text : str
        ``"<value> <unit>"``.

    Returns
    -------
    str
    """
    triad, _, name = term.partition(".")
    value, _, unit = text.partition(" ")
    shown = TERMS[name].display.get(triad) if name in TERMS else None
    return f"{value} {shown[1]}" if shown and unit == shown[0] else text
