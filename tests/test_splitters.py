"""Stream splitters: frames fed one byte at a time, in random chunks, after junk, back to back; resync
after garbage; and that no byte sequence makes ``feed`` raise."""

from __future__ import annotations

import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modbus_edu import pdu as P
from modbus_edu.crc import crc16, lrc
from modbus_edu.errors import ConfigError, FrameError
from modbus_edu.framing import (
    AsciiFrame,
    AsciiSplitter,
    RtuFrame,
    RtuSplitter,
    TcpFrame,
    TcpSplitter,
    decode_frame,
    splitter_for,
)

FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def random_pdu(rng: random.Random, role: str) -> P.Pdu:
    """A random valid PDU of every function (sizes kept mostly small, sometimes maximal)."""
    small = rng.random() < 0.8

    def n(limit: int) -> int:
        return rng.randint(1, 12 if small else limit)

    address = rng.randrange(0, 60000)
    if role == "request":
        kind = rng.randrange(8)
        if kind < 4:
            cls = (P.ReadCoilsRequest, P.ReadDiscreteInputsRequest,
                   P.ReadHoldingRegistersRequest, P.ReadInputRegistersRequest)[kind]
            return cls(address=address, count=n(125))
        if kind == 4:
            return P.WriteSingleCoilRequest(address=address, value=rng.random() < 0.5)
        if kind == 5:
            return P.WriteSingleRegisterRequest(address=address, value=rng.randrange(65536))
        if kind == 6:
            coils = [rng.random() < 0.5 for _ in range(n(1968))]
            return P.WriteMultipleCoilsRequest(address=address, values=coils)
        values = [rng.randrange(65536) for _ in range(n(123))]
        return P.WriteMultipleRegistersRequest(address=address, values=values)
    kind = rng.randrange(9)
    if kind < 2:
        cls = (P.ReadCoilsResponse, P.ReadDiscreteInputsResponse)[kind]
        return cls(bits=[rng.random() < 0.5 for _ in range(8 * n(250))])
    if kind < 4:
        cls = (P.ReadHoldingRegistersResponse, P.ReadInputRegistersResponse)[kind - 2]
        return cls(registers=[rng.randrange(65536) for _ in range(n(125))])
    if kind == 4:
        return P.WriteSingleCoilResponse(address=address, value=rng.random() < 0.5)
    if kind == 5:
        return P.WriteSingleRegisterResponse(address=address, value=rng.randrange(65536))
    if kind == 6:
        return P.WriteMultipleCoilsResponse(address=address, count=n(1968))
    if kind == 7:
        return P.WriteMultipleRegistersResponse(address=address, count=n(123))
    return P.ExceptionResponse(function=rng.choice([1, 2, 3, 4, 5, 6, 15, 16]), code=rng.randint(1, 11))


def random_frames(mode: str, role: str, count: int, seed: int) -> list[bytes]:
    rng = random.Random(seed)
    frames = []
    for _ in range(count):
        pdu = random_pdu(rng, role)
        if mode == "rtu":
            frames.append(RtuFrame(rng.randint(1, 247), pdu).encode())
        elif mode == "ascii":
            frames.append(AsciiFrame(rng.randint(0, 247), pdu).encode())
        else:
            frames.append(TcpFrame(rng.randrange(1, 65536), rng.randint(0, 255), pdu).encode())
    return frames


def chunks(data: bytes, rng: random.Random, largest: int = 20) -> list[bytes]:
    out, at = [], 0
    while at < len(data):
        size = rng.randint(1, largest)
        out.append(data[at:at + size])
        at += size
    return out


def feed_all(splitter, pieces) -> list[bytes]:
    frames: list[bytes] = []
    for piece in pieces:
        frames += splitter.feed(piece)
    return frames


CASES = [("rtu", "request"), ("rtu", "response"), ("ascii", "request"), ("ascii", "response"),
         ("tcp", "request"), ("tcp", "response")]


