"""TestTool: the robot test-tool paper's Modbus test tool rebuilt as a notebook panel, one module per part.

The paper: S. Chakraborty, P. S. Aithal, "Demonstration of Modbus Protocol for Robot Communication Using C#",
IJAEML 5(2), 2021.

* :mod:`.panel` -- the :class:`TestTool` widget: its controls and their layout in tabs
  (connection / data / traffic / settings), the role and what it shows;
* :mod:`.connection` -- loopback partner, serial port or TCP; polling (master) and answering (slave);
* :mod:`.grid` -- the data grid of the chosen function's table, writes, dummy data;
* :mod:`.traffic` -- counters, TX/RX lamps, the TX and RX logs;
* :mod:`.config` -- every setting (:class:`TestToolSettings`) as a dict or JSON file;
* :mod:`.controls` -- the roles, option lists and small control factories they share.
"""

from __future__ import annotations

from .controls import ROLES, Role, TestToolSettings
from .panel import TestTool

__all__ = ["TestTool", "TestToolSettings", "ROLES", "Role"]
