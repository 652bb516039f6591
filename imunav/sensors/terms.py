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
ignored (``tests/sensors/test_terms.py`` checks every registered term). Adding a term is one
:class:`Term` subclass and one :func:`register` call — nothing else in imunav changes. The
contract is :mod:`~imunav.sensors.term_base`; the built-in terms live by family in
:mod:`~imunav.sensors.noise_terms` (random processes), :mod:`~imunav.sensors.constant_terms`
(drawn once per run) and :mod:`~imunav.sensors.signal_terms` (the signal chain), and are
registered below in the order models list them; every name is re-exported here.

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

May import: ``imunav.core``, ``imunav.sensors.term_base``, ``imunav.sensors.noise_terms``,
``imunav.sensors.constant_terms``, ``imunav.sensors.signal_terms``.
"""

from __future__ import annotations

from imunav.core import units as U
from imunav.core.validation import ImunavError, show
from imunav.sensors.constant_terms import (
    OFF_DIAGONAL,
    GSensitivity,
    Misalignment,
    ScaleFactor,
    TurnOnBias,
)
from imunav.sensors.noise_terms import (
    BiasInstability,
    RandomWalk,
    WhiteNoise,
    bias_instability_sigma,
    flicker_bank,
)
from imunav.sensors.signal_terms import Bandwidth, InternalRate, Range, Resolution, aliasing_gain
from imunav.sensors.term_base import (
    DRAW_ORDER,
    STAGES,
    TRIADS,
    LinearisationContext,
    Parameter,
    SensorErrorStates,
    Term,
)

__all__ = ["DRAW_ORDER", "MAX_VALUE", "OFF_DIAGONAL", "STAGES", "TERMS", "TRIADS", "Bandwidth",
           "BiasInstability", "GSensitivity", "InternalRate", "LinearisationContext",
           "Misalignment", "Parameter", "RandomWalk", "Range", "Resolution", "ScaleFactor",
           "SensorErrorStates", "Term", "TurnOnBias", "WhiteNoise", "aliasing_gain",
           "bias_instability_sigma", "flicker_bank", "parameters", "parse", "printed", "register",
           "terms_for", "unregister"]


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