@pytest.mark.parametrize(("mode", "role"), CASES)
def test_back_to_back_in_one_chunk(mode: str, role: str) -> None:
    frames = random_frames(mode, role, 40, seed=1)
    splitter = splitter_for(mode, role)
    assert splitter.feed(b"".join(frames)) == frames
    assert splitter.discarded == 0 and splitter.pending == b""


@pytest.mark.parametrize(("mode", "role"), CASES)
def test_one_byte_at_a_time(mode: str, role: str) -> None:
    frames = random_frames(mode, role, 25, seed=2)
    splitter = splitter_for(mode, role)
    stream = b"".join(frames)
    got = feed_all(splitter, [stream[i:i + 1] for i in range(len(stream))])
    assert got == frames
    assert splitter.discarded == 0 and splitter.pending == b""


@pytest.mark.parametrize(("mode", "role"), CASES)
@pytest.mark.parametrize("seed", [3, 4, 5])
def test_random_chunks(mode: str, role: str, seed: int) -> None:
    frames = random_frames(mode, role, 30, seed=seed)
    rng = random.Random(seed)
    splitter = splitter_for(mode, role)
    assert feed_all(splitter, chunks(b"".join(frames), rng)) == frames
    assert splitter.discarded == 0


@pytest.mark.parametrize(("mode", "role"), CASES)
def test_frames_come_out_as_soon_as_complete(mode: str, role: str) -> None:
    splitter = splitter_for(mode, role)
    for frame in random_frames(mode, role, 10, seed=6):
        assert splitter.feed(frame[:-1]) == []
        assert splitter.pending == frame[:-1]
        assert splitter.feed(frame[-1:]) == [frame]
        assert splitter.pending == b""


# junk that no splitter can take for the start of a frame: RTU units 248-255 are reserved, there is no ':'
# in it, and for TCP bytes 2-3 of any header that starts in it are not 00 00
JUNK = bytes([0xF8, 0xFF, 0xFA, 0x99, 0xFE, 0xFB, 0xF9])


@pytest.mark.parametrize(("mode", "role"), CASES)
def test_junk_before_each_frame_is_counted(mode: str, role: str) -> None:
    frames = random_frames(mode, role, 20, seed=7)
    rng = random.Random(7)
    stream = b"".join(JUNK[: rng.randint(1, len(JUNK))] + f for f in frames)
    junk = len(stream) - sum(map(len, frames))
    splitter = splitter_for(mode, role)
    assert feed_all(splitter, chunks(stream, rng, 9)) == frames
    assert splitter.discarded == junk
    assert splitter.pending == b""


@pytest.mark.parametrize(("mode", "role"), CASES)
@pytest.mark.parametrize("seed", [8, 9])
def test_random_junk_then_frames(mode: str, role: str, seed: int) -> None:
    """Arbitrary junk (which may look like the start of a frame) before a run of frames: after at most
    the junk and the frames it swallowed, the splitter is back in step.  ``flush`` at the end of the
    stream stands for the silence that ends an RTU frame."""
    rng = random.Random(seed)
    frames = random_frames(mode, role, 15, seed=seed)
    junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 30)))
    if mode == "ascii":
        junk = junk.replace(b":", b"")
    splitter = splitter_for(mode, role)
    got = feed_all(splitter, chunks(junk + b"".join(frames), rng, 12)) + splitter.flush()
    if mode == "tcp":
        assert got[-10:] == frames[-10:]  # a bad length may swallow a frame or two; the rest is in step
    else:
        assert got == frames
        assert splitter.discarded == len(junk)


def test_rtu_resync_after_a_corrupted_frame() -> None:
    good = RtuFrame(1, P.ReadHoldingRegistersRequest(0, 1)).encode()
    bad = bytearray(good)
    bad[3] ^= 0x40  # CRC now wrong
    splitter = RtuSplitter("request")
    assert splitter.feed(bytes(bad) + good + good) == [good, good]
    assert splitter.discarded == len(bad)


