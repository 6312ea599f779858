"""Every wait has an absolute deadline, whatever the other end sends, on every link.

A peer here streams bytes at the link as fast as loopback carries them (junk, another unit's frames, a
run of ':'), for a bounded time, and the Master must give up at its timeout as if the line were silent.
Times are asserted with a generous margin (a loaded 2-core machine); before these defences the same
waits took 5 to 40 times their timeout.
"""

from __future__ import annotations

import select
import socket
import threading
import time

import pytest
from conftest_io import HOST

import modbus_edu as mb
from modbus_edu.links.base import READ_CHUNK

TIMEOUT = 0.3
#: what a deadline may overshoot on a loaded machine; the defects it guards against overshot by seconds
MARGIN = 0.5


class StreamingPeer:
    """A TCP listener on 127.0.0.1 that sends ``payload`` over and over to each connection, until
    ``seconds`` after it was connected, and then (if ``then`` is given) answers each request it reads with
    ``then(request)``, as a device that stops babbling would.  Every connection is served."""

    def __init__(self, payload: bytes, seconds: float = 8.0, then=None) -> None:
        self.payload = payload * max(1, 65536 // len(payload))
        self.seconds = seconds
        self.then = then
        self.sent = 0
        self.errors: list[BaseException] = []
        self.listener = socket.create_server((HOST, 0))
        self.listener.settimeout(0.1)
        self.port = self.listener.getsockname()[1]
        self.stop = threading.Event()
        self.threads = [threading.Thread(target=self._accept, daemon=True)]
        self.threads[0].start()

    def _accept(self) -> None:
        while not self.stop.is_set():
            try:
                conn, _ = self.listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            thread = threading.Thread(target=self._serve, args=(conn,), daemon=True)
            self.threads.append(thread)
            thread.start()

    def _serve(self, conn: socket.socket) -> None:
        conn.settimeout(0.1)
        end = time.monotonic() + self.seconds
        try:
            while not self.stop.is_set() and time.monotonic() < end:
                try:
                    self.sent += conn.send(self.payload)
                except (TimeoutError, BlockingIOError):
                    continue
            conn.settimeout(5.0)  # the flood may still fill the send buffer: an answer waits behind it
            while self.then is not None and not self.stop.is_set():
                if not select.select([conn], [], [], 0.1)[0]:
                    continue
                request = conn.recv(4096)
                if not request:
                    break
                conn.sendall(self.then(request))
        except (ConnectionError, TimeoutError):
            pass  # the link dropped this connection (and made another)
        except BaseException as exc:  # noqa: BLE001 - reported by close()
            self.errors.append(exc)
        finally:
            conn.close()

    def close(self) -> None:
        self.stop.set()
        self.listener.close()
        for thread in self.threads:
            thread.join(5)
        assert not self.errors, self.errors

    def __enter__(self) -> StreamingPeer:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


def _timed_read(master: mb.Master) -> float:
    start = time.monotonic()
    with pytest.raises(mb.ModbusError):
        master.read_holding_registers(unit=1, address=0, count=1)
    return time.monotonic() - start


OTHER_UNIT = mb.RtuFrame(unit=7, pdu=mb.ReadHoldingRegistersResponse(registers=[2000])).encode()


@pytest.mark.parametrize("mode, payload", [
    ("rtu", b"\xff" * 1024),
    ("rtu", OTHER_UNIT),
    ("ascii", b":" * 1024),
    ("ascii", mb.AsciiFrame(unit=7, pdu=mb.ReadHoldingRegistersResponse(registers=[2000])).encode()),
], ids=["rtu junk", "rtu another unit's frames", "ascii run of ':'", "ascii another unit's frames"])
def test_a_serial_link_over_a_socket_keeps_its_deadline_under_a_stream(mode, payload):
    with StreamingPeer(payload) as peer:
        with mb.serial_link(f"socket://{HOST}:{peer.port}", mode=mode) as link:
            master = mb.Master(link, timeout=TIMEOUT)
            elapsed = [_timed_read(master) for _ in range(2)]
            assert peer.sent > 0
    assert max(elapsed) < TIMEOUT + MARGIN, f"a {TIMEOUT} s timeout took {max(elapsed):.2f} s"


def test_a_tcp_link_keeps_its_deadline_under_a_stream_of_junk():
    with StreamingPeer(b"\xff" * 1024) as peer:
        with mb.tcp_link(HOST, peer.port) as link:
            master = mb.Master(link, timeout=TIMEOUT)
            elapsed = [_timed_read(master) for _ in range(2)]
    assert max(elapsed) < TIMEOUT + MARGIN, f"a {TIMEOUT} s timeout took {max(elapsed):.2f} s"


def _tcp_answer(request: bytes) -> bytes:
    frame = mb.TcpFrame.decode(request[:12], role="request")
    return mb.TcpFrame(transaction_id=frame.transaction_id, unit=frame.unit,
                       pdu=mb.ReadHoldingRegistersResponse(registers=[1234])).encode()


def _recovers(master: mb.Master) -> None:
    """After a flood ends, every request answers or gives up at its deadline, and one is answered.

    How much of the flood is still queued when the next request goes out (megabytes, in the sockets of
    both ends) and how fast it can be dropped depend on the machine; what may not depend on it is that
    no request waits past its deadline, and that the backlog, which is finite, stops hiding the answer.
    """
    for _ in range(20):
        start = time.monotonic()
        try:
            answer = master.read_holding_registers(unit=1, address=0, count=1)
        except mb.ModbusError:
            elapsed = time.monotonic() - start
            assert elapsed < TIMEOUT + MARGIN, f"a {TIMEOUT} s timeout took {elapsed:.2f} s"
            continue
        assert answer == [1234]
        return
    pytest.fail("20 requests after the flood ended, none was answered")


def test_after_a_flood_of_foreign_frames_ends_the_next_request_is_answered():
    foreign = mb.TcpFrame(transaction_id=0xBEEF, unit=1,
                          pdu=mb.ReadHoldingRegistersResponse(registers=[1])).encode()
    with StreamingPeer(foreign, seconds=0.6, then=_tcp_answer) as peer:
        with mb.tcp_link(HOST, peer.port) as link:
            master = mb.Master(link, timeout=TIMEOUT)
            elapsed = _timed_read(master)            # during the flood: a timeout, on time
            assert elapsed < TIMEOUT + MARGIN, f"a {TIMEOUT} s timeout took {elapsed:.2f} s"
            time.sleep(0.6)                          # the flood ends; megabytes of it may still be queued
            _recovers(master)


def _queued_junk(size: int):
    """A listener whose one connection gets ``size`` bytes of 0xFF at once, then nothing (kept open)."""
    listener = socket.create_server((HOST, 0))
    done = threading.Event()

    def serve() -> None:
        conn, _ = listener.accept()
        with conn:
            conn.sendall(b"\xff" * size)
            done.wait(5)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    return listener, done, thread


def test_a_tcp_read_cuts_a_bounded_amount_of_junk_between_two_looks_at_its_deadline():
    """Cutting junk costs time in proportion to its bytes: a read that took 64 KiB at a time spent tens
    of milliseconds (more on a busy machine) past its deadline on each.  Counted in bytes, not seconds,
    so the bound is the same on any machine: one look at a link whose deadline has passed cuts at most
    READ_CHUNK bytes."""
    listener, done, thread = _queued_junk(1 << 20)
    try:
        with mb.tcp_link(HOST, listener.getsockname()[1]) as link:
            deadline = time.monotonic() + 5
            while not select.select([link._sock], [], [], 0.05)[0] and time.monotonic() < deadline:
                pass
            time.sleep(0.05)  # let the megabyte queue up
            assert link.receive(0) is None
            assert 0 < link.discarded <= READ_CHUNK
            assert link.receive(0) is None
            assert link.discarded <= 2 * READ_CHUNK
    finally:
        done.set()
        listener.close()
        thread.join(5)


def _rtu_answer(request: bytes) -> bytes:
    return mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[1234])).encode()


def test_after_a_serial_flood_ends_the_next_request_is_answered():
    with StreamingPeer(OTHER_UNIT, seconds=0.6, then=_rtu_answer) as peer:
        with mb.serial_link(f"socket://{HOST}:{peer.port}", mode="rtu") as link:
            master = mb.Master(link, timeout=TIMEOUT)
            elapsed = _timed_read(master)
            assert elapsed < TIMEOUT + MARGIN, f"a {TIMEOUT} s timeout took {elapsed:.2f} s"
            time.sleep(0.6)
            _recovers(master)
