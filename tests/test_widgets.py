"""The widgets, headless: driven the way ipywidgets' own tests drive widgets (set ``.value``, ``.click()``).

Every frame a panel shows must be the library's frame (VECTORS.md), every invalid input must end up on
the panel's message line, and nothing may raise into the notebook.
"""

from __future__ import annotations

import asyncio
import json
import re
from html import escape

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modbus_edu.crc import crc16, crc_bytes, lrc
from modbus_edu.explain import explain
from modbus_edu.framing import parse_hex
from modbus_edu.pdu import FunctionCode
from modbus_edu.values import format_registers
from modbus_edu.widgets import CrcExplorer, FrameBuilder, FrameDecoder, MeterDashboard, TestTool

# (mode, builder fields, expected frame as in VECTORS.md)
VECTORS = [
    ("rtu", dict(unit=1, function=3, address=0, count=1), "01 03 00 00 00 01 84 0A"),
    ("rtu", dict(unit=1, function=3, address=0, count=10), "01 03 00 00 00 0A C5 CD"),
    ("rtu", dict(unit=1, function=3, address=0, count=3), "01 03 00 00 00 03 05 CB"),
    ("rtu", dict(unit=1, function=3, role="response", registers="0x0003, 0x5571"),
     "01 03 04 00 03 55 71 F5 47"),
    ("rtu", dict(unit=1, function=3, role="exception", exception_code=2), "01 83 02 C0 F1"),
    ("rtu", dict(unit=1, function=16, address=1, values="0x000A, 0x0102"),
     "01 10 00 01 00 02 04 00 0A 01 02 92 30"),
    ("rtu", dict(unit=17, function=5, address=172, coil=True), "11 05 00 AC FF 00 4E 8B"),
    ("rtu", dict(unit=17, function=5, role="response", address=172, coil=True), "11 05 00 AC FF 00 4E 8B"),
    ("rtu", dict(unit=17, function=15, address=19, values="1011001110"), "11 0F 00 13 00 0A 02 CD 01 BF 0B"),
    ("rtu", dict(unit=17, function=1, address=19, count=37), "11 01 00 13 00 25 0E 84"),
    ("rtu", dict(unit=17, function=3, address=107, count=3), "11 03 00 6B 00 03 76 87"),
    ("ascii", dict(unit=5, function=6, address=0x1001, value=0x0200), ":050610010200E2"),
    ("ascii", dict(unit=5, function=6, role="response", address="0x1001", value="0x0200"), ":050610010200E2"),
    ("ascii", dict(unit=5, function=3, address=0x1000, count=2), ":050310000002E6"),
    ("ascii", dict(unit=5, function=3, role="response", registers="0xFF06, 0x0064"), ":050304FF0600648B"),
    ("tcp", dict(transaction_id=0x0118, unit=1, function=3, address=0, count=1),
     "01 18 00 00 00 06 01 03 00 00 00 01"),
    ("tcp", dict(transaction_id="0x0118", unit=1, function=3, role="response", registers="1234"),
     "01 18 00 00 00 05 01 03 02 04 D2"),
]
IDS = [f"{m}-{e.replace(' ', '')[:20]}" for m, _f, e in VECTORS]


def _bytes(expected: str) -> bytes:
    return parse_hex(expected)


# --- FrameBuilder ----------------------------------------------------------------------------------
@pytest.mark.parametrize(("mode", "fields", "expected"), VECTORS, ids=IDS)
def test_frame_builder_shows_the_vector_frame(mode, fields, expected):
    fb = FrameBuilder(mode=mode, **fields)
    want = _bytes(expected)
    assert fb.error is None, fb.message.text
    assert fb.frame == want
    assert fb.dissection is not None and fb.dissection.ok
    assert fb.adu is not None and fb.adu.encode() == want
    html = fb.frame_view.value
    assert " ".join(f"{b:02X}" for b in want) in html
    if mode == "ascii":
        assert expected in html  # the characters as a terminal shows them
    # one coloured span per dissection row, and the dissection table below
    assert html.count('class="mbe-field"') == len(fb.dissection.rows)
    assert "modbus-edu-dissection" in fb.dissection_view.value
    assert fb.message.kind == "ok"


@pytest.mark.parametrize(("mode", "fields", "expected"), VECTORS, ids=IDS)
def test_frame_builder_follows_changes_made_like_a_user(mode, fields, expected):
    """Start from the defaults and type the fields in, one ``.value`` at a time."""
    fb = FrameBuilder()
    fb.mode.value = mode
    fb.role.value = fields.get("role", "request")
    fb.function.value = fields["function"]
    for name, value in fields.items():
        if name in ("role", "function"):
            continue
        box = getattr(fb, name)
        box.value = value if isinstance(value, bool) or name == "exception_code" else str(value)
    assert fb.frame == _bytes(expected), fb.message.text


def test_frame_builder_shows_only_the_fields_a_function_needs():
    fb = FrameBuilder()
    assert fb.visible_fields() == ["unit", "address", "count"]
    hidden = ["value", "coil", "values", "bits", "registers", "exception_code", "transaction_id"]
    assert all(fb._rows[name].layout.display == "none" for name in hidden)  # each field with its error
    fb.mode.value = "tcp"
    assert fb.visible_fields() == ["unit", "transaction_id", "address", "count"]
    assert fb._rows["transaction_id"].layout.display != "none"
    fb.mode.value = "rtu"
    expected = {
        (1, "request"): ["address", "count"], (1, "response"): ["bits"],
        (2, "response"): ["bits"], (3, "response"): ["registers"], (4, "request"): ["address", "count"],
        (5, "request"): ["address", "coil"], (5, "response"): ["address", "coil"],
        (6, "request"): ["address", "value"], (15, "request"): ["address", "values"],
        (15, "response"): ["address", "count"], (16, "request"): ["address", "values"],
        (16, "response"): ["address", "count"], (3, "exception"): ["exception_code"],
    }
    for (function, role), names in expected.items():
        fb.function.value = function
        fb.role.value = role
        assert fb.visible_fields() == ["unit", *names], (function, role)
        for name in fb._field_map():
            assert (fb._rows[name].layout.display != "none") == (name in names), (function, role, name)
    fb.function.value = 15
    fb.role.value = "request"
    assert fb.values.description == "coil values"
    fb.function.value = 16
    assert fb.values.description == "register values"


def test_frame_builder_every_function_and_role_gives_a_frame_the_library_decodes():
    fb = FrameBuilder()
    for mode in ("rtu", "ascii", "tcp"):
        fb.mode.value = mode
        for fc in FunctionCode:
            fb.function.value = int(fc)
            for role in ("request", "response", "exception"):
                fb.role.value = role
                assert fb.frame, (mode, fc, role, fb.message.text)
                d = explain(fb.frame, mode, "request" if role == "request" else "response")
                # (a read-bits response decoded from bytes alone carries its padding bits too)
                assert d.ok and d.frame.encode() == fb.frame, (mode, fc, role)


