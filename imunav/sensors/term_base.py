"""What a sensor error term is made of (the contract of :mod:`imunav.sensors.terms`): its
datasheet :class:`Parameter` s with their units, its step of the sensor pipeline
(:data:`STAGES`), its realisation hooks and its linearisation (:class:`Term`), and what the
linearisation gives (:class:`SensorErrorStates`, for a :class:`LinearisationContext`).

May import: ``imunav.core``.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from imunav.core.deprecation import REMOVAL, renamed
from imunav.core.kernels import FloatArray

__all__ = ["DRAW_ORDER", "STAGES", "TRIADS", "LinearisationContext", "Parameter",
           "SensorErrorStates", "Term", "both_triads", "identity_input", "main_parameter",
           "no_input", "per_triad"]

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
    kind : {"increments", "rates"}
        The signal kind the analysis is for (``output``, its former name, warns).
    decimate : int
        Internal samples per output sample.
    peak : float
        Largest ``|u|`` the triad measures over the motion (``|ω_b|`` or ``|f_b|``, SI).
    warnings : list of str
        Where a term without a linear model appends why the linear analysis may be wrong.
    """

    triad: str
    h: float
    kind: str = "increments"
    decimate: int = 1
    peak: float = 0.0
    warnings: list[str] = field(default_factory=list)

    @property
    def output(self) -> str:
        """Deprecated: the signal kind, now :attr:`kind` (one name per argument, issue 35)."""
        warnings.warn(f"LinearisationContext.output is now LinearisationContext.kind; output "
                      f"will stop working in {REMOVAL}", DeprecationWarning, stacklevel=2)
        return self.kind


#: ``LinearisationContext(..., output=...)``, its former keyword, still constructs it (warning).
LinearisationContext.__init__ = renamed(output="kind")(LinearisationContext.__init__)


def no_input(u: FloatArray, f: FloatArray) -> FloatArray:
    """The input matrix of a source without states: ``(n, 3, 0)``."""
    return np.zeros(u.shape[:1] + (3, 0))


def identity_input(u: FloatArray, f: FloatArray) -> FloatArray:
    """The input matrix of three states that add to the output: ``I`` at every step."""
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
    input_matrix: Callable[[FloatArray, FloatArray], FloatArray] = no_input
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


def per_triad(gyro: Mapping[str, float], accel: Mapping[str, float]) -> dict[str, Mapping]:
    """``{"gyro": gyro, "accel": accel}``: a parameter's unit tables (or texts) per triad."""
    return {"gyro": gyro, "accel": accel}


def both_triads(text: str) -> dict[str, str]:
    """The same description for both triads."""
    return {"gyro": text, "accel": text}


def main_parameter(term_name: str, units, description, default: float | None = 0.0,
                   limits=None) -> Parameter:
    """A term's main parameter: its key is the term's name."""
    return Parameter(term_name, units, description, default, limits)
