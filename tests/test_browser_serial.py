"""The browser's serial port (mb.browser_serial) without a browser: the page's side is a stand-in that
hands the link what a page would (bytes in bursts, a lost port, no Web Serial), through the event loop
as a kernel's comm messages come, or from another thread as a script's would.

What is tested: frames cut by expected length before any silence, and by the silence when the length
cannot be known; a port unplugged mid-frame (a clear error at once, no hang); a wrong baud rate
(timeouts counted, said in one line); a blocking wait inside an event loop (refused at once, not a
deadlock) and from a thread (allowed); the master, the scanner and the test tool through it; the widget.
"""

from __future__ import annotations

import asyncio
import threading
import time

import pytest

import modbus_edu as mb
from modbus_edu.errors import ConfigError, LinkError, ModbusTimeoutError
from modbus_edu.links.browser_serial import BROWSER_LATENCY
from modbus_edu.links.webserial_port import NO_WEB_SERIAL, SCRIPT, make_port
from modbus_edu.links.wire import SerialTiming


def _slave(unit: int = 1) -> mb.Slave:
    slave = mb.Slave(unit=unit, bank=mb.DataBank())
    slave.bank.holding_registers[0:4] = [1234, 5678, 42, 7]
    return slave


def uart_misheard(data: bytes, sent_baud: int, heard_baud: int, parity: str = "E") -> bytes:
    """What a UART at ``heard_baud`` makes of ``data`` sent at ``sent_baud`` (8 data bits, ``parity``,
    1 stop bit): it waits for a start bit, samples 8 data bits in their middles at its own rate, and
    skips its own frame's length. A wrong baud rate turns a device's answer into this."""
    bits: list[int] = [1] * 4
    for byte in data:
        data_bits = [(byte >> i) & 1 for i in range(8)]
        bits += [0, *data_bits] + ([sum(data_bits) % 2] if parity in "EO" else []) + [1]
    bits += [1] * 24
    ratio = sent_baud / heard_baud  # one heard bit, in sent bits
    char = 10 + (1 if parity in "EO" else 0)
    out, t, n = bytearray(), 0.0, len(bits)
    while t < n:
        if bits[int(t)] == 0:
            samples = [bits[min(n - 1, int(t + (k + 0.5) * ratio))] for k in range(1, 9)]
            out.append(sum(bit << i for i, bit in enumerate(samples)))
            t += ratio * char
        else:
            t += ratio / 16
    return bytes(out)


class StandInPage:
    """The page's side of the link: what is written goes to ``slave``; its answer comes back in
    ``chunks`` (sizes) ``gap`` seconds apart, through the running event loop (as comm messages reach a
    kernel) or, with ``thread=True``, from another thread."""

    def __init__(self, slave: mb.Slave | None, *, chunks: tuple[int, ...] = (3, 4), gap: float = 0.01,
                 thread: bool = False, mode: str = "rtu", garble: bool = False) -> None:
        self.slave, self.chunks, self.gap, self.thread, self.mode = slave, chunks, gap, thread, mode
        self.garble = garble
        self.written: list[bytes] = []
        self.closed = False
        self.deliver = None

    def listen(self, deliver) -> None:
        self.deliver = deliver
        deliver({"type": "opened", "info": {"usbVendorId": 0x0403}})

    def write(self, data: bytes) -> None:
        self.written.append(data)
        answer = self.slave.handle(data, self.mode) if self.slave is not None else None
        if not answer:
            return
        if self.garble:  # the device answers at 19200 baud, the port listens at 9600
            answer = uart_misheard(answer, 19200, 9600)
        pieces, at = [], 0
        for size in self.chunks:
            pieces.append(answer[at:at + size])
            at += size
        pieces.append(answer[at:])
        self.later([{"type": "data", "hex": piece.hex()} for piece in pieces if piece])

    def later(self, messages: list[dict]) -> None:
        """Deliver ``messages`` one every ``gap`` seconds."""
        if self.thread:
            def run() -> None:
                for message in messages:
                    time.sleep(self.gap)
                    self.deliver(message)
            threading.Thread(target=run, daemon=True).start()
            return
        loop = asyncio.get_running_loop()
        for i, message in enumerate(messages, start=1):
            loop.call_later(self.gap * i, self.deliver, message)

    def close(self) -> None:
        self.closed = True


def _link(page: StandInPage, **kwargs) -> mb.BrowserSerialLink:
    return mb.browser_serial(9600, "E", port=page, **kwargs)


