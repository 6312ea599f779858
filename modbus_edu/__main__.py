"""``python -m modbus_edu``: the command line (see :mod:`modbus_edu.cli`).

Only run as a script: importing this module (as anything that looks a class up by its module's name
might) runs nothing."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
