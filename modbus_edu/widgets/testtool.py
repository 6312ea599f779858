"""TestTool: source 000's Modbus test tool rebuilt as a notebook panel.

One panel is an RTU master, an RTU slave, a TCP client or a TCP server.  Two panels in one notebook
talk to each other over an in-process loopback wire (:func:`modbus_edu.links.loopback_serial` or
:func:`~modbus_edu.links.loopback_tcp`), or a panel talks to the outside world through a serial port
(pyserial) or a TCP socket.  All protocol work is the library's: a master panel drives a
:class:`~modbus_edu.master.Master`, a slave panel owns a :class:`~modbus_edu.slave.Slave`; the panel
only holds settings, a data grid and counters.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import ipywidgets as W

from ..clock import RealClock, VirtualClock
from ..datamodel import DataBank, Table
from ..devices.generators import AutoFill, Uniform, increment_fill, random_fill
from ..errors import ConfigError, ModbusError, ModbusTimeoutError
from ..links.loopback import loopback_serial, loopback_tcp
from ..master import Master
from ..pdu import FunctionCode
from ..slave import Slave
from ..traffic import TrafficLog
from ..values import FORMATS, format_registers, parse_formatted
from .common import MONO, MessageLine, esc, guarded, parse_bit_list, shown

__all__ = ["TestTool", "ROLES"]


@dataclass(frozen=True)
class Role:
    """One of the four roles of source 000's tool."""

    key: str
    title: str
    mode: str  # "rtu" or "tcp"
    side: str  # "master" (asks) or "slave" (answers)
    background: str
    border: str


ROLES: dict[str, Role] = {
    "rtu_master": Role("rtu_master", "RTU master", "rtu", "master", "#e7f5ff", "#1c7ed6"),
    "rtu_slave": Role("rtu_slave", "RTU slave", "rtu", "slave", "#ebfbee", "#2f9e44"),
    "tcp_client": Role("tcp_client", "TCP client", "tcp", "master", "#fff4e6", "#e8590c"),
    "tcp_server": Role("tcp_server", "TCP server", "tcp", "slave", "#f8f0fc", "#ae3ec9"),
}
ROLE_OPTIONS = [(r.title, r.key) for r in ROLES.values()]
FUNCTION_OPTIONS = [(f"{int(fc):02d} {fc.title}", int(fc)) for fc in FunctionCode]
BAUD_RATES = [1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200]
FORMAT_OPTIONS = [(f.replace("_", " "), f) for f in FORMATS]
MAX_CELLS = 250
COLUMNS = 10
LOG_LINES = 200

CONFIG_KEYS = (
    "role", "name", "connection", "url", "baudrate", "parity", "stopbits", "host", "port", "timeout",
    "unit", "address", "length", "function", "transaction_id", "interval", "continuous", "display",
    "fill_start", "fill_increment", "fill_step", "auto_interval", "newest_on_top", "seed",
)


def _running_loop() -> asyncio.AbstractEventLoop | None:
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None


def _small(widget: W.DOMWidget, width: str = "210px", label: str = "95px") -> W.DOMWidget:
    widget.layout.width = width
    if hasattr(widget, "style") and hasattr(widget.style, "description_width"):
        widget.style.description_width = label
    return widget


def _button(label: str, icon: str = "", css: str = "", tip: str = "", style: str = "") -> W.Button:
    b = W.Button(description=label, icon=icon, tooltip=tip or label, button_style=style,
                 layout=W.Layout(width="auto"))
    if css:
        b.add_class(css)
    return b