@pytest.mark.parametrize(("field", "text", "words"), [
    ("count", "126", ["QuantityError", "125"]),
    ("count", "0", ["QuantityError"]),
    ("count", "126", ["QuantityError", "quantity"]),
    ("address", "abc", ["ValueFormatError", "address"]),
    ("address", "65535", ["AddressRangeError"]),
    ("address", "70000", ["address", "65535"]),
    ("unit", "300", ["unit"]),
    ("unit", "", ["unit", "empty"]),
])
def test_frame_builder_invalid_input_shows_the_library_error_in_place(field, text, words):
    fb = FrameBuilder(mode="rtu", unit=1, function=3, address=0, count=2)
    getattr(fb, field).value = text  # must not raise
    assert fb.frame == b""
    assert fb.error is not None and fb.dissection is None
    assert fb.message.kind == "error"
    error = fb.field_errors[field]  # beside the field it is about, in that field's words
    for word in words:
        assert word in error
    assert error not in fb.message.text  # once: the message line only points at the marked field
    label = fb._error_labels[field].value
    assert "color:#c92a2a" in label and label.count("&#9888;") == 1
    assert "mbe-invalid" in getattr(fb, field)._dom_classes and list(fb.field_errors) == [field]
    # the rest keeps its size and its last good content, greyed out
    assert "mbe-stale" in fb.frame_view.value and "mbe-stale" in fb.dissection_view.value
    getattr(fb, field).value = {"count": "2", "address": "0", "unit": "1"}[field]
    assert fb.frame == _bytes("01 03 00 00 00 02 C4 0B")
    assert fb.error is None and fb.field_errors == {} and fb._error_labels[field].value == ""
    assert "mbe-invalid" not in getattr(fb, field)._dom_classes


@pytest.mark.parametrize(("function", "role", "field", "text"), [
    (16, "request", "values", ""),
    (16, "request", "values", "1, 70000"),
    (16, "request", "values", ", ".join(["1"] * 124)),
    (15, "request", "values", "1, 2"),
    (1, "response", "bits", "yes, maybe"),
    (3, "response", "registers", "x"),
    (6, "request", "value", "65536"),
])
def test_frame_builder_bad_lists_and_values_never_raise(function, role, field, text):
    fb = FrameBuilder(function=function, role=role)
    getattr(fb, field).value = text
    assert fb.frame == b"" and fb.message.kind == "error" and fb.message.text
    assert list(fb.field_errors) == [field]


def test_frame_builder_builds_for_a_reserved_serial_unit_and_tcp_units():
    fb = FrameBuilder(mode="rtu", unit=250)  # reserved on a serial line, but some devices answer it
    assert fb.frame[0] == 250
    assert "reserved" in fb.field_notes["unit"] and fb.field_errors == {}  # said beside the unit, amber
    fb.mode.value = "tcp"
    assert fb.frame and fb.frame[6] == 250


# --- FrameDecoder -----------------------------------------------------------------------------------
@pytest.mark.parametrize(("mode", "fields", "expected"), VECTORS, ids=IDS)
def test_frame_decoder_decodes_the_vector_frame_back(mode, fields, expected):
    fd = FrameDecoder(expected)
    want = _bytes(expected)
    assert fd.frame == want
    assert fd.error is None and fd.dissection is not None and fd.dissection.ok, fd.message.text
    assert fd.dissection.mode == mode
    assert fd.dissection.frame.encode() == want
    # a write response echoes its request: only the chosen role tells them apart
    fd.role.value = {"exception": "response"}.get(fields.get("role"), fields.get("role", "request"))
    assert fd.dissection.frame == FrameBuilder(mode=mode, **fields).adu
    assert f"{mode.upper()} (detected: " in fd.message.text and fd.message.kind == "ok"
    assert "modbus-edu-dissection" in fd.dissection_view.value


def test_frame_decoder_takes_a_tcp_frame_with_a_swapped_length_for_tcp_and_says_why():
    fd = FrameDecoder("01 18 00 00 05 00 01 03 02 04 D2")  # the length 00 05 written low byte first
    assert fd.dissection.mode == "tcp" and fd.message.kind == "error"
    assert fd.message.text.startswith("TCP (detected: protocol 0 in bytes 2-3, and the length, read low "
                                      "byte first, counts the 5 bytes that follow): MbapError")
    assert "CrcError" not in fd.message.text


def test_frame_builder_to_frame_decoder_round_trip():
    fb = FrameBuilder(mode="rtu", unit=17, function=15, address=19, values="1011001110")
    fd = FrameDecoder()
    fd.text.value = fb.frame.hex(" ")
    assert fd.dissection.frame == fb.adu
    assert fd.dissection.frame.pdu.values == (True, False, True, True, False, False, True, True, True, False)


@pytest.mark.parametrize("text", [
    "01 03 00 00 00 01 84 0A", "010300000001840A", "0x01,0x03,0x00,0x00,0x00,0x01,0x84,0x0A",
    "01-03-00-00-00-01-84-0a", "  01 03 00 00\n00 01 84 0A  ",
])
def test_frame_decoder_accepts_common_spacings(text):
    fd = FrameDecoder(text)
    assert fd.frame == _bytes("01 03 00 00 00 01 84 0A")
    assert fd.dissection.ok
    assert "Read Holding Registers" in fd.message.text


def test_frame_decoder_shows_a_bad_crc_with_the_expected_value():
    fd = FrameDecoder("01 03 00 00 00 01 84 0B")
    assert fd.frame == _bytes("01 03 00 00 00 01 84 0B")
    assert fd.message.kind == "error"
    assert "CrcError" in fd.message.text and "84 0A" in fd.message.text and "0x0A84" in fd.message.text
    # the bytes are still dissected; the CRC row is marked
    assert fd.dissection.rows[-1].ok is False
    assert "border-bottom: 3px solid #c92a2a" in fd.frame_view.value


def test_frame_decoder_mode_and_role_can_be_chosen():
    fd = FrameDecoder("01 03 02 04 D2 3A D9")
    assert fd.dissection.role == "response"
    fd.role.value = "request"
    assert fd.message.kind == "error" and fd.dissection.role == "request"
    fd.role.value = "auto"
    fd.mode.value = "tcp"
    assert fd.message.kind == "error" and fd.dissection.mode == "tcp"
    fd.mode.value = "rtu"
    assert fd.dissection.ok and "(chosen)" in fd.message.text


@pytest.mark.parametrize("text", ["zz", "0x", "123", ":05 03 zz", "01 03", "\u00e9",
                                  "01 03 00 00 00 01 84 0A 00"])
def test_frame_decoder_errors_in_place_never_raise(text):
    fd = FrameDecoder()
    fd.text.value = text
    assert fd.message.kind == "error" and fd.error is not None
    assert fd.message.text


def test_frame_decoder_empty_text_asks_for_a_frame():
    fd = FrameDecoder()
    assert fd.frame == b"" and fd.dissection is None and "paste" in fd.message.text


# --- CrcExplorer ------------------------------------------------------------------------------------
@pytest.mark.parametrize("text", ["01 03 00 00 00 01", "31 32 33 34 35 36 37 38 39", "11 03 00 6B 00 03", ""])
def test_crc_explorer_final_value_matches_crc16(text):
    data = parse_hex(text) if text else b""
    cx = CrcExplorer(text)
    assert cx.data == data and cx.position == 0 and cx.register == 0xFFFF
    assert len(cx.steps) == 9 * len(data)
    cx.run_to_end.click()
    assert cx.register == crc16(data) == cx.result
    assert cx.wire == crc_bytes(data)
    if data:
        assert " ".join(f"{b:02X}" for b in crc_bytes(data)) in cx.result_view.value
        assert f"0x{crc16(data):04X}" in cx.result_view.value
    cx.method.value = "table"
    assert len(cx.steps) == len(data) and cx.position == 0
    cx.run_to_end.click()
    assert cx.register == crc16(data)


