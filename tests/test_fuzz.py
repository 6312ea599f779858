"""Fuzzing the decoders, the splitters and explain() with random bytes and mutated valid frames.

The rules checked here are the library's promise to a learner who types anything:

* a decoder either raises a ModbusError (nothing else: no IndexError, struct.error, TypeError, ...) or
  returns an object that re-encodes to exactly the bytes it was given (no silently wrong value);
* a splitter never raises for any bytes, loses no byte without counting it, and hands out only frames
  that pass its own checks;
* explain() never raises at all, and its rows cover every byte of the input, in order.
"""

from __future__ import annotations

import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modbus_edu import pdu as P
from modbus_edu.crc import crc16, lrc
from modbus_edu.errors import ModbusError
from modbus_edu.explain import explain
from modbus_edu.framing import (
    AsciiFrame,
    AsciiSplitter,
    RtuFrame,
    RtuSplitter,
    TcpFrame,
    TcpSplitter,
    decode_frame,
    detect_mode,
    parse_hex,
)

SETTINGS = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ROLES = ("request", "response")
MODES = ("rtu", "ascii", "tcp")
FRAME_CLASSES = {"rtu": RtuFrame, "ascii": AsciiFrame, "tcp": TcpFrame}


# --- valid material to mutate ------------------------------------------------------------------------
def bits_of(data: bytes) -> list[bool]:
    return [bool(byte >> bit & 1) for byte in data for bit in range(8)]


def span(limit: int):
    return st.integers(1, limit).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), st.just(n)))


REGISTER = st.integers(0, 0xFFFF)
ADDRESS = st.integers(0, 0xFFFF)

def _read(cls, limit):
    return span(limit).map(lambda ac: cls(ac[0], ac[1]))


def _bit_list(n: int):
    return st.binary(min_size=(n + 7) // 8, max_size=(n + 7) // 8).map(lambda b: bits_of(b)[:n])


REQUEST_PDUS = st.one_of(
    _read(P.ReadCoilsRequest, 2000), _read(P.ReadDiscreteInputsRequest, 2000),
    _read(P.ReadHoldingRegistersRequest, 125), _read(P.ReadInputRegistersRequest, 125),
    st.builds(P.WriteSingleCoilRequest, ADDRESS, st.booleans()),
    st.builds(P.WriteSingleRegisterRequest, ADDRESS, REGISTER),
    st.integers(1, 40).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), _bit_list(n))).map(
        lambda av: P.WriteMultipleCoilsRequest(av[0], av[1])),
    st.integers(1, 20).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), st.lists(
        REGISTER, min_size=n, max_size=n))).map(lambda av: P.WriteMultipleRegistersRequest(av[0], av[1])),
)
RESPONSE_PDUS = st.one_of(
    st.binary(min_size=1, max_size=30).map(lambda b: P.ReadCoilsResponse(bits=bits_of(b))),
    st.binary(min_size=1, max_size=30).map(lambda b: P.ReadDiscreteInputsResponse(bits=bits_of(b))),
    st.lists(REGISTER, min_size=1, max_size=20).map(lambda r: P.ReadHoldingRegistersResponse(registers=r)),
    st.lists(REGISTER, min_size=1, max_size=20).map(lambda r: P.ReadInputRegistersResponse(registers=r)),
    st.builds(P.WriteSingleCoilResponse, ADDRESS, st.booleans()),
    st.builds(P.WriteSingleRegisterResponse, ADDRESS, REGISTER),
    _read(P.WriteMultipleCoilsResponse, 1968), _read(P.WriteMultipleRegistersResponse, 123),
    st.builds(P.ExceptionResponse, st.integers(1, 127), st.integers(1, 255)),
)
PDUS_BY_ROLE = {"request": REQUEST_PDUS, "response": RESPONSE_PDUS}


@st.composite
def valid_frames(draw, modes=MODES, roles=ROLES):
    """(mode, role, frame bytes) of a valid frame."""
    mode = draw(st.sampled_from(modes))
    pdu = draw(PDUS_BY_ROLE[draw(st.sampled_from(roles))])
    if mode == "tcp":
        frame = TcpFrame(transaction_id=draw(st.integers(0, 0xFFFF)), unit=draw(st.integers(0, 255)), pdu=pdu)
    else:
        frame = FRAME_CLASSES[mode](unit=draw(st.integers(0, 247)), pdu=pdu)
    return mode, pdu.role, frame.encode()


