"""What every part of the TestTool shares: the four roles, the option lists, limits and small control
factories (a labelled control of a given width, a button with a tooltip, a row that wraps)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import ipywidgets as W

from ...datamodel import table_kind
from ...errors import ModbusError
from ...pdu import FunctionCode
from ...values import FORMATS
from ..common import running_loop  # the loop polling runs on, shared with the panels' typing

__all__ = ["Role", "ROLES", "ROLE_OPTIONS", "FUNCTION_OPTIONS", "BAUD_RATES", "FORMAT_OPTIONS", "MAX_CELLS",
           "COLUMNS", "LOG_LINES", "TAB_TITLES", "GRID_HEIGHT", "LOG_HEIGHT", "CONFIG_KEYS",
           "TestToolSettings", "running_loop", "small", "button", "row"]


@dataclass(frozen=True)
class Role:
    """One of the four roles of the robot test-tool paper's tool."""

    key: str
    title: str
    mode: str  # "rtu" or "tcp"
    side: str  # "master" (asks) or "slave" (answers)
    background: str
    border: str


ROLES: dict[str, Role] = {
    "rtu_master": Role("rtu_master", "RTU master", "rtu", "master", "#e7f5ff", "#1c7ed6"),
    "rtu_slave": Role("rtu_slave", "RTU slave", "rtu", "slave", "#ebfbee", "#2b6e35"),
    "tcp_client": Role("tcp_client", "TCP client", "tcp", "master", "#fff4e6", "#e8590c"),
    "tcp_server": Role("tcp_server", "TCP server", "tcp", "slave", "#f8f0fc", "#ae3ec9"),
}
ROLE_OPTIONS = [(r.title, r.key) for r in ROLES.values()]


def _reaches_a_table(fc: FunctionCode) -> bool:
    """Whether the data model says which table this function reads or writes (the grid shows it)."""
    try:
        table_kind(int(fc))
    except ModbusError:
        return False
    return True


#: The functions the tool polls with: those that reach one of the four tables (the grid is that table).
FUNCTION_OPTIONS = [(f"{int(fc):02d} {fc.title}", int(fc)) for fc in FunctionCode if _reaches_a_table(fc)]
BAUD_RATES = [1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200]
FORMAT_OPTIONS = [(f.replace("_", " "), f) for f in FORMATS]
MAX_CELLS = 250
COLUMNS = 10
LOG_LINES = 200
#: The tabs under the always-visible header (title, role, status, message, polling and counters).
TAB_TITLES = ("connection", "data", "traffic", "settings")
#: A panel stays within 700 px of height: the grid and the logs scroll inside boxes this tall.
GRID_HEIGHT = "250px"
LOG_HEIGHT = "300px"

@dataclass
class TestToolSettings:
    """Every setting of a :class:`~modbus_edu.widgets.TestTool`: what its constructor takes as keywords,
    what :meth:`~modbus_edu.widgets.TestTool.config` returns (as a dict) and what a saved configuration
    holds.  ``None`` (name, connection) leaves the control as the role sets it."""

    __test__ = False  # not a pytest test class, whatever its name says

    role: str = "rtu_master"
    name: str | None = None
    connection: str | None = None
    url: str = "loop://"
    baudrate: int = 9600
    parity: str = "N"
    stopbits: float = 1
    host: str = "127.0.0.1"
    port: int = 5020
    timeout: float = 1.0
    unit: int = 1
    address: int = 0
    length: int = 10
    function: int = 3
    transaction_id: int = 1
    interval: float = 1.0
    continuous: bool = True
    display: str = "unsigned"
    fill_start: int = 0
    fill_increment: bool = True
    fill_step: int = 1
    auto_interval: float = 1.0
    newest_on_top: bool = True
    seed: int = 0


CONFIG_KEYS = tuple(item.name for item in fields(TestToolSettings))
"""The settings' names, in the order :meth:`~modbus_edu.widgets.TestTool.config` gives them."""




def small(widget: W.DOMWidget, width: str = "210px", label: str = "95px") -> W.DOMWidget:
    """Give a labelled control its width and the width of its label."""
    widget.layout.width = width
    if hasattr(widget, "style") and hasattr(widget.style, "description_width"):
        widget.style.description_width = label
    return widget


def button(label: str, icon: str = "", css: str = "", tip: str = "", style: str = "") -> W.Button:
    """A button whose tooltip says what it does (``tip``; the label when no tip is given)."""
    b = W.Button(description=label, icon=icon, tooltip=tip or label, button_style=style,
                 layout=W.Layout(width="auto", flex="0 0 auto"))  # never squeezed into "write cell (FC…"
    if css:
        b.add_class(css)
    return b


def row(*children: W.Widget, css: str = "") -> W.HBox:
    """A row of controls that wraps onto a second line rather than run past the panel's width."""
    box = W.HBox(list(children), layout=W.Layout(flex_flow="row wrap", align_items="center"))
    if css:
        box.add_class(css)
    return box
