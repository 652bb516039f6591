"""Layer 3 — strapdown integration: attitude, velocity and position from rates or increments.

Modules: :mod:`~imunav.strapdown.scan` (the blocked quaternion scan kernels),
:mod:`~imunav.strapdown.classic` (textbook, coning/sculling and multi-sample algorithms),
:mod:`~imunav.strapdown.highorder` (local polynomial fits + Magnus), :mod:`~imunav.strapdown.reference`
(plain loops: test oracles and the compiled benchmark baseline), :mod:`~imunav.strapdown.alignment`
(levelling and static biases), :mod:`~imunav.strapdown.initial` (the initial state from what a
log gives: levelled at rest, heading from GNSS velocity), :mod:`~imunav.strapdown.rotating` (the
navigation-frame side on the rotating WGS-84 Earth: :class:`EarthIntegrator`),
:mod:`~imunav.strapdown.registry` (:data:`ALGORITHMS`, :func:`navigate`, flat or ``earth="wgs84"``).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.sensors.signals``.
"""

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

#: Former name of :class:`~imunav.core.states.States` for navigation output (kept as an alias).
NavResult = States

__all__ = ["ALGORITHMS", "DEFAULT_ALGORITHM", "Algorithm", "EarthIntegrator", "InitialState",
           "NavResult", "StreamNavigator", "cumulative_product", "exp_product", "gnss_alignment",
           "navigate", "navigate_batch", "prefix_product", "resolve", "static_alignment"]