@st.composite
def mutated(draw, data: bytes) -> bytes:
    """One to three mutations: bit flips, byte changes, truncation, extension, insertion, deletion."""
    out = bytearray(data)
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["flip", "byte", "truncate", "extend", "insert", "delete"]))
        if kind in ("flip", "byte", "delete") and not out:
            kind = "extend"
        if kind == "flip":
            i = draw(st.integers(0, len(out) - 1))
            out[i] ^= 1 << draw(st.integers(0, 7))
        elif kind == "byte":
            out[draw(st.integers(0, len(out) - 1))] = draw(st.integers(0, 255))
        elif kind == "truncate":
            del out[draw(st.integers(0, len(out))):]
        elif kind == "extend":
            out += draw(st.binary(min_size=1, max_size=6))
        elif kind == "insert":
            out.insert(draw(st.integers(0, len(out))), draw(st.integers(0, 255)))
        else:
            del out[draw(st.integers(0, len(out) - 1))]
    return bytes(out)


# --- the decoder contract ----------------------------------------------------------------------------
def canonical(mode: str, data: bytes) -> bytes:
    """What a successfully decoded frame must re-encode to (ASCII decode accepts lowercase hex)."""
    return data.upper() if mode == "ascii" else data


def check_pdu_decoder(data: bytes, role: str) -> None:
    try:
        result = P.decode_pdu(data, role)
    except ModbusError:
        return
    assert result.role == role or isinstance(result, P.ExceptionResponse)
    assert result.encode() == data, (
        f"decode_pdu({data.hex(' ')}, {role}) gave {result}, which re-encodes differently")


def check_frame_decoder(mode: str, data: bytes, role: str) -> None:
    try:
        frame = FRAME_CLASSES[mode].decode(data, role=role)
    except ModbusError:
        return
    assert frame.encode() == canonical(mode, data), (
        f"{mode} decode({data!r}, {role}) gave {frame}, which re-encodes differently")
    # decode_frame is the same decoder under another name
    assert decode_frame(data, mode, role) == frame


def check_everything(data: bytes) -> None:
    for role in ROLES:
        check_pdu_decoder(data, role)
        for mode in MODES:
            check_frame_decoder(mode, data, role)


@SETTINGS
@given(st.binary(max_size=300))
def test_random_bytes_to_every_decoder(data: bytes) -> None:
    check_everything(data)


@SETTINGS
@given(st.integers(1, 0xFF), st.binary(max_size=260))
def test_random_pdus_behind_every_function_code(function: int, rest: bytes) -> None:
    # bytes that start with a plausible function code get past the first check more often
    check_pdu_decoder(bytes([function]) + rest, "request")
    check_pdu_decoder(bytes([function]) + rest, "response")


@SETTINGS
@given(st.integers(0, 255), st.binary(min_size=1, max_size=254))
def test_random_bodies_with_a_correct_crc(unit: int, body: bytes) -> None:
    # a correct CRC lets random PDUs through to the PDU checks
    data = bytes([unit]) + body
    data += crc16(data).to_bytes(2, "little")
    for role in ROLES:
        check_frame_decoder("rtu", data, role)


@SETTINGS
@given(st.integers(0, 255), st.binary(min_size=1, max_size=254), st.booleans())
def test_random_bodies_with_a_correct_lrc(unit: int, body: bytes, lower: bool) -> None:
    raw = bytes([unit]) + body
    text = (raw + bytes([lrc(raw)])).hex()
    data = b":" + (text if lower else text.upper()).encode() + b"\r\n"
    for role in ROLES:
        check_frame_decoder("ascii", data, role)


@SETTINGS
@given(st.integers(0, 0xFFFF), st.integers(0, 255), st.binary(min_size=1, max_size=253))
def test_random_bodies_with_a_correct_mbap(tid: int, unit: int, body: bytes) -> None:
    data = tid.to_bytes(2, "big") + b"\x00\x00" + (len(body) + 1).to_bytes(2, "big") + bytes([unit]) + body
    for role in ROLES:
        check_frame_decoder("tcp", data, role)


