"""Physical and numeric constants used throughout imunav (one place for each).

May import: nothing from imunav.
"""

import math

#: Standard gravity (m/s²), the default magnitude of ``g_n = [0, 0, +g]``.
G0 = 9.80665

#: One degree in radians.
DEG = math.pi / 180
