"""TestTool, the panel: the robot test-tool paper's Modbus test tool rebuilt as a notebook panel.

One panel is an RTU master, an RTU slave, a TCP client or a TCP server.  Two panels in one notebook
talk to each other over an in-process loopback wire (:func:`modbus_edu.links.loopback_serial` or
:func:`~modbus_edu.links.loopback_tcp`), or a panel talks to the outside world through a serial port
(pyserial) or a TCP socket.  All protocol work is the library's: a master panel drives a
:class:`~modbus_edu.master.Master`, a slave panel owns a :class:`~modbus_edu.slave.Slave`; the panel
only holds settings, a data grid and counters.
"""

from __future__ import annotations

import asyncio
import dataclasses
import random
from typing import Any

import ipywidgets as W

from ...clock import RealClock
from ...datamodel import DataBank
from ...devices.generators import AutoFill
from ...errors import ConfigError, ModbusError
from ...master import Master
from ...slave import Slave
from ...traffic import TrafficLog
from ..common import MessageLine, esc, focus_after_click, guarded, panel_style, scroll_box, shown
from ..picture import StaticView
from ..throttle import Throttle
from .config import ConfigMixin
from .connection import ConnectionMixin
from .controls import (
    BAUD_RATES,
    CONFIG_KEYS,
    FORMAT_OPTIONS,
    FUNCTION_OPTIONS,
    GRID_HEIGHT,
    LOG_HEIGHT,
    ROLE_OPTIONS,
    ROLES,
    TAB_TITLES,
    Role,
    TestToolSettings,
    button,
    row,
    small,
)
from .grid import GridMixin
from .traffic import TrafficMixin

__all__ = ["TestTool"]