def test_crc_explorer_steps_bit_by_bit_and_byte_by_byte():
    cx = CrcExplorer("01 03 00 00 00 01")
    cx.next_bit.click()
    assert cx.position == 1 and cx.register == 0xFFFE  # 0xFFFF XOR 0x01
    step = re.sub("<[^>]+>", "", cx.step_view.value)
    assert "1111 1111 1111 1110" in step and "0xFFFE" in step
    cx.next_bit.click()  # LSB of 0xFFFE is 0: shift only
    assert cx.register == 0x7FFF and "no XOR" in cx.step_view.value
    cx.next_bit.click()  # LSB of 0x7FFF is 1: shift and XOR 0xA001
    assert cx.register == 0x3FFF ^ 0xA001
    assert "XOR 0xA001" in cx.step_view.value and "1010 0000 0000 0001" in cx.step_view.value
    cx.next_byte.click()
    assert cx.position == 9
    cx.next_byte.click()
    assert cx.position == 18
    cx.back.click()
    assert cx.position == 17
    cx.reset.click()
    assert cx.position == 0 and cx.back.disabled and cx.reset.disabled
    cx.run_to_end.click()
    assert cx.register == 0x0A84 and cx.next_bit.disabled and cx.next_byte.disabled
    assert "84 0A" in cx.result_view.value


def test_crc_explorer_table_method_shows_index_and_entry():
    cx = CrcExplorer("01 03 00 00 00 01", method="table")
    cx.next_bit.click()
    s = cx.steps[0]
    assert (s.index, s.table_value) == (0xFE, 0x8081)
    text = cx.step_view.value
    assert "table[0xFE]" in text and "0x8081" in text and "= 0xFE" in text
    assert "[FE] 8081" in text  # the table row, the entry used highlighted


def test_crc_explorer_lrc_mode():
    cx = CrcExplorer("05 06 10 01 02 00")
    cx.method.value = "lrc"
    assert len(cx.steps) == 6 and cx.register == 0
    cx.run_to_end.click()
    assert cx.result == lrc(parse_hex("05 06 10 01 02 00")) == 0xE2
    assert cx.wire == b"\xe2" and "0xE2" in cx.result_view.value and "&#x27;E2&#x27;" in cx.result_view.value


def test_crc_explorer_bad_hex_shows_an_error():
    cx = CrcExplorer()
    cx.text.value = "01 0G"
    assert cx.message.kind == "error" and "not a hex digit" in cx.message.text
    assert cx.steps == [] and cx.data == b"" and "mbe-invalid" in cx.text._dom_classes
    assert cx.children.index(cx.message) == cx.children.index(cx.text) + 1  # the error under its field
    assert "mbe-stale" in cx.step_view.value  # the last good step stays, greyed out
    cx.next_bit.click()
    cx.run_to_end.click()  # nothing to do, nothing raised
    cx.text.value = "01"
    assert cx.message.kind == "info" and len(cx.steps) == 9 and "mbe-invalid" not in cx.text._dom_classes
    assert "mbe-stale" not in cx.step_view.value


@pytest.mark.parametrize("method", ["bitwise", "table", "lrc"])
def test_crc_explorer_labels_never_run_into_their_values(method):
    cx = CrcExplorer(method=method)
    text = re.sub(r"<[^>]+>", "", cx.step_view.value)
    assert re.search(r"start (register|running sum) +[01]{4} ", text), text
    for _ in range(3):
        cx.step(1)
        for line in re.sub(r"<[^>]+>", "", cx.step_view.value).splitlines():
            assert not re.search(r"[g-wyz\]][01]{4} ", line), line  # "register1111", "sum0000"


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=24))
def test_crc_explorer_agrees_with_crc16_on_any_bytes(data):
    cx = CrcExplorer(data)
    cx.run_to_end.click()
    assert cx.register == crc16(data)
    cx.method.value = "table"
    cx.run_to_end.click()
    assert cx.register == crc16(data)


# --- TestTool -----------------------------------------------------------------------------------------
def _pair(mode="rtu", **master_kwargs):
    roles = ("rtu_slave", "rtu_master") if mode == "rtu" else ("tcp_server", "tcp_client")
    slave = TestTool(roles[0], unit=1, length=10)
    slave.fill_increment(start=100, step=10)
    master = TestTool(roles[1], partner=slave, unit=1, address=0, length=10, **master_kwargs)
    return master, slave


def _adds_up(tool):
    c = tool.counts
    return c["polls"] == c["valid"] + c["timeouts"] + c["errors"]


@pytest.mark.parametrize("mode", ["rtu", "tcp"])
def test_two_test_tools_poll_over_loopback_and_the_counters_add_up(mode):
    master, slave = _pair(mode)
    assert master.connected and slave.connected and master.partner is slave and slave.partner is master
    results = master.run_polls(5)
    assert results[-1] == [100, 110, 120, 130, 140, 150, 160, 170, 180, 190]
    assert master.values == slave.values
    assert master.counts == {"polls": 5, "valid": 5, "timeouts": 0, "errors": 0}
    assert slave.slave.counters.requests == 5 and slave.slave.counters.responses == 5
    assert master.master.stats.valid_responses == 5
    # the grid shows what was read, the counters panel says so
    assert [c.value for c in master._cells] == [str(v) for v in range(100, 200, 10)]
    assert ">5</b>" in master.counters.value
    assert 'class="mbe-tt-request-count">5<' in slave.request_count.value
    # polls are spaced by the interval on the virtual clock
    assert master.clock is slave.clock and master.clock.now >= 4 * master.interval.value

    slave.stop()  # the slave stops answering: the master times out
    master.run_polls(3)
    assert master.counts == {"polls": 8, "valid": 5, "timeouts": 3, "errors": 0}
    assert "ModbusTimeoutError" in master.message.text
    slave.start()
    master.function.value = 3
    master.length.value = 126  # the library refuses the request: an error, counted
    master.poll_once()
    assert master.counts["errors"] == 1 and "QuantityError" in master.message.text
    master.length.value = 10
    master.poll_once()
    assert master.counts == {"polls": 10, "valid": 6, "timeouts": 3, "errors": 1}
    assert _adds_up(master)
    master.reset_button.click()
    assert master.counts == {"polls": 0, "valid": 0, "timeouts": 0, "errors": 0}
    assert master.master.stats.requests == 0


def test_tcp_client_transaction_id_goes_up_by_one_per_request():
    master, slave = _pair("tcp", transaction_id=0x0118)
    assert master.transaction_id.layout.display != "none"
    assert slave.transaction_id.layout.display == "none"
    master.read_button.click()
    first = master.master.log[0]
    assert first.data[:2] == b"\x01\x18"
    master.read_button.click()
    assert master.master.log.search(direction="tx")[1].data[:2] == b"\x01\x19"
    assert master.transaction_id.value == 0x011A


def test_master_writes_the_selected_cell_with_fc06_and_a_range_with_fc16():
    master, slave = _pair()
    master.poll_once()
    master.selected.value = 3
    assert master.write_value.value == "130"
    master.write_value.value = "777"
    master.write_one_button.click()
    assert slave.bank.holding_registers[3] == 777
    tx = master.master.log.search(direction="tx")
    assert tx[-1].function == 6 and "FC06" in master.message.text
    master.set_cell(4, "1000")
    master.set_cell(5, "1001")
    assert slave.bank.holding_registers[4] == 140  # edited locally only, not yet written
    master.write_count.value = 2
    master.selected.value = 4
    master.write_many_button.click()
    assert slave.bank.holding_registers.read(3, 3) == [777, 1000, 1001]
    assert master.master.log.search(direction="tx")[-1].function == 16
    # a 32-bit float typed into the grid takes two registers: written with FC16
    master.display.value = "float32_ABCD"
    assert master.write_cell(6, "1.5")
    assert slave.bank.holding_registers.read(6, 2) == [0x3FC0, 0x0000]
    # coils: FC05 and FC15
    master.function.value = 1
    assert master.write_one_button.description == "write cell (FC05)"
    assert master.write_cell(2, "1")
    assert slave.bank.coils[2] is True
    master.set_cell(3, "1")
    assert master.write_cells(0, 4)
    assert slave.bank.coils.read(0, 4) == [False, False, True, True]
    # input registers cannot be written by a master: said, not raised
    master.function.value = 4
    assert not master.write_cell(0, "1")
    assert "cannot write the input registers" in master.message.text


