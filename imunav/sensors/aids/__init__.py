"""The aids: one module per aiding sensor, each holding its ``AIDING.toml`` table, its reading
file, its simulation and its measurement model, registered in :data:`AIDS` (in the order the
filter uses the readings of one epoch); :mod:`~imunav.sensors.aids.config` reads a whole
``AIDING.toml``, holds the readings, simulates them and builds the aids the filter takes.

A new aid: a module here with a :class:`~imunav.sensors.aids.base.TableConfig`, a
:class:`~imunav.sensors.aids.base.Measurement` and an
:class:`~imunav.sensors.aids.base.AidSpec` passed to ``register``, and its import below.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``.
"""

from imunav.sensors.aids import gnss, baro, heading, nhc, zupt, odometer  # noqa: F401,I001 — registration order
from imunav.sensors.aids.base import (
    AIDS,
    ANGLE_UNITS,
    Aid,
    AidSpec,
    AidStates,
    Key,
    Measurement,
    NavPoint,
    Readings,
    TableConfig,
    euler_jacobian,
    reading_times,
    register,
    wrap_angle,
    yaw_of,
)
from imunav.sensors.aids.baro import Baro, BaroConfig
from imunav.sensors.aids.config import (
    AIDING_STREAM,
    SECTIONS,
    AidingConfig,
    AidingData,
    InitialConfig,
    MountingConfig,
    aid_stream,
    aiding_streams,
    aids_from,
    build_measurements,
    simulate_aiding,
)
from imunav.sensors.aids.gnss import GnssConfig, GnssFix
from imunav.sensors.aids.heading import Heading, HeadingConfig
from imunav.sensors.aids.nhc import Nhc, NhcConfig
from imunav.sensors.aids.odometer import Odometer, OdometerConfig
from imunav.sensors.aids.zupt import (
    SHOE_SIGMA_A,
    SHOE_SIGMA_G,
    STANCE_SPEED,
    Zupt,
    ZuptConfig,
    intervals_of,
    nodes_within,
    shoe_intervals,
    shoe_statistic,
    true_stance,
)

__all__ = ["AIDING_STREAM", "AIDS", "ANGLE_UNITS", "SECTIONS", "SHOE_SIGMA_A", "SHOE_SIGMA_G",
           "STANCE_SPEED", "Aid", "AidSpec", "AidStates", "AidingConfig", "AidingData", "Baro",
           "BaroConfig", "GnssConfig", "GnssFix", "Heading", "HeadingConfig", "InitialConfig",
           "Key", "Measurement", "MountingConfig", "NavPoint", "Nhc", "NhcConfig", "Odometer",
           "OdometerConfig", "Readings", "TableConfig", "Zupt", "ZuptConfig", "aid_stream",
           "aiding_streams", "aids_from", "build_measurements", "euler_jacobian",
           "intervals_of", "nodes_within", "reading_times", "register", "shoe_intervals",
           "shoe_statistic", "simulate_aiding", "true_stance", "wrap_angle", "yaw_of"]