@SETTINGS
@given(st.data())
def test_mutated_valid_frames(data) -> None:
    mode, role, frame = data.draw(valid_frames())
    # the unmutated frame decodes in its role and re-encodes to itself
    assert FRAME_CLASSES[mode].decode(frame, role=role).encode() == frame
    bad = data.draw(mutated(frame))
    for any_role in ROLES:
        for any_mode in MODES:
            check_frame_decoder(any_mode, bad, any_role)
    # and the mutated PDU alone
    if mode == "rtu":
        pdu_bytes = frame[1:-2]
    elif mode == "tcp":
        pdu_bytes = frame[7:]
    else:
        pdu_bytes = bytes.fromhex(frame[1:-2].decode())[1:-1]
    mutated_pdu = data.draw(mutated(pdu_bytes))
    for any_role in ROLES:
        check_pdu_decoder(mutated_pdu, any_role)


ODD_INPUTS = [None, 5, 1.5, "01 03 00 00 00 01 84 0A", [1, 2, 300], object(), b"\x00" * 1000]


@pytest.mark.parametrize("thing", ODD_INPUTS)
@pytest.mark.parametrize("mode", MODES)
def test_odd_inputs_to_frame_decoders(thing, mode: str) -> None:
    for role in ROLES:
        with pytest.raises(ModbusError):
            FRAME_CLASSES[mode].decode(thing, role=role)


@pytest.mark.parametrize("thing", [None, 1.5, "03 00 00 00 01", [3, 0, 300], object()])
def test_odd_inputs_to_decode_pdu(thing) -> None:
    for role in ROLES:
        with pytest.raises(ModbusError):
            P.decode_pdu(thing, role)


# --- splitters ---------------------------------------------------------------------------------------
def make_splitters():
    return [RtuSplitter("request"), RtuSplitter("response"), AsciiSplitter(), AsciiSplitter(strict=True),
            TcpSplitter()]


def frame_is_acceptable(splitter, frame: bytes) -> bool:
    """What each splitter promises about the frames it hands out."""
    if isinstance(splitter, RtuSplitter):
        return 4 <= len(frame) <= 256 and crc16(frame[:-2]) == int.from_bytes(frame[-2:], "little")
    if isinstance(splitter, AsciiSplitter):
        return frame.startswith(b":") and frame.endswith(b"\r\n") and len(frame) <= 513
    length = int.from_bytes(frame[4:6], "big")
    return len(frame) >= 8 and frame[2:4] == b"\x00\x00" and length == len(frame) - 6


def feed_all(splitter, chunks: list[bytes], flush: bool = False) -> list[bytes]:
    frames: list[bytes] = []
    for chunk in chunks:
        out = splitter.feed(chunk)
        assert isinstance(out, list)
        frames += out
    if flush:
        frames += splitter.flush()
    return frames