# -- framing ------------------------------------------------------------------------------------------
def test_a_frame_is_cut_by_its_expected_length_before_any_silence() -> None:
    async def main() -> tuple[list[int], float, float]:
        page = StandInPage(_slave(), chunks=(2, 3, 2), gap=0.02)
        link = _link(page)
        master = mb.Master(link, timeout=2.0)
        start = time.monotonic()
        values = await master.aread_holding_registers(unit=1, address=0, count=2)
        return values, time.monotonic() - start, link.frame_gap

    values, took, gap = asyncio.run(main())
    assert values == [1234, 5678]
    # four bursts 20 ms apart: the frame is complete after the last one, and is taken then - well before
    # a silence of frame_gap (t3.5 + 250 ms) could have ended it
    assert gap == pytest.approx(3.5 * 11 / 9600 + BROWSER_LATENCY)
    assert took < 0.08 + gap / 2


def test_a_frame_of_unknown_length_ends_at_the_silence_and_a_broken_one_is_dropped() -> None:
    body = bytes([1, 0x41, 0x10, 0x20])  # function 0x41: no length rule known, the CRC checks
    frame = body + mb.crc16(body).to_bytes(2, "little")

    async def main() -> tuple:
        page = StandInPage(None)
        link = _link(page, latency=0.05)
        page.later([{"type": "data", "hex": frame.hex()}])
        start = time.monotonic()
        got = await link.areceive(2.0)
        waited = time.monotonic() - start
        page.later([{"type": "data", "hex": "0103040001"}])  # a frame cut short
        start = time.monotonic()
        nothing = await link.areceive(0.4)
        return got, waited, nothing, time.monotonic() - start, link

    got, waited, nothing, waited2, link = asyncio.run(main())
    assert got == frame
    assert link.frame_gap <= waited < link.frame_gap + 0.2  # not before the silence, not much after
    assert nothing is None and 0.4 <= waited2 < 0.6  # the absolute deadline
    assert link.discarded == 5 and link.timeouts == 1


def test_ascii_frames_through_the_port() -> None:
    async def main() -> list[int]:
        page = StandInPage(_slave(), chunks=(5, 5), mode="ascii")
        master = mb.Master(mb.browser_serial(9600, "E", mode="ascii", port=page), timeout=2.0)
        return await master.aread_holding_registers(unit=1, address=2, count=2)

    assert asyncio.run(main()) == [42, 7]


# -- what goes wrong ----------------------------------------------------------------------------------
def test_a_port_unplugged_mid_frame_ends_the_wait_at_once_with_what_had_come() -> None:
    class Unplugged(StandInPage):
        def write(self, data: bytes) -> None:
            self.written.append(data)
            self.later([{"type": "data", "hex": "010304"},
                        {"type": "lost", "reason": "The device has been lost."}])

    async def main() -> tuple[BaseException, float, mb.Master]:
        master = mb.Master(_link(Unplugged(_slave())), timeout=5.0)
        start = time.monotonic()
        with pytest.raises(LinkError) as caught:
            await master.aread_holding_registers(unit=1, address=0, count=2)
        return caught.value, time.monotonic() - start, master

    error, took, master = asyncio.run(main())
    assert took < 0.5  # not the 5 s timeout
    text = str(error)
    assert "lost" in text and "3 byte(s) had come (01 03 04)" in text and "choose the port again" in text
    with pytest.raises(LinkError, match="lost"):  # and the next request says so before sending
        asyncio.run(master.aread_holding_registers(unit=1, address=0, count=2))


def test_a_wrong_baud_rate_counts_timeouts_and_says_so_in_one_line() -> None:
    assert uart_misheard(b"\x01\x03\x04", 9600, 9600) == b"\x01\x03\x04"  # the model of a UART is right

    async def main() -> tuple[mb.Master, mb.BrowserSerialLink, list[str]]:
        link = _link(StandInPage(_slave(), garble=True), latency=0.02)
        master = mb.Master(link, timeout=0.3)
        errors = []
        for _ in range(3):
            with pytest.raises(ModbusTimeoutError) as caught:
                await master.aread_holding_registers(unit=1, address=0, count=2)
            errors.append(str(caught.value))
        return master, link, errors

    master, link, errors = asyncio.run(main())
    assert master.stats.timeouts == 3 and link.timeouts == 3 and master.stats.valid_responses == 0
    line = link.summary()
    assert "\n" not in line and "3 timeouts" in line
    assert "made no frame" in line and "9600 baud 8E1" in line and "check the baud rate" in line
    assert "check the baud rate" in errors[-1]


def test_without_web_serial_a_request_says_chrome_or_edge_in_one_line() -> None:
    class NoWebSerial(StandInPage):
        def listen(self, deliver) -> None:
            deliver({"type": "unavailable", "reason": "no navigator.serial"})

    master = mb.Master(_link(NoWebSerial(_slave())), timeout=1.0)
    with pytest.raises(LinkError) as caught:
        asyncio.run(master.aread_holding_registers(unit=1, address=0, count=1))
    assert str(caught.value) == NO_WEB_SERIAL and "Chrome or Edge" in NO_WEB_SERIAL


