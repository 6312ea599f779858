"""``python -m modbus_edu.cli``: the command line, as ``modbus-edu``."""

import sys

from . import main

sys.exit(main())
