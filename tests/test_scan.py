"""scan: finds simulated devices with their line settings, through a gateway too, within its budget."""

import modbus_edu as mb
from modbus_edu.scan import scan


def _devices():
    return [mb.Slave(unit=3, bank=mb.DataBank()), mb.Slave(unit=17, bank=mb.DataBank())]


def test_scan_finds_devices_and_their_settings():
    devices = _devices()

    def open_bus(baudrate, parity):
        # the devices are set to 19200 E; at other settings they hear only noise and stay silent
        listening = devices if (baudrate, parity) == (19200, "E") else []
        return mb.loopback_serial(listening, baudrate=baudrate, parity=parity)

    settings = [{"baudrate": b, "parity": p} for b in (9600, 19200) for p in ("N", "E")]
    report = scan(open_bus, range(1, 21), settings=settings, timeout=0.05)
    assert [(h.unit, h.settings) for h in report] == [
        (3, {"baudrate": 19200, "parity": "E"}),
        (17, {"baudrate": 19200, "parity": "E"}),
    ]
    assert report.complete and report.asked == 80


def test_scan_through_a_gateway_and_budget():
    bus = mb.loopback_serial(_devices(), baudrate=9600)
    with mb.TcpGateway(bus, timeout=0.05) as gw, mb.tcp_link(*gw.address) as tcp:
        report = scan(tcp, range(1, 20), timeout=2)
        assert [h.unit for h in report] == [3, 17]
    bus = mb.loopback_serial(_devices(), baudrate=9600)
    report = scan(bus, range(1, 248), timeout=0.1, budget=1.0)
    assert not report.complete and report.asked < 20


def test_cli_scan_over_tcp(capsys):
    from modbus_edu.cli import main

    with mb.TcpServer(_devices()) as server:
        host, port = server.address[:2]
        assert main(["scan", "--tcp", f"{host}:{port}", "--units", "1-20", "--timeout", "1"]) == 0
    out = capsys.readouterr().out
    assert "unit   3: register 0 = 0" in out and "unit  17" in out and "2 found, 20 asked" in out


def test_cli_gateway_needs_both_sides(capsys):
    from modbus_edu.cli import main

    assert main(["gateway", "--tcp", "127.0.0.1:0"]) == 1
    assert "needs both sides" in capsys.readouterr().err
