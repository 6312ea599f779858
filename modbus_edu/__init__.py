"""modbus_edu: learn Modbus by doing.

The public API is re-exported here; each name lives in the module that owns it (see the README's
architecture section).
"""

from __future__ import annotations

from .errors import *  # noqa: F401,F403
from .errors import ModbusError  # noqa: F401

__version__ = "0.1.0"
