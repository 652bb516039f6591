"""The layout of the navigation error state, written once: what the error model, the aids'
measurement models and the filters index it by.

The error state starts with the navigation errors — attitude error φ (rad, ``C_est = (I − [φ×])
C_nb``), velocity error δv (m/s), position error δp (m), three components each in the
navigation frame — and continues with the sensor and aid error states (their places are given
by the filter's layout).

May import: nothing in imunav.
"""

from __future__ import annotations

__all__ = ["DP", "DV", "NAV", "PHI"]

#: The navigation error states: attitude error φ, velocity error δv, position error δp.
PHI, DV, DP = slice(0, 3), slice(3, 6), slice(6, 9)
#: Number of navigation error states.
NAV = 9