def test_polling_with_a_write_function_sends_the_grid():
    master, slave = _pair()
    master.function.value = 16
    master.fill_increment(start=7, step=0)
    master.poll_once()
    assert slave.bank.holding_registers.read(0, 10) == [7] * 10
    assert master.counts["valid"] == 1


def test_display_formats_follow_values_format_registers():
    master, slave = _pair()
    slave.set_cell(0, 0x4142)
    master.poll_once()
    regs = master.values
    for fmt in ("hex", "binary", "signed", "ascii_char", "ascii_value", "uint32_CDAB", "float32_DCBA",
                "float64_ABCD"):
        master.display.value = fmt
        assert [c.value for c in master._cells] == format_registers(regs, fmt)
    master.display.value = "ascii_char"
    assert master._cells[0].value == "AB"


def test_editing_a_slave_cell_is_served_at_once():
    master, slave = _pair()
    slave.display.value = "signed"
    slave._cells[2].value = "-2"  # as if typed in the page
    assert slave.bank.holding_registers[2] == 0xFFFE
    master.poll_once()
    assert master.values[2] == 0xFFFE
    slave._cells[3].value = "not a number"
    assert slave.grid_message.kind == "error" and slave.bank.holding_registers[3] == 130
    assert slave.message.kind != "error"  # said once, under the grid it is about
    assert slave._cells[3].value == "130"  # the cell shows the table again
    slave._cells[3].value = "131"
    assert slave.grid_message.text == "" and slave.bank.holding_registers[3] == 131


def test_dummy_data_random_fill_is_seeded_and_auto_fill_runs_on_the_wire_clock():
    a, b = TestTool("rtu_slave", seed=7), TestTool("rtu_slave", seed=7)
    assert a.random_fill() == b.random_fill()
    assert a.values == b.values
    master, slave = _pair(interval=1.0)
    slave.auto_interval.value = 1.0
    slave.auto_fill_start()
    seen = {tuple(v) for v in master.run_polls(4)}
    assert len(seen) == 4  # a new random set every virtual second
    slave.auto_fill_stop()
    seen = {tuple(v) for v in master.run_polls(3)}
    assert len(seen) == 1
    slave.increment.value = False
    slave.fill_start.value = 5
    slave.fill_button.click()
    assert slave.values == [5] * 10


def test_logs_have_timestamps_search_newest_on_top_and_clear():
    master, slave = _pair()
    master.run_polls(3)
    tx, rx = master.tx_log.value, master.rx_log.value
    assert "TX log (sent) (3)" in tx and "RX log (received) (3)" in rx
    assert "01 03 00 00 00 0A C5 CD" in tx and "01 03 14 00 64" in rx
    times = [float(t) for t in re.findall(r"^\s*(\d+\.\d{6})\s+tx", tx, re.M)]
    assert times == sorted(times, reverse=True)  # newest on top
    master.newest_on_top.value = False
    times = [float(t) for t in re.findall(r"^\s*(\d+\.\d{6})\s+tx", master.tx_log.value, re.M)]
    assert times == sorted(times) and times[0] == 0.0
    assert "RX log (received) (3)" in slave.tx_log.value.replace("TX log (sent)", "RX log (received)")
    master.search.value = "no such thing"
    assert "(0)" in master.tx_log.value and "(empty)" in master.tx_log.value
    master.search.value = "c5 cd"
    assert "TX log (sent) (3)" in master.tx_log.value and "RX log (received) (0)" in master.rx_log.value
    master.clear_button.click()
    assert len(master.master.log) == 0 and "(0)" in master.tx_log.value


def test_save_and_load_round_trip(tmp_path):
    tool = TestTool("tcp_client", name="bench", host="127.0.0.1", port=1502, unit=7, address=100, length=20,
                    function=4, transaction_id=42, interval=0.5, continuous=False, display="float32_CDAB",
                    fill_start=3, fill_step=2, auto_interval=2.0, newest_on_top=False, seed=11, timeout=0.25)
    path = tool.save_config(tmp_path / "tool.json")
    assert path is not None and json.loads(path.read_text())["role"] == "tcp_client"
    other = TestTool()
    assert other.load_config(path)
    assert other.config() == tool.config()
    assert other.role_info.title == "TCP client"
    # to and from a dict, and a new tool from a saved configuration
    third = TestTool.from_config(tool.config())
    assert third.config() == tool.config()
    fourth = TestTool.from_config(path)
    assert fourth.config() == tool.config()
    # the button uses the path field
    other.config_path.value = str(tmp_path / "button.json")
    other.save_button.click()
    fifth = TestTool()
    fifth.config_path.value = str(tmp_path / "button.json")
    fifth.load_button.click()
    assert fifth.config() == tool.config()


@pytest.mark.parametrize("bad", [
    {"colour": "red"}, {"role": "plc"}, {"display": "decimal"}, {"baudrate": 12345}, {"unit": "one"}, [1, 2],
])
def test_load_config_rejects_bad_settings_on_the_message_line(bad):
    tool = TestTool()
    before = tool.config()
    assert tool.load_config(bad) is False
    assert tool.message.kind == "error" and "ConfigError" in tool.message.text
    assert tool.config() == before


def test_load_config_from_a_missing_or_broken_file(tmp_path):
    tool = TestTool()
    assert not tool.load_config(tmp_path / "missing.json") and "cannot read" in tool.message.text
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    assert not tool.load_config(broken) and "not valid JSON" in tool.message.text
    assert tool.save_config(tmp_path / "no" / "such" / "dir.json") is None and tool.message.kind == "error"


def test_invalid_use_shows_an_error_and_raises_nothing():
    master = TestTool("rtu_master")
    assert master.poll_once() is None and "not connected" in master.message.text
    master.read_button.click()
    master.start_button.click()
    master.write_one_button.click()
    other_master = TestTool("rtu_master")
    assert master.connect(other_master) is False and "cannot talk" in master.message.text
    tcp_server = TestTool("tcp_server")
    assert master.connect(tcp_server) is False and "different modes" in master.message.text
    assert master.connect() is False and "partner" in master.message.text
    assert master.run_polls(-1) == [] and master.message.kind == "error"
    slave = TestTool("rtu_slave")
    assert slave.poll_once() is None and slave.message.kind == "warn"
    slave.unit.value = 0  # the broadcast address: no slave owns it (the library says so)
    assert slave.message.kind == "error" and "broadcast" in slave.message.text
    bad = TestTool("no_such_role")
    assert "unknown role" in bad.message.text and bad.role.value == "rtu_master"
    # a TCP client with nothing listening: the library's LinkError, on the message line
    client = TestTool("tcp_client", connection="tcp", host="127.0.0.1", port=1, timeout=0.5)
    assert client.connect() is False and "LinkError" in client.message.text
    assert not client.connected


def test_colour_per_role_and_role_change():
    roles = ("rtu_master", "rtu_slave", "tcp_client", "tcp_server")
    borders = {TestTool(role).layout.border for role in roles}
    assert len(borders) == 4
    tool = TestTool("rtu_master")
    assert "mbe-role-rtu_master" in tool._dom_classes
    tool.role.value = "tcp_server"
    assert "mbe-role-tcp_server" in tool._dom_classes and "mbe-role-rtu_master" not in tool._dom_classes
    assert tool.slave is not None and tool.read_button.layout.display == "none"
    assert [v for _label, v in tool.connection.options] == ["loopback", "tcp"]


def test_disconnect_from_either_side():
    master, slave = _pair()
    master.poll_once()
    slave.disconnect_button.click()
    assert not master.connected and not slave.connected and master.partner is None
    assert master.poll_once() is None and "not connected" in master.message.text
    assert master.connect(slave)
    assert master.poll_once() == list(range(100, 200, 10))


