"""``python -m batball.cli``: the ``batball`` command."""

import sys

from batball.cli import main

sys.exit(main())
