"""Layer 4 — analysis: how far navigation drifts from the truth, and whether an IMU is good
enough.

Modules: :mod:`~imunav.analysis.metrics` (errors against the truth, fitted orders),
:mod:`~imunav.analysis.roundtrip` (simulate → navigate → errors), :mod:`~imunav.analysis.family`
(the algorithm family on benchmarks), :mod:`~imunav.analysis.montecarlo`,
:mod:`~imunav.analysis.assessment` (the verdict).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``.
"""

from imunav.analysis.assessment import assess, format_verdict, min_sample_rate
from imunav.analysis.metrics import NavErrors, fit_order, nav_errors
from imunav.analysis.montecarlo import MonteCarloResult, monte_carlo
from imunav.analysis.roundtrip import RoundTrip, error_table, initial_state, round_trip

__all__ = ["MonteCarloResult", "NavErrors", "RoundTrip", "assess", "error_table", "fit_order",
           "format_verdict", "initial_state", "min_sample_rate", "monte_carlo", "nav_errors",
           "round_trip"]
