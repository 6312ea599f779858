"""``python -m modbus_edu.cli``: the command line, as ``modbus-edu``."""

import sys

from . import main

if __name__ == "__main__":
    sys.exit(main())