def test_continuous_polling_runs_on_the_asyncio_loop():
    master, slave = _pair(interval=0.01)

    async def scenario():
        assert master.start()
        assert master.polling and master.start_button.disabled and not master.stop_button.disabled
        ticks = 0
        for _ in range(500):  # the loop keeps running while the tool polls: it does not block it
            await asyncio.sleep(0.01)
            ticks += 1
            if master.counts["polls"] >= 3:
                break
        master.stop()
        await asyncio.sleep(0)
        assert ticks >= 2

    asyncio.run(scenario())
    assert not master.polling
    polls = master.counts["polls"]
    assert polls >= 3 and master.counts["valid"] == polls and slave.slave.counters.requests == polls
    # without a running loop, start() says so
    assert master.start() is False and "asyncio" in master.message.text
    # "continuous" unticked: one poll, then the task ends by itself
    master.continuous.value = False

    async def once():
        master.start()
        await asyncio.sleep(0.05)

    asyncio.run(once())
    assert master.counts["polls"] == polls + 1 and not master.polling


def test_real_tcp_server_and_client_on_127_0_0_1():
    server = TestTool("tcp_server", connection="tcp", host="127.0.0.1", port=0, unit=1, length=4)
    server.fill_increment(start=1, step=1)
    try:
        assert server.connect(), server.message.text
        port = server.port.value
        assert port > 0
        client = TestTool("tcp_client", connection="tcp", host="127.0.0.1", port=port, unit=1, length=4,
                          timeout=2.0)
        assert client.connect(), client.message.text
        assert client.poll_once() == [1, 2, 3, 4]
        assert client.counts == {"polls": 1, "valid": 1, "timeouts": 0, "errors": 0}
        client.disconnect()
    finally:
        server.disconnect()
    assert server.server is None


def test_frame_builder_values_field_remembers_coils_and_registers():
    fb = FrameBuilder(function=16, values="1, 2, 3")
    assert fb.frame == FrameBuilder(function=16, values=[1, 2, 3]).frame
    fb.function.value = 15
    assert fb.values.value == "1, 0, 1, 1" and fb.error is None
    fb.values.value = "1, 1"
    fb.function.value = 16
    assert fb.values.value == "1, 2, 3"
    fb.function.value = 15
    assert fb.values.value == "1, 1" and fb.pdu.values == (True, True)


# --- MeterDashboard -------------------------------------------------------------------------------------
def test_meter_dashboard_reads_003s_trials_scaled_as_table_6():
    from modbus_edu.devices import TRIALS, PowerMeter

    for trial in (1, 2):
        dash = MeterDashboard(PowerMeter(unit=1, trial=trial))
        assert dash.master.link.timing.baudrate == 19200  # the meter's own line settings (003: 8N1)
        values = dash.read_once()
        for name, expected in TRIALS[trial].items():
            assert values[name] == pytest.approx(expected)
        dash.read_button.click()
        assert dash.counts == {"reads": 2, "valid": 2, "timeouts": 0, "errors": 0}
    rows = dict(dash.table_rows())
    assert rows["Phase voltage - VL1"] == "412.6 V" and rows["Current - AL1"] == "288.9 A"
    assert rows["Power factor - PF1"] == "0.60"
    dash._render()
    assert "412.6 V" in dash.table.value and "40001" in dash.table.value


def test_meter_dashboard_trends_on_the_virtual_clock():
    from modbus_edu.devices import PowerMeter

    dash = MeterDashboard(PowerMeter(unit=1, trial=1, live=True), interval=2.0)
    out = dash.run(30)
    assert len(out) == 30 and all(v is not None for v in out)
    times, volts = dash.series("VL1")
    assert times[0] == 0.0 and times[-1] == pytest.approx(58.0)  # one reading every 2 s of line time
    assert len(set(volts)) > 1 and all(395 < v < 412 for v in volts)  # drifting around 403.6 V
    assert dash.plot_png.startswith(b"\x89PNG") and dash.image.png == dash.plot_png
    before = dash.plot_png
    dash.plot_group.value = "A"
    assert dash.plot_png != before
    dash.clear_button.click()
    assert dash.history == [] and dash.counts["reads"] == 0


def test_meter_dashboard_errors_are_counted_and_shown():
    from modbus_edu.devices import PowerMeter

    dash = MeterDashboard(PowerMeter(unit=2), unit=3, timeout=0.05)  # nobody answers unit 3
    assert dash.read_once() is None
    assert dash.counts["timeouts"] == 1 and "ModbusTimeoutError" in dash.message.text
    assert "timed out" in dash.status.value  # the status says so too, not a plain "stopped"
    assert [dash.tabs.get_title(i) for i in range(2)] == ["trend", "values"]
    assert dash.table.layout.overflow == "auto"  # the table scrolls in its own (tabbable) view
    wrong = MeterDashboard("not a meter")
    assert "ConfigError" in wrong.message.text and wrong.read_once() is None
    assert wrong.run(-1) == [] and wrong.message.kind == "error"


def test_meter_dashboard_through_a_master_and_periodic_reading():
    from modbus_edu.devices import PowerMeter
    from modbus_edu.links import loopback_serial
    from modbus_edu.master import Master

    meter = PowerMeter(unit=1, trial=1)
    dash = MeterDashboard(Master(loopback_serial(meter, baudrate=19200)), interval=0.01)

    async def scenario():
        assert dash.start()
        for _ in range(500):
            await asyncio.sleep(0.01)
            if dash.counts["valid"] >= 2:
                break
        dash.stop()

    asyncio.run(scenario())
    assert dash.counts["valid"] >= 2 and not dash.start_button.disabled
    assert dash.start() is False and "asyncio" in dash.message.text


def test_meter_dashboard_without_a_source_reads_a_simulated_meter():
    dash = MeterDashboard()
    assert dash.device is not None and dash.read_once()["VL1"] == pytest.approx(403.6, abs=3)


def test_rtu_master_tool_on_a_pyserial_url():
    """The serial path: the master tool opens ``socket://`` (a serial line tunnelled through TCP) to a
    slave served by the library's SerialServer on 127.0.0.1."""
    from modbus_edu.links.serial import SerialServer, TcpSerialPort
    from modbus_edu.slave import Slave

    slave = Slave(unit=1)
    slave.bank.holding_registers.write(0, [11, 22, 33])
    with SerialServer(slave, TcpSerialPort("127.0.0.1", 0), baudrate=19200) as server:
        host, port = server.port.address
        master = TestTool("rtu_master", connection="serial", url=f"socket://{host}:{port}", baudrate=19200,
                          unit=1, address=0, length=3, timeout=2.0)
        assert master.serial_box.layout.display != "none" and master.tcp_box.layout.display == "none"
        assert master.connect(), master.message.text
        try:
            assert master.poll_once() == [11, 22, 33]
            assert master.write_cell(1, "99")
            assert slave.bank.holding_registers[1] == 99
            assert master.counts == {"polls": 1, "valid": 1, "timeouts": 0, "errors": 0}
        finally:
            master.disconnect()
    assert not master.connected


def test_tx_and_rx_lamps_show_the_last_exchange():
    """Source 000's TX/RX indicators: both light on an answered poll, only TX when nobody answers."""
    slave = TestTool(role="rtu_slave", unit=1, length=4)
    master = TestTool(role="rtu_master", partner=slave, unit=1, address=0, length=4)
    assert master.lamps == {"tx": False, "rx": False}
    master.poll_once()
    assert master.lamps == {"tx": True, "rx": True}
    assert slave.lamps == {"tx": True, "rx": True}  # the slave received a request and sent an answer
    assert "mbe-tt-lamp-tx mbe-tt-lamp-on" in master.counters.value
    master.refresh()  # nothing new on the wire: the lamps go dark
    assert master.lamps == {"tx": False, "rx": False}
    master.unit.value = 7  # no slave answers unit 7
    master.poll_once()
    assert master.lamps == {"tx": True, "rx": False}
    assert master.counts["timeouts"] == 1