def test_before_a_port_is_chosen_a_request_says_what_to_click() -> None:
    class Waiting(StandInPage):
        def listen(self, deliver) -> None:
            deliver({"type": "ready"})

    with pytest.raises(LinkError, match="no serial port chosen yet.*choose serial port"):
        mb.Master(_link(Waiting(_slave()))).write_single_register(unit=1, address=0, value=1)


# -- no deadlock -----------------------------------------------------------------------------------------
def test_a_blocking_call_inside_an_event_loop_is_refused_at_once_not_a_hang() -> None:
    """Inside a kernel the page's bytes come through the loop a blocking call would stop: it says to
    await, at once, instead of waiting out its timeout for bytes that cannot come."""

    async def main() -> tuple[BaseException, float, list[int]]:
        master = mb.Master(_link(StandInPage(_slave())), timeout=5.0)
        start = time.monotonic()
        with pytest.raises(LinkError) as caught:
            master.read_holding_registers(unit=1, address=0, count=1)
        took = time.monotonic() - start
        # awaited on the same loop, the same request is answered
        return caught.value, took, await master.aread_holding_registers(unit=1, address=0, count=1)

    error, took, values = asyncio.run(main())
    assert took < 0.5 and "await master.aread_holding_registers" in str(error)
    assert values == [1234]


def test_a_blocking_call_inside_an_event_loop_sends_nothing() -> None:
    page = StandInPage(_slave())

    async def main() -> mb.Master:
        master = mb.Master(_link(page), timeout=5.0)
        with pytest.raises(LinkError, match="await"):
            master.write_single_register(unit=1, address=0, value=7)
        return master

    master = asyncio.run(main())
    assert page.written == [] and master.stats.requests == 0


def test_a_script_outside_any_loop_may_block_while_the_page_answers_from_another_thread() -> None:
    master = mb.Master(_link(StandInPage(_slave(), thread=True)), timeout=2.0)
    master.write_multiple_registers(unit=1, address=10, values=[11, 22])
    assert master.read_holding_registers(unit=1, address=10, count=2) == [11, 22]
    assert master.stats.valid_responses == 2


def test_every_wait_ends_at_its_deadline_while_bytes_keep_coming() -> None:
    """A babbling line (junk every 10 ms) never lets a silence end anything: the wait still ends."""

    async def main() -> float:
        page = StandInPage(None, gap=0.01)
        link = _link(page, latency=0.05)
        page.later([{"type": "data", "hex": "ff"}] * 100)
        start = time.monotonic()
        assert await link.areceive(0.3) is None
        return time.monotonic() - start

    assert 0.3 <= asyncio.run(main()) < 0.5


# -- the master's other calls, the scanner, the test tool -----------------------------------------------
def test_awaited_and_blocking_calls_count_alike() -> None:
    async def main() -> mb.Master:
        master = mb.Master(_link(StandInPage(_slave())), timeout=1.0, retries=1)
        await master.awrite_single_register(unit=1, address=5, value=99)
        await master.awrite_single_coil(unit=1, address=3, value=True)
        await master.awrite_multiple_coils(unit=1, address=8, values=[True, False, True])
        assert await master.aread_coils(unit=1, address=8, count=3) == [True, False, True]
        assert await master.aread_input_registers(unit=1, address=0, count=1) == [0]
        assert await master.aread_discrete_inputs(unit=1, address=0, count=2) == [False, False]
        assert await master.aread_holding_registers(unit=1, address=5, count=1) == [99]
        with pytest.raises(mb.ModbusExceptionError):
            await master.aexecute(1, mb.ReadFifoQueueRequest(0))  # a count of 1234: over 31, exception 03
        return master

    master = asyncio.run(main())
    assert master.stats.requests == 8 and master.stats.valid_responses == 7 and master.stats.exceptions == 1
    assert [entry.direction for entry in master.log][:2] == ["tx", "rx"]


def test_the_scanner_finds_the_unit_behind_the_browser_port() -> None:
    class Bus(StandInPage):
        def write(self, data: bytes) -> None:
            if data[0] == self.slave.unit:
                super().write(data)

    report = asyncio.run(mb.ascan(_link(Bus(_slave(unit=3))), range(1, 6), timeout=0.1, budget=5))
    assert [hit.unit for hit in report] == [3] and report.asked == 5 and report.complete
    assert report.hits[0].answer == "register 0 = 1234"


