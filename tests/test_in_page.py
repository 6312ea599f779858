"""Modbus/TCP between the roles of one notebook in a browser (modbus_edu.links.in_page), simulated on
CPython: a TcpServer on 127.0.0.1 and a tcp_link to it meet in memory, as notebook 12 needs in the Lite
site; a real host, TLS, or a port where nothing listens still refuse, in one line."""

from __future__ import annotations

import pytest

import modbus_edu as mb
from modbus_edu import platform
from modbus_edu.devices import PowerMeter
from modbus_edu.links import in_page
from modbus_edu.widgets import TestTool


@pytest.fixture
def in_browser(monkeypatch):
    monkeypatch.setattr(platform, "IN_BROWSER", True)
    monkeypatch.setattr(in_page, "_LISTENING", {})  # a fresh kernel's port table


def test_a_server_and_a_link_of_one_page_meet_in_memory(in_browser):
    meter = PowerMeter(unit=1, trial=1)
    server = mb.TcpServer(meter, host="127.0.0.1", port=0).start()
    assert isinstance(server, in_page.InPageTcpServer)
    assert server.address == ("127.0.0.1", in_page.FIRST_FREE_PORT)
    with mb.tcp_link(*server.address) as link:
        master = mb.Master(link)
        direct = mb.Master(mb.loopback_tcp(PowerMeter(unit=1, trial=1)))
        expected = direct.read_holding_registers(unit=1, address=0, count=4)
        assert master.read_holding_registers(unit=1, address=0, count=4) == expected
        with pytest.raises(mb.ModbusExceptionError) as refused:  # the meter's own answer, through the page
            master.write_single_register(unit=1, address=0, value=1234)
        assert refused.value.code == 1
        assert "inside this page" in link.description
    counters = server.counters
    assert (counters.connections, counters.requests, counters.responses) == (1, 2, 2)
    second = mb.TcpServer(mb.Slave(unit=2)).start()  # the next free port, as a system would give
    assert second.address[1] == in_page.FIRST_FREE_PORT + 1
    with pytest.raises(mb.LinkError, match="already listens there"):
        mb.TcpServer(mb.Slave(unit=3), port=second.address[1]).start()
    server.close()
    second.close()
    assert in_page._LISTENING == {}


def test_closing_the_server_resets_its_clients_and_frees_the_port(in_browser):
    with mb.TcpServer(mb.Slave(unit=1), host="localhost", port=5020) as server:
        link = mb.tcp_link("127.0.0.1", 5020)
        assert server.connection_count == 1
    with pytest.raises(mb.LinkError, match="closed"):
        link.send(bytes.fromhex("0001 0000 0006 01 03 0000 0001"))
    with pytest.raises(mb.LinkError, match="connection refused") as caught:
        mb.tcp_link("127.0.0.1", 5020)
    assert "\n" not in str(caught.value)


def test_the_test_tool_connects_to_a_server_of_the_same_page_as_notebook_12_does(in_browser):
    server = mb.TcpServer(PowerMeter(unit=1, trial=1), host="127.0.0.1", port=0).start()
    host, port = server.address
    tester = TestTool("tcp_client", connection="tcp", host=host, port=port, unit=1, address=0, length=4,
                      function=3)
    assert tester.connect(), tester.message.text
    for _ in range(3):
        tester.poll_once()
    assert tester.counts["valid"] == 3 and server.counters.responses == 3
    device = TestTool("tcp_server", connection="tcp", host="127.0.0.1", port=0, unit=1, length=2)
    assert device.connect(), device.message.text
    assert device.port.value == in_page.FIRST_FREE_PORT + 1
    tester.disconnect()
    device.disconnect()
    server.close()


@pytest.mark.parametrize("start, said", [
    (lambda: mb.TcpServer(mb.Slave(unit=1), host="0.0.0.0"), "TcpServer"),
    (lambda: mb.tcp_link("192.0.2.10", 502), "tcp_link"),
    (lambda: mb.tcp_link("127.0.0.1", 802, tls=object()), "TLS"),
    (lambda: mb.TcpServer(mb.Slave(unit=1), framing="rtu"), "framing='rtu'"),
])
def test_what_a_page_cannot_do_still_refuses_in_one_line(in_browser, start, said):
    with pytest.raises(mb.BrowserError) as caught:
        start()
    message = str(caught.value)
    assert said in message and "local Python or Binder" in message and "\n" not in message


def test_outside_a_browser_tcp_server_is_the_real_one():
    with mb.TcpServer(mb.Slave(unit=1)) as server:
        assert type(server) is mb.TcpServer and server.address[1] != 0
