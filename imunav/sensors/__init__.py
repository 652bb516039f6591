"""Layer 2 — sensors and simulation: what an IMU outputs on a motion, ideal or with datasheet
errors.

Modules: :mod:`~imunav.sensors.signals` (:class:`ImuSignals`), :mod:`~imunav.sensors.simulate`
(ideal rates and exact increments), :mod:`~imunav.sensors.aids` (the aids, one module each:
their AIDING.toml table, file, simulation and measurement model; the SHOE detector),
:mod:`~imunav.sensors.models` (error models from datasheets), :mod:`~imunav.sensors.terms`
(the error terms: units, realisation, linearisation),
:mod:`~imunav.sensors.presets`, :mod:`~imunav.sensors.allan`.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``.
"""

from imunav.sensors.aids import AIDS, AidingConfig, AidingData, Readings, simulate_aiding
from imunav.sensors.allan import allan_deviation, fit_allan, gauss_markov_allan_variance
from imunav.sensors.models import (
    ImuModel,
    MeasureStream,
    TriadModel,
    TriadStream,
    apply_triad,
    measure,
)
from imunav.sensors.presets import PRESETS
from imunav.sensors.quadrature import integrate_consecutive, integrate_intervals
from imunav.sensors.signals import KINDS, ImuSignals
from imunav.sensors.simulate import sample_times, simulate_imu, truth_states
from imunav.sensors.terms import TERMS, Term, bias_instability_sigma, register

__all__ = ["AIDS", "KINDS", "PRESETS", "TERMS", "AidingConfig", "AidingData", "ImuModel", "Readings",
           "ImuSignals", "MeasureStream", "TriadModel",
           "TriadStream", "allan_deviation", "apply_triad", "bias_instability_sigma", "fit_allan",
           "gauss_markov_allan_variance", "integrate_consecutive", "integrate_intervals",
           "measure", "register", "sample_times", "simulate_aiding", "simulate_imu", "Term", "truth_states"]
