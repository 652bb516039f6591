"""Floor 4 — estimation: the navigation error model and the generic Kalman steps, shared by the
covariance analysis and (next) the aided filters.

Modules: :mod:`~imunav.estimation.error_model` (the error state, its dynamics along a
trajectory, the sensor error terms as error sources), :mod:`~imunav.estimation.discretisation`
(exact ``Φ`` and ``Q_d`` of a step), :mod:`~imunav.estimation.propagation` (covariance
propagation, a piece of trajectory at a time), :mod:`~imunav.estimation.kalman` (prediction and
the Joseph-form measurement update), :mod:`~imunav.estimation.measurements` (one class per
aiding measurement), :mod:`~imunav.estimation.filters` (the aided error-state filter) and
:mod:`~imunav.estimation.smoother` (the RTS smoother).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.strapdown``.
"""

from imunav.estimation.discretisation import flat_transition, phi_functions, process_noise, van_loan
from imunav.estimation.error_model import (
    DP,
    DV,
    EARTH,
    EARTH_HOLD,
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
from imunav.estimation.filters import (
    SD_COLUMNS,
    AidedSystem,
    FilterResult,
    Innovations,
    build_measurements,
    run_filter,
)
from imunav.estimation.kalman import Update, predict, update
from imunav.estimation.measurements import Baro, GnssFix, Heading, Measurement, NavPoint, Nhc, Zupt
from imunav.estimation.propagation import propagate, propagate_chunks
from imunav.estimation.smoother import rts, rts_step

__all__ = ["DP", "DV", "EARTH", "EARTH_HOLD", "FLAT", "NAV", "PHI", "SD_COLUMNS", "AidedSystem",
           "Baro", "EarthErrorModel", "ErrorSource", "FilterResult", "FlatErrorModel", "GnssFix",
           "Heading", "Innovations", "Measurement", "NavPoint", "Nhc", "Trajectory", "Update",
           "Zupt", "build_measurements", "error_model", "flat_transition", "linearise",
           "phi_functions", "predict", "process_noise", "propagate", "propagate_chunks", "rts",
           "rts_step", "run_filter", "update", "van_loan"]
