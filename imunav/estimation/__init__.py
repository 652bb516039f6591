"""Floor 4 — estimation: the navigation error model, the Kalman core, and the aided filters.

Modules: :mod:`~imunav.estimation.error_model` (the error state and its dynamics along a
trajectory: the nominal trajectory in :mod:`~imunav.estimation.nominal`, the sensor error terms
as error sources in :mod:`~imunav.estimation.error_sources`, the flat frame's and the Earth's
dynamics in :mod:`~imunav.estimation.flat_model` and :mod:`~imunav.estimation.earth_model`),
:mod:`~imunav.estimation.discretisation` (exact ``Φ`` and ``Q_d`` of a step),
:mod:`~imunav.estimation.propagation` (covariance propagation, a piece of trajectory at a time),
:mod:`~imunav.estimation.kalman` (the Kalman core: block prediction, Joseph update with its χ²
gate — for one filter or a batch),
:mod:`~imunav.estimation.system` (the aided filter's error state and discrete dynamics),
:mod:`~imunav.estimation.schedule` (readings mapped to IMU nodes),
:mod:`~imunav.estimation.measurements` (the measurement contract and the aids' models),
:mod:`~imunav.estimation.filters` (the aided error-state filter, one run or a batch),
:mod:`~imunav.estimation.inertial` (its navigation side on the rotating Earth) and
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
    LazyTrajectory,
    Trajectory,
    frame_model,
    linearise,
    local_error_map,
)
from imunav.estimation.filters import (
    SD_COLUMNS,
    BatchResult,
    FilterResult,
    Innovations,
    run_filter,
    run_filter_batch,
    run_smoother,
)
from imunav.estimation.kalman import StepBlocks, Update, predict, predict_blocks, update, update_batch
from imunav.estimation.measurements import (
    Aid,
    Baro,
    GnssFix,
    Heading,
    Measurement,
    NavPoint,
    Nhc,
    Odometer,
    Zupt,
)
from imunav.estimation.propagation import propagate, propagate_chunks
from imunav.estimation.smoother import rts, rts_step
from imunav.estimation.system import AidedSystem

__all__ = ["DP", "DV", "EARTH", "EARTH_HOLD", "FLAT", "NAV", "PHI", "SD_COLUMNS", "Aid", "AidedSystem",
           "Baro", "BatchResult", "EarthErrorModel", "ErrorSource", "FilterResult", "FlatErrorModel",
           "GnssFix", "Heading", "Innovations", "LazyTrajectory", "Measurement", "NavPoint", "Nhc",
           "Odometer", "StepBlocks", "Trajectory", "Update", "Zupt", "flat_transition", "frame_model",
           "linearise", "local_error_map", "phi_functions", "predict", "predict_blocks", "process_noise",
           "propagate", "propagate_chunks", "rts", "rts_step", "run_filter", "run_filter_batch",
           "run_smoother", "update", "update_batch", "van_loan"]
