"""MeterDashboard: the power-meter paper's data acquisition -- read a power meter periodically, tabulate, plot
trends."""

from __future__ import annotations

import asyncio
import io
from collections.abc import Iterable, Sequence
from typing import Any

import ipywidgets as W

from ..clock import VirtualClock
from ..devices.meter import METER_MAP, MeterRegister, PowerMeter, read_meter
from ..errors import ConfigError, MissingDependencyError, ModbusError, ModbusTimeoutError, shown
from ..links.loopback import loopback_serial
from ..master import Master
from ..platform import require_plotting
from ..slave import Slave
from .common import MONO, MessageLine, PlotImage, esc, focus_after_click, guarded, panel_style, scroll_box
from .picture import StaticView

__all__ = ["MeterDashboard"]

_GROUP_TITLES = {"V": "voltages (V)", "A": "currents (A)", "%": "THD (%)", "": "power factors",
                 "kWh": "energy (kWh)"}


def _group_title(unit: str) -> str:
    return _GROUP_TITLES.get(unit, unit or "values")


class MeterDashboard(StaticView, W.VBox):
    """Read a power meter every few seconds, show the scaled values in a table and plot their trends.

    ``source`` is a device (a :class:`~modbus_edu.devices.PowerMeter`, or any slave with the same
    register map) -- the dashboard then puts it on a virtual RS-485 line with the device's own serial
    settings (003: 19200 baud 8N1) and reads it through a :class:`~modbus_edu.master.Master` -- or a
    ``Master`` already connected to a real or virtual meter.  Without a source it reads a simulated
    ``PowerMeter(unit=1, trial=1, live=True)``.  The register map comes from the device
    module (:data:`modbus_edu.devices.meter.METER_MAP`, the power-meter paper's Table 5; a device may carry
    its own as ``register_map``); each read is :func:`modbus_edu.devices.meter.read_meter` (function 03, one
    request per contiguous block, unsigned 32-bit values high word first, scaled).

    Controls: *read once*, *start* / *stop* (every ``interval`` s on the kernel's asyncio loop, not
    blocking the notebook), the quantities to plot, *clear*.  Headless: :meth:`read_once` and
    :meth:`run` (``run(600)`` on a virtual line simulates ten minutes of readings, 3000 transactions,
    in a few seconds).  State: ``values`` (the last reading, ``{"VL1": 403.6, ...}``), ``history`` (a list of
    ``(time, values)`` on the link's clock), ``counts`` (reads, valid, timeouts, errors), ``plot_png``.

    Example (the power-meter paper's first trial, the values drifting as on a running machine)::

        from modbus_edu.devices import PowerMeter
        from modbus_edu.widgets import MeterDashboard
        dash = MeterDashboard(PowerMeter(unit=1, trial=1, live=True), interval=1.0)
        dash.run(600)            # ten minutes, one reading a second, on the virtual clock
        dash                     # the table of the last reading and the trend plot
        dash.plot_group.value = "A"   # plot the three currents instead of the voltages
    """

    def __init__(
        self,
        source: Slave | Master | None = None,
        *,
        unit: int | None = None,
        entries: Iterable[MeterRegister] | None = None,
        interval: float = 1.0,
        plot: str = "V",
        max_history: int = 10_000,
        timeout: float = 1.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.add_class("mbe-meterdashboard")
        self.message = MessageLine()
        self.history: list[tuple[float, dict[str, float]]] = []
        self.values: dict[str, float] = {}
        self.counts = {"reads": 0, "valid": 0, "timeouts": 0, "errors": 0}
        self.max_history = max_history
        self.plot_png: bytes = b""
        self._polling = False
        self._last = ""  # how the last read ended: "", "valid", "timeout", "error" (the status says it)
        self._task: asyncio.Task | None = None
        self.device: Slave | None = None
        self.master: Master | None = None

        if source is None:
            source = PowerMeter(unit=1, trial=1, live=True)
        if entries is None:
            entries = getattr(source, "register_map", None) or METER_MAP
        self.entries: tuple[MeterRegister, ...] = tuple(entries)
        groups = list(dict.fromkeys(e.unit for e in self.entries))

        # step None: the page's step is "any", so that every value from 0.01 s on is valid (a step of 0.5
        # from a minimum of 0.01 made the default, 1, invalid in the browser)
        self.interval = W.BoundedFloatText(value=interval, min=0.01, max=3600, step=None,
                                           description="interval (s)", style={"description_width": "80px"},
                                           layout=W.Layout(width="190px"))
        self.read_button = W.Button(description="read once", icon="download",
                                    layout=W.Layout(width="auto", flex="0 0 auto"),
                                    tooltip="read every quantity once (function 03)")
        self.start_button = W.Button(description="start", icon="play", button_style="primary",
                                     layout=W.Layout(width="auto", flex="0 0 auto"),
                                     tooltip="read every interval seconds")
        self.stop_button = W.Button(description="stop", icon="stop",
                                    layout=W.Layout(width="auto", flex="0 0 auto"),
                                    tooltip="stop reading")
        self.clear_button = W.Button(description="clear history", icon="trash",
                                     layout=W.Layout(width="auto", flex="0 0 auto"),
                                     tooltip="forget the readings plotted so far")
        self.plot_group = W.Dropdown(options=[(_group_title(g), g) for g in groups],
                                     value=plot if plot in groups else groups[0], description="plot",
                                     style={"description_width": "40px"}, layout=W.Layout(width="220px"))
        for b, css in ((self.read_button, "read"), (self.start_button, "start"), (self.stop_button, "stop"),
                       (self.clear_button, "clear")):
            b.add_class(f"mbe-md-{css}")
        self.status = W.HTML()
        # the table scrolls in its own view, which Tab reaches (ipywidgets 8.1 makes no Box tabbable)
        self.table = scroll_box(W.HTML(layout=W.Layout(flex="0 0 auto", max_height="420px", overflow="auto")),
                                "the last reading, one row per quantity (scrolls)")
        self.table.add_class("mbe-md-table")
        self.image = PlotImage("the trend plot (drawn after the first reading)", css="mbe-md-plot",
                               layout=W.Layout(max_width="100%"))
        self.plot_note = W.HTML()  # where matplotlib is missing: the one line that says so
        self.plot_note.add_class("mbe-md-plot-note")
        # tabs keep the panel within 700 px: the buttons and the plot are on screen together
        self.table_box = W.Box([self.table])
        self.tabs = W.Tab(children=[W.VBox([self.plot_note, self.image]), self.table_box],
                          titles=("trend", "values"))
        self.tabs.add_class("mbe-md-tabs")
        self.children = [
            W.HTML("<b>Power meter dashboard</b> &mdash; the meter's register map, read "
                   "with function 03"),
            self.message,
            W.HBox([self.interval, self.read_button, self.start_button, self.stop_button, self.plot_group,
                    self.clear_button], layout=W.Layout(flex_flow="row wrap", align_items="center")),
            self.status,
            self.tabs,
            panel_style(),
        ]
        g = guarded
        self.read_button.on_click(g(self.message, lambda _b: self.read_once()))
        self.start_button.on_click(g(self.message, lambda _b: self.start()))
        self.stop_button.on_click(g(self.message, lambda _b: self.stop()))
        focus_after_click(self.start_button, self.stop_button)
        focus_after_click(self.stop_button, self.start_button)
        self.clear_button.on_click(g(self.message, lambda _b: self.clear()))
        self.plot_group.observe(g(self.message, lambda _c: self._render_plot()), names="value")

        try:
            self._attach(source, unit, timeout)
        except ModbusError as exc:
            self.message.error(exc)
        self._render()

    # -- wiring ------------------------------------------------------------------------------------
    def _attach(self, source: Any, unit: int | None, timeout: float) -> None:
        if isinstance(source, Master):
            self.master = source
            self.unit = 1 if unit is None else unit
        elif isinstance(source, Slave):
            self.device = source
            self.unit = unit if unit is not None else (source.unit or 1)
            link = loopback_serial(source, baudrate=getattr(source, "BAUDRATE", 19200),
                                   parity=getattr(source, "PARITY", "N"),
                                   stopbits=getattr(source, "STOPBITS", 1))
            self.master = Master(link, timeout=timeout)
            self.message.show(f"reading {source.name} on a {link.description}")
        else:
            self.unit = 1
            raise ConfigError(f"MeterDashboard reads a meter device (a Slave such as PowerMeter) or through "
                              f"a Master; got {type(source).__name__}")

    @property
    def clock(self) -> Any:
        return self.master.clock if self.master is not None else None

    # -- reading -----------------------------------------------------------------------------------
    def read_once(self) -> dict[str, float] | None:
        """Read every quantity of the map once; returns the scaled values (``None`` after an error, which
        is counted and shown on the message line)."""
        if self.master is None:
            self.message.show("nothing to read: give the dashboard a meter or a Master", "error")
            return None
        self.counts["reads"] += 1
        t = self.master.clock.now
        try:
            values = read_meter(self.master, self.unit, self.entries)
        except ModbusTimeoutError as exc:
            self.counts["timeouts"] += 1
            self._last = "timeout"
            self.message.error(exc)
            self._render_status()
            return None
        except ModbusError as exc:
            self.counts["errors"] += 1
            self._last = "error"
            self.message.error(exc)
            self._render_status()
            return None
        self.counts["valid"] += 1
        self._last = "valid"
        self.values = values
        self.history.append((t, values))
        del self.history[:-self.max_history]
        self.message.show(f"read at t = {t:.3f} s", "ok")
        return values

    def run(self, n: int, render: bool = True) -> list[dict[str, float] | None]:
        """Read ``n`` times, one every ``interval`` seconds of the link's clock (instant on a virtual
        line)."""
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            self.message.error(ConfigError(f"run(n): n must be a whole number >= 0, got {shown(n)}"))
            return []
        out: list[dict[str, float] | None] = []
        if self.master is None:
            self.read_once()
            return out
        clock = self.master.clock
        start = clock.now
        for i in range(n):
            due = start + i * float(self.interval.value)
            if due > clock.now:
                clock.sleep(due - clock.now)
            out.append(self.read_once())
        if render:
            self._render()
        return out

    def start(self) -> bool:
        """Read every ``interval`` seconds on the kernel's asyncio loop until :meth:`stop`."""
        if self._polling:
            return True
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            self.message.show("periodic reading needs a running asyncio loop (a Jupyter kernel has one); "
                              "here, use run(n)", "error")
            return False
        self._polling = True
        self._task = loop.create_task(self._loop())
        self._render_status()
        return True

    async def _loop(self) -> None:
        clock = self.clock
        start, k = (clock.now if clock is not None else 0.0), 0
        try:
            while self._polling:
                if isinstance(clock, VirtualClock):
                    due = start + k * float(self.interval.value)
                    if due > clock.now:
                        clock.sleep(due - clock.now)
                self.read_once()
                self._render()
                k += 1
                await asyncio.sleep(float(self.interval.value))
        except Exception as exc:  # noqa: BLE001 - report, never die silently
            self.message.error(exc)
        finally:
            self._polling = False
            self._task = None
            self._render_status()

    def stop(self) -> None:
        self._polling = False
        if self._task is not None:
            self._task.cancel()
            self._task = None
        self._render_status()

    def clear(self) -> None:
        """Forget the readings (the counters too)."""
        self.history.clear()
        self.values = {}
        for key in self.counts:
            self.counts[key] = 0
        self._render()

    # -- views -----------------------------------------------------------------------------------------
    def series(self, name: str) -> tuple[list[float], list[float]]:
        """``(times, values)`` of one quantity over the history."""
        times = [t for t, v in self.history if name in v]
        return times, [v[name] for _t, v in self.history if name in v]

    def _render(self) -> None:
        self._render_status()
        self._render_table()
        self._render_plot()

    def _render_status(self) -> None:
        c = self.counts
        state = f"reading every {float(self.interval.value):g} s" if self._polling else "stopped"
        if self._last == "timeout":
            state += ", the last read timed out (no answer)"
        elif self._last == "error":
            state += ", the last read failed"
        self.status.value = (
            f'<div style="color:#495057">{state} &middot; reads <b>{c["reads"]}</b> &middot; '
            f'valid <b class="mbe-md-valid">{c["valid"]}</b> &middot; timeouts <b>{c["timeouts"]}</b>'
            f' &middot; errors <b>{c["errors"]}</b></div>')
        self.start_button.disabled = self._polling or self.master is None
        self.stop_button.disabled = not self._polling
        self.read_button.disabled = self._polling or self.master is None

    def _render_table(self) -> None:
        rows = []
        for e in self.entries:
            if e.name in self.values:
                value = self.values[e.name]
                shown = e.format(value)
                raw = " ".join(f"{r:04X}" for r in e.registers(value))
            else:
                shown, raw = "&ndash;", ""
            pad = "padding:1px 8px;white-space:nowrap"
            rows.append(f"<tr><td style=\"{pad}\">{esc(e.label)}</td>"
                        f"<td style=\"text-align:right;{MONO};{pad}\">{esc(shown)}</td>"
                        f"<td style=\"{MONO};color:#5c636a;{pad}\">{raw}</td>"
                        f"<td style=\"{pad}\">{esc(e.reference)}</td>"
                        f"<td style=\"{pad}\">{esc(e.raw_unit)}</td></tr>")
        self.table.value = (
            '<table style="border-collapse:collapse;font-size:0.9em;margin-right:12px">'
            "<tr><th>parameter</th><th>value</th><th>registers</th><th>reference</th><th>sent as</th></tr>"
            + "".join(rows) + "</table>")

    def _render_plot(self) -> None:
        """Draw the trend of the chosen group of quantities into a PNG (matplotlib, no pyplot state), in
        the course's plot style (:mod:`modbus_edu.plotstyle`: size, fonts, the legend beside the data).
        Without matplotlib (a browser that carries none) the trend tab says so in one line; the values
        tab works as before."""
        try:
            mpl = require_plotting("The dashboard's trend plot")
        except MissingDependencyError as exc:
            self.plot_note.value = esc(str(exc))
            return
        from ..plotstyle import HEIGHT, STYLE, WIDTH, Figure, legend_outside  # deferred: matplotlib, to plot

        group = self.plot_group.value
        members = [e for e in self.entries if e.unit == group]
        with mpl.rc_context(STYLE):
            fig = Figure(figsize=(WIDTH, HEIGHT), dpi=STYLE["figure.dpi"], layout="constrained")
            ax = fig.add_subplot(1, 1, 1)
            for e in members:
                times, values = self.series(e.name)
                if times:
                    ax.plot(times, values, label=e.name, linewidth=1.2,
                            marker="." if len(times) < 30 else None)
            ax.set_xlabel("time on the line's clock (s)")
            ax.set_ylabel(_group_title(group))
            ax.set_title(f"{_group_title(group)}: {len(self.history)} readings")
            if any(self.series(e.name)[0] for e in members):
                legend_outside(ax)
            ax.grid(True, alpha=0.3)
            buf = io.BytesIO()
            fig.savefig(buf, format="png")
        self.plot_png = buf.getvalue()
        self.image.show(self.plot_png, f"trend plot of {_group_title(group)} over {len(self.history)} "
                                       "readings (the values tab lists the last reading)")

    def table_rows(self, names: Sequence[str] | None = None) -> list[tuple[str, str]]:
        """``[(label, "403.6 V"), ...]``: the last reading as the power-meter paper's Table 6 prints it."""
        chosen = [e for e in self.entries if names is None or e.name in names]
        return [(e.label, e.format(self.values[e.name])) for e in chosen if e.name in self.values]

    def static_text(self) -> str:
        return "Meter dashboard panel: the power meter polled periodically, values and trends"

    def __repr__(self) -> str:
        return f"<MeterDashboard {len(self.entries)} values, counts={self.counts}>"
