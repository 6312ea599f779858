"""The TestTool's wire: loopback partner, serial port or TCP; polling (master) and answering (slave)."""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any

from ... import pdu as _pdu
from ...clock import VirtualClock
from ...datamodel import Table
from ...errors import ConfigError, ModbusError, ModbusTimeoutError, shown
from ...links.browser_serial import browser_serial
from ...links.loopback import loopback_serial, loopback_tcp
from ...links.serial import SerialServer, serial_link
from ...links.tcp_client import tcp_link
from ...links.tcp_server import TcpServer
from ...master import Master
from ...master_steps import Steps, arun_steps, run_steps
from ...pdu import FunctionCode
from ...slave import Slave
from ..common import esc
from .controls import running_loop


class ConnectionMixin:
    """Connect, disconnect, poll (a master) or answer (a slave); the status line says which, now."""

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

    def connect(self, partner: ConnectionMixin | None = None) -> bool:
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

    def _connect(self, partner: ConnectionMixin | None) -> None:
        if partner is not None and not isinstance(partner, ConnectionMixin):
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
        elif kind == "browser":
            self._connect_browser()
        else:
            self._connect_tcp()

    def _connect_loopback(self, partner: ConnectionMixin) -> None:
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
        url = self.url.value.strip()
        settings = (self.baudrate.value, self.parity.value, self.stopbits.value)
        if self.is_master:
            link = serial_link(url, *settings, mode="rtu")
            self._use_link(link, f"connected: {link.description}")
        else:
            slave = self._slave_on_real_time()
            self.server = SerialServer(slave, url, *settings, mode="rtu").start()
            self._serving(f"serving unit {slave.unit} on {url}")

    def _connect_browser(self) -> None:
        """The browser's serial port (Web Serial): its *choose serial port* button shows under the
        settings; requests wait on the kernel's loop (polling is awaited there)."""
        settings = (self.baudrate.value, self.parity.value, self.stopbits.value)
        port = self._browser_port
        if port is None or port.closed or port.state in ("lost", "closed") or \
                (port.timing.baudrate, port.timing.parity, port.timing.stopbits) != settings:
            port = self._browser_port = browser_serial(*settings, mode="rtu")
        self.browser_box.children = (port.widget,) if hasattr(port.widget, "_repr_mimebundle_") else ()
        self.link = port
        self.master = Master(port, timeout=float(self.timeout.value),
                             transaction_id=self.transaction_id.value)
        if port.state in ("error", "unavailable"):  # no widget here, or no Web Serial in this browser
            self.message.show(f"{port.description}: {port.reason or port.state}", "warn")
            return
        opened = "the port is open" if port.state == "open" else "press 'choose serial port' below"
        self.message.show(f"connected: {port.description}; {opened}", "ok")

    def _connect_tcp(self) -> None:
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
        if self.link is not None and self.partner is None and self.link is not self._browser_port:
            with contextlib.suppress(Exception):  # the browser's port stays open for the next connect
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
        self.last_outcome = ""
        self._render_status()
        if not quiet:
            self.message.show("disconnected")

    def _render_status(self) -> None:
        """The status line says how things are now: not connected, connected (and whether the last
        exchange timed out or failed), or a slave that is connected but not answering."""
        on = self.connected
        colour = "#2b6e35" if on else "#c92a2a"
        text = "connected" if on else "not connected"
        if on and not self.is_master and not self._answering:
            colour, text = "#9c4a00", "connected, not answering"
        if on and self.partner is not None:
            text += f" to {esc(self.partner.label)}"
        if on and self.is_master and self.last_outcome == "timeout":
            colour, text = "#9c4a00", text + ", last request timed out (no answer)"
        elif on and self.is_master and self.last_outcome == "error":
            colour, text = "#9c4a00", text + ", last request failed"
        self.status.value = (f'<span class="mbe-tt-status mbe-tt-status-{"on" if on else "off"}" '
                             f'style="color:{colour};font-size:1.2em">&#9679;</span>'
                             f' <span class="mbe-tt-status-text" style="color:{colour}">{text}</span>')

    def _note_outcome(self, exc: BaseException | None) -> None:
        """Remember how the last exchange ended (the status line shows it) and say so on the message line."""
        if exc is None:
            self.last_outcome = "valid"
        else:
            self.last_outcome = "timeout" if isinstance(exc, ModbusTimeoutError) else "error"
            self.message.error(exc)

    def _clear_stale(self) -> None:
        """Traffic went by: an info or ok message about something earlier (say "auto fill stopped") no
        longer describes the present, so the message line empties.  Errors and warnings stay."""
        if self.message.kind in ("info", "ok"):
            self.message.clear()

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
        """Send one request with the chosen function (the robot test-tool paper's READ button); return the
        values.

        A read returns the values read (and fills the grid); a write sends the grid's values and returns
        them.  Errors (timeout, exception response, a bad setting) are counted, shown on the message
        line and returned as ``None``: nothing raises.
        """
        if not self._begin_poll():
            return None
        assert self.master is not None
        if getattr(self.master.link, "needs_await", False):  # the browser's port: wait on the loop
            loop = running_loop()
            if loop is None:
                self._end_poll(None, ConfigError("this link is waited for on an asyncio loop (a Jupyter "
                                                 "kernel has one): await tool.apoll_once()"))
                return None
            self._pending_poll = loop.create_task(self._apoll_begun())
            return None
        try:
            result = run_steps(self.master.link, self._transact_steps())
        except ModbusError as exc:
            return self._end_poll(None, exc)
        return self._end_poll(result, None)

    async def apoll_once(self) -> Any:
        """:meth:`poll_once`, awaited: the way to poll a link whose bytes come through the kernel's loop
        (the browser's serial port)."""
        if not self._begin_poll():
            return None
        return await self._apoll_begun()

    async def _apoll_begun(self) -> Any:
        assert self.master is not None
        try:
            result = await arun_steps(self.master.link, self._transact_steps())
        except ModbusError as exc:
            return self._end_poll(None, exc)
        return self._end_poll(result, None)

    def _begin_poll(self) -> bool:
        """Whether a poll can go out now (else the message line says why); count it."""
        if not self.is_master:
            self.message.show("a slave answers, it does not poll: poll from the master tool", "warn")
            return False
        if self.master is None:
            self.message.show("not connected: press connect (or give a partner)", "error")
            return False
        if self._autofill is not None:
            self._autofill.update(self.clock.now)
        self.counts["polls"] += 1
        return True

    def _end_poll(self, result: Any, exc: ModbusError | None) -> Any:
        """Count how the poll ended and say so; ``result`` is returned (None after an error)."""
        if isinstance(exc, ModbusTimeoutError):
            self.counts["timeouts"] += 1
            self._note_outcome(exc)
        elif exc is not None:
            self.counts["errors"] += 1
            self._note_outcome(exc)
        else:
            self.counts["valid"] += 1
            self._note_outcome(None)
            fc = FunctionCode(self.function.value)
            stats = self.master.stats if self.master is not None else None
            lat = stats.latencies[-1] * 1000 if stats is not None and stats.latencies else 0.0
            self.message.show(f"poll {self.counts['polls']}: {fc.title}, unit {self.unit.value}, "
                              f"{len(result)} value(s) from address {self.address.value} ({lat:.2f} ms)",
                              "ok")
        self.last_result = result
        self._after_exchange()
        return result

    read_once = poll_once

    def _transact_steps(self) -> Steps:
        """One exchange with the chosen function, as the master's steps (run blocking or awaited)."""
        master, fc = self.master, self.function.value
        assert master is not None
        unit, address, length = self.unit.value, self.address.value, self.length.value
        table = self.table

        def ask(request: Any) -> Steps:
            return master.execute_steps(unit, request, True)

        if fc in (1, 2, 3, 4):
            values = yield from master.read_steps(fc, unit, address, length)
            table.write(address, values)
            return values
        if fc == 5:
            value = table[address]
            yield from ask(_pdu.WriteSingleCoilRequest(address=address, value=value))
            return [value]
        if fc == 6:
            value = table[address]
            yield from ask(_pdu.WriteSingleRegisterRequest(address=address, value=value))
            return [value]
        if fc == 22:  # the register at the start address, with the grid's first two cells as AND, OR masks
            and_mask, or_mask = table.read(address, 2)
            yield from ask(_pdu.MaskWriteRegisterRequest(address, and_mask, or_mask))
            return [and_mask, or_mask]
        if fc == 23:  # write the grid's values, read the same registers back in the same transaction
            written = table.read(address, length)
            request = _pdu.ReadWriteMultipleRegistersRequest(address, length, address, written)
            values = list((yield from ask(request)).registers)
            table.write(address, values)
            return values
        if fc == 24:  # the queue behind the pointer at the start address: its values follow it
            values = list((yield from ask(_pdu.ReadFifoQueueRequest(address))).values)
            table.write(address + 1, values)
            return values
        values = table.read(address, length)
        if fc == 15:
            yield from ask(_pdu.WriteMultipleCoilsRequest(address=address, values=values))
        else:
            yield from ask(_pdu.WriteMultipleRegistersRequest(address=address, values=values))
        return values

    def run_polls(self, n: int) -> list:
        """Poll ``n`` times, one every ``interval`` seconds of the link's clock, and return the results.

        On a loopback wire the clock is virtual: it runs at once.  On a real link this blocks for
        about ``n * interval`` seconds (use *start* for polling in the background).
        """
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            self.message.error(ConfigError(f"run_polls(n): n must be a whole number >= 0, got {shown(n)}"))
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
        loop = running_loop()
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
                if getattr(self.master.link, "needs_await", False):
                    await self.apoll_once()  # the loop runs while the answer comes
                else:
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
        self.refresh()  # a loopback partner's slave redraws its own panel (TestTool.follow)

    # =====================================================================================================
    # the slave's hook and the real-time ticker
    # =====================================================================================================
    def _on_read(self, slave: Slave, table_kind: str, address: int, count: int) -> None:
        """Before the slave answers a read: let auto fill write the values of the current time."""
        if self._autofill is not None:
            self._autofill.update(slave.clock.now if slave.clock is not None else self.clock.now)

    def _start_ticker(self) -> None:
        """On a real wire, refresh the panel (and auto fill) a few times a second on the asyncio loop."""
        loop = running_loop()
        if loop is None or (self._tick_task is not None and not self._tick_task.done()):
            return
        self._tick_task = loop.create_task(self._tick_loop())

    async def _tick_loop(self) -> None:
        seen = self._requests_seen()
        try:
            while self.server is not None or (self._autofill is not None and self._autofill.running):
                if self._autofill is not None and self.link is None:
                    with self._lock():
                        self._autofill.update(self.clock.now)
                if self._requests_seen() != seen:  # requests came in: older info is not the present
                    seen = self._requests_seen()
                    self._clear_stale()
                self.refresh()
                await asyncio.sleep(0.5)
        except Exception as exc:  # noqa: BLE001
            self.message.error(exc)
        finally:
            self._tick_task = None

    def _requests_seen(self) -> int:
        """How many requests this tool's slave has received (0 without a slave)."""
        return self.slave.counters.as_dict().get("requests", 0) if self.slave is not None else 0

    def _lock(self) -> Any:
        lock = getattr(self.server, "lock", None)
        return lock if lock is not None else contextlib.nullcontext()