# --- status lines say how things are now (issue 12) ------------------------------------------------------
def _status_text(tool: TestTool) -> str:
    return re.sub(r"<[^>]+>", "", tool.status.value).replace("&#9679;", "").strip()


def test_a_master_whose_request_timed_out_is_not_shown_as_plainly_connected():
    slave = TestTool("rtu_slave", unit=1, length=4)
    master = TestTool("rtu_master", partner=slave, unit=1, length=4, timeout=0.2)
    master.poll_once()
    assert master.last_outcome == "valid" and "#2b6e35" in master.status.value
    assert _status_text(master).startswith("connected")
    slave.stop()  # the slave falls silent
    master.poll_once()
    assert master.last_outcome == "timeout"
    assert "timed out" in _status_text(master) and "#2b6e35" not in master.status.value
    slave.start()
    master.poll_once()
    assert "timed out" not in _status_text(master) and "#2b6e35" in master.status.value
    master.disconnect()
    assert _status_text(master) == "not connected"


def test_a_message_about_the_past_clears_when_traffic_goes_by():
    slave = TestTool("rtu_slave", unit=1, length=4)
    master = TestTool("rtu_master", partner=slave, unit=1, length=4)
    slave.auto_fill_start()
    assert "every 1 s" in slave.auto_state.value and slave.auto_start_button.disabled
    slave.auto_fill_stop()
    assert slave.message.text == "auto fill stopped" and "auto fill: off" in slave.auto_state.value
    assert not slave.auto_start_button.disabled and slave.auto_stop_button.disabled
    master.poll_once()
    assert slave.message.text == ""  # the stale line went; the state beside the buttons stays "off"
    assert "auto fill: off" in slave.auto_state.value
    slave.unit.value = 0  # an error is not stale: it stays until it is fixed
    master.poll_once()
    assert slave.message.kind == "error"


def test_the_cells_field_follows_the_grid_length():
    master = TestTool("rtu_master", length=4)
    assert master.write_count.value == 4 and len(master._cells) == 4
    master.length.value = 7
    assert master.write_count.value == 7 and len(master._cells) == 7


def test_the_test_tool_is_laid_out_in_tabs_and_every_button_says_what_it_does():
    tool = TestTool("rtu_master")
    assert [tool.tabs.get_title(i) for i in range(4)] == ["connection", "data", "traffic", "settings"]
    assert tool.tx_log.layout.overflow == "auto" and tool.rx_log.layout.overflow == "auto"
    assert tool.grid.layout.overflow == "auto"
    buttons = [w for w in vars(tool).values() if isinstance(w, type(tool.start_button))]
    assert len(buttons) >= 14
    for b in buttons:
        assert b.tooltip and (b.tooltip != b.description or b in (tool.start_button, tool.stop_button)), b


# --- a saved notebook keeps no widget state: each panel shows its picture (issues 12 and 20) ------------
PANELS = {
    "builder": lambda: FrameBuilder(mode="rtu", unit=17, function=3, address=107, count=3),
    "decoder": lambda: FrameDecoder("01 03 00 00 00 01 84 0B"),
    "crc": lambda: CrcExplorer("01 03 00 00 00 01"),
    "dashboard": lambda: MeterDashboard(),
    "tool": lambda: TestTool("tcp_server", name="meter"),
}


@pytest.mark.parametrize("make", PANELS.values(), ids=PANELS.keys())
def test_a_panel_output_says_what_it_is_and_to_run_the_cell(make):
    panel = make()
    bundle = panel._repr_mimebundle_()
    text = bundle["text/plain"]
    assert "panel" in text and text.endswith("run this cell to use it]")
    assert type(panel).__name__ in repr(panel)  # repr() stays the live summary for code
    html = bundle["text/html"]
    assert html.count("run this cell to use it") == 1 and escape(panel.static_text()) in html
    assert "application/vnd.jupyter.widget-view+json" in bundle  # the live panel, preferred when it exists
    # a picture, inert: nothing to type into or click, no script
    assert not re.search(r"<(input|select|textarea|button|script)\b", html, re.I), html[:300]
    if isinstance(panel, TestTool):
        assert "TCP server 'meter'" in text
        panel.disconnect(quiet=True)


def test_a_panel_picture_shows_its_fields_and_the_library_s_frame():
    fb = PANELS["builder"]()
    html = fb._repr_mimebundle_()["text/html"]
    assert "11 03 00 6B 00 03 76 87" in html           # the frame of VECTORS.md, as the library built it
    assert fb.dissection_view.value in html             # the library's dissection table, as on screen
    for label, value in (("address", "107"), ("quantity", "3"), ("unit (slave id)", "17")):
        field = rf">{re.escape(label)}</span><span class=\"mbe-picture-field\"[^>]*>{value}<"
        assert re.search(field, html), label
    assert "transaction id" not in html                 # hidden on RTU, so not in the picture either
    assert "03 Read Holding Registers" in html          # a dropdown shows its choice
    fb.mode.value = "tcp"                                # the picture is of the panel as it is now
    html = fb._repr_mimebundle_()["text/html"]
    assert "transaction id" in html and "00 01 00 00 00 06 11 03 00 6B 00 03" in html

    cx = PANELS["crc"]()
    cx.run_to_end.click()
    html = cx._repr_mimebundle_()["text/html"]
    assert "CRC = 0x0A84" in html and "84 0A" in html and "CRC-16 bit by bit" in html

    fd = PANELS["decoder"]()
    html = fd._repr_mimebundle_()["text/html"]
    assert "01 03 00 00 00 01 84 0B" in html and "CrcError" in html

    tool = TestTool("rtu_master", unit=7)
    html = tool._repr_mimebundle_()["text/html"]
    for title in ("connection", "data", "traffic", "settings"):
        assert f">{title}</span>" in html                # the tab bar; the open tab's controls below
    assert ">unit (slave id)</span>" in html and ">7<" in html


@pytest.mark.parametrize("output_type", ["execute_result", "display_data"])
def test_executed_notebooks_keep_no_widget_state_but_each_panel_s_picture(output_type):
    import nbformat

    from modbus_edu.course import WIDGET_VIEW, strip_widget_state

    panel = FrameBuilder()
    nb = nbformat.v4.new_notebook()
    nb.metadata["widgets"] = {"application/vnd.jupyter.widget-state+json": {"state": {}}}
    cell = nbformat.v4.new_code_cell("FrameBuilder()")
    bundle = panel._repr_mimebundle_()
    cell.outputs = [nbformat.v4.new_output(output_type, data=dict(bundle))]
    nb.cells.append(cell)
    assert strip_widget_state(nb) == 1
    data = cell.outputs[0]["data"]
    assert "widgets" not in nb.metadata and WIDGET_VIEW not in data
    assert "run this cell to use it" in data["text/plain"]
    assert data["text/html"] == bundle["text/html"] and "run this cell to use it" in data["text/html"]
    nbformat.validate(nb)


# --- the panels follow the typing (issue 20) -------------------------------------------------------------
def _type(box, text: str) -> None:
    """What the page sends while a learner types ``text``: the box's value after each key."""
    for i in range(len(text) + 1):
        box.set_state({"value": text[:i]})


def _counting(panel) -> list:
    calls: list = []
    apply = panel.typing.apply

    def counted():
        calls.append(1)
        apply()

    panel.typing.apply = counted
    return calls


