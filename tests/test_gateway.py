"""TcpGateway: pymodbus's TCP client reads and writes two slaves on a loopback serial bus through it,
gets 0x0B for an absent unit after the gateway's timeout, and 10 clients at once get their own replies."""

import select
import socket
import threading
import time

from pymodbus.client import ModbusTcpClient

import modbus_edu as mb

HOST = "127.0.0.1"


def _bus():
    a, b = mb.Slave(unit=1, bank=mb.DataBank()), mb.Slave(unit=2, bank=mb.DataBank())
    a.bank.holding_registers[0:3] = [11, 12, 13]
    b.bank.holding_registers[0:3] = [21, 22, 23]
    return mb.loopback_serial([a, b], baudrate=9600), a, b


def test_pymodbus_client_through_gateway():
    bus, a, b = _bus()
    with mb.TcpGateway(bus, timeout=0.2) as gw:
        client = ModbusTcpClient(HOST, port=gw.address[1], timeout=5, retries=0)
        assert client.connect()
        try:
            assert client.read_holding_registers(0, count=3, device_id=1).registers == [11, 12, 13]
            assert client.read_holding_registers(0, count=3, device_id=2).registers == [21, 22, 23]
            assert not client.write_register(7, 0xBEEF, device_id=2).isError()
            assert b.bank.holding_registers[7] == 0xBEEF
            start = bus.clock.now
            r = client.read_holding_registers(0, count=1, device_id=9)
            assert r.isError() and r.exception_code == 0x0B
            # the absent unit costs the request's 8 characters on the line, then the gateway's timeout
            # (it starts when the request has left, as a serial master's response timeout does)
            assert abs((bus.clock.now - start) - (8 * 10 / 9600 + 0.2)) < 1e-9
            r = client.read_holding_registers(0, count=1, device_id=0)
            assert r.isError() and r.exception_code == 0x0A
            r = client.read_holding_registers(65535, count=2, device_id=1)  # the slave's own exception 02
            assert r.isError() and r.exception_code == 0x02
        finally:
            client.close()
    assert gw.counters["no_response"] == 1 and gw.counters["path_unavailable"] == 1


def test_round_trip_on_the_virtual_wire_matches_the_arithmetic():
    bus, _, _ = _bus()
    with mb.TcpGateway(bus) as gw, mb.tcp_link(*gw.address) as tcp:
        master = mb.Master(tcp, timeout=5)
        master.read_holding_registers(unit=1, address=0, count=1)
        t0 = bus.clock.now
        master.read_holding_registers(unit=1, address=0, count=1)
        # (8 + 3.5 + 7 + 3.5) characters of 10 bits at 9600 baud = 22.92 ms
        assert abs((bus.clock.now - t0) - 22 * 10 / 9600) < 1e-6


