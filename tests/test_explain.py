"""explain(): rows that cover every byte, the check field, errors recorded not raised, the three views."""

from __future__ import annotations

import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modbus_edu import pdu as P
from modbus_edu.crc import crc16
from modbus_edu.errors import AsciiFormatError, ConfigError, CrcError, LrcError, MbapError, ModbusError
from modbus_edu.explain import Dissection, Row, explain, explain_pdu
from modbus_edu.framing import MODES, AsciiFrame, RtuFrame, TcpFrame, parse_hex

FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])

VECTORS = [  # (frame as parse_hex accepts it, mode, role)
    ("01 03 00 00 00 01 84 0A", "rtu", "request"),
    ("01 03 00 00 00 0A C5 CD", "rtu", "request"),
    ("01 03 00 00 00 03 05 CB", "rtu", "request"),
    ("01 03 04 00 03 55 71 F5 47", "rtu", "response"),
    ("01 83 02 C0 F1", "rtu", "response"),
    ("01 10 00 01 00 02 04 00 0A 01 02 92 30", "rtu", "request"),
    ("11 05 00 AC FF 00 4E 8B", "rtu", "request"),
    ("11 0F 00 13 00 0A 02 CD 01 BF 0B", "rtu", "request"),
    ("11 01 00 13 00 25 0E 84", "rtu", "request"),
    ("11 03 00 6B 00 03 76 87", "rtu", "request"),
    (":050610010200E2", "ascii", "request"),
    (":050310000002E6", "ascii", "request"),
    (":050304FF0600648B", "ascii", "response"),
    ("01 18 00 00 00 06 01 03 00 00 00 01", "tcp", "request"),
    ("01 18 00 00 00 05 01 03 02 04 D2", "tcp", "response"),
]


def assert_covers(d: Dissection) -> None:
    """Rows are contiguous, start at 0, never empty, and their bytes are the frame's bytes."""
    at = 0
    for row in d.rows:
        assert isinstance(row, Row)
        assert row.offset == at and row.raw
        assert d.data[row.offset:row.offset + len(row.raw)] == row.raw
        at += len(row.raw)
    assert at == len(d.data)


def assert_views(d: Dissection) -> None:
    text = d.to_text()
    assert text == str(d)
    assert (d.summary in text) if d.ok else (str(d.error) in text and "not valid" in text)
    page = d._repr_html_()
    assert "<table" in page and "</table>" in page and "<th>" in page
    assert page.count("<tr") == len(d.rows) + 1
    json.dumps(d.to_dict())


@pytest.mark.parametrize(("text", "mode", "role"), VECTORS)
def test_vectors_dissect_cleanly(text: str, mode: str, role: str) -> None:
    d = explain(text)
    assert (d.mode, d.role, d.error, d.ok) == (mode, role, None, True)
    assert d.frame is not None and d.frame.encode() == d.data
    assert all(row.ok for row in d.rows)
    assert_covers(d)
    assert_views(d)
    assert explain(d.data, mode=mode, role=role).rows == d.rows


def test_summary_lines() -> None:
    assert explain("01 03 00 00 00 01 84 0A").summary == (
        "RTU request: unit 1, Read Holding Registers, address 0, count 1")
    assert explain("01 18 00 00 00 05 01 03 02 04 D2").summary == (
        "TCP response: transaction 280, unit 1, Read Holding Registers, registers [1234]")
    assert explain(":050610010200E2", role="response").summary == (
        "ASCII response: unit 5, Write Single Register, address 4097, value 512")
    assert explain("01 83 02 C0 F1").summary.startswith(
        "RTU response: unit 1, exception response to Read Holding Registers: code 02, illegal data address")


def test_rtu_rows() -> None:
    d = explain(bytes.fromhex("010300000001840A"))
    assert [(r.offset, r.raw.hex(" "), r.field, r.value) for r in d.rows] == [
        (0, "01", "unit (slave address)", 1),
        (1, "03", "function code", 3),
        (2, "00 00", "starting address", 0),
        (4, "00 01", "quantity", 1),
        (6, "84 0a", "CRC", "0x0A84"),
    ]
    assert "low byte first" in d.rows[-1].meaning


def test_bad_crc_row_shows_the_computed_value() -> None:
    d = explain("01 03 00 00 00 01 85 0A")
    assert isinstance(d.error, CrcError) and d.frame is None and not d.ok
    crc = d.rows[-1]
    assert crc.field == "CRC" and crc.value == "0x0A85" and not crc.ok
    assert "mismatch: computed 0x0A84" in crc.meaning and "84 0A" in crc.meaning
    assert [r.field for r in d.rows[:4]] == ["unit (slave address)", "function code", "starting address",
                                             "quantity"]  # dissected as far as it goes
    assert_covers(d)
    assert "computed 0x0A84" in d.to_text() and "CrcError" in d.to_text()
    message = d.to_dict()["error"]
    assert message.startswith("CRC mismatch: frame carries 0x0A85, computed 0x0A84 over bytes 0-5")
    with pytest.raises(CrcError):
        explain("01 03 00 00 00 01 85 0A", strict=True)