TYPED = [
    ("builder", lambda: FrameBuilder(unit=1, function=3, address=0, count=1), "count", "5",
     lambda p: p.frame.hex(" ").upper(), "01 03 00 00 00 05 85 C9"),
    ("decoder", lambda: FrameDecoder(""), "text", "11 03 00 6B 00 03 76 87",
     lambda p: p.dissection and p.dissection.summary,
     "RTU request: unit 17, Read Holding Registers, address 107, count 3"),
    ("crc", lambda: CrcExplorer(""), "text", "01 03 00 00 00 01",
     lambda p: (len(p.steps), p.wire.hex(" ").upper()), (54, "84 0A")),
]


@pytest.mark.parametrize(("make", "field", "typed", "seen", "want"), [t[1:] for t in TYPED],
                         ids=[t[0] for t in TYPED])
def test_typing_in_the_page_updates_the_panel_after_a_pause(make, field, typed, seen, want):
    from modbus_edu.widgets.common import TYPING_DELAY

    async def learner():
        panel = make()
        box = getattr(panel, field)
        assert box.continuous_update is True  # the page sends every keystroke
        before = seen(panel)
        calls = _counting(panel)
        _type(box, typed)
        assert panel.typing.pending and seen(panel) == before and not calls   # still typing
        await asyncio.sleep(TYPING_DELAY * 3)   # the pause: its timer is due first, whatever the load
        assert not panel.typing.pending and seen(panel) == want
        assert len(calls) == 1                  # one update for the whole word, not one per key
        return panel

    asyncio.run(asyncio.wait_for(learner(), timeout=10))


def test_an_incomplete_field_shows_its_message_beside_it_while_typing():
    async def learner():
        fb = FrameBuilder(unit=1, function=3, address=0, count=1)
        _type(fb.address, "0x")
        assert fb.typing.flush()                           # deterministic: apply what waits now
        assert "address" in fb.field_errors and "'0x' is not a whole number" in fb.field_errors["address"]
        label = fb._error_labels["address"]
        assert label.layout.display != "none" and "not a whole number" in label.value
        assert "mbe-invalid" in fb.address._dom_classes and fb.frame == b""
        assert "mbe-stale" in fb.frame_view.value and "01 03 00 00 00 01 84 0A" in fb.frame_view.value
        _type(fb.address, "0x6B")
        assert fb.typing.flush() and not fb.typing.flush()  # nothing left to apply the second time
        pdu = bytes.fromhex("01 03 00 6B 00 01")
        assert fb.field_errors == {} and fb.frame == pdu + crc_bytes(pdu)

        fd = FrameDecoder("")
        _type(fd.text, "01 0")
        fd.typing.flush()
        assert fd.message.kind == "error" and "mbe-invalid" in fd.text._dom_classes
        cx = CrcExplorer("")
        _type(cx.text, "01 0G")
        cx.typing.flush()
        assert cx.message.kind == "error" and "mbe-invalid" in cx.text._dom_classes and cx.steps == []

    asyncio.run(asyncio.wait_for(learner(), timeout=10))


def test_a_value_set_from_code_or_chosen_in_a_list_applies_at_once():
    async def learner():
        fb = FrameBuilder(unit=1, function=3, address=0, count=1)
        fb.count.value = "2"                  # code: no waiting, the next line sees the frame
        assert not fb.typing.pending and fb.frame.hex(" ") == "01 03 00 00 00 02 c4 0b"
        _type(fb.count, "3")
        assert fb.typing.pending
        fb.mode.set_state({"index": 2})       # TCP chosen in the page: at once, with the typed text
        assert not fb.typing.pending and fb.frame.hex(" ") == "00 01 00 00 00 06 01 03 00 00 00 03"

    asyncio.run(asyncio.wait_for(learner(), timeout=10))
    fb = FrameBuilder(unit=1, function=3, address=0, count=1)
    _type(fb.count, "4")                      # no running loop (a script): typed text applies at once
    assert not fb.typing.pending and fb.frame.hex(" ") == "01 03 00 00 00 04 44 09"


def test_frame_decoder_says_each_error_once_under_its_field():
    fd = FrameDecoder("01 03 00 00 00 01 84 0B")  # a CRC one bit off
    assert fd.message.kind == "error" and "CrcError" in fd.message.text
    assert "CrcError" not in fd.dissection_view.value  # the table marks the row; the words are said once
    assert fd.children.index(fd.message) == fd.children.index(fd.text) + 1
    fd.text.value = "01 03 00 00 00 01 84 0A"
    good = fd.dissection_view.value
    fd.text.value = "01 0G"
    assert "mbe-invalid" in fd.text._dom_classes and fd.message.text.count("not a hex digit") == 1
    assert "mbe-stale" in fd.dissection_view.value and good in fd.dissection_view.value
    fd.text.value = "01 03 00 00 00 01 84 0A"
    assert "mbe-invalid" not in fd.text._dom_classes and fd.dissection_view.value == good


def test_panel_fields_follow_the_typing_and_the_test_tool_s_numbers_apply_on_enter():
    fb = FrameBuilder()
    for box in (fb.unit, fb.transaction_id, fb.address, fb.count, fb.values, FrameDecoder().text,
                CrcExplorer().text):
        assert box.continuous_update is True, box.description
    tool = TestTool("rtu_master")
    for box in (tool.address, tool.length, tool.unit):   # a poll setting changes on Enter or Tab
        assert box.continuous_update is False, box.description


def test_a_real_server_clears_a_stale_message_when_requests_arrive():
    server = TestTool("tcp_server", connection="tcp", host="127.0.0.1", port=0, unit=1, length=4)
    try:
        assert server.connect(), server.message.text
        client = TestTool("tcp_client", connection="tcp", host="127.0.0.1", port=server.port.value, unit=1,
                          length=4, timeout=2.0)
        assert client.connect(), client.message.text
        server.auto_fill_stop()
        assert server.message.text == "auto fill stopped"

        async def one_tick():
            task = asyncio.ensure_future(server._tick_loop())
            await asyncio.sleep(0.1)
            assert client.poll_once() == [0, 0, 0, 0]
            await asyncio.sleep(0.7)  # the ticker looks twice a second, on the real clock
            task.cancel()

        asyncio.run(asyncio.wait_for(one_tick(), timeout=5))
        assert server.message.text == ""
        client.disconnect()
    finally:
        server.disconnect()


def test_the_test_tool_offers_only_functions_whose_table_its_grid_shows():
    from modbus_edu.datamodel import table_kind

    tool = TestTool("rtu_master")
    offered = [value for _label, value in tool.function.options]
    assert offered == [1, 2, 3, 4, 5, 6, 15, 16, 22, 23, 24]
    for fc in offered:
        table_kind(fc)  # each reaches a table
    assert tool.apply_config({"function": 7}) is False and tool.message.kind == "error"


def test_the_test_tools_master_offers_mask_write_read_write_and_fifo():
    slave = TestTool("rtu_slave", unit=1, address=0, length=4)
    slave.set_cell(0, 0x12)
    master = TestTool("rtu_master", partner=slave, unit=1, address=0, length=4, function=22)
    master.set_cell(0, 0xF2)                       # the AND mask
    master.set_cell(1, 0x25)                       # the OR mask
    assert master.poll_once() == [0xF2, 0x25] and slave.values[0] == 0x17
    master.function.value = 23
    master.set_cell(2, 7)
    assert master.poll_once() == [0xF2, 0x25, 7, 0] == slave.values[:4]
    slave.slave.bank.holding_registers.write(10, [2, 11, 12])
    master.function.value = 24
    master.address.value = 10
    assert master.poll_once() == [11, 12] and master.values[1:3] == [11, 12]


