"""The library in a browser (Pyodide), simulated on CPython: sockets refuse with a BrowserError that
teaches, the serial module imports with Pyodide's stand-in termios, and a build exercise keeps its time
limit where no thread can start."""

from __future__ import annotations

import importlib.util
import sys
import threading
import time
import types
from pathlib import Path

import pytest
from pymodbus.simulator import DataType, SimData, SimDevice

import modbus_edu as mb
from modbus_edu import exercises, platform
from modbus_edu.exercises import misconceptions
from modbus_edu.exercises.build import build_exercise
from modbus_edu.exercises.calls import run_within
from modbus_edu.interop import pymodbus_server


@pytest.fixture
def in_browser(monkeypatch):
    monkeypatch.setattr(platform, "IN_BROWSER", True)


def _pymodbus_server():
    device = SimDevice(id=1, simdata=[SimData(0, values=[1], datatype=DataType.REGISTERS)])
    with pymodbus_server(device):
        pass


@pytest.mark.parametrize("what, start", [
    ("TcpServer", lambda: mb.TcpServer(mb.Slave(unit=1), host="0.0.0.0")),  # 127.0.0.1: in the page
    ("UdpServer", lambda: mb.UdpServer(mb.Slave(unit=1))),
    ("tcp_link", lambda: mb.tcp_link("192.0.2.10", 502)),  # a device: 127.0.0.1 reaches the page's servers
    ("udp_link", lambda: mb.udp_link("127.0.0.1", 502)),
    ("pymodbus_server", _pymodbus_server),
    ("TcpGateway", lambda: mb.TcpGateway(mb.loopback_serial())),
])
def test_in_a_browser_every_socket_refuses_and_says_where_it_works(in_browser, what, start):
    with pytest.raises(mb.BrowserError) as caught:
        start()
    message = str(caught.value)
    assert isinstance(caught.value, mb.ModbusError)
    assert what in message and "local Python or Binder" in message and "mybinder.org" in message
    assert "cannot listen on a socket" in message


def test_outside_a_browser_nothing_changes():
    assert platform.IN_BROWSER is (sys.platform == "emscripten") is False
    platform.require_sockets("anything")  # returns
    with mb.TcpServer(mb.Slave(unit=1)) as server:
        assert server.address[0] == "127.0.0.1"


def test_the_serial_module_imports_with_a_termios_that_has_no_error(monkeypatch):
    """Pyodide's stand-in termios has no termios.error: the serial link imports, refusing nothing."""
    monkeypatch.setitem(sys.modules, "termios", types.ModuleType("termios"))
    path = Path(mb.__file__).parent / "links" / "serial.py"
    spec = importlib.util.spec_from_file_location("modbus_edu.links._serial_in_browser", path)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)
    spec.loader.exec_module(module)
    assert module._OS_REFUSALS == ()
    assert module.open_serial is not None


@pytest.fixture
def crc_exercise():
    item = build_exercise("99.9", "a CRC function", reference=mb.crc16,
                          inputs=lambda rng: (rng.randbytes(rng.randrange(0, 40)),),
                          edge_cases=[(b"",), (b"123456789",)], hint="shift right, XOR 0xA001",
                          wrong=lambda data: 0)
    yield item
    del exercises.EXERCISES["99.9"]


@pytest.fixture
def no_threads(monkeypatch):
    """Thread.start raises as in Pyodide: "can't start new thread"."""
    def start(self):
        raise RuntimeError("can't start new thread")

    monkeypatch.setattr(threading.Thread, "start", start)


def test_without_threads_a_right_function_is_accepted(no_threads, crc_exercise):
    result = exercises.evaluate("99.9", misconceptions.crc16_reflected)
    assert result.ok is True, result.message


def test_without_threads_a_wrong_function_shows_the_failing_input(no_threads, crc_exercise):
    result = exercises.evaluate("99.9", lambda data: 0)
    assert result.ok is False and "should give 65535 (0xFFFF)" in result.message


def test_without_threads_an_endless_loop_is_stopped_at_the_time_limit(no_threads, crc_exercise):
    def forever(data):
        while True:
            pass

    start = time.monotonic()
    result = exercises.evaluate("99.9", forever)
    elapsed = time.monotonic() - start
    assert result.ok is False and "did not finish within 2 s" in result.message, result.message
    assert 2.0 <= elapsed < 3.0
    assert sys.gettrace() is None  # the trace function is gone: the notebook runs at full speed again


def test_without_threads_the_previous_trace_function_is_restored(no_threads):
    def tracer(frame, event, arg):
        return None

    sys.settrace(tracer)
    try:
        assert run_within(lambda: None, 1.0) is True
        assert sys.gettrace() is tracer
    finally:
        sys.settrace(None)


def test_under_emscripten_no_thread_is_tried(monkeypatch):
    monkeypatch.setattr(sys, "platform", "emscripten")
    started = []
    monkeypatch.setattr(threading.Thread, "start", lambda self: started.append(self))
    assert run_within(lambda: None, 1.0) is True
    assert started == []


def test_in_a_browser_without_scapy_a_capture_stops_in_one_line(monkeypatch):
    import builtins

    from modbus_edu import capture
    from modbus_edu.errors import MissingDependencyError

    real_import = builtins.__import__

    def no_scapy(name, *args, **kwargs):
        if name.startswith("scapy"):
            raise ImportError(f"no module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(capture, "IN_BROWSER", True)
    monkeypatch.setattr(capture, "_SCAPY", None)
    monkeypatch.setattr(builtins, "__import__", no_scapy)
    with pytest.raises(MissingDependencyError) as caught:
        capture._scapy()
    assert caught.value._render_traceback_() == [f"MissingDependencyError: {caught.value}"]
    assert "local Python or Binder" in str(caught.value) and "scapy" in str(caught.value)