def test_two_frames_run_together() -> None:
    good = bytes.fromhex("010300000001840A")
    d = explain(good + good[:3], mode="rtu")
    assert isinstance(d.error, CrcError)
    assert d.rows[4].field == "CRC" and d.rows[4].ok
    assert d.rows[-1].field == "extra bytes" and d.rows[-1].raw == good[:3]


def test_exception_response_rows() -> None:
    d = explain("01 83 02 C0 F1")
    assert d.role == "response" and isinstance(d.frame.pdu, P.ExceptionResponse)
    fc, code = d.rows[1], d.rows[2]
    assert fc.raw == b"\x83" and "0x80" in fc.meaning and "Read Holding Registers" in fc.meaning
    assert code.field == "exception code" and code.value == 2 and "illegal data address" in code.meaning


def test_an_exception_code_is_never_a_request() -> None:
    d = explain("01 83 02 C0 F1", role="request")
    assert d.error is not None and not d.rows[1].ok and "never a request" in d.rows[1].meaning


def test_broadcast_note() -> None:
    frame = RtuFrame(0, P.WriteSingleRegisterRequest(1, 3)).encode()
    d = explain(frame)
    assert d.rows[0].value == 0 and "broadcast" in d.rows[0].meaning
    assert "unit 0 (broadcast)" in d.summary


def test_reserved_unit_is_flagged() -> None:
    body = bytes.fromhex("F803000000 01".replace(" ", ""))
    d = explain(body + crc16(body).to_bytes(2, "little"), mode="rtu")
    assert d.rows[0].ok and "reserved" in d.rows[0].meaning and d.error is None
    assert_covers(d)


def test_tcp_rows_mbap_big_endian() -> None:
    d = explain("01 18 00 00 00 06 01 03 00 00 00 01")
    fields = [(r.offset, r.field, r.value) for r in d.rows[:4]]
    assert fields == [(0, "transaction identifier", 280), (2, "protocol identifier", 0), (4, "length", 6),
                      (6, "unit identifier", 1)]
    assert "big-endian" in d.rows[0].meaning and "big-endian" in d.rows[2].meaning
    assert d.rows[4].offset == 7 and d.rows[4].field == "function code"


def test_tcp_bad_header_still_dissected() -> None:
    d = explain(bytes.fromhex("011800010006010300000001"), mode="tcp")
    assert isinstance(d.error, MbapError) and not d.rows[1].ok
    assert_covers(d)
    d = explain(bytes.fromhex("01180000000901030000000100"), mode="tcp")
    assert isinstance(d.error, MbapError) and "but 7 do" in d.rows[2].meaning
    assert_covers(d)
    d = explain(bytes.fromhex("0118000000"), mode="tcp")
    assert d.rows[-1].field == "length (incomplete)"
    assert_covers(d)


def test_ascii_rows_are_in_characters() -> None:
    d = explain(b":050304FF0600648B\r\n")
    assert [(r.offset, r.raw) for r in d.rows] == [
        (0, b":"), (1, b"05"), (3, b"03"), (5, b"04"), (7, b"FF06"), (11, b"0064"), (15, b"8B"),
        (17, b"\r\n")]
    assert d.rows[-2].field == "LRC" and d.rows[-2].value == "0x8B"
    assert d.rows[-1].value == "CR LF"
    assert d.to_dict()["rows"][-1]["chars"] == "CR LF"


def test_ascii_bad_lrc_row_shows_the_computed_value() -> None:
    d = explain(":050304FF0600648C")
    assert isinstance(d.error, LrcError)
    assert "computed 0x8B" in d.rows[-2].meaning and not d.rows[-2].ok
    assert_covers(d)


@pytest.mark.parametrize("frame", [b":0503G4FF\r\n", b":05031\r\n", b"050310000002E6\r\n",
                                   b":050310000002E6", b":050310000002E6\r", b":\r\n", b":", b"\r\n"])
def test_broken_ascii_is_dissected_as_far_as_possible(frame: bytes) -> None:
    d = explain(frame, mode="ascii")
    assert d.error is not None and not d.ok
    assert_covers(d)
    assert_views(d)