# --- a panel follows its slave's traffic, throttled --------------------------------------------------
class _ManualTimers:
    """A clock and a scheduler that move only when the test says: throttling without real time."""

    def __init__(self) -> None:
        self.now = 0.0
        self.waiting: list = []

    def clock(self) -> float:
        return self.now

    def schedule(self, delay: float, callback):
        timers = self

        class Handle:
            when = round(self.now + delay, 9)

            def cancel(self) -> None:
                timers.waiting.remove(self)

        handle = Handle()
        handle.callback = callback
        self.waiting.append(handle)
        return handle

    def advance(self, seconds: float) -> None:
        """Time goes by ``seconds``; each timer due fires at its own time."""
        end = round(self.now + seconds, 9)
        while due := [h for h in self.waiting if h.when <= end + 1e-9]:
            handle = min(due, key=lambda h: h.when)
            self.waiting.remove(handle)
            self.now = round(handle.when, 9)
            handle.callback()
        self.now = end


def _shown(tool: TestTool) -> tuple[list, int]:
    """What the panel shows now: the grid's texts and the request counter in its counters line."""
    requests = re.search(r'mbe-tt-count-requests">(\d+)<', tool.counters.value)
    return [cell.value for cell in tool._cells], int(requests.group(1))


def test_throttle_runs_first_at_once_then_at_most_once_per_interval_and_once_after_a_burst():
    from modbus_edu.widgets.throttle import Throttle

    timers, runs = _ManualTimers(), []
    throttle = Throttle(lambda: runs.append(timers.now), 0.2, clock=timers.clock, schedule=timers.schedule)
    throttle.poke()
    assert runs == [0.0] and not throttle.pending          # the first change shows at once
    for _ in range(50):                                      # a burst: nothing more until 0.2 s
        timers.advance(0.001)
        throttle.poke()
    assert runs == [0.0] and throttle.pending and len(timers.waiting) == 1
    timers.advance(0.2)
    assert runs == [0.0, 0.2] and not throttle.pending     # the trailing run, at the interval's end
    timers.advance(1.0)
    throttle.poke()
    assert runs == [0.0, 0.2, 1.25]                          # quiet for long (at 1.25 s): at once again
    throttle.poke()
    assert throttle.flush() and runs[-1] == 1.25 and len(runs) == 4 and not throttle.flush()
    throttle.poke()
    throttle.cancel()
    timers.advance(1.0)
    assert len(runs) == 4 and not timers.waiting


def test_a_slave_tool_s_grid_and_counters_follow_another_link_without_refresh():
    from modbus_edu.links import loopback_serial
    from modbus_edu.master import Master
    from modbus_edu.widgets.throttle import Throttle

    stand_in = TestTool("rtu_slave", unit=1, address=0, length=4)
    stand_in.fill_increment(start=100, step=10)
    timers = _ManualTimers()
    stand_in.follow = Throttle(stand_in.follow.action, 0.2, clock=timers.clock, schedule=timers.schedule)
    assert _shown(stand_in) == (["100", "110", "120", "130"], 0)
    program = Master(loopback_serial(stand_in.slave, baudrate=9600), timeout=1.0)  # not the tool's wire
    program.write_single_register(unit=1, address=0, value=1234)
    assert _shown(stand_in) == (["1234", "110", "120", "130"], 1)
    timers.advance(0.05)
    program.write_multiple_registers(unit=1, address=1, values=[7, 8, 9])
    timers.advance(0.05)
    program.read_holding_registers(unit=1, address=0, count=4)
    assert _shown(stand_in) == (["1234", "110", "120", "130"], 1)   # throttled: not yet
    timers.advance(0.1)                                              # 0.2 s after the first redraw
    assert _shown(stand_in) == (["1234", "7", "8", "9"], 3)
    assert "01 10 00 01 00 03" in stand_in.rx_log.value                # the RX log follows too
    assert stand_in.follow.runs == 2


def test_without_an_event_loop_the_panel_follows_each_request_at_once():
    from modbus_edu.links import loopback_tcp
    from modbus_edu.master import Master

    device = TestTool("tcp_server", unit=1, address=0, length=3)
    Master(loopback_tcp(device.slave)).write_multiple_registers(unit=1, address=0, values=[5, 6, 7])
    assert _shown(device) == (["5", "6", "7"], 1)


def test_a_panel_made_in_a_kernel_follows_a_real_server_s_thread_on_its_own_loop():
    from modbus_edu.links.tcp import TcpServer, tcp_link

    async def scenario():
        stand_in = TestTool("tcp_server", unit=1, address=0, length=2)
        with TcpServer(stand_in.slave, host="127.0.0.1", port=0) as server:  # the learner's own server
            link = tcp_link(*server.address, timeout=2.0)
            try:
                from modbus_edu.master import Master

                program = Master(link, timeout=2.0)
                for value in (1, 2, 3):
                    program.write_single_register(unit=1, address=0, value=value)
                assert _shown(stand_in) == (["0", "0"], 0)  # the server's thread never draws
                for _ in range(100):  # the loop draws: the first change, then the last after 0.2 s
                    await asyncio.sleep(0.05)
                    if _shown(stand_in) == (["3", "0"], 3):
                        break
            finally:
                link.close()
        assert _shown(stand_in) == (["3", "0"], 3) and stand_in.follow.runs <= 3

    asyncio.run(asyncio.wait_for(scenario(), timeout=10))


# Run in a fresh interpreter in which matplotlib cannot be imported, as in a browser that carries none.
WITHOUT_MATPLOTLIB = r"""
import sys
sys.modules["matplotlib"] = None  # import matplotlib now raises ImportError, as where it is not installed
from modbus_edu.crc import crc16
from modbus_edu.devices import PowerMeter
from modbus_edu.errors import MissingDependencyError
from modbus_edu.widgets import CrcExplorer, FrameBuilder, FrameDecoder, MeterDashboard, TestTool

builder = FrameBuilder(mode="rtu", unit=17, function=3, address=107, count=3)
assert builder.frame == bytes.fromhex("1103006B00037687"), builder.frame.hex(" ")
decoder = FrameDecoder(text="11 03 00 6B 00 03 76 87")
assert decoder.frame == bytes.fromhex("1103006B00037687") and decoder.error is None
crc = CrcExplorer(data="01 03 00 00 00 01")
crc.run_to_end.click()
assert crc.result == crc16(bytes.fromhex("010300000001"))
slave = TestTool("rtu_slave", unit=1, length=3)
slave.fill_increment(start=100, step=10)
master = TestTool("rtu_master", partner=slave, unit=1, address=0, length=3)
assert master.run_polls(2)[-1] == [100, 110, 120]
assert master.counts == {"polls": 2, "valid": 2, "timeouts": 0, "errors": 0}, master.counts
dash = MeterDashboard(PowerMeter(unit=1, trial=2))
dash.run(3)
assert dash.counts["valid"] == 3 and dash.plot_png == b"" and "412.6" in dash.table.value
note = dash.plot_note.value
assert "matplotlib" in note and "\n" not in note, note
try:
    crc.plot()
except MissingDependencyError as exc:
    assert exc._render_traceback_() == [f"MissingDependencyError: {exc}"]
else:
    raise AssertionError("CrcExplorer.plot drew without matplotlib")
print("ok")
"""


def test_every_panel_but_the_plots_works_without_matplotlib():
    """A browser without matplotlib (the offline site): the frame builder, decoder, CRC explorer and test
    tool import and work; the dashboard reads and tabulates, and its trend tab says in one line that the
    plot needs matplotlib."""
    import os
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", WITHOUT_MATPLOTLIB], capture_output=True, text=True,
                          timeout=120, env=os.environ)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "ok"
