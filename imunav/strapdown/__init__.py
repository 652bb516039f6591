"""Layer 3 — strapdown integration: attitude, velocity and position from rates or increments.

Modules: :mod:`~imunav.strapdown.scan` (the blocked quaternion scan kernels),
:mod:`~imunav.strapdown.classic` (textbook, coning/sculling and multi-sample algorithms),
:mod:`~imunav.strapdown.highorder` (local polynomial fits + Magnus),
:mod:`~imunav.strapdown.reference` (plain loops: test oracles and the compiled benchmark
baseline), :mod:`~imunav.strapdown.initial` (the initial state: levelling and static biases at
rest, and what a log gives — levelled at rest, heading from GNSS velocity),
:mod:`~imunav.strapdown.rotating` (the navigation-frame side on the rotating WGS-84 Earth:
:class:`EarthIntegrator`, with its block kernels in :mod:`~imunav.strapdown.rotating_blocks`),
:mod:`~imunav.strapdown.algorithms` (:data:`ALGORITHMS`), :mod:`~imunav.strapdown.stream` (the
one driver, :class:`StreamNavigator`) and :mod:`~imunav.strapdown.registry` (:func:`navigate`,
flat or ``earth="wgs84"``: where callers import all of it from).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.sensors.signals``.
"""

from imunav.core.deprecation import deprecated_names
from imunav.core.states import States
from imunav.strapdown.initial import InitialState, gnss_alignment, static_alignment
from imunav.strapdown.registry import (
    ALGORITHMS,
    DEFAULT_ALGORITHM,
    Algorithm,
    StreamNavigator,
    navigate,
    navigate_batch,
    resolve,
)
from imunav.strapdown.rotating import EarthIntegrator
from imunav.strapdown.scan import cumulative_product, exp_product, prefix_product

#: ``NavResult``, the former name of :class:`~imunav.core.states.States` for navigation output:
#: one name for one type (issue 35); the old one warns until it goes.
__getattr__ = deprecated_names(__name__, {"NavResult": (States, "imunav.States")})

__all__ = ["ALGORITHMS", "DEFAULT_ALGORITHM", "Algorithm", "EarthIntegrator", "InitialState",
           "StreamNavigator", "cumulative_product", "exp_product", "gnss_alignment",
           "navigate", "navigate_batch", "prefix_product", "resolve", "static_alignment"]