def test_strict_and_bad_text() -> None:
    d = explain("01 0G")
    assert isinstance(d.error, AsciiFormatError) and d.rows == [] and "position 4" in str(d.error)
    assert_views(d)
    with pytest.raises(AsciiFormatError):
        explain("01 0G", strict=True)
    assert explain("01 03 00 00 00 01 84 0A", strict=True).ok
    with pytest.raises(ConfigError):
        explain(b"\x01", mode="udp")
    with pytest.raises(ConfigError):
        explain(b"\x01", role="master")
    assert isinstance(explain(12345).error, ModbusError)  # type: ignore[arg-type]


def test_role_is_chosen_by_what_decodes() -> None:
    assert explain("01 03 04 00 03 55 71 F5 47").role == "response"
    assert explain("11 05 00 AC FF 00 4E 8B").role == "request"  # both decode: request first
    assert explain("11 05 00 AC FF 00 4E 8B", role="response").role == "response"


def test_html_escapes_content() -> None:
    d = explain(b":05\x80<b>\r\n", mode="ascii")
    table = d._repr_html_().split("</table>")[0]
    assert "<b>" not in table and "&lt;b&gt;" in table


def test_to_dict_shape() -> None:
    out = explain("01 18 00 00 00 05 01 03 02 04 D2").to_dict()
    assert json.loads(json.dumps(out)) == out
    assert out["mode"] == "tcp" and out["role"] == "response" and out["error"] is None
    assert out["frame"]["transaction_id"] == 280 and out["frame"]["fields"] == {"registers": [1234]}
    assert out["rows"][0] == {"offset": 0, "raw": "01 18", "field": "transaction identifier", "value": 280,
                              "meaning": out["rows"][0]["meaning"], "ok": True}
    bad = explain("01 03 00 00 00 01 85 0A").to_dict()
    assert bad["frame"] is None and bad["error_type"] == "CrcError"


# --- fuzzing: explain never raises, rows always cover the frame ---------------------------------------------
def _explain_everything(data: bytes) -> None:
    for mode in (None, *MODES):
        for role in (None, "request", "response"):
            d = explain(data, mode=mode, role=role)
            assert_covers(d)
            assert (d.frame is None) != (d.error is None)
            d.to_text()
            d._repr_html_()
            json.dumps(d.to_dict())


@FUZZ
@given(st.binary(max_size=80))
def test_random_bytes_never_raise(data: bytes) -> None:
    _explain_everything(data)


@FUZZ
@given(st.text(alphabet="0123456789ABCDEF:\r\nG ", max_size=40))
def test_random_ascii_text_never_raises(text: str) -> None:
    _explain_everything(text.encode())
    explain(text)


@st.composite
def mutated(draw) -> bytes:
    text, _mode, _role = draw(st.sampled_from(VECTORS))
    data = bytearray(parse_hex(text))
    for _ in range(draw(st.integers(0, 3))):
        index = draw(st.integers(0, len(data) - 1))
        data[index] ^= 1 << draw(st.integers(0, 7))
    action = draw(st.sampled_from(["none", "truncate", "extend"]))
    if action == "truncate":
        data = data[: draw(st.integers(0, len(data)))]
    elif action == "extend":
        data += draw(st.binary(min_size=1, max_size=10))
    return bytes(data)


@FUZZ
@given(mutated())
def test_mutated_vectors_never_raise(data: bytes) -> None:
    _explain_everything(data)


@FUZZ
@given(st.sampled_from(["rtu", "ascii", "tcp"]), st.integers(0, 247), st.integers(0, 0xFFFF),
       st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=125))
def test_generated_frames_dissect_cleanly(mode, unit, tid, registers) -> None:
    pdu = P.ReadHoldingRegistersResponse(registers=registers)
    frames = {"rtu": RtuFrame(unit, pdu), "ascii": AsciiFrame(unit, pdu), "tcp": TcpFrame(tid, unit, pdu)}
    frame = frames[mode]
    d = explain(frame.encode(), mode=mode)
    assert d.ok and d.frame == frame and d.role == "response"
    assert_covers(d)
    assert [r.value for r in d.rows if r.field.startswith("register ")] == list(registers)