def test_rtu_junk_announcing_a_long_frame_does_not_hold_back_a_complete_frame() -> None:
    """Junk that announces a long FC16 request: the complete frame behind it comes out at once."""
    good = RtuFrame(1, P.ReadHoldingRegistersRequest(0, 1)).encode()
    junk = bytes([0x01, 0x10, 0x00, 0x00, 0x00, 0x40, 0x80])  # 'byte count 128': wait for 128 + 2 bytes
    splitter = RtuSplitter("request")
    assert splitter.feed(junk + good * 3) == [good] * 3
    assert splitter.discarded == len(junk) and splitter.pending == b""


def test_rtu_a_long_frame_fed_byte_by_byte_is_not_cut_short() -> None:
    """While a real long frame arrives, the look-ahead finds no false frame inside its data."""
    long = RtuFrame(1, P.WriteMultipleRegistersRequest(0, list(range(0, 1230, 10)))).encode()
    splitter = RtuSplitter("request")
    out = [frame for byte in long for frame in splitter.feed(bytes([byte]))]
    assert out == [long] and splitter.discarded == 0


def test_rtu_flush_is_the_silence_after_a_frame() -> None:
    """Junk whose announced frame is still incomplete waits for the silence; flush drops it."""
    junk = bytes([0x01, 0x10, 0x00, 0x00, 0x00, 0x40, 0x80, 0x12, 0x34])
    splitter = RtuSplitter("request")
    assert splitter.feed(junk) == []
    assert splitter.pending == junk
    assert splitter.flush() == []
    assert splitter.discarded == len(junk) and splitter.pending == b""


def test_rtu_unknown_function_and_reserved_unit_are_dropped_at_once() -> None:
    good = RtuFrame(9, P.WriteSingleRegisterRequest(1, 2)).encode()
    splitter = RtuSplitter("request")
    assert splitter.feed(bytes([0xF8, 0x01, 0x07, 0x01, 0x2B]) + good) == [good]
    assert splitter.discarded == 5


def test_rtu_role_matters() -> None:
    """FC3 request and response have different lengths: a response read as requests is not found."""
    response = RtuFrame(1, P.ReadHoldingRegistersResponse(registers=(3, 0x5571))).encode()
    assert RtuSplitter("response").feed(response) == [response]
    as_request = RtuSplitter("request")
    assert as_request.feed(response) == []
    assert as_request.flush() == [] and as_request.discarded == len(response)


def test_ascii_junk_restart_and_overlong() -> None:
    good = b":050610010200E2\r\n"
    splitter = AsciiSplitter()
    # junk before ':', a half frame cut short by a new ':', then a good frame
    assert splitter.feed(b"xx\r\n:0506" + good) == [good]
    assert splitter.discarded == 4 + 5
    # a frame that never ends within 513 characters is dropped; the next frame is found
    splitter.reset()
    assert splitter.discarded == 0
    assert splitter.feed(b":" + b"0" * 600) == []
    assert splitter.feed(b"\r\n" + good) == [good]
    assert splitter.discarded == 601 + 2


def test_ascii_returns_frames_as_cut_unless_strict() -> None:
    bad_lrc = b":050610010200E3\r\n"
    not_hex = b":05XY\r\n"
    good = b":050310000002E6\r\n"
    assert AsciiSplitter().feed(bad_lrc + not_hex + good) == [bad_lrc, not_hex, good]
    strict = AsciiSplitter(strict=True)
    assert strict.feed(bad_lrc + not_hex + good) == [good]
    assert strict.discarded == len(bad_lrc) + len(not_hex)


def test_ascii_cr_and_lf_in_different_chunks() -> None:
    splitter = AsciiSplitter()
    assert splitter.feed(b":050310000002E6\r") == []
    assert splitter.feed(b"\n") == [b":050310000002E6\r\n"]


