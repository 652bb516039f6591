"""Floor 5 — analysis: how far navigation drifts from the truth, and whether an IMU is good
enough.

Modules: :mod:`~imunav.analysis.metrics` (errors against the truth, fitted orders),
:mod:`~imunav.analysis.roundtrip` (simulate → navigate → errors), :mod:`~imunav.analysis.family`
(the algorithm family on benchmarks), :mod:`~imunav.analysis.montecarlo`,
:mod:`~imunav.analysis.assessment` (the verdict), :mod:`~imunav.analysis.covariance` (linear
covariance analysis, with :mod:`~imunav.analysis.gaussnorm` for the percentiles of the error
norm), :mod:`~imunav.analysis.design` (the worst IMU that still meets a tolerance),
:mod:`~imunav.analysis.recordings` (analyses of real recordings); and aided, mirroring them:
:mod:`~imunav.analysis.aided_covariance` (the aided filter along the truth),
:mod:`~imunav.analysis.aided_montecarlo` (the aided filter's Monte Carlo: errors, NEES),
:mod:`~imunav.analysis.aided_assessment` (the aided verdict), :mod:`~imunav.analysis.outage`
(the longest bridgeable outage), :mod:`~imunav.analysis.aided_design` (the aided design).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.io``,
``imunav.strapdown``, ``imunav.estimation``.
"""

from imunav.analysis.aided_assessment import assess_aided, format_aided_verdict, outage_budget
from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.aided_design import design_aided, format_outage_design
from imunav.analysis.aided_montecarlo import (
    AidedMonteCarlo,
    FilterMonteCarlo,
    aided_monte_carlo,
    filter_monte_carlo,
    nees,
    nees_band,
)
from imunav.analysis.assessment import (
    assess,
    assess_covariance,
    format_verdict,
    min_sample_rate,
)
from imunav.analysis.covariance import CovarianceResult, covariance
from imunav.analysis.design import design, format_design
from imunav.analysis.metrics import NavErrors, fit_order, nav_errors
from imunav.analysis.montecarlo import MonteCarloResult, monte_carlo
from imunav.analysis.outage import bridgeable_outages, find_outage
from imunav.analysis.roundtrip import RoundTrip, error_table, initial_state, round_trip

__all__ = ["aided_monte_carlo", "AidedMonteCarlo", "AlongTruth", "assess", "assess_aided",
           "assess_covariance",            "bridgeable_outages", "covariance",
           "CovarianceResult", "design", "design_aided",            "error_table",
           "filter_monte_carlo", "FilterMonteCarlo", "find_outage", "fit_order",
           "format_aided_verdict", "format_design", "format_outage_design",
           "format_verdict",            "initial_state", "min_sample_rate",
           "monte_carlo", "MonteCarloResult", "nav_errors",            "NavErrors",
           "nees", "nees_band", "outage_budget", "round_trip", "RoundTrip"]
