"""Floor 5 — analysis: how far navigation drifts from the truth, and whether an IMU is good
enough.

Modules: :mod:`~imunav.analysis.metrics` (errors against the truth, fitted orders),
:mod:`~imunav.analysis.roundtrip` (simulate → navigate → errors), :mod:`~imunav.analysis.family`
(the algorithm family on benchmarks), :mod:`~imunav.analysis.montecarlo`,
:mod:`~imunav.analysis.assessment` (the verdict), :mod:`~imunav.analysis.covariance` (linear
covariance analysis, with :mod:`~imunav.analysis.gaussnorm` for the percentiles of the error
norm), :mod:`~imunav.analysis.design` (the worst IMU that still meets a tolerance),
:mod:`~imunav.analysis.recordings` (analyses of real recordings), :mod:`~imunav.analysis.aided`
(Monte Carlo of the aided filter: NEES with known truth).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.io``,
``imunav.strapdown``, ``imunav.estimation``.
"""

from imunav.analysis.aided import FilterMonteCarlo, filter_monte_carlo, nees, nees_band
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
from imunav.analysis.roundtrip import RoundTrip, error_table, initial_state, round_trip

__all__ = ["CovarianceResult", "FilterMonteCarlo", "MonteCarloResult", "NavErrors", "RoundTrip", "assess",
           "assess_covariance", "covariance", "design", "error_table", "filter_monte_carlo", "fit_order",
           "format_design", "format_verdict", "initial_state", "min_sample_rate", "monte_carlo", "nav_errors",
           "nees", "nees_band", "round_trip"]
