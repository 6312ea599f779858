"""``python -m modbus_edu``: the command line (see :mod:`modbus_edu.cli`)."""

import sys

from .cli import main

sys.exit(main())