# --- explain_pdu: the same table for a bare PDU ------------------------------------------------------------
PDUS = [  # one of each class, as notebook 02 shows them
    P.ReadCoilsRequest(address=19, count=37),
    P.ReadCoilsResponse(bits=[1, 0, 1, 1, 0, 0, 1, 1, 1, 0, 1]),
    P.ReadDiscreteInputsRequest(address=196, count=22),
    P.ReadDiscreteInputsResponse(bits=[0, 0, 1, 1, 0, 1, 0, 1]),
    P.ReadHoldingRegistersRequest(address=107, count=3),
    P.ReadHoldingRegistersResponse(registers=[555, 0, 100]),
    P.ReadInputRegistersRequest(address=8, count=1),
    P.ReadInputRegistersResponse(registers=[10]),
    P.WriteSingleCoilRequest(address=172, value=True),
    P.WriteSingleCoilResponse(address=172, value=False),
    P.WriteSingleRegisterRequest(address=1, value=3),
    P.WriteSingleRegisterResponse(address=1, value=3),
    P.WriteMultipleCoilsRequest(address=19, values=[1, 0, 1, 1, 0, 0, 1, 1, 1, 0]),
    P.WriteMultipleCoilsResponse(address=19, count=10),
    P.WriteMultipleRegistersRequest(address=1, values=[0x000A, 0x0102]),
    P.WriteMultipleRegistersResponse(address=1, count=2),
    P.ExceptionResponse(function=3, code=2),
]


@pytest.mark.parametrize("pdu", PDUS, ids=lambda p: type(p).__name__)
def test_explain_pdu_of_an_object_is_its_fields(pdu: P.Pdu) -> None:
    d = explain_pdu(pdu)
    assert (d.mode, d.role, d.pdu, d.frame, d.error, d.ok) == ("pdu", pdu.role, pdu, None, None, True)
    assert d.data == pdu.encode()
    assert [(r.offset, r.raw, r.field, r.value, r.meaning) for r in d.rows] == [
        (f.offset, f.raw, f.name, f.value, f.meaning) for f in pdu.fields()]
    assert_covers(d)
    assert_views(d)
    assert d.summary.startswith(f"PDU {pdu.role}: ")
    # the bytes give the same table (the role given: some requests and responses share their bytes)
    # (a bits response decodes to whole bytes of bits: the padding shows, so compare with the decoded PDU)
    again = explain_pdu(d.data, role=pdu.role)
    decoded = P.decode_pdu(d.data, pdu.role)
    assert again.ok and again.pdu == decoded and again.rows == explain_pdu(decoded).rows
    assert explain_pdu(d.data.hex(" "), role=pdu.role).rows == again.rows
    # in a notebook the object shows as that table
    assert pdu._repr_html_() == d._repr_html_()


def test_explain_pdu_text_and_dict() -> None:
    d = explain_pdu("03 06 02 2B 00 00 00 64")
    assert d.role == "response" and repr(d) == "<Dissection PDU response: Read Holding Registers, " \
                                               "registers [555, 0, 100]>"
    lines = d.to_text().splitlines()
    assert lines[0] == "PDU response: Read Holding Registers, registers [555, 0, 100]"
    assert lines[1].split() == ["offset", "bytes", "field", "value", "meaning"]
    assert lines[3].split()[:5] == ["1", "06", "byte", "count", "6"]
    out = d.to_dict()
    assert json.loads(json.dumps(out)) == out
    assert out["mode"] == "pdu" and out["frame"] is None
    assert out["pdu"] == {"function_code": 3, "pdu": "ReadHoldingRegistersResponse",
                          "fields": {"registers": [555, 0, 100]}}
    assert "pdu" not in explain("01 03 00 00 00 01 84 0A").to_dict()  # a frame's dict is unchanged


def test_explain_pdu_records_errors_and_still_shows_rows() -> None:
    d = explain_pdu("03 00 00 00 C8")  # 200 registers: too many
    assert not d.ok and d.pdu is None and d.role == "request"
    assert type(d.error).__name__ == "QuantityError" and "at bytes 3-4" in str(d.error)
    assert d.rows[0].field == "function code" and not d.rows[-1].ok
    assert_covers(d)
    assert_views(d)
    extra = explain_pdu("03 00 6B 00 03 FF", role="request")
    assert [r.field for r in extra.rows][-1] == "extra bytes" and extra.rows[-1].raw == b"\xff"
    assert explain_pdu("83 02").role == "response"  # only a response can start with 0x83
    assert explain_pdu(b"").error is not None and explain_pdu(b"").rows == []
    assert explain_pdu("zz").summary.startswith("PDU, not valid: ")
    with pytest.raises(ModbusError):
        explain_pdu("03 00 00 00 C8", strict=True)
    with pytest.raises(ConfigError):
        explain_pdu(P.ReadCoilsRequest(address=0, count=1), role="response")
    with pytest.raises(ConfigError):
        explain_pdu(b"\x03", role="master")


@FUZZ
@given(st.binary(max_size=40))
def test_explain_pdu_never_raises(data: bytes) -> None:
    for role in (None, "request", "response"):
        d = explain_pdu(data, role=role)
        assert_covers(d)
        assert (d.pdu is None) != (d.error is None)
        d.to_text()
        d._repr_html_()
        json.dumps(d.to_dict())