class TestTool(W.VBox):
    """Source 000's Modbus test tool in a notebook: RTU master, RTU slave, TCP client or TCP server.

    **Connection.**  A *loopback partner* (another TestTool in the same notebook: ``TestTool(...,
    partner=other)`` or ``tool.connect(other)``) puts both on an in-process wire that runs on a
    virtual clock; a *serial port* (a port name or a pyserial URL such as ``loop://``, with baud rate,
    parity and stop bits) or a *TCP host and port* reach real devices.  The status LED says whether it
    is connected.

    **Device parameters.**  Unit (slave id), start address, length, function (the eight everyday
    functions), the transaction id of the next TCP request (+1 per request) and, on a slave, the count
    of requests it received.

    **Polling** (master and client).  *Read once* sends one request with the chosen function (a read
    fills the grid; a write sends the grid's values); *start*/*stop* poll every ``interval`` seconds
    on the kernel's asyncio loop, without blocking the notebook (untick *continuous* to poll once).
    Counters: polls, valid responses, timeouts, errors (polls = valid + timeouts + errors), and
    *reset*.  A slave's *start*/*stop* makes it answer or fall silent.  Headless and in tests:
    :meth:`poll_once` and :meth:`run_polls` (synchronous; on a loopback wire virtual time passes).

    **Data grid.**  The table of the chosen function, from the start address; edit a cell (Enter) and
    the value goes into the grid's table (a slave serves it at once).  Display formats of
    :func:`modbus_edu.values.format_registers`: hex, binary, unsigned, signed, ASCII char, ASCII value,
    and 32-/64-bit integers and floats in the four word/byte orders.  A master writes the selected cell
    with FC06 (FC05 for a coil) and a range with FC16 (FC15); the last edited cell is the selected one.

    **Dummy data** (:mod:`modbus_edu.devices.generators`): random fill (seeded), fill with a start value
    and an increment, auto fill with random data every ``auto interval`` seconds, start and stop.

    **Logs.**  TX and RX logs (the :class:`~modbus_edu.traffic.TrafficLog` of the master or the slave)
    with their time stamps (seconds on the link's clock), newest on top if you like, a search box and
    *clear*.  **Messages** go to one line under the title, never to a pop-up.  **Config** saves and
    loads every setting as JSON, to a file or a dict.  Each role has its own colour.

    Example: two tools in one notebook, the master polling the slave's registers::

        from modbus_edu.widgets import TestTool
        slave = TestTool("rtu_slave", unit=1, length=10)
        slave.fill_increment(start=100, step=10)       # the slave's holding registers 0..9
        master = TestTool("rtu_master", partner=slave, unit=1, address=0, length=10)
        master.run_polls(5)                             # or press "start" for continuous polling
        master.counts                                   # {'polls': 5, 'valid': 5, 'timeouts': 0, 'errors': 0}
        master.values                                   # [100, 110, ..., 190]
        display(master, slave)
    """

    __test__ = False  # not a pytest test class, whatever its name says

    def __init__(
        self,
        role: str = "rtu_master",
        *,
        partner: TestTool | None = None,
        name: str | None = None,
        connection: str | None = None,
        url: str = "loop://",
        baudrate: int = 9600,
        parity: str = "N",
        stopbits: float = 1,
        host: str = "127.0.0.1",
        port: int = 5020,
        timeout: float = 1.0,
        unit: int = 1,
        address: int = 0,
        length: int = 10,
        function: int = 3,
        transaction_id: int = 1,
        interval: float = 1.0,
        continuous: bool = True,
        display: str = "unsigned",
        fill_start: int = 0,
        fill_increment: bool = True,
        fill_step: int = 1,
        auto_interval: float = 1.0,
        newest_on_top: bool = True,
        seed: int = 0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.add_class("mbe-testtool")
        self.bank = DataBank()
        """The tool's own four tables: what a master read (and will write), what a slave serves."""
        self.slave: Slave | None = None
        self.master: Master | None = None
        self.link: Any = None
        self.server: Any = None
        self.partner: TestTool | None = None
        self.counts = {"polls": 0, "valid": 0, "timeouts": 0, "errors": 0}
        self.last_result: Any = None
        self._rng = random.Random(seed)
        self._seed = seed
        self._autofill: AutoFill | None = None
        self._real_clock = RealClock()
        self._poll_task: asyncio.Task | None = None
        self._tick_task: asyncio.Task | None = None
        self._polling = False
        self._answering = True
        self._updating = False
        self._empty_log = TrafficLog()
        self._lamp_log: TrafficLog | None = None  # the log the TX/RX lamps last looked at, and how far
        self._lamp_seen = 0
        self.lamps: dict[str, bool] = {"tx": False, "rx": False}

        self._build()
        self._apply_role()
        settings = dict(
            role=role, name=name, connection=connection or ("loopback" if partner is not None else None),
            url=url, baudrate=baudrate, parity=parity, stopbits=stopbits, host=host, port=port,
            timeout=timeout, unit=unit, address=address, length=length, function=function,
            transaction_id=transaction_id, interval=interval, continuous=continuous, display=display,
            fill_start=fill_start, fill_increment=fill_increment, fill_step=fill_step,
            auto_interval=auto_interval, newest_on_top=newest_on_top, seed=seed,
        )
        if role not in ROLES:
            settings.pop("role")
        self.apply_config({k: v for k, v in settings.items() if v is not None})
        if self.message.kind == "info":
            self.message.clear()
        if role not in ROLES:
            self.message.error(ConfigError(f"unknown role {role!r}: expected one of {', '.join(ROLES)}"))
        if partner is not None:
            self.connect(partner)
        elif self.role_info.side == "slave" and self.connection.value == "loopback" \
                and self.message.kind != "error":
            self.message.show("waiting for a master: give this tool as partner= to a master tool")

    # =====================================================================================================
    # building the panel
    # =====================================================================================================
    def _build(self) -> None:
        """Create every control with its default value (the constructor then applies the settings)."""
        g = guarded
        self.message = MessageLine()
        self.title = W.HTML()
        self.role = _small(W.Dropdown(options=ROLE_OPTIONS, value="rtu_master", description="role"), "230px",
                           "40px")
        self.role.add_class("mbe-tt-role")
        self.name = _small(W.Text(value="", description="name", placeholder="a name for messages"),
                           "230px", "40px")

        # -- connection --------------------------------------------------------------------------------
        self.connection = _small(W.Dropdown(options=[("loopback partner", "loopback")],
                                            description="connection"),
                                 "300px")
        self.url = _small(W.Text(value="loop://", description="port / URL",
                                 placeholder="loop://, /dev/ttyUSB0, COM3, socket://host:port"), "300px")
        self.baudrate = _small(W.Dropdown(options=BAUD_RATES, value=9600, description="baud"))
        self.parity = _small(W.Dropdown(options=[("none (N)", "N"), ("even (E)", "E"), ("odd (O)", "O")],
                                        value="N", description="parity"))
        self.stopbits = _small(W.Dropdown(options=[("1", 1), ("2", 2)], value=1,
                                          description="stop bits"))
        self.host = _small(W.Text(value="127.0.0.1", description="host"))
        self.port = _small(W.BoundedIntText(value=5020, min=0, max=65535, description="TCP port"))
        self.timeout = _small(W.BoundedFloatText(value=1.0, min=0.001, max=60, step=0.1,
                                                 description="timeout (s)"))
        self.connect_button = _button("connect", "plug", "mbe-tt-connect", style="success")
        self.disconnect_button = _button("disconnect", "times", "mbe-tt-disconnect")
        self.status = W.HTML()
        self.connect_button.on_click(g(self.message, lambda _b: self.connect()))
        self.disconnect_button.on_click(g(self.message, lambda _b: self.disconnect()))

        # -- device parameters ---------------------------------------------------------------------------
        self.unit = _small(W.BoundedIntText(value=1, min=0, max=255, description="unit (slave id)"))
        self.unit.add_class("mbe-tt-unit")
        self.address = _small(W.BoundedIntText(value=0, min=0, max=65535, description="start address"))
        self.address.add_class("mbe-tt-address")
        self.length = _small(W.BoundedIntText(value=10, min=1, max=2000, description="length"))
        self.function = _small(W.Dropdown(options=FUNCTION_OPTIONS, value=3,
                                          description="function"),
                               "320px")
        self.transaction_id = _small(W.BoundedIntText(value=1, min=0, max=65535,
                                                      description="transaction id"))
        self.request_count = W.HTML()

        # -- polling -------------------------------------------------------------------------------------
        self.interval = _small(W.BoundedFloatText(value=1.0, min=0.01, max=3600, step=0.1,
                                                  description="interval (s)"))
        self.continuous = W.Checkbox(value=True, description="continuous", indent=False,
                                     layout=W.Layout(width="110px"))
        self.read_button = _button("read once", "download", "mbe-tt-read",
                                   "one request with the chosen function")
        self.start_button = _button("start", "play", "mbe-tt-start", style="primary")
        self.stop_button = _button("stop", "stop", "mbe-tt-stop")
        self.reset_button = _button("reset counters", "undo", "mbe-tt-reset")
        self.counters = W.HTML()
        self.counters.add_class("mbe-tt-counters")
        self.read_button.on_click(g(self.message, lambda _b: self.poll_once()))
        self.start_button.on_click(g(self.message, lambda _b: self.start()))
        self.stop_button.on_click(g(self.message, lambda _b: self.stop()))
        self.reset_button.on_click(g(self.message, lambda _b: self.reset_counters()))

        # -- data grid -------------------------------------------------------------------------------------
        self.display = _small(W.Dropdown(options=FORMAT_OPTIONS, value="unsigned", description="display"),
                              "260px",
                              "60px")
        self.grid = W.VBox()
        self.grid.add_class("mbe-tt-grid")
        self._cells: list[W.Text] = []
        self._grid_shape: tuple | None = None
        self.selected = _small(W.BoundedIntText(value=0, min=0, max=65535, description="cell address"))
        self.write_value = _small(W.Text(description="value", placeholder="from the grid"))
        self._write_value_typed = False
        self.write_value.observe(lambda _c: self._write_value_edited(), names="value")
        self.write_count = _small(W.BoundedIntText(value=10, min=1, max=1968,
                                                   description="cells"))
        self.write_one_button = _button("write cell (FC06)", "pencil", "mbe-tt-write-one")
        self.write_many_button = _button("write cells (FC16)", "pencil-square-o", "mbe-tt-write-many")
        self.write_one_button.on_click(g(self.message, lambda _b: self.write_cell()))
        self.write_many_button.on_click(g(self.message, lambda _b: self.write_cells()))
        self.write_box = W.HBox([self.selected, self.write_value, self.write_one_button, self.write_count,
                                 self.write_many_button])

        # -- dummy data --------------------------------------------------------------------------------------
        self.fill_start = _small(W.IntText(value=0, description="first value"), "190px", "75px")
        self.increment = W.Checkbox(value=True, description="increment", indent=False,
                                         layout=W.Layout(width="100px"))
        self.fill_step = _small(W.IntText(value=1, description="by"), "120px", "25px")
        self.auto_interval = _small(W.BoundedFloatText(value=1.0, min=0.05, max=3600,
                                                       description="every (s)"), "160px", "60px")
        self.random_button = _button("random fill", "random", "mbe-tt-random")
        self.fill_button = _button("fill", "sort-numeric-asc", "mbe-tt-fill")
        self.auto_start_button = _button("auto fill start", "play-circle", "mbe-tt-auto-start")
        self.auto_stop_button = _button("auto fill stop", "stop-circle", "mbe-tt-auto-stop")
        self.random_button.on_click(g(self.message, lambda _b: self.random_fill()))
        self.fill_button.on_click(g(self.message, lambda _b: self.fill_increment()))
        self.auto_start_button.on_click(g(self.message, lambda _b: self.auto_fill_start()))
        self.auto_stop_button.on_click(g(self.message, lambda _b: self.auto_fill_stop()))

        # -- logs ------------------------------------------------------------------------------------------
        self.newest_on_top = W.Checkbox(value=True, description="newest on top", indent=False,
                                        layout=W.Layout(width="130px"))
        self.search = _small(W.Text(description="search", placeholder="hex, note, unit ..."), "260px", "50px")
        self.clear_button = _button("clear logs", "trash", "mbe-tt-clear")
        self.clear_button.on_click(g(self.message, lambda _b: self.clear_logs()))
        self.tx_log = W.HTML(layout=W.Layout(width="50%", overflow="hidden"))  # each log scrolls in its half
        self.rx_log = W.HTML(layout=W.Layout(width="50%", overflow="hidden"))
        self.tx_log.add_class("mbe-tt-tx-log")
        self.rx_log.add_class("mbe-tt-rx-log")

        # -- config ----------------------------------------------------------------------------------------
        self.config_path = _small(W.Text(value="testtool.json", description="config file"), "300px", "75px")
        self.save_button = _button("save config", "save", "mbe-tt-save")
        self.load_button = _button("load config", "folder-open", "mbe-tt-load")
        self.save_button.on_click(g(self.message, lambda _b: self.save_config()))
        self.load_button.on_click(g(self.message, lambda _b: self.load_config()))

        def section(title: str) -> W.HTML:
            return W.HTML(f'<div style="font-weight:bold;margin-top:6px;border-bottom:1px solid #ccc">'
                          f"{esc(title)}</div>")

        self.serial_box = W.HBox([self.url, self.baudrate, self.parity, self.stopbits])
        self.tcp_box = W.HBox([self.host, self.port])
        self.polling_box = W.VBox([
            section("Polling"),
            W.HBox([self.interval, self.continuous, self.read_button, self.start_button, self.stop_button,
                    self.reset_button]),
            self.counters,
        ])
        self.children = [
            self.title,
            W.HBox([self.role, self.name]),
            self.message,
            section("Connection"),
            W.HBox([self.connection, self.timeout, self.connect_button, self.disconnect_button, self.status]),
            self.serial_box,
            self.tcp_box,
            section("Device parameters"),
            W.HBox([self.unit, self.address, self.length, self.function]),
            W.HBox([self.transaction_id, self.request_count]),
            self.polling_box,
            section("Data grid"),
            W.HBox([self.display]),
            self.grid,
            self.write_box,
            section("Dummy data"),
            W.HBox([self.random_button, self.fill_start, self.increment, self.fill_step, self.fill_button]),
            W.HBox([self.auto_interval, self.auto_start_button, self.auto_stop_button]),
            section("Traffic"),
            W.HBox([self.newest_on_top, self.search, self.clear_button]),
            W.HBox([self.tx_log, self.rx_log]),
            section("Configuration"),
            W.HBox([self.config_path, self.save_button, self.load_button]),
        ]

        refresh = g(self.message, lambda _c: self.refresh())
        self.role.observe(g(self.message, lambda _c: self._role_changed()), names="value")
        self.connection.observe(g(self.message, lambda _c: self._show_connection()), names="value")
        for box in (self.address, self.length, self.function, self.display):
            box.observe(refresh, names="value")
        self.unit.observe(g(self.message, lambda _c: self._unit_changed()), names="value")
        self.transaction_id.observe(g(self.message, lambda _c: self._tid_changed()), names="value")
        self.timeout.observe(g(self.message, lambda _c: self._timeout_changed()), names="value")
        self.name.observe(g(self.message, lambda _c: self._render_title()), names="value")
        for box in (self.newest_on_top, self.search):
            box.observe(g(self.message, lambda _c: self._render_logs()), names="value")
        self.selected.observe(g(self.message, lambda _c: self._selected_changed()), names="value")

    # =====================================================================================================
    # role and visibility
    # =====================================================================================================
    @property
    def role_info(self) -> Role:
        return ROLES[self.role.value]

    @property
    def is_master(self) -> bool:
        """True for the asking roles (RTU master, TCP client)."""
        return self.role_info.side == "master"

    @property
    def label(self) -> str:
        return self.name.value or self.role_info.title

    def _role_changed(self) -> None:
        self.disconnect(quiet=True)
        self._apply_role()
        self.message.show(f"role: {self.role_info.title}")

    def _apply_role(self) -> None:
        r = self.role_info
        real = ("serial", "serial port / pyserial URL") if r.mode == "rtu" else ("tcp", "TCP host and port")
        current = self.connection.value
        self.connection.options = [("loopback partner", "loopback"), (real[1], real[0])]
        self.connection.value = current if current in ("loopback", real[0]) else "loopback"
        if r.side == "slave":
            self._ensure_slave()
        for b in (self.read_button,):
            shown(b, r.side == "master")
        shown(self.interval, r.side == "master")
        shown(self.continuous, r.side == "master")
        shown(self.write_box, r.side == "master")
        shown(self.transaction_id, r.key == "tcp_client")
        shown(self.request_count, r.side == "slave")
        self.start_button.tooltip = "poll continuously" if r.side == "master" else "answer requests"
        self.stop_button.tooltip = ("stop polling" if r.side == "master"
                                    else "stop answering (the master times out)")
        self.layout.border = f"3px solid {r.border}"
        self.layout.padding = "6px"
        for key in ROLES:
            self.remove_class(f"mbe-role-{key}")
        self.add_class(f"mbe-role-{r.key}")
        self._show_connection()
        self._render_title()
        self.refresh()

    def _render_title(self) -> None:
        r = self.role_info
        name = f" &mdash; {esc(self.name.value)}" if self.name.value else ""
        self.title.value = (
            f'<div style="background:{r.background};border-left:8px solid {r.border};padding:4px 8px;'
            f'font-size:1.1em"><b>Modbus test tool: {esc(r.title)}</b>{name}</div>')

    def _show_connection(self) -> None:
        kind = self.connection.value
        shown(self.serial_box, kind == "serial")
        shown(self.tcp_box, kind == "tcp")
        # on a loopback wire the master's line settings are the wire's: show them for RTU
        if kind == "loopback" and self.role_info.mode == "rtu":
            shown(self.serial_box, True)
            shown(self.url, False)
        else:
            shown(self.url, True)
        self._render_status()

    def _ensure_slave(self) -> Slave:
        if self.slave is None:
            unit = self.unit.value
            try:
                self.slave = Slave(unit=unit, bank=self.bank, on_read=self._on_read, name=self.label)
            except ModbusError as exc:  # unit 0 (broadcast) in the field: serve unit 1 until it is fixed
                self.message.error(exc)
                self.slave = Slave(unit=1, bank=self.bank, on_read=self._on_read, name=self.label)
        return self.slave

    def _unit_changed(self) -> None:
        if self.slave is not None:
            unit = self.unit.value
            Slave(unit=unit)  # the library checks the unit (ConfigError for 0, the broadcast address)
            self.slave.unit = unit
        self.refresh()

    def _tid_changed(self) -> None:
        if self.master is not None and not self._updating:
            self.master.transaction_id = self.transaction_id.value

    def _timeout_changed(self) -> None:
        if self.master is not None:
            self.master.timeout = float(self.timeout.value)

    # =====================================================================================================
    # connection
    # =====================================================================================================
    @property
    def connected(self) -> bool:
        if self.is_master:
            return self.master is not None
        return self.link is not None or self.server is not None

    @property
    def clock(self) -> Any:
        """The clock of the wire: virtual on a loopback, real otherwise."""
        if self.link is not None:
            return self.link.clock
        return self._real_clock

    def connect(self, partner: TestTool | None = None) -> bool:
        """Connect as the settings say; ``partner`` (another TestTool) means a loopback wire to it.

        Returns True when connected; otherwise the reason is on the message line.
        """
        try:
            self._connect(partner)
        except Exception as exc:  # noqa: BLE001 - shown on the message line, never raised
            self.message.error(exc)
            self._render_status()
            return False
        self._render_status()
        self.refresh()
        return True

    def _connect(self, partner: TestTool | None) -> None:
        if partner is not None and not isinstance(partner, TestTool):
            raise ConfigError(f"partner must be another TestTool, got {type(partner).__name__}")
        if partner is not None:
            self.connection.value = "loopback"
        kind = self.connection.value
        self.disconnect(quiet=True)
        if kind == "loopback":
            partner = partner or self.partner
            if partner is None:
                raise ConfigError("a loopback wire needs a partner: TestTool.connect(other_tool), or "
                                  "TestTool(..., partner=other_tool)")
            self._connect_loopback(partner)
        elif kind == "serial":
            self._connect_serial()
        else:
            self._connect_tcp()

    def _connect_loopback(self, partner: TestTool) -> None:
        if partner is self:
            raise ConfigError("a tool cannot be its own partner")
        me, other = self.role_info, partner.role_info
        if me.side == other.side:
            raise ConfigError(f"{me.title} and {other.title} cannot talk: one must ask (master/client) and "
                              f"the other answer (slave/server)")
        if me.mode != other.mode:
            raise ConfigError(f"{me.title} and {other.title} speak different modes ({me.mode.upper()} and "
                              f"{other.mode.upper()}): pair an RTU master with an RTU slave, a TCP client "
                              f"with a TCP server")
        partner.disconnect(quiet=True)
        master_tool, slave_tool = (self, partner) if me.side == "master" else (partner, self)
        slave = slave_tool._ensure_slave()
        if me.mode == "rtu":
            link = loopback_serial(slave, baudrate=master_tool.baudrate.value,
                                   parity=master_tool.parity.value,
                                   stopbits=master_tool.stopbits.value, mode="rtu")
            for box in ("baudrate", "parity", "stopbits"):
                getattr(slave_tool, box).value = getattr(master_tool, box).value
        else:
            link = loopback_tcp(slave)
        slave.clock = link.clock
        master_tool.master = Master(link, timeout=float(master_tool.timeout.value),
                                    transaction_id=master_tool.transaction_id.value)
        for tool, other_tool in ((master_tool, slave_tool), (slave_tool, master_tool)):
            tool.link = link
            tool.partner = other_tool
            tool.connection.value = "loopback"
            tool._answering = True
        slave_tool._render_status()
        slave_tool.refresh()
        text = f"connected on a loopback wire: {link.description}"
        master_tool.message.show(text, "ok")
        slave_tool.message.show(f"{text}; answering as unit {slave.unit}", "ok")

    def _use_link(self, link: Any, text: str) -> None:
        """A master tool talks through ``link`` from now on."""
        self.link = link
        self.master = Master(link, timeout=float(self.timeout.value),
                             transaction_id=self.transaction_id.value)
        self.message.show(text, "ok")

    def _slave_on_real_time(self) -> Slave:
        """The slave a server will answer with, timestamped on the real clock."""
        slave = self._ensure_slave()
        slave.clock = self._real_clock
        return slave

    def _serving(self, text: str) -> None:
        """A slave tool's server has started: answer, keep the panel fresh, say where."""
        self._answering = True
        self._start_ticker()
        self.message.show(text, "ok")

    def _connect_serial(self) -> None:
        from ..links.serial import SerialServer, serial_link

        url = self.url.value.strip()
        settings = (self.baudrate.value, self.parity.value, self.stopbits.value)
        if self.is_master:
            link = serial_link(url, *settings, mode="rtu")
            self._use_link(link, f"connected: {link.description}")
        else:
            slave = self._slave_on_real_time()
            self.server = SerialServer(slave, url, *settings, mode="rtu").start()
            self._serving(f"serving unit {slave.unit} on {url}")

    def _connect_tcp(self) -> None:
        from ..links.tcp import TcpServer, tcp_link

        host = self.host.value.strip()
        if self.is_master:
            link = tcp_link(host, self.port.value, timeout=float(self.timeout.value))
            self._use_link(link, f"connected to {host}:{self.port.value}")
        else:
            slave = self._slave_on_real_time()
            self.server = TcpServer(slave, host=host, port=self.port.value).start()
            if self.server.address:
                self.port.value = self.server.address[1]
            self._serving(f"serving unit {slave.unit} on {host}:{self.port.value}")

    def disconnect(self, quiet: bool = False) -> None:
        """Stop polling, close the link or the server; a loopback partner is disconnected too."""
        self.stop(quiet=True)
        partner_link = self.link if self.partner is not None else None
        if self.server is not None:
            with contextlib.suppress(Exception):
                self.server.close()
            self.server = None
        if self.link is not None and self.partner is None:
            with contextlib.suppress(Exception):
                self.link.close()
        if partner_link is not None:
            with contextlib.suppress(Exception):
                partner_link.close()
            other = self.partner
            self.partner = None
            if other is not None and other.link is partner_link:
                other.stop(quiet=True)
                other.link = None
                other.master = None
                other.partner = None
                other._render_status()
                if not quiet:
                    other.message.show(f"{self.label} disconnected the wire", "warn")
        self.link = None
        self.master = None
        self._render_status()
        if not quiet:
            self.message.show("disconnected")

    def _render_status(self) -> None:
        on = self.connected
        colour = "#2f9e44" if on else "#c92a2a"
        text = "connected" if on else "not connected"
        if on and not self.is_master and not self._answering:
            colour, text = "#e67700", "connected, not answering"
        if on and self.partner is not None:
            text += f" to {esc(self.partner.label)}"
        self.status.value = (f'<span class="mbe-tt-status" style="color:{colour};font-size:1.2em">'
                             f"&#9679;</span>"
                             f' <span style="color:{colour}">{text}</span>')

    # =====================================================================================================
    # polling (master side)
    # =====================================================================================================
    @property
    def table(self) -> Table:
        """The grid's table: the one the chosen function reaches (``DataBank.table(function)``)."""
        return self.bank.table(self.function.value)

    @property
    def values(self) -> list:
        """The grid's values: ``length`` elements of :attr:`table` from the start address."""
        return self.table.read(self.address.value, self.length.value)

    def poll_once(self) -> Any:
        """Send one request with the chosen function (source 000's READ button); return the values.

        A read returns the values read (and fills the grid); a write sends the grid's values and returns
        them.  Errors (timeout, exception response, a bad setting) are counted, shown on the message
        line and returned as ``None``: nothing raises.
        """
        if not self.is_master:
            self.message.show("a slave answers, it does not poll: poll from the master tool", "warn")
            return None
        if self.master is None:
            self.message.show("not connected: press connect (or give a partner)", "error")
            return None
        if self._autofill is not None:
            self._autofill.update(self.clock.now)
        self.counts["polls"] += 1
        result: Any = None
        try:
            result = self._transact()
        except ModbusTimeoutError as exc:
            self.counts["timeouts"] += 1
            self.message.error(exc)
        except ModbusError as exc:
            self.counts["errors"] += 1
            self.message.error(exc)
        else:
            self.counts["valid"] += 1
            fc = FunctionCode(self.function.value)
            lat = self.master.stats.latencies[-1] * 1000 if self.master.stats.latencies else 0.0
            self.message.show(f"poll {self.counts['polls']}: {fc.title}, unit {self.unit.value}, "
                              f"{len(result)} value(s) from address {self.address.value} ({lat:.2f} ms)",
                              "ok")
        self.last_result = result
        self._after_exchange()
        return result

    read_once = poll_once

    def _transact(self) -> list:
        master, fc = self.master, self.function.value
        assert master is not None
        unit, address, length = self.unit.value, self.address.value, self.length.value
        table = self.table
        if fc in (1, 2, 3, 4):
            values = master.read_once(fc, unit, address, length)
            table.write(address, values)
            return values
        if fc == 5:
            value = table[address]
            master.write_single_coil(unit, address, value)
            return [value]
        if fc == 6:
            value = table[address]
            master.write_single_register(unit, address, value)
            return [value]
        values = table.read(address, length)
        if fc == 15:
            master.write_multiple_coils(unit, address, values)
        else:
            master.write_multiple_registers(unit, address, values)
        return values

    def run_polls(self, n: int) -> list:
        """Poll ``n`` times, one every ``interval`` seconds of the link's clock, and return the results.

        On a loopback wire the clock is virtual: it runs at once.  On a real link this blocks for
        about ``n * interval`` seconds (use *start* for polling in the background).
        """
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            self.message.error(ConfigError(f"run_polls(n): n must be a whole number >= 0, got {n!r}"))
            return []
        results = []
        clock = self.clock
        start = clock.now
        for i in range(n):
            due = start + i * float(self.interval.value)
            if due > clock.now:
                clock.sleep(due - clock.now)
            results.append(self.poll_once())
            if self.master is None:
                break
        return results

    def start(self) -> bool:
        """Master: poll every ``interval`` s on the kernel's asyncio loop.  Slave: answer requests."""
        if not self.is_master:
            return self._start_answering()
        if self.master is None:
            self.message.show("not connected: press connect first", "error")
            return False
        if self._polling:
            return True
        loop = _running_loop()
        if loop is None:
            self.message.show("continuous polling needs a running asyncio loop (a Jupyter kernel has one); "
                              "here, use run_polls(n)", "error")
            return False
        self._polling = True
        self._poll_task = loop.create_task(self._poll_loop())
        self._render_buttons()
        return True

    async def _poll_loop(self) -> None:
        clock = self.clock
        start, k = clock.now, 0
        try:
            while self._polling and self.master is not None:
                if isinstance(clock, VirtualClock):  # keep the virtual wire on the polling schedule
                    due = start + k * float(self.interval.value)
                    if due > clock.now:
                        clock.sleep(due - clock.now)
                self.poll_once()
                k += 1
                if not self.continuous.value:
                    break
                await asyncio.sleep(float(self.interval.value))
        except Exception as exc:  # noqa: BLE001 - a background task must report, not die silently
            self.message.error(exc)
        finally:
            self._polling = False
            self._poll_task = None
            self._render_buttons()

    def stop(self, quiet: bool = False) -> None:
        """Stop polling (master) or stop answering (slave: the master will time out)."""
        if not self.is_master and not quiet:
            self._stop_answering()
            return
        self._polling = False
        if self._poll_task is not None:
            self._poll_task.cancel()
            self._poll_task = None
        self._render_buttons()
        if not quiet and self.is_master:
            self.message.show(f"polling stopped after {self.counts['polls']} polls")

    @property
    def polling(self) -> bool:
        return self._polling

    def _start_answering(self) -> bool:
        if self.server is None and self.link is None:
            if self.connection.value == "loopback":
                self.message.show("waiting for a master: connect a master tool to this one", "warn")
                return False
            return self.connect()
        if self.link is not None and self.slave is not None and hasattr(self.link, "attach"):
            self.link.attach(self.slave)
        self._answering = True
        self._render_status()
        self.message.show(f"answering requests for unit {self.unit.value}", "ok")
        return True

    def _stop_answering(self) -> None:
        if self.link is not None and self.slave is not None and hasattr(self.link, "detach"):
            self.link.detach(self.slave)
            self._answering = False
            self.message.show("stopped answering: the master will time out", "warn")
        elif self.server is not None:
            self.disconnect(quiet=True)
            self._answering = False
            self.message.show("server stopped")
        self._render_status()

    def reset_counters(self) -> None:
        """Back to zero: the panel's counters, the master's statistics, the slave's counters."""
        for key in self.counts:
            self.counts[key] = 0
        if self.master is not None:
            self.master.stats.reset()
        if self.slave is not None:
            self.slave.counters.reset()
        self._render_counters()
        self.message.show("counters reset")

    def _after_exchange(self) -> None:
        if self.master is not None:
            previous, self._updating = self._updating, True
            try:
                self.transaction_id.value = self.master.transaction_id
            finally:
                self._updating = previous
        self.refresh()
        if self.partner is not None:
            self.partner.refresh()

    # =====================================================================================================
    # the slave's hook and the real-time ticker
    # =====================================================================================================
    def _on_read(self, slave: Slave, table_kind: str, address: int, count: int) -> None:
        """Before the slave answers a read: let auto fill write the values of the current time."""
        if self._autofill is not None:
            self._autofill.update(slave.clock.now if slave.clock is not None else self.clock.now)

    def _start_ticker(self) -> None:
        """On a real wire, refresh the panel (and auto fill) a few times a second on the asyncio loop."""
        loop = _running_loop()
        if loop is None or (self._tick_task is not None and not self._tick_task.done()):
            return
        self._tick_task = loop.create_task(self._tick_loop())

    async def _tick_loop(self) -> None:
        try:
            while self.server is not None or (self._autofill is not None and self._autofill.running):
                if self._autofill is not None and self.link is None:
                    with self._lock():
                        self._autofill.update(self.clock.now)
                self.refresh()
                await asyncio.sleep(0.5)
        except Exception as exc:  # noqa: BLE001
            self.message.error(exc)
        finally:
            self._tick_task = None

    def _lock(self) -> Any:
        lock = getattr(self.server, "lock", None)
        return lock if lock is not None else contextlib.nullcontext()

    # =====================================================================================================
    # the data grid
    # =====================================================================================================
    def refresh(self) -> None:
        """Redraw the grid, counters and logs from the tables and logs (called after every exchange)."""
        with self._lock():
            self._render_grid()
            self._render_counters()
            self._render_logs()
        self._render_buttons()
        self._render_status()

    def _grid_texts(self, values: list) -> list[str]:
        if self.table.is_bits:
            return ["1" if v else "0" for v in values]
        return format_registers(values, self.display.value)

    def _render_grid(self) -> None:
        try:
            values = self.values
        except ModbusError as exc:
            self.message.error(exc)
            self.grid.children = []
            self._cells = []
            self._grid_shape = None
            return
        address, n = self.address.value, min(len(values), MAX_CELLS)
        shape = (address, n, self.table.kind)
        if shape != self._grid_shape:
            self._build_grid(address, n)
            self._grid_shape = shape
        texts = self._grid_texts(values)[:n]
        wide = not self.table.is_bits and self.display.value not in FORMATS[:6]
        previous, self._updating = self._updating, True
        try:
            for cell, text in zip(self._cells, texts):
                cell.value = text
                cell.disabled = wide and text in ("", "—")
        finally:
            self._updating = previous
        if not self._write_value_typed and self._cells:
            self._selected_changed()

    def _build_grid(self, address: int, n: int) -> None:
        cells = []
        rows = [W.HBox([W.HTML(f'<div style="width:70px;{MONO};color:#868e96">address</div>')] +
                       [W.HTML(f'<div style="width:84px;text-align:center;{MONO};color:#868e96">+{c}</div>')
                        for c in range(min(COLUMNS, n))])]
        for start in range(0, n, COLUMNS):
            row = [W.HTML(f'<div style="width:70px;{MONO}">{address + start}</div>')]
            for i in range(start, min(start + COLUMNS, n)):
                cell = W.Text(continuous_update=False, layout=W.Layout(width="84px"))
                cell.add_class("mbe-tt-cell")
                cell.observe(guarded(self.message, lambda change, i=i: self._cell_edited(i, change)),
                             names="value")
                cells.append(cell)
                row.append(cell)
            rows.append(W.HBox(row))
        more = len(self.table.read(address, self.length.value)) - n if self.length.value > n else 0
        if more:
            rows.append(W.HTML(f"<i>... and {more} more (the grid shows the first {MAX_CELLS})</i>"))
        self._cells = cells
        self.grid.children = rows

    def _cell_edited(self, index: int, change: dict) -> None:
        if self._updating:
            return
        address = self.address.value + index
        self.set_cell(address, change["new"])

    def set_cell(self, address: int, text: str | int) -> bool:
        """Put a value into the grid's table at ``address``, as typed in the current display format.

        A wide format (say ``float32_ABCD``) writes all the registers of the value.  A slave serves the
        new value at once; a master keeps it for *write cell* / *write cells*.  Returns False (and
        says why on the message line) when the text does not fit the format.
        """
        table = self.table
        try:
            if table.is_bits:
                bits = parse_bit_list(str(text), f"cell {address}")
                if len(bits) != 1:
                    raise ConfigError(f"cell {address}: one bit (1 or 0), got {text!r}")
                new: list = bits
            else:
                new = parse_formatted(str(text), self.display.value) if not isinstance(text, int) \
                    else parse_formatted(str(text), "unsigned")
            with self._lock():
                table.write(address, new)
        except ModbusError as exc:
            self.message.error(exc)
            self._render_grid()
            return False
        previous, self._updating = self._updating, True
        try:
            self.selected.value = address
        finally:
            self._updating = previous
        self._selected_changed()
        self._render_grid()
        self.message.show(f"cell {address} = {text}", "info")
        return True

    def _write_value_edited(self) -> None:
        if not self._updating:
            self._write_value_typed = True

    def _selected_changed(self) -> None:
        """Show the selected cell's value in the write box (source 000: row and column in a text box)."""
        self._write_value_typed = False
        address = self.selected.value
        try:
            values = self.table.read(address, 4)
        except ModbusError:
            try:
                values = self.table.read(address, 1)
            except ModbusError as exc:
                self.message.error(exc)
                return
        previous, self._updating = self._updating, True
        try:
            self.write_value.value = self._grid_texts(values)[0] or ""
        finally:
            self._updating = previous

    # -- writes (master) -----------------------------------------------------------------------------------
    def _writable_table(self) -> Table:
        table = self.table
        if not table.writable:
            raise ConfigError(f"a master cannot write the {table.kind.replace('_', ' ')}: choose a function "
                              f"that reaches the coils (1, 5, 15) or the holding registers (3, 6, 16)")
        return table

    def write_cell(self, address: int | None = None, value: str | int | None = None) -> bool:
        """Write one cell to the device: FC06 for a register (FC16 for a 32/64-bit display format, whose
        value spans several registers), FC05 for a coil.  Defaults: the selected cell and its value."""
        if not self._check_master():
            return False
        try:
            table = self._writable_table()
            address = self.selected.value if address is None else address
            text = self.write_value.value if value is None else value
            if not self.set_cell(address, text):
                return False
            unit = self.unit.value
            assert self.master is not None
            if table.is_bits:
                self.master.write_single_coil(unit, address, table[address])
                what = f"FC05: coil {address} = {'ON' if table[address] else 'OFF'}"
            else:
                regs = parse_formatted(str(text), self.display.value) if not isinstance(text, int) else [text]
                if len(regs) == 1:
                    self.master.write_single_register(unit, address, regs[0])
                    what = f"FC06: register {address} = {regs[0]}"
                else:
                    self.master.write_multiple_registers(unit, address, regs)
                    what = (f"FC16 (a {self.display.value} value takes {len(regs)} registers): "
                            f"address {address}")
        except ModbusError as exc:
            self.message.error(exc)
            self._after_exchange()
            return False
        self.message.show(f"written, {what}", "ok")
        self._after_exchange()
        return True

    def write_cells(self, address: int | None = None, count: int | None = None) -> bool:
        """Write ``count`` cells from ``address`` (default: the selected cell, *cells*) with FC16 (FC15)."""
        if not self._check_master():
            return False
        try:
            table = self._writable_table()
            address = self.selected.value if address is None else address
            count = self.write_count.value if count is None else count
            values = table.read(address, count)
            assert self.master is not None
            if table.is_bits:
                self.master.write_multiple_coils(self.unit.value, address, values)
                what = f"FC15: {count} coils from {address}"
            else:
                self.master.write_multiple_registers(self.unit.value, address, values)
                what = f"FC16: {count} registers from {address}"
        except ModbusError as exc:
            self.message.error(exc)
            self._after_exchange()
            return False
        self.message.show(f"written, {what}", "ok")
        self._after_exchange()
        return True

    def _check_master(self) -> bool:
        if not self.is_master:
            self.message.show("only a master (or client) writes to a device; a slave's grid is its data",
                              "warn")
            return False
        if self.master is None:
            self.message.show("not connected: press connect first", "error")
            return False
        return True

    # =====================================================================================================
    # dummy data
    # =====================================================================================================
    def random_fill(self) -> list:
        """Fill the grid (start address, length) with random values (seeded: the same every run)."""
        with self._lock():
            values = random_fill(self.table, self.address.value, self.length.value, self._rng)
        self.refresh()
        self.message.show(f"random fill: {len(values)} values")
        return values

    def fill_increment(self, start: int | None = None, step: int | None = None) -> list:
        """Fill the grid with ``start, start+step, ...`` (without *increment*: ``start`` everywhere)."""
        if start is not None:
            self.fill_start.value = start
        if step is not None:
            self.fill_step.value = step
            self.increment.value = True
        step_value = self.fill_step.value if self.increment.value else 0
        with self._lock():
            values = increment_fill(self.table, self.address.value, self.length.value, self.fill_start.value,
                                    step_value)
        self.refresh()
        self.message.show(f"fill: {len(values)} values from {self.fill_start.value}, step {step_value}")
        return values

    def auto_fill_start(self) -> None:
        """Refresh the grid with random values every *every (s)* seconds of the wire's clock."""
        interval = float(self.auto_interval.value)
        generator = Uniform(seed=self._rng.randrange(2**31), period=interval)
        self._autofill = AutoFill(self.table, self.address.value, self.length.value, generator,
                                  interval=interval, first=self.clock.now)
        with self._lock():
            self._autofill.update(self.clock.now)
        if self.link is None:
            self._start_ticker()
        self.refresh()
        self.message.show(f"auto fill: new random values every {interval:g} s", "ok")

    def auto_fill_stop(self) -> None:
        if self._autofill is not None:
            self._autofill.stop()
        self._autofill = None
        self.message.show("auto fill stopped")

    # =====================================================================================================
    # counters and logs
    # =====================================================================================================
    @property
    def traffic(self) -> TrafficLog:
        """The log shown: the master's (tx = requests sent) or the slave's (rx = requests received)."""
        if self.is_master:
            return self.master.log if self.master is not None else self._empty_log
        return self.slave.log if self.slave is not None else self._empty_log

    def _render_counters(self) -> None:
        chip = ('<span style="display:inline-block;margin-right:14px"><span style="color:#868e96">{k}</span> '
                '<b class="mbe-tt-count-{c}">{v}</b></span>')
        if self.is_master:
            n = self.counts
            items = [("polls", "polls", n["polls"]), ("valid responses", "valid", n["valid"]),
                     ("timeouts", "timeouts", n["timeouts"]), ("errors", "errors", n["errors"])]
            extra = esc(self.master.stats.summary()) if self.master is not None else ""
        else:
            c = self.slave.counters if self.slave is not None else None
            d = c.as_dict() if c is not None else {}
            items = [(k.replace("_", " "), k, v) for k, v in d.items()]
            extra = ""
            self.request_count.value = (f'<span style="margin-left:10px">request count: '
                                        f'<b class="mbe-tt-request-count">{d.get("requests", 0)}</b></span>')
        html = self._lamps_html() + "".join(chip.format(k=esc(k), c=c, v=v) for k, c, v in items)
        self.counters.value = (f"<div>{html}</div>" +
                               (f'<div style="font-size:0.85em;color:#868e96">{extra}</div>'
                                if extra else ""))

    def _update_lamps(self) -> None:
        """Source 000's TX and RX indicators: lit when a frame went that way since the last redraw."""
        log = self.traffic
        if log is not self._lamp_log or len(log) < self._lamp_seen:  # another log, or it was cleared
            self._lamp_log, self._lamp_seen = log, 0
        directions = {log[i].direction for i in range(self._lamp_seen, len(log))}
        self._lamp_seen = len(log)
        self.lamps = {"tx": "tx" in directions, "rx": "rx" in directions}

    def _lamps_html(self) -> str:
        self._update_lamps()
        colours = {"tx": "#f08c00", "rx": "#2f9e44"}
        return "".join(
            f'<span class="mbe-tt-lamp-{d}{" mbe-tt-lamp-on" if on else ""}" style="display:inline-block;'
            f'margin-right:12px"><span style="color:{colours[d] if on else "#ced4da"};font-size:1.2em">'
            f'&#9679;</span> {d.upper()}</span>' for d, on in self.lamps.items())

    def _render_buttons(self) -> None:
        if self.is_master:
            self.start_button.disabled = self._polling or self.master is None
            self.stop_button.disabled = not self._polling
            self.read_button.disabled = self.master is None or self._polling
            single = "FC05" if self.table.is_bits else "FC06"
            many = "FC15" if self.table.is_bits else "FC16"
            self.write_one_button.description = f"write cell ({single})"
            self.write_many_button.description = f"write cells ({many})"
        else:
            self.start_button.disabled = self.connected and self._answering
            self.stop_button.disabled = not (self.connected and self._answering)
            self.read_button.disabled = True

    def _log_html(self, log: TrafficLog, title: str) -> str:
        entries = list(log)[-LOG_LINES:]
        text = TrafficLog(entries).to_text(newest_first=self.newest_on_top.value) if entries else "(empty)"
        return (f'<div style="font-weight:bold">{esc(title)} ({len(log)})</div>'
                f'<pre style="{MONO};white-space:pre;font-size:0.8em;max-height:180px;overflow:auto;'
                f'width:100%;box-sizing:border-box;border:1px solid #dee2e6;margin:0 4px 0 0;padding:2px">'
                f'{esc(text)}</pre>')

    def _render_logs(self) -> None:
        log = self.traffic
        needle = self.search.value.strip() or None
        self.tx_log.value = self._log_html(log.search(text=needle, direction="tx"), "TX log (sent)")
        self.rx_log.value = self._log_html(log.search(text=needle, direction="rx"), "RX log (received)")

    def clear_logs(self) -> None:
        """Forget the traffic shown in the TX and RX logs."""
        self.traffic.clear()
        self._render_logs()
        self.message.show("logs cleared")

    # =====================================================================================================
    # configuration
    # =====================================================================================================
    def config(self) -> dict[str, Any]:
        """Every setting as a JSON-able dict (what *save config* writes)."""
        return {
            "role": self.role.value, "name": self.name.value, "connection": self.connection.value,
            "url": self.url.value, "baudrate": self.baudrate.value, "parity": self.parity.value,
            "stopbits": self.stopbits.value, "host": self.host.value, "port": self.port.value,
            "timeout": float(self.timeout.value), "unit": self.unit.value, "address": self.address.value,
            "length": self.length.value, "function": self.function.value,
            "transaction_id": self.transaction_id.value, "interval": float(self.interval.value),
            "continuous": self.continuous.value, "display": self.display.value,
            "fill_start": self.fill_start.value, "fill_increment": self.increment.value,
            "fill_step": self.fill_step.value, "auto_interval": float(self.auto_interval.value),
            "newest_on_top": self.newest_on_top.value, "seed": self._seed,
        }

    def apply_config(self, config: dict[str, Any]) -> bool:
        """Set every setting found in ``config`` (a dict as :meth:`config` returns).  Unknown keys or bad
        values are reported on the message line and nothing is changed.  Returns True on success."""
        try:
            if not isinstance(config, dict):
                raise ConfigError(f"a configuration is a dict (JSON object), got {type(config).__name__}")
            unknown = sorted(set(config) - set(CONFIG_KEYS) - {"version"})
            if unknown:
                raise ConfigError(f"unknown configuration key(s): {', '.join(unknown)}; "
                                  f"expected some of {', '.join(CONFIG_KEYS)}")
            if "role" in config and config["role"] not in ROLES:
                raise ConfigError(f"unknown role {config['role']!r}: expected one of {', '.join(ROLES)}")
            if "display" in config and config["display"] not in FORMATS:
                raise ConfigError(f"unknown display format {config['display']!r}")
            before = self.config()
            key = "role"
            try:
                if "role" in config and config["role"] != self.role.value:
                    self.role.value = config["role"]
                for key in CONFIG_KEYS:
                    if key in ("role", "seed") or key not in config:
                        continue
                    self._config_widget(key).value = config[key]
                if "seed" in config:
                    key = "seed"
                    if isinstance(config["seed"], bool) or not isinstance(config["seed"], int):
                        raise ValueError("the seed is a whole number")
                    self._seed = config["seed"]
                    self._rng = random.Random(self._seed)
            except Exception as exc:  # a widget refused a value (TraitError): put everything back
                self._restore(before)
                raise ConfigError(f"bad value for {key!r}: {config[key]!r} ({exc})") from None
        except ModbusError as exc:
            self.message.error(exc)
            return False
        self.refresh()
        return True

    def _restore(self, before: dict[str, Any]) -> None:
        if self.role.value != before["role"]:
            self.role.value = before["role"]
        for key in CONFIG_KEYS:
            if key not in ("role", "seed"):
                with contextlib.suppress(Exception):
                    self._config_widget(key).value = before[key]

    def _config_widget(self, key: str) -> W.ValueWidget:
        return self.increment if key == "fill_increment" else getattr(self, key)

    def save_config(self, path: str | Path | None = None) -> Path | None:
        """Write :meth:`config` as JSON to ``path`` (default: the *config file* field)."""
        target = Path(path if path is not None else self.config_path.value).expanduser()
        try:
            target.write_text(json.dumps({"version": 1, **self.config()}, indent=2) + "\n")
        except OSError as exc:
            self.message.error(ConfigError(
                f"cannot save the configuration to {target}: {exc.strerror or exc}"))
            return None
        self.message.show(f"configuration saved to {target}", "ok")
        return target

    def load_config(self, source: str | Path | dict[str, Any] | None = None) -> bool:
        """Load settings from a JSON file (default: the *config file* field) or from a dict."""
        if source is not None and not isinstance(source, (str, Path)):
            ok = self.apply_config(source)
            if ok:
                self.message.show("configuration loaded", "ok")
            return ok
        target = Path(source if source is not None else self.config_path.value).expanduser()
        try:
            config = json.loads(target.read_text())
        except OSError as exc:
            self.message.error(ConfigError(f"cannot read {target}: {exc.strerror or exc}"))
            return False
        except ValueError as exc:
            self.message.error(ConfigError(f"{target} is not valid JSON: {exc}"))
            return False
        ok = self.apply_config(config)
        if ok:
            self.message.show(f"configuration loaded from {target}", "ok")
        return ok

    @classmethod
    def from_config(cls, source: str | Path | dict, **kwargs: Any) -> TestTool:
        """A new tool with the settings of a saved configuration (a path or a dict)."""
        if isinstance(source, dict):
            config = dict(source)
        else:
            config = json.loads(Path(source).expanduser().read_text())
        config.pop("version", None)
        role = config.pop("role", "rtu_master")
        tool = cls(role, **kwargs)
        tool.apply_config(config)
        return tool

    # =====================================================================================================
    def __repr__(self) -> str:
        state = "connected" if self.connected else "not connected"
        return f"<TestTool {self.role_info.title} {self.label!r}, {state}, counts={self.counts}>"