def test_the_test_tool_polls_the_browser_port_on_the_loop() -> None:
    from modbus_edu.widgets import TestTool

    async def main() -> tuple:
        tool = TestTool("rtu_master")
        assert "browser" in [value for _, value in tool.connection.options]
        tool.baudrate.value, tool.parity.value = 9600, "E"
        tool._browser_port = _link(StandInPage(_slave()))  # the page's stand-in instead of the widget
        tool.connection.value = "browser"
        assert tool.connect() and tool.master.link is tool._browser_port
        tool.length.value = 3
        first = await tool.apoll_once()
        assert tool.poll_once() is None  # a button's click: the poll runs on the loop
        second = await tool._pending_poll
        tool.continuous.value = False
        assert tool.start()  # the panel's start: polls as a task on the loop, each awaited
        await tool._poll_task
        tool.function.value = 6
        tool.bank.holding_registers[0] = 4321
        await tool.apoll_once()
        return first, second, dict(tool.counts), tool

    first, second, counts, tool = asyncio.run(main())
    assert first == second == [1234, 5678, 42]
    assert counts["polls"] == 4 and counts["valid"] == 4
    assert tool.master.link.port.written[-1][:2] == b"\x01\x06"


# -- the widget -------------------------------------------------------------------------------------------
def test_the_widget_carries_the_line_settings_and_the_page_messages() -> None:
    port = make_port(SerialTiming(baudrate=19200, parity="O", stopbits=2, bytesize=8, mode="rtu"))
    assert (port.baudrate, port.parity, port.stopbits, port.databits) == (19200, "odd", 2, 8)
    link = mb.browser_serial(9600, "N")
    link.port._from_page(None, {"type": "opened", "info": {}}, [])
    assert link.state == "open"
    link.port._from_page(None, {"type": "data", "hex": "0103"}, [])
    assert link.bytes_in == 2
    script = SCRIPT.read_text()
    for needed in ("navigator.serial.requestPort", "port.open", "getReader", "getWriter", "msg:custom",
                   "no_web_serial", '"lost"'):
        assert needed in script
    with pytest.raises(ConfigError, match="1 or 2 stop bits"):
        mb.browser_serial(9600, "N", stopbits=1.5)


def test_without_anywidget_a_request_says_why_in_one_line(monkeypatch) -> None:
    from modbus_edu.links import webserial_port

    def missing() -> type:
        raise mb.errors.MissingDependencyError("the browser's serial port needs anywidget, absent here")

    monkeypatch.setattr(webserial_port, "port_class", missing)
    link = mb.browser_serial(9600, "E")
    with pytest.raises(LinkError) as caught:
        asyncio.run(mb.Master(link).aread_holding_registers(unit=1, address=0, count=1))
    assert "\n" not in str(caught.value) and "needs anywidget" in str(caught.value)
    assert "text/html" in link._repr_mimebundle_()


def test_an_older_ipykernel_is_named_when_nothing_reached_the_kernel(monkeypatch) -> None:
    """ipykernel before 7.4 handles comm messages only between cells: an awaited call there times out,
    and its message says why and what works instead."""
    import sys
    import types

    class Silent(StandInPage):
        def write(self, data: bytes) -> None:
            self.written.append(data)

    monkeypatch.setitem(sys.modules, "ipykernel", types.SimpleNamespace(__version__="7.3.0"))
    master = mb.Master(_link(Silent(_slave())), timeout=0.1)
    with pytest.raises(ModbusTimeoutError, match="ipykernel 7.3.0 handles the page's messages only between"):
        asyncio.run(master.aread_holding_registers(unit=1, address=0, count=1))
    monkeypatch.setitem(sys.modules, "ipykernel", types.SimpleNamespace(__version__="7.4.0"))
    with pytest.raises(ModbusTimeoutError, match="nothing came back at all: check the unit id"):
        asyncio.run(master.aread_holding_registers(unit=1, address=0, count=1))


def test_in_jupyterlite_the_message_says_the_page_s_bytes_arrive_between_cells(monkeypatch) -> None:
    """JupyterLite's Pyodide kernel, like an old ipykernel, hands the page's messages to the kernel only
    between cells: an awaited call times out there, and its message names the kernel and what works
    (a task started in one cell, read in the next), not the wiring."""
    from modbus_edu import platform

    class Silent(StandInPage):
        def write(self, data: bytes) -> None:
            self.written.append(data)

    monkeypatch.setattr(platform, "IN_BROWSER", True)
    master = mb.Master(_link(Silent(_slave())), timeout=0.1)
    with pytest.raises(ModbusTimeoutError) as caught:
        asyncio.run(master.aread_holding_registers(unit=1, address=0, count=1))
    message = str(caught.value)
    assert "JupyterLite's Pyodide kernel handles the page's messages only between cells" in message
    assert "asyncio.ensure_future" in message and "task.result() in the next" in message
    assert "wiring" not in message and "ipykernel 7.4" not in message
