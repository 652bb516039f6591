"""Floor 4 — estimation: the navigation error model and the generic Kalman steps, shared by the
covariance analysis and (next) the aided filters.

Modules: :mod:`~imunav.estimation.error_model` (the error state, its dynamics along a
trajectory, the sensor error terms as error sources), :mod:`~imunav.estimation.discretisation`
(exact ``Φ`` and ``Q_d`` of a step), :mod:`~imunav.estimation.propagation` (covariance
propagation, a piece of trajectory at a time), :mod:`~imunav.estimation.kalman` (prediction and
the Joseph-form measurement update).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``.
"""

from imunav.estimation.discretisation import flat_transition, phi_functions, process_noise, van_loan
from imunav.estimation.error_model import (
    DP,
    DV,
    EARTH,
    FLAT,
    NAV,
    PHI,
    EarthErrorModel,
    ErrorSource,
    FlatErrorModel,
    Trajectory,
    error_model,
    linearise,
)
from imunav.estimation.kalman import Update, predict, update
from imunav.estimation.propagation import propagate, propagate_chunks

__all__ = ["DP", "DV", "EARTH", "FLAT", "NAV", "PHI", "EarthErrorModel", "ErrorSource",
           "FlatErrorModel", "Trajectory", "error_model",
           "Update", "flat_transition", "linearise", "phi_functions", "predict",
           "process_noise", "propagate", "propagate_chunks", "update", "van_loan"]