def test_tcp_bad_header_resync() -> None:
    good = TcpFrame(0x0118, 1, P.ReadHoldingRegistersRequest(0, 1)).encode()
    bad_protocol = bytes.fromhex("0118 0001 0006 01 03 00 00 00 01".replace(" ", ""))
    splitter = TcpSplitter()
    assert splitter.feed(bad_protocol + good) == [good]
    assert splitter.discarded == len(bad_protocol)
    bad_length = bytes.fromhex("0118 0000 00FF 01".replace(" ", ""))
    splitter.reset()
    assert splitter.feed(bad_length + good) == [good]
    assert splitter.discarded == len(bad_length)


def test_tcp_waits_for_the_announced_length() -> None:
    splitter = TcpSplitter()
    head = bytes.fromhex("000100000006")
    assert splitter.feed(head) == []
    assert splitter.feed(bytes.fromhex("0103000000")) == []
    assert splitter.feed(b"\x01\xff") == [head + bytes.fromhex("010300000001")]
    assert splitter.pending == b"\xff"
    assert splitter.flush() == [] and splitter.discarded == 1


def test_cut_frames_decode() -> None:
    for mode, role in CASES:
        for frame in feed_all(splitter_for(mode, role), [b"".join(random_frames(mode, role, 10, 11))]):
            decode_frame(frame, mode, role)


def test_splitter_arguments() -> None:
    with pytest.raises(ConfigError):
        RtuSplitter("both")
    with pytest.raises(ConfigError):
        splitter_for("udp")
    with pytest.raises(FrameError):
        TcpSplitter().feed("0001")  # type: ignore[arg-type]
    assert isinstance(splitter_for("ascii"), AsciiSplitter)
    assert splitter_for("rtu", "response").role == "response"


# --- fuzzing: feed never raises, and what comes out is a frame ---------------------------------------------
def _check_cut(mode: str, frame: bytes) -> None:
    if mode == "rtu":
        assert 4 <= len(frame) <= 256
        assert crc16(frame[:-2]) == int.from_bytes(frame[-2:], "little")
    elif mode == "ascii":
        assert frame[:1] == b":" and frame.endswith(b"\r\n") and len(frame) <= 513
        assert b":" not in frame[1:]
    else:
        assert frame[2:4] == b"\0\0" and 2 <= int.from_bytes(frame[4:6], "big") == len(frame) - 6 <= 254


@FUZZ
@given(st.sampled_from(CASES), st.lists(st.binary(max_size=40), max_size=12))
def test_random_bytes_never_raise(case, pieces) -> None:
    mode, role = case
    splitter = splitter_for(mode, role)
    strict = AsciiSplitter(strict=True)
    total = 0
    for piece in pieces:
        for frame in splitter.feed(piece):
            _check_cut(mode, frame)
            total += len(frame)
        for frame in strict.feed(piece):
            raw = bytes.fromhex(frame[1:-2].decode())
            assert lrc(raw[:-1]) == raw[-1]
    for frame in splitter.flush():
        _check_cut(mode, frame)
        total += len(frame)
    assert total + splitter.discarded == sum(map(len, pieces))  # every byte is a frame's or discarded


@FUZZ
@given(st.sampled_from(CASES), st.integers(0, 10_000), st.binary(max_size=30), st.data())
def test_mutated_streams_never_raise(case, seed, junk, data) -> None:
    mode, role = case
    stream = bytearray(b"".join(random_frames(mode, role, 4, seed)))
    for _ in range(data.draw(st.integers(0, 4))):
        index = data.draw(st.integers(0, len(stream) - 1))
        stream[index] ^= 1 << data.draw(st.integers(0, 7))
    cut = data.draw(st.integers(0, len(stream)))
    stream = bytes(stream[:cut]) + junk + bytes(stream[cut:])
    splitter = splitter_for(mode, role)
    rng = random.Random(seed)
    for frame in feed_all(splitter, chunks(stream, rng, 16)) + splitter.flush():
        _check_cut(mode, frame)
    assert splitter.pending == b""