class TestTool(StaticView, ConnectionMixin, GridMixin, TrafficMixin, ConfigMixin, W.VBox):
    """The robot test-tool paper's Modbus test tool in a notebook: RTU master, RTU slave, TCP client or TCP
    server.

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
        settings: TestToolSettings | None = None,
        **kwargs: Any,
    ) -> None:
        """``role`` and every field of :class:`~.controls.TestToolSettings` as a keyword (``unit=2``,
        ``url="loop://"``, ...), or ``settings=`` all at once (its role wins over the default ``role``);
        other keywords go to the widget box."""
        chosen = {key: kwargs.pop(key) for key in CONFIG_KEYS if key in kwargs and key != "role"}
        if settings is None or role != "rtu_master":
            chosen["role"] = role
        settings = dataclasses.replace(settings or TestToolSettings(), **chosen)
        role, seed = settings.role, settings.seed
        super().__init__(**kwargs)
        self.add_class("mbe-testtool")
        self.bank = DataBank()
        """The tool's own four tables: what a master read (and will write), what a slave serves."""
        self.slave: Slave | None = None
        self.master: Master | None = None
        self.link: Any = None
        self._browser_port: Any = None  # the browser's serial port, kept open between connects
        self._pending_poll: Any = None  # a poll awaiting the browser's port on the kernel's loop
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
        self.last_outcome = ""
        """How the master's last exchange ended: "" (none yet), "valid", "timeout" or "error"."""

        self._build()
        self.follow = Throttle(guarded(self.message, self._follow_traffic))
        """Redraws the panel after its slave's traffic, from any link, at most every 0.2 s (a
        :class:`~modbus_edu.widgets.throttle.Throttle`): the grid and counters follow without
        :meth:`refresh`."""
        self._apply_role()
        self._render_auto_state()
        values = dataclasses.asdict(settings)
        if values["connection"] is None and partner is not None:
            values["connection"] = "loopback"
        if role not in ROLES:
            values.pop("role")
        self.apply_config({k: v for k, v in values.items() if v is not None})
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
        self.role = small(W.Dropdown(options=ROLE_OPTIONS, value="rtu_master", description="role"), "230px",
                           "40px")
        self.role.add_class("mbe-tt-role")
        self.name = small(W.Text(value="", description="name", placeholder="a name for messages"),
                           "230px", "40px")

        # -- connection --------------------------------------------------------------------------------
        self.connection = small(W.Dropdown(options=[("loopback partner", "loopback")],
                                            description="connection"),
                                 "300px")
        self.url = small(W.Text(value="loop://", description="port / URL",
                                 placeholder="loop://, /dev/ttyUSB0, COM3, socket://host:port"), "300px")
        self.baudrate = small(W.Dropdown(options=BAUD_RATES, value=9600, description="baud"))
        self.parity = small(W.Dropdown(options=[("none (N)", "N"), ("even (E)", "E"), ("odd (O)", "O")],
                                        value="N", description="parity"))
        self.stopbits = small(W.Dropdown(options=[("1", 1), ("2", 2)], value=1,
                                          description="stop bits"))
        self.host = small(W.Text(value="127.0.0.1", description="host"))
        self.port = small(W.BoundedIntText(value=5020, min=0, max=65535, description="TCP port"))
        # step None (the page's "any"): a step of 0.1 from a minimum of 0.001 made 1.0 invalid in the page
        self.timeout = small(W.BoundedFloatText(value=1.0, min=0.001, max=60, step=None,
                                                 description="timeout (s)"))
        self.connect_button = button("connect", "plug", "mbe-tt-connect",
                                     "open the wire the connection settings describe", style="success")
        self.disconnect_button = button("disconnect", "times", "mbe-tt-disconnect",
                                        "close the wire (a loopback partner is disconnected too)")
        self.status = W.HTML()
        self.connect_button.on_click(g(self.message, lambda _b: self.connect()))
        self.disconnect_button.on_click(g(self.message, lambda _b: self.disconnect()))

        # -- device parameters ---------------------------------------------------------------------------
        self.unit = small(W.BoundedIntText(value=1, min=0, max=255, description="unit (slave id)"))
        self.unit.add_class("mbe-tt-unit")
        self.address = small(W.BoundedIntText(value=0, min=0, max=65535, description="start address"))
        self.address.add_class("mbe-tt-address")
        self.length = small(W.BoundedIntText(value=10, min=1, max=2000, description="length"))
        self.function = small(W.Dropdown(options=FUNCTION_OPTIONS, value=3,
                                          description="function"),
                               "320px")
        self.transaction_id = small(W.BoundedIntText(value=1, min=0, max=65535,
                                                      description="transaction id"))
        self.request_count = W.HTML()

        # -- polling -------------------------------------------------------------------------------------
        self.interval = small(W.BoundedFloatText(value=1.0, min=0.01, max=3600, step=None,
                                                  description="interval (s)"))
        self.continuous = W.Checkbox(value=True, description="continuous", indent=False,
                                     layout=W.Layout(width="110px"))
        self.read_button = button("read once", "download", "mbe-tt-read",
                                   "one request with the chosen function")
        self.start_button = button("start", "play", "mbe-tt-start", style="primary")
        self.stop_button = button("stop", "stop", "mbe-tt-stop")
        self.reset_button = button("reset counters", "undo", "mbe-tt-reset",
                                   "set polls, valid responses, timeouts and errors back to zero")
        self.counters = W.HTML()
        self.counters.add_class("mbe-tt-counters")
        self.read_button.on_click(g(self.message, lambda _b: self.poll_once()))
        self.start_button.on_click(g(self.message, lambda _b: self.start()))
        self.stop_button.on_click(g(self.message, lambda _b: self.stop()))
        focus_after_click(self.start_button, self.stop_button)
        focus_after_click(self.stop_button, self.start_button)
        self.reset_button.on_click(g(self.message, lambda _b: self.reset_counters()))

        # -- data grid -------------------------------------------------------------------------------------
        self.display = small(W.Dropdown(options=FORMAT_OPTIONS, value="unsigned", description="display"),
                              "260px",
                              "60px")
        self.grid = W.VBox(layout=W.Layout(max_height=GRID_HEIGHT, overflow="auto"))  # scrolls past 8 rows
        self.grid.add_class("mbe-tt-grid")
        self.grid_message = MessageLine()  # errors of a cell or of the write fields, right beside them
        self.grid_message.add_class("mbe-tt-grid-message")
        self._cells: list[W.Text] = []
        self._grid_shape: tuple | None = None
        self.selected = small(W.BoundedIntText(value=0, min=0, max=65535, description="cell address"))
        self.write_value = small(W.Text(description="value", placeholder="from the grid"))
        self._write_value_typed = False
        self.write_value.observe(lambda _c: self._write_value_edited(), names="value")
        self.write_count = small(W.BoundedIntText(value=10, min=1, max=1968,
                                                   description="cells"))
        self.write_one_button = button("write cell (FC06)", "pencil", "mbe-tt-write-one",
                                       "write the selected cell to the device (FC06, FC05 for a coil)")
        self.write_many_button = button("write cells (FC16)", "pencil-square-o", "mbe-tt-write-many",
                                        "write cells from the selected one (FC16, FC15 for coils)")
        self.write_one_button.on_click(g(self.message, lambda _b: self.write_cell()))
        self.write_many_button.on_click(g(self.message, lambda _b: self.write_cells()))
        self.write_box = row(self.selected, self.write_value, self.write_one_button, self.write_count,
                             self.write_many_button)

        # -- dummy data --------------------------------------------------------------------------------------
        self.fill_start = small(W.IntText(value=0, description="first value"), "190px", "75px")
        self.increment = W.Checkbox(value=True, description="increment", indent=False,
                                         layout=W.Layout(width="100px"))
        self.fill_step = small(W.IntText(value=1, description="by"), "120px", "25px")
        self.auto_interval = small(W.BoundedFloatText(value=1.0, min=0.05, max=3600,
                                                       description="every (s)"), "160px", "60px")
        self.auto_state = W.HTML()
        self.auto_state.add_class("mbe-tt-auto-state")
        self.random_button = button("random fill", "random", "mbe-tt-random",
                                    "random values in the grid (seeded: the same every run)")
        self.fill_button = button("fill", "sort-numeric-asc", "mbe-tt-fill",
                                  "the first value, then + step in each cell (no increment: all the same)")
        self.auto_start_button = button("auto fill start", "play-circle", "mbe-tt-auto-start",
                                        "new random values every few seconds")
        self.auto_stop_button = button("auto fill stop", "stop-circle", "mbe-tt-auto-stop",
                                       "stop the auto fill; the values stay")
        self.random_button.on_click(g(self.message, lambda _b: self.random_fill()))
        self.fill_button.on_click(g(self.message, lambda _b: self.fill_increment()))
        self.auto_start_button.on_click(g(self.message, lambda _b: self.auto_fill_start()))
        self.auto_stop_button.on_click(g(self.message, lambda _b: self.auto_fill_stop()))
        focus_after_click(self.auto_start_button, self.auto_stop_button)
        focus_after_click(self.auto_stop_button, self.auto_start_button)

        # -- logs ------------------------------------------------------------------------------------------
        self.newest_on_top = W.Checkbox(value=True, description="newest on top", indent=False,
                                        layout=W.Layout(width="130px"))
        self.search = small(W.Text(description="search", placeholder="hex, note, unit ..."), "260px", "50px")
        self.clear_button = button("clear logs", "trash", "mbe-tt-clear",
                                   "forget the traffic shown in both logs")
        self.clear_button.on_click(g(self.message, lambda _b: self.clear_logs()))
        # each log scrolls inside its own half, both ways (long frames, the note column)
        self.tx_log = W.HTML(layout=W.Layout(width="50%", max_height=LOG_HEIGHT, overflow="auto"))
        self.rx_log = W.HTML(layout=W.Layout(width="50%", max_height=LOG_HEIGHT, overflow="auto"))
        self.tx_log.add_class("mbe-tt-tx-log")
        self.rx_log.add_class("mbe-tt-rx-log")
        scroll_box(self.tx_log, "TX log: the frames sent (scrolls)")
        scroll_box(self.rx_log, "RX log: the frames received (scrolls)")

        # -- config ----------------------------------------------------------------------------------------
        self.config_path = small(W.Text(value="testtool.json", description="config file"), "300px", "75px")
        self.save_button = button("save config", "save", "mbe-tt-save",
                                  "write every setting as JSON to the config file")
        self.load_button = button("load config", "folder-open", "mbe-tt-load",
                                  "read every setting from the config file")
        self.save_button.on_click(g(self.message, lambda _b: self.save_config()))
        self.load_button.on_click(g(self.message, lambda _b: self.load_config()))

        def section(title: str) -> W.HTML:
            return W.HTML(f'<div style="font-weight:bold;margin-top:4px;border-bottom:1px solid #ccc">'
                          f"{esc(title)}</div>")

        self.serial_box = row(self.url, self.baudrate, self.parity, self.stopbits)
        self.tcp_box = row(self.host, self.port)
        self.browser_box = W.Box()  # the browser's serial port: its "choose serial port" button
        # always on screen: who this is, what happened, whether it is connected, start/stop and the counters
        self.polling_box = W.VBox([
            row(self.interval, self.continuous, self.read_button, self.start_button, self.stop_button,
                self.reset_button),
            self.counters,
        ])
        connection_tab = W.VBox([
            section("Connection"),
            row(self.connection, self.timeout, self.connect_button, self.disconnect_button),
            self.serial_box,
            self.browser_box,
            self.tcp_box,
            section("Device parameters"),
            row(self.unit, self.address, self.length, self.function),
            row(self.transaction_id, self.request_count),
        ])
        data_tab = W.VBox([
            row(self.display),
            self.grid,
            self.write_box,
            self.grid_message,
            section("Dummy data"),
            row(self.random_button, self.fill_start, self.increment, self.fill_step, self.fill_button),
            row(self.auto_interval, self.auto_start_button, self.auto_stop_button, self.auto_state),
        ])
        traffic_tab = W.VBox([
            row(self.newest_on_top, self.search, self.clear_button),
            W.HBox([self.tx_log, self.rx_log], layout=W.Layout(width="100%")),
        ])
        settings_tab = W.VBox([
            section("Configuration"),
            row(self.config_path, self.save_button, self.load_button),
        ])
        self.tabs = W.Tab(children=[connection_tab, data_tab, traffic_tab, settings_tab],
                          titles=TAB_TITLES)  # stretched by the panel (width 100% + margins overflowed)
        self.tabs.add_class("mbe-tt-tabs")
        self.children = [
            self.title,
            row(self.role, self.name, self.status),
            self.message,
            self.polling_box,
            self.tabs,
            panel_style(),
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
        self.length.observe(g(self.message, lambda _c: self._length_changed()), names="value")

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
        options = [("loopback partner", "loopback"), (real[1], real[0])]
        if r.key == "rtu_master":  # the learner's own adapter, through the page (Chrome, Edge)
            options.append(("browser serial port (Web Serial)", "browser"))
        self.connection.options = options
        self.connection.value = current if current in [value for _, value in options] else "loopback"
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
        shown(self.serial_box, kind in ("serial", "browser"))
        shown(self.browser_box, kind == "browser")
        shown(self.tcp_box, kind == "tcp")
        # on a loopback wire the master's line settings are the wire's: show them for RTU
        if kind == "loopback" and self.role_info.mode == "rtu":
            shown(self.serial_box, True)
            shown(self.url, False)
        else:
            shown(self.url, kind != "browser")
        self._render_status()

    def _ensure_slave(self) -> Slave:
        if self.slave is None:
            unit = self.unit.value
            try:
                self.slave = Slave(unit=unit, bank=self.bank, on_read=self._on_read, name=self.label)
            except ModbusError as exc:  # unit 0 (broadcast) in the field: serve unit 1 until it is fixed
                self.message.error(exc)
                self.slave = Slave(unit=1, bank=self.bank, on_read=self._on_read, name=self.label)
            self.slave.listeners.append(lambda _slave: self.follow.poke())
        return self.slave

    def _follow_traffic(self) -> None:
        """The slave handled requests (from any link): what the panel showed is no longer the present."""
        self._clear_stale()
        self.refresh()

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
    def static_text(self) -> str:
        name = f" {self.name.value!r}" if self.name.value else ""
        return f"Modbus test tool panel, {self.role_info.title}{name}"

    def static_html(self) -> str:
        """The picture as the panel is now: a redraw still waiting for the throttle is drawn first."""
        self.follow.flush()
        return super().static_html()

    def __repr__(self) -> str:
        state = "connected" if self.connected else "not connected"
        return f"<TestTool {self.role_info.title} {self.label!r}, {state}, counts={self.counts}>"
