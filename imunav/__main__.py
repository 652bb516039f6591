import sys

from imunav.cli import main

sys.exit(main())
