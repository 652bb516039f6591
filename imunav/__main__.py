"""``python -m imunav``: the command line.

May import: ``imunav.cli``.
"""

import sys

from imunav.cli import main

sys.exit(main())