def test_ten_clients_get_their_own_replies():
    bus, a, b = _bus()
    for i in range(10):
        a.bank.holding_registers[100 + i] = 1000 + i
        b.bank.holding_registers[100 + i] = 2000 + i
    errors = []
    with mb.TcpGateway(bus, timeout=0.2) as gw:

        def client(i):
            try:
                with mb.tcp_link(*gw.address) as tcp:
                    m = mb.Master(tcp, timeout=10, transaction_id=i * 1000)
                    for k in range(20):
                        unit = 1 + (i + k) % 2
                        got = m.read_holding_registers(unit=unit, address=100 + i, count=1)
                        if got != [unit * 1000 + i]:
                            errors.append((i, k, unit, got))
            except Exception as exc:  # pragma: no cover - reported below
                errors.append((i, repr(exc)))

        threads = [threading.Thread(target=client, args=(i,)) for i in range(10)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(timeout=60)
    assert errors == []
    assert gw.counters["forwarded"] == 200


# ------------------------------------------------------------------------------------------------------
# isolation: a late answer reaches nobody, a dead unit stalls nobody, the queues are bounded
# ------------------------------------------------------------------------------------------------------
REQUEST_AIRTIME = 8 * 10 / 9600  # an FC 3 request, 8 characters at 9600 baud 8N1


def _ask(gw, unit, address, timeout=10):
    """One read through the gateway on a connection of its own: the value, or the exception code."""
    with mb.tcp_link(*gw.address) as tcp:
        try:
            return mb.Master(tcp, timeout=timeout).read_holding_registers(unit=unit, address=address, count=1)
        except mb.ModbusExceptionError as exc:
            return exc.code


def _slow_bus(slave):
    slave.bank.holding_registers[0:3] = [2000, 2100, 2200]
    return mb.loopback_serial([mb.Slave(unit=1), slave], baudrate=9600)


class _SlowOnce(mb.Slave):
    """A slave whose first answer takes longer than the gateway waits; the others come at once."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.delays = [0.25]

    def response_delay(self, arrival_time):
        return self.delays.pop() if self.delays else 0.0


def test_a_late_answer_reaches_nobody():
    # unit 2 answers A (register 0, 2000) after the gateway gave up; B asks for register 1 next
    bus = _slow_bus(_SlowOnce(unit=2, bank=mb.DataBank()))
    with mb.TcpGateway(bus, timeout=0.2) as gw:
        assert _ask(gw, 2, 0) == 0x0B  # A
        assert _ask(gw, 2, 1) == [2100]  # B reads its own register, never A's 2000
        assert gw.counters["late"] == 1 and gw.counters["no_response"] == 1


def test_a_slave_slower_than_the_timeout_never_answers_the_wrong_request():
    slave = mb.Slave(unit=2, bank=mb.DataBank(), processing_time=0.25)
    bus = _slow_bus(slave)
    with mb.TcpGateway(bus, timeout=0.2) as gw:
        assert _ask(gw, 2, 0) == 0x0B  # A: its answer (2000) comes 0.25 s after the request
        assert _ask(gw, 2, 1) == 0x0B  # B: 0B, because the slave is too slow for B too - but never 2000
        slave.processing_time = 0.0
        assert _ask(gw, 2, 2) == [2200]  # C after the slave has recovered: its own, not B's late 2100
        assert _ask(gw, 1, 0) == [0]
        assert gw.counters["late"] == 2
    # without the late window, the same bus gives B the answer to A: what the window is for
    slave = mb.Slave(unit=2, bank=mb.DataBank(), processing_time=0.25)
    bus = _slow_bus(slave)
    with mb.TcpGateway(bus, timeout=0.2, late_window=0) as gw:
        assert _ask(gw, 2, 0) == 0x0B
        assert _ask(gw, 2, 1) == [2000]


def test_a_frame_that_arrives_before_the_request_has_left_is_not_its_answer():
    from modbus_edu.clock import VirtualClock
    from modbus_edu.gateway import _Line
    from modbus_edu.links.base import Link
    from modbus_edu.links.wire import SerialTiming

    class Scripted(Link):
        """A line on which frames arrive at given times, whatever is sent."""

        timing = SerialTiming(9600)

        def __init__(self, arrivals):
            self.clock, self.arrivals = VirtualClock(), list(arrivals)

        def send(self, frame):
            pass

        def receive(self, timeout):
            if self.arrivals and self.arrivals[0][0] <= self.clock.now + timeout:
                when, frame = self.arrivals.pop(0)
                self.clock.advance(max(0.0, when - self.clock.now))
                return frame
            self.clock.advance(timeout)
            return None

    early, answer = bytes.fromhex("02 03 02 07 D0 BB 28"), bytes.fromhex("02 03 02 08 34 BA 93")
    line = _Line(Scripted([(0.005, early), (0.020, answer)]))
    line.send(bytes.fromhex("02 03 00 01 00 01 D5 F9"))  # leaves after 8.33 ms
    assert abs(line.left_at - REQUEST_AIRTIME) < 1e-12
    assert line.receive(1.0) == answer and line.early == 1  # the frame complete at 5 ms was dropped


def _queue_then_serve(gw, units):
    """Send one FC 3 request per unit in ``units``, each on its own connection, before the bus thread has
    started (the gateway's server alone reads and queues them). The open links, in that order."""
    gw.server.start()
    links = [mb.tcp_link(*gw.address) for _ in units]
    request = mb.ReadHoldingRegistersRequest(address=0, count=1)
    for i, (link, unit) in enumerate(zip(links, units)):
        link.send(mb.TcpFrame(transaction_id=i, unit=unit, pdu=request).encode())
        deadline = time.monotonic() + 5  # in this order: each is queued before the next is sent
        while gw.server.counters.requests <= i and time.monotonic() < deadline:
            time.sleep(0.002)
    return links


def _together(clients):
    """Run the client functions at once, each on its own thread; return when all are done."""
    threads = [threading.Thread(target=client) for client in clients]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)


def _answers_in_turn(gw, units):
    """Queue one request per unit (in that order), then start the bus thread: the answers, in order."""
    links = _queue_then_serve(gw, units)
    try:
        gw.start()
        return [link.receive(10.0) for link in links]
    finally:
        for link in links:
            link.close()
        gw.close()


def test_a_dead_unit_keeps_a_live_client_waiting_one_timeout_at_most():
    # eight clients ask a silent unit, then one asks a live unit: the live one goes second, not ninth
    bus, a, _ = _bus()
    timeout = 0.25
    gw = mb.TcpGateway(bus, timeout=timeout)
    answers = _answers_in_turn(gw, [5] * 8 + [1])
    assert [f[7:9] for f in answers[:8]] == [bytes([0x83, 0x0B])] * 8
    assert answers[8][7:] == bytes([0x03, 0x02, 0x00, 0x0B])
    # its wait in bus time: the one dead transaction under way (8 characters, then the timeout)
    assert abs(gw.worst_wait[1] - (REQUEST_AIRTIME + timeout)) < 1e-9
    assert gw.worst_wait[5] > 7 * timeout


def test_after_a_silence_a_unit_that_answers_goes_first():
    # four dead units and a live one that has answered before: the live one waits one dead transaction
    bus, _, _ = _bus()
    gw = mb.TcpGateway(bus, timeout=0.1, late_window=0)
    answers = _answers_in_turn(gw, [1, 5, 6, 7, 8, 5, 6, 7, 8, 1])
    assert [f[8] for f in answers] == [0x02] + [0x0B] * 8 + [0x02]
    # turns: 1, 5, then 1 (it answers) before 6, 7, 8; its second request waited 2 transactions
    assert abs(gw.worst_wait[1] - (22 * 10 / 9600 + REQUEST_AIRTIME + 0.1)) < 1e-9


def test_many_clients_of_a_dead_unit_and_one_live_client_at_once():
    bus, a, _ = _bus()
    a.bank.holding_registers[0] = 1234
    results, errors = [], []
    with mb.TcpGateway(bus, timeout=0.25) as gw:

        def dead_client():
            for _ in range(3):
                results.append(_ask(gw, 5, 0, timeout=30))

        def live_client():
            for _ in range(10):
                got = _ask(gw, 1, 0, timeout=30)
                if got != [1234]:
                    errors.append(got)

        _together([dead_client] * 8 + [live_client])
        assert gw.worst_wait[1] <= 0.25 + REQUEST_AIRTIME + 1e-9
        assert gw.counters["overloaded"] == 0
    assert errors == [] and results == [0x0B] * 24


def test_the_queues_are_bounded_and_answer_0a_beyond():
    bus, _, _ = _bus()
    gw = mb.TcpGateway(bus, timeout=0.2, max_queued_per_unit=2, max_queued=3)
    try:
        links = _queue_then_serve(gw, [1, 1, 1, 2, 2])
        # the third request for unit 1, and a fourth in all, are answered at once with 0A, gateway path
        # unavailable: the TCP guide's answer for an overloaded gateway
        for i in (2, 4):
            frame = links[i].receive(5.0)
            assert frame is not None and frame[7:] == bytes([0x83, 0x0A]), frame
        gw.start()  # the bus thread serves what was queued
        for i in (0, 1, 3):
            frame = links[i].receive(5.0)
            assert frame is not None and frame[7] == 0x03, frame
        assert gw.counters["overloaded"] == 2 and gw.counters["forwarded"] == 3
        assert gw.counters["path_unavailable"] == 0
    finally:
        for link in links:
            link.close()
        gw.close()


# ------------------------------------------------------------------------------------------------------
# a real line over socket://: lost and reopened; a babbling unit
# ------------------------------------------------------------------------------------------------------
def _device_server(port=0):
    """A serial device server on 127.0.0.1 (raw TCP) with unit 1 on its line: (server, port)."""
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers[0] = 77
    server = mb.SerialServer(slave, mb.TcpSerialPort("127.0.0.1", port), mode="rtu").start()
    return server, server.port.address[1]


def test_a_lost_socket_line_is_reopened_when_the_device_server_returns():
    server, port = _device_server()
    link = mb.serial_link(f"socket://127.0.0.1:{port}", baudrate=9600)
    try:
        with mb.TcpGateway(link, timeout=0.3) as gw:
            assert _ask(gw, 1, 0) == [77]
            server.close()  # the device server goes away
            assert _ask(gw, 1, 0) == 0x0A
            assert _ask(gw, 1, 0) == 0x0A  # answered at once while the line is down
            server, _ = _device_server(port)  # it comes back on the same port
            deadline = time.monotonic() + 10
            got = None
            while got != [77] and time.monotonic() < deadline:
                got = _ask(gw, 1, 0)
                assert got in ([77], 0x0A)
                time.sleep(0.05)
            assert got == [77] and gw.counters["reopened"] >= 1
    finally:
        server.close()
        link.close()


def test_a_babbling_unit_does_not_stall_the_other_clients():
    # a device server whose unit 7 answers a request with a stream of frames (up to 400 kB in 2 s);
    # unit 1 on the same line answers as usual, between the babble's frames
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers[0] = 77
    babble = mb.RtuFrame(unit=7, pdu=mb.ReadHoldingRegistersResponse(registers=list(range(100)))).encode()
    listener = socket.create_server(("127.0.0.1", 0))
    stop = threading.Event()
    lock = threading.Lock()
    babbling = []

    def babbler(conn):
        end = time.monotonic() + 2.0
        try:
            while time.monotonic() < end and not stop.is_set():
                # a device server drops what the network does not take (its buffer is not endless)
                if select.select([], [conn], [], 0)[1]:
                    with lock:
                        conn.sendall(babble)
                time.sleep(0.001)
        except OSError:
            pass
        babbling.clear()

    def device():
        conn, _ = listener.accept()
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)  # as a device server does
        splitter = mb.RtuSplitter(role="request")
        while not stop.is_set():
            try:  # the socket stays blocking: a babbled frame is written whole or not at all
                if not select.select([conn], [], [], 0.05)[0]:
                    continue
                data = conn.recv(4096)
            except OSError:
                return
            if not data:
                return
            for frame in splitter.feed(data):
                if frame[0] == 7 and not babbling:  # one stream at a time
                    babbling.append(threading.Thread(target=babbler, args=(conn,), daemon=True))
                    babbling[0].start()
                elif frame[0] == 1:
                    answer = slave.handle(frame, "rtu")
                    try:
                        with lock:
                            conn.sendall(answer)
                    except OSError:
                        return

    threading.Thread(target=device, daemon=True).start()
    link = mb.serial_link(f"socket://127.0.0.1:{listener.getsockname()[1]}", baudrate=9600)
    waits, results = [], []
    try:
        with mb.TcpGateway(link, timeout=0.25) as gw:

            def babble_client():
                for _ in range(3):
                    results.append(_ask(gw, 7, 0))

            def live_client():
                for _ in range(10):
                    start = time.monotonic()
                    results.append(_ask(gw, 1, 0))
                    waits.append(time.monotonic() - start)

            _together([babble_client] * 2 + [live_client])
            time.sleep(2.0)  # the babble is over: the line recovers (what is stale is dropped)
            after = [_ask(gw, 1, 0) for _ in range(3)]
            late = gw.counters["late"]
    finally:
        stop.set()
        link.close()
        listener.close()
    # every answer is the right one or 0B (never a babbled frame), and each came in bounded time:
    # at most one babbling transaction (the timeout) before its own, with room for a loaded machine
    assert all(r in (0x0B, [77]) for r in results), results
    assert max(waits) < 1.5, waits
    assert results.count([77]) >= 5 and after == [[77]] * 3 and late > 0


def test_a_failure_inside_the_bus_thread_is_answered_04_and_the_thread_carries_on():
    bus, _, _ = _bus()
    with mb.TcpGateway(bus, timeout=0.2) as gw:
        execute = gw.master.execute
        gw.master.execute = lambda *args, **kwargs: 1 / 0
        assert _ask(gw, 1, 0) == 0x04
        gw.master.execute = execute
        assert _ask(gw, 1, 0) == [11]


def test_over_socket_the_line_has_no_airtime():
    # a pyserial URL carries bytes at network speed: an answer may come before 8 characters' time at
    # 9600 baud, and must not be taken for early; the timeout starts when the request is written
    from modbus_edu.gateway import _Line

    link = mb.serial_link("loop://", baudrate=9600)
    try:
        assert _Line(link).airtime(8) == 0.0
        assert _Line(mb.loopback_serial(baudrate=9600)).airtime(8) == REQUEST_AIRTIME
    finally:
        link.close()
