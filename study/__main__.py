"""``python -m study``: the command line (see :mod:`study.cli`)."""

import sys

from .cli import main

sys.exit(main())