def chunked(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({min(c, len(data)) for c in cuts} | {0, len(data)})
    return [data[a:b] for a, b in zip(points, points[1:])] or [b""]


@SETTINGS
@given(st.lists(st.binary(max_size=80), max_size=8), st.booleans())
def test_splitters_never_raise_and_account_for_every_byte(chunks: list[bytes], flush: bool) -> None:
    total = sum(len(c) for c in chunks)
    for splitter in make_splitters():
        frames = feed_all(splitter, chunks, flush=flush)
        for frame in frames:
            assert isinstance(frame, bytes)
            assert frame_is_acceptable(splitter, frame), (type(splitter).__name__, frame)
        pending = len(splitter.pending)
        assert sum(map(len, frames)) + splitter.discarded + pending == total, type(splitter).__name__
        if flush:
            assert pending == 0
        splitter.reset()
        assert splitter.discarded == 0 and splitter.pending == b""


@SETTINGS
@given(st.data())
def test_splitters_on_mutated_streams(data) -> None:
    frames = data.draw(st.lists(valid_frames(), min_size=1, max_size=4))
    stream = b"".join(f for _, _, f in frames)
    bad = data.draw(mutated(stream))
    cuts = data.draw(st.lists(st.integers(0, len(bad)), max_size=6))
    for splitter in make_splitters():
        out = feed_all(splitter, chunked(bad, cuts), flush=True)
        assert all(frame_is_acceptable(splitter, f) for f in out)
        assert sum(map(len, out)) + splitter.discarded == len(bad)


@SETTINGS
@given(st.data())
def test_splitters_cut_valid_streams_exactly(data) -> None:
    mode = data.draw(st.sampled_from(MODES))
    role = data.draw(st.sampled_from(ROLES))
    frames = data.draw(st.lists(valid_frames(modes=(mode,), roles=(role,)), min_size=1, max_size=5))
    raw = [f for _, _, f in frames]
    stream = b"".join(raw)
    cuts = data.draw(st.lists(st.integers(0, len(stream)), max_size=10))
    splitter = {"rtu": RtuSplitter(role), "ascii": AsciiSplitter(strict=data.draw(st.booleans())),
                "tcp": TcpSplitter()}[mode]
    assert feed_all(splitter, chunked(stream, cuts)) == raw
    assert splitter.discarded == 0
    assert splitter.pending == b""


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.data())
def test_serial_splitters_resynchronise_after_junk(data) -> None:
    # derandomized: for RTU a junk start could (about once in 65536 tries) carry a correct CRC by chance
    mode = data.draw(st.sampled_from(("rtu", "ascii")))
    role = data.draw(st.sampled_from(ROLES))
    frames = data.draw(st.lists(valid_frames(modes=(mode,), roles=(role,)), min_size=1, max_size=3))
    raw = [f for _, _, f in frames]
    junk = data.draw(st.binary(min_size=1, max_size=20))
    stream = junk + b"".join(raw)
    cuts = data.draw(st.lists(st.integers(0, len(stream)), max_size=6))
    splitter = RtuSplitter(role) if mode == "rtu" else AsciiSplitter()
    out = feed_all(splitter, chunked(stream, cuts), flush=True)
    assert out[len(out) - len(raw):] == raw
    assert sum(map(len, out)) + splitter.discarded == len(stream)


# --- explain -----------------------------------------------------------------------------------------
def check_explain(data, mode=None, role=None) -> None:
    result = explain(data, mode=mode, role=role)  # must not raise, whatever the input
    text = result.to_text()
    assert isinstance(text, str) and text
    assert str(result) == text
    assert isinstance(result._repr_html_(), str)
    json.dumps(result.to_dict())
    assert (result.frame is None) != (result.error is None)
    if result.error is not None:
        assert isinstance(result.error, ModbusError)
    if isinstance(data, bytes):
        assert result.data == data
        # the rows cover every byte (every character in ASCII), in order
        assert b"".join(row.raw for row in result.rows) == data
        offset = 0
        for row in result.rows:
            assert row.offset == offset
            offset += len(row.raw)
    if result.frame is not None:
        assert result.frame.encode() == canonical(result.mode, result.data)


@SETTINGS
@given(st.binary(max_size=300), st.sampled_from([None, *MODES]), st.sampled_from([None, *ROLES]))
def test_explain_random_bytes(data: bytes, mode, role) -> None:
    check_explain(data, mode, role)


@SETTINGS
@given(st.data())
def test_explain_mutated_frames(data) -> None:
    mode, role, frame = data.draw(valid_frames())
    good = explain(frame, mode=mode, role=role)
    assert good.error is None and good.frame is not None
    assert explain(frame).error is None  # detection of mode and role finds a reading
    bad = data.draw(mutated(frame))
    check_explain(bad, data.draw(st.sampled_from([None, mode])), data.draw(st.sampled_from([None, role])))


@SETTINGS
@given(st.text(max_size=80))
def test_explain_random_text(text: str) -> None:
    check_explain(text)


@SETTINGS
@given(st.text(alphabet="0123456789abcdefABCDEF :,x-\r\n\\", max_size=80))
def test_explain_hexish_text_and_parse_hex(text: str) -> None:
    check_explain(text)
    try:
        parsed = parse_hex(text)
    except ModbusError:
        return
    assert isinstance(parsed, bytes)
    assert detect_mode(parsed) in MODES
