"""ipywidgets panels for the course: thin views over the library.

* :class:`FrameBuilder` -- fields in, the frame out, every byte coloured by its field;
* :class:`FrameDecoder` -- hex in, the dissection out;
* :class:`CrcExplorer` -- the CRC-16 bit by bit or by table, and the LRC, step by step;
* :class:`TestTool` -- the robot test-tool paper's tool: RTU master / RTU slave / TCP client / TCP server;
* :class:`MeterDashboard` -- the power-meter paper's power meter read periodically, values and trends.

Each panel is an ipywidgets widget: put it last in a cell to display it.  No panel holds protocol logic:
every byte, check and decision comes from :mod:`modbus_edu`.
Before its cell runs (a saved notebook on GitHub or nbviewer, or before Run All) a panel shows its
static picture (:mod:`.picture`), labelled "run this cell to use it".
"""

from __future__ import annotations

from ..errors import require

require("ipywidgets", "modbus_edu.widgets")  # the course extra: say how to install it, not a bare ImportError
# matplotlib is not required here: only the dashboard's trend plot and CrcExplorer.plot draw, and each
# imports it when it draws (a browser without matplotlib still has every other panel)

from .crcexplorer import CrcExplorer  # noqa: E402
from .dashboard import MeterDashboard  # noqa: E402
from .framebuilder import FrameBuilder  # noqa: E402
from .framedecoder import FrameDecoder  # noqa: E402
from .testtool import TestTool  # noqa: E402

__all__ = ["FrameBuilder", "FrameDecoder", "CrcExplorer", "TestTool", "MeterDashboard"]
