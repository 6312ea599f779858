"""Every exercise's hints escalate, as notebook 00 promises: the idea from the first wrong try, then the
next step, then the same idea worked on other numbers, never the exercise's own answer; and every number
and frame of a worked example is the library's."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import serial

import modbus_edu as mb
from modbus_edu.devices import METER_BY_NAME
from modbus_edu.devices.arduino import loop_time_experiment, reply_time
from modbus_edu.exercises import EXERCISES, inventory, levels
from modbus_edu.exercises.checkers.nb06 import _slave_answer
from modbus_edu.exercises.core import LINES, TRIES_BEFORE_LINE, count_try, evaluate, wrong_tries
from modbus_edu.links.echo import strip_echo

ROOT = Path(__file__).resolve().parents[1]
KEYS = sorted(EXERCISES)


def hexes(data: bytes) -> str:
    return data.hex(" ").upper()


def test_every_exercise_has_the_idea_then_two_levels():
    for key in KEYS:
        idea, levels_ = EXERCISES[key].hint, LINES.get(key, ())
        assert isinstance(idea, str) and idea, key
        assert len(levels_) == 2, f"{key} has {len(levels_)} levels after the idea, not a step and an example"
        step, example = levels_
        assert len(step) >= 40 and len(example) >= 30 and len({idea, step, example}) == 3, key


def test_a_notebook_s_import_gives_every_level():
    """What a notebook imports (check, from the package) registers every level, with nothing else imported:
    the learner's kernel, the grader and the browser's copy all load the exercises this way."""
    code = ("from modbus_edu.exercises import check\n"
            "from modbus_edu.exercises.core import EXERCISES, LINES\n"
            "print(sum(len(LINES.get(key, ())) == 2 for key in EXERCISES), len(EXERCISES))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    given, registered = map(int, run.stdout.split())
    assert given == registered == len(EXERCISES), run.stderr[-2000:]


def test_each_level_is_given_once():
    """levels.py adds levels only where the checker gives none (or only the step); a checker that gains its
    own levels must leave levels.py's table, not be overridden by it."""
    given = levels.GIVEN_BY_CHECKERS
    assert {key for key in levels.STEPS_AND_EXAMPLES if given[key]} == set()
    assert {key: len(given[key]) for key in levels.EXAMPLES} == dict.fromkeys(levels.EXAMPLES, 1)
    replaced = levels.EXAMPLES_REPLACED
    assert {key: len(given[key]) for key in replaced} == dict.fromkeys(replaced, 2)
    for key in levels.EXAMPLES_REPLACED:
        assert LINES[key][0] == given[key][0] and LINES[key][1] != given[key][1]
    mine = set(levels.STEPS_AND_EXAMPLES) | set(levels.EXAMPLES) | set(levels.EXAMPLES_REPLACED)
    assert len(mine) == len(levels.STEPS_AND_EXAMPLES) + len(levels.EXAMPLES) + len(levels.EXAMPLES_REPLACED)


def test_check_shows_the_step_then_the_example():
    key = "02.2"
    wrong_tries.pop(key, None)
    shown = [count_try(evaluate(key, 300 // 125)).message for _ in range(TRIES_BEFORE_LINE + 1)]
    step, example = LINES[key]
    assert step not in shown[0] and f"After 2 tries, the next step: {step}" in shown[1]
    assert example not in shown[1] and f"After 3 tries, the same idea on other numbers: {example}" in shown[2]
    assert count_try(evaluate(key, math.ceil(300 / 125))).ok and key not in wrong_tries


def test_notebook_00_promises_what_is_true():
    cells = json.loads((ROOT / "notebooks" / "00_welcome.ipynb").read_text(encoding="utf-8"))["cells"]
    text = " ".join("".join(cell["source"]) for cell in cells if cell["cell_type"] == "markdown")
    text = " ".join(text.split())
    assert "Every exercise goes further: a second wrong try adds the next step, a third the same idea" in text


# --- no level gives the exercise's answer away ----------------------------------------------------------

def _flat(text: str) -> str:
    """Lower case, with every space and quote gone: "02 03 00" and "020300" read the same."""
    return re.sub(r"[\s'\"]", "", text.lower())


def _numbers(text: str) -> set[str]:
    """The numbers a text writes, as it writes them (0x1F, 31, 0.893)."""
    return set(re.findall(r"(?<![\w.])(?:0x[0-9a-f]+|\d+(?:\.\d+)?)(?![\w]|\.\d)", text.lower()))


def _scalar_spellings(answer) -> tuple[set[str], set[str]]:
    """(texts, numbers) that write one right value: a level holding any of them gives it away.  Small
    numbers (under 10) and True/False are written by every hint for other reasons: none."""
    if isinstance(answer, bool):
        return set(), set()
    if isinstance(answer, (bytes, bytearray)):
        return ({answer.hex()} if len(answer) >= 2 else set()), set()
    if isinstance(answer, int):
        return set(), ({str(answer), f"0x{answer:x}", f"0x{answer:02x}", f"0x{answer:04x}"} if answer >= 10
                       else set())
    if isinstance(answer, float):
        return set(), ({f"{answer:g}"} if answer >= 10 or answer != int(answer) else set())
    if isinstance(answer, str) and len(answer.strip()) >= 3:
        text = answer.strip()
        try:
            data = bytes.fromhex(text)
        except ValueError:
            return {_flat(text)}, set()
        return ({data.hex()} if len(data) >= 2 else set()), set()
    return set(), set()


def _leaks(answer, level: str) -> bool:
    """True if ``level`` writes the right ``answer``: a value in one of its spellings; a pair or list by
    all its parts that can be spelt (or written out: "3, 54, 6"); a dict by any of its pairs."""
    flat, numbers = _flat(level), _numbers(level)
    if isinstance(answer, dict):
        return any(_flat(f"{situation}{joint}{value}") in flat
                   for situation, value in answer.items() for joint in (": ", " gives ", " is "))
    if isinstance(answer, (list, tuple, set, frozenset)):
        items = list(answer)
        if items and all(isinstance(x, int) and not isinstance(x, bool) for x in items) and \
                _flat(", ".join(map(str, items))) in flat and len(items) > 1:
            return True
        spelt = [item for item in items
                 if any(_scalar_spellings(item)) or isinstance(item, (list, tuple, dict))]
        return bool(spelt) and all(_leaks(item, level) for item in spelt)
    texts, spellings = _scalar_spellings(answer)
    return any(text in flat for text in texts) or bool(spellings & numbers)


def _solution_lines(key: str) -> set[str]:
    """A build exercise's answer is code: its worked solution's lines long enough to give it away."""
    path = ROOT / "notebooks" / EXERCISES[key].solution
    lines = path.read_text(encoding="utf-8").splitlines() if path.exists() else []
    code = [re.sub(r"^(return|answer\s*=)\s*", "", line.split("#")[0].strip()) for line in lines]
    return {_flat(line) for line in code
            if len(line) >= 12 and re.search(r"[(\[=+*/-]", line)
            and not line.startswith(("def ", "import ", "from ", "check("))}


NAMES_AMONG_OTHERS = {"05.4": "the step says what each of the four MBAP fields must hold, the wrong one too"}
"""Exercises whose answer is a word that a level names only among all the choices, as the task does."""


@pytest.mark.parametrize("key", KEYS)
def test_no_level_holds_the_exercise_s_answer(key):
    item = EXERCISES[key]
    code = _solution_lines(key) if item.kind == "build" else set()
    for level in LINES[key]:
        if key not in NAMES_AMONG_OTHERS:
            assert not [answer for answer in item.accepts if _leaks(answer, level)], \
                f"{key}: a level holds the answer: {level}"
        assert not [line for line in code if line in _flat(level)], f"{key}: a level holds the solution"


def test_the_answer_finder_finds_answers():
    """The test above catches an answer in each of its forms: 00.3's frame, an address, a pair, a dict."""
    assert _leaks(bytes.fromhex("02 03 00 00 00 02 C4 38"), "its bytes: 02 03 00 00 00 02 c4 38.")
    assert _leaks("02 03 00 00 00 02 C4 38", "the frame 020300000002C438")
    assert _leaks(249, "so the address is 249.") and _leaks(249, "0xF9") and not _leaks(249, "address 2490")
    assert _leaks(("input_registers", False), "the answer is ('input_registers', False)")
    assert not _leaks(("CDAB", 135.541), "decode with ABCD and with CDAB")
    assert _leaks(("CDAB", 135.541), "CDAB gives 135.541 A") and _leaks((3, 54, 6), "(3, 54, 6)")
    assert _leaks({"request for a unit nobody has": "timeout"}, "a request for a unit nobody has: timeout")
    assert _leaks(41.67, "it takes 41.67 ms") and not _leaks(41.67, "it takes 141.67 ms")


# --- every worked example's numbers are the library's ------------------------------------------------------

def _rtu(unit, pdu) -> str:
    return hexes(mb.RtuFrame(unit=unit, pdu=pdu).encode())


def _unanswered(pauses, baudrate):
    """The pauses (character times, before byte 4 of a read) that leave the request unanswered."""
    unanswered = []
    for chars in pauses:
        link = mb.loopback_serial(mb.Slave(unit=1), baudrate=baudrate)
        link.faults.insert_gap(at_byte=4, chars=chars, target="request")
        try:
            mb.Master(link, timeout=0.1).read_holding_registers(unit=1, address=0, count=1)
        except mb.ModbusError:
            unanswered.append(chars)
    return unanswered


def _raised(call) -> type:
    try:
        call()
    except mb.ModbusError as error:
        return type(error)
    raise AssertionError("no error raised")


def _refused(function: int) -> bytes:
    """What the library's slave (20 holding registers) answers to a bare request of ``function``."""
    bank = mb.DataBank(sparse=True)
    bank.holding_registers.declare(0, 20)
    body = bytes([1, function])
    answer = mb.Slave(unit=1, bank=bank).handle(body + mb.crc16(body).to_bytes(2, "little"), mode="rtu")
    return mb.RtuFrame.decode(answer, "response").pdu.encode()


def _flip_response() -> type:
    link = mb.loopback_serial(mb.Slave(unit=1))
    link.faults.flip_bits(1, target="response")
    return _raised(lambda: mb.Master(link, timeout=0.5).read_holding_registers(unit=1, address=0, count=1))


def _gateway_passes_exceptions() -> int:
    """The exception code a client behind the library's gateway gets when the pump (unit 2) refuses."""
    pump = mb.DataBank(sparse=True)
    pump.holding_registers.declare(0, 10)
    bus = mb.loopback_serial([mb.Slave(unit=1), mb.Slave(unit=2, bank=pump)], baudrate=9600)
    with mb.TcpGateway(bus, timeout=0.2) as gateway, mb.tcp_link(*gateway.address) as tcp:
        try:
            mb.Master(tcp, timeout=5).read_holding_registers(unit=2, address=9999, count=1)
        except mb.ModbusExceptionError as error:
            return error.code
    raise AssertionError("the gateway passed no exception on")


def _float_orders() -> set:
    return {mb.decode_value(registers, "float32", order) for registers, order in
            [([0x4049, 0x0FDB], "ABCD"), ([0x0FDB, 0x4049], "CDAB"), ([0x4940, 0xDB0F], "BADC"),
             ([0xDB0F, 0x4940], "DCBA")]}


def _pdu(hex_text: str, role: str = "request"):
    return mb.decode_pdu(mb.parse_hex(hex_text), role)


def _rtu_read(hex_text: str) -> mb.RtuFrame:
    return mb.RtuFrame.decode(mb.parse_hex(hex_text))


def _tcp_read(hex_text: str) -> mb.TcpFrame:
    return mb.TcpFrame.decode(mb.parse_hex(hex_text))


def _four_registers():
    return mb.ReadHoldingRegistersResponse(registers=[0] * 4)


def _handled(pdu: str) -> str:
    """What the library's slave answers, over the registers [10, 20, 30], to ``pdu``."""
    return hexes(_slave_answer([10, 20, 30], mb.parse_hex(pdu)))


def _ms(seconds: float, digits: int = 2) -> str:
    return f"{seconds * 1000:.{digits}f} ms"


def _timing(baudrate: int, parity: str = "N") -> mb.SerialTiming:
    return mb.SerialTiming(baudrate=baudrate, parity=parity)


CHECKS = {
    "00.0": lambda: (inventory.read("BC?A" + "?" * 8, "00.0") == inventory.read(
        {1: "b", 2: "c", 3: "?", 4: "a"} | {n: "?" for n in range(5, 13)}, "00.0"), ['"BC?A"']),
    "00.1": lambda: (True, [_rtu(0x1F, mb.ReadHoldingRegistersRequest(address=0, count=1)),
                            f"1 x 16 + 15 (F) = {_rtu_read('1F 03 00 00 00 01 87 B4').unit}"]),
    "00.2": lambda: (True, [hexes(mb.TcpFrame(transaction_id=1, unit=5, pdu=mb.ReadInputRegistersRequest(
        address=10, count=2)).encode()), hexes(mb.ReadInputRegistersRequest(address=10, count=2).encode()),
        f"address {_pdu('04 00 0A 00 02').address}, count {_pdu('04 00 0A 00 02').count}"]),
    "00.3": lambda: (True, [_rtu(9, mb.WriteSingleRegisterRequest(address=5, value=500)),
                            f"0x{mb.crc16(mb.parse_hex('09 06 00 05 01 F4')):04X}",
                            hexes(mb.WriteSingleRegisterRequest(address=5, value=500).encode())]),
    "01.1": lambda: (True, [f"17 - 1 = {mb.parse_reference('40017').address}"]),
    "01.2": lambda: (True, [f'"{mb.format_reference("holding_registers", 41)}"']),
    "01.3": lambda: (mb.table_kind(3) == mb.table_kind(6), [f'("{mb.table_kind(3)}", True)']),
    "01.5": lambda: (_raised(lambda: mb.parse_reference("30000")) is mb.ReferenceNumberError,
                     [f'("{mb.parse_reference("10020").kind}", {mb.parse_reference("10020").address})',
                      "mb.ReferenceNumberError"]),
    "02.2": lambda: (mb.MAX_READ_REGISTERS == 125,
                     [f"500 / 125 = {500 // 125} exactly, so {math.ceil(500 / 125)} requests",
                      f"130 / 125 = {130 / 125}, rounded up to {math.ceil(130 / 125)} requests "
                      f"(125, then {130 - 125})"]),
    "02.3": lambda: (True, [hexes(mb.ExceptionResponse(5, 3).encode()),
                            f"{mb.ExceptionCode(3).name} is 0{int(mb.ExceptionCode(3))}"]),
    "02.4": lambda: (True, [f"0x0A is {0x0A >> 4:04b} {0x0A & 15:04b}", "coils {} and {} are ON".format(
        *[n for n, bit in enumerate(mb.ReadCoilsResponse.decode(mb.parse_hex("01 01 0A")).bits) if bit])]),
    "03.3": lambda: (_raised(lambda: mb.RtuFrame.decode(mb.parse_hex("01 03 00 00 00 01 84 0B"))) is not None,
                     [f"0x{mb.crc16(mb.parse_hex('01 03 00 00 00 01')):04X}",
                      _rtu(1, mb.ReadHoldingRegistersRequest(address=0, count=1))[-5:]]),
    "03.4": lambda: (True, [f"1 + 1 + 1 + 8 + 2 = {len(mb.parse_hex(_rtu(1, _four_registers())))}"]),
    "05.1": lambda: (True, [f"1 x 256 + 12 = "
                            f"{_tcp_read('01 0C 00 00 00 06 01 03 00 00 00 01').transaction_id}"]),
    "05.3": lambda: (1 + 1 + 1 + 8 == 0x0B,
                     [hexes(mb.TcpFrame(transaction_id=1, unit=1, pdu=_four_registers()).encode())]),
    "06.1": lambda: ((8 + 3.5 + 9 + 3.5) * 10 == 240 and 240 / 19200 == _timing(19200).transaction_time(8, 9),
                     [f"= {_timing(19200).transaction_time(8, 9):.4f} s = "
                      f"{_ms(_timing(19200).transaction_time(8, 9))}"]),
    "06.2": lambda: (_refused(0x41) == bytes([0xC1, 1]), [".code is 1 (ILLEGAL_FUNCTION)"]),
    "06.4": lambda: (_flip_response() is mb.CrcError and issubclass(mb.CrcError, mb.ChecksumError),
                     ["mb.CrcError, a mb.ChecksumError"]),
    "06.5": lambda: (0x01F4 == 500, [
        f"from address 1) is answered {_handled('03 00 01 00 02')}",
        f"03 00 02 00 02 runs past the end: {_handled('03 00 02 00 02')}",
        f"at address 0 and is answered {_handled('06 00 00 01 F4')}"]),
    "07.1": lambda: (True, [_rtu(5, mb.ExceptionResponse(4, 3)), "0x84 - 0x80 = 4", "(4, 3)"]),
    "07.3": lambda: (_refused(0x41) == bytes([0xC1, 1]),
                     ["0x41, which the slave does not implement, gets exception 01"]),
    "07.4": lambda: (0x10 | 0x80 == 0x90, [hexes(mb.ExceptionResponse(16, 4).encode())]),
    "08.3": lambda: (True, ["{} and {} are more than 1.5".format(*_unanswered([0.5, 1.2, 1.6, 4.0], 19200))]),
    "08.4": lambda: (_timing(38400, "E").t35 == 0.00175,
                     [f"{_timing(38400, 'E').bits_per_char} bits, "
                      f"{_ms(_timing(38400, 'E').char_time, 4)} a character",
                      f"= {_ms(_timing(38400, 'E').transaction_time(8, 7), 3)}",
                      f"{_timing(38400, 'E').transaction_time(8, 7):.6f} s"]),
    "09.3": lambda: (loop_time_experiment([0.8], timeout=0.9) == [(0.8, 1.0)],
                     [f"{reply_time(9 + 3.5) * 1000:.0f} ms reply",
                      f"0.88 + 0.013 = {0.8 * 1.1 + reply_time(12.5):.3f} s",
                      "[(0.8, 1.0)]"]),
    "10.3": lambda: (True, [f"at addresses {METER_BY_NAME['VL1'].address} and {METER_BY_NAME['AL1'].address}",
                            f"(3, {METER_BY_NAME['VL1'].address}, {METER_BY_NAME['AL1'].address + 2})"]),
    "10.4": lambda: (len(_float_orders()) == 1,
                     [f"{mb.decode_value([0x4049, 0x0FDB], 'float32'):.7f}", "40 49 0F DB"]),
    "11.1": lambda: (_pdu("06 00 03 00 64") == mb.WriteSingleRegisterRequest(address=3, value=100),
                     [f"transaction {_tcp_read('00 05 00 00 00 06 01 06 00 03 00 64').transaction_id}"
                      ", function 6, address 3, value 0x0064 = 100"]),
    "11.3": lambda: (True, [f'"{serial.serial_for_url("socket://10.0.0.7:950", do_not_open=True).port}"']),
    "12.4": lambda: (True, [hexes(mb.TcpFrame(transaction_id=300, unit=7, pdu=mb.ReadHoldingRegistersRequest(
        address=1000, count=5)).encode())]),
    "13.2": lambda: (True, [f"ABCD gives 0x{mb.decode_value([0x0001, 0x86A0], 'uint32', 'ABCD'):08X} = "
                            f"{mb.decode_value([0x0001, 0x86A0], 'uint32', 'ABCD')} mA = "
                            f"{mb.decode_value([0x0001, 0x86A0], 'uint32', 'ABCD') / 1000:.1f} A",
                            f"CDAB gives 0x{mb.decode_value([0x0001, 0x86A0], 'uint32', 'CDAB'):08X} = "
                            f"{mb.decode_value([0x0001, 0x86A0], 'uint32', 'CDAB')} mA"]),
    "13.5": lambda: (True, [f"the CRC is 0x{mb.crc16(mb.parse_hex('02 06 00 01 00 0A')):04X}",
                            _rtu(2, mb.WriteSingleRegisterRequest(address=1, value=10))]),
    "15.1": lambda: (_timing(9600, "O").bits_per_char == 11 and 22 * 11 == 242,
                     [f"242 / 9600 = {_ms(_timing(9600, 'O').transaction_time(8, 7))}"]),
    "15.2": lambda: (_raised(lambda: mb.RtuFrame.decode(mb.parse_hex("05 06 00 01 00 64 D8 66"))) is not None,
                     [_rtu(5, mb.WriteSingleRegisterRequest(address=1, value=100)),
                      hexes(mb.TcpFrame(transaction_id=1, unit=5, pdu=mb.WriteSingleRegisterRequest(
                          address=1, value=100)).encode())]),
    "15.3": lambda: (True, [f"answers exception 0{_gateway_passes_exceptions()}",
                            f"hands the client 0{_gateway_passes_exceptions()} as it is"]),
    "16.4": lambda: (_raised(lambda: strip_echo(mb.parse_hex("01 03 00 00 00 01 84 0A"),
                                                mb.parse_hex("01 03 02 00 2A 39 9B"))) is not None,
                     [_rtu(1, mb.ReadHoldingRegistersRequest(address=0, count=1)),
                      hexes(strip_echo(mb.parse_hex("01 03 00 00 00 01 84 0A"),
                                       mb.parse_hex("01 03 00 00 00 01 84 0A 01 03 02 00 2A 39 9B"))),
                      _rtu(1, mb.ReadHoldingRegistersResponse(registers=[42]))]),
    "17.1": lambda: (True, [f"0x03E8 = 3 x 256 + 232 = {_pdu('06 00 01 03 E8').value} into address "
                            f"{_pdu('06 00 01 03 E8').address}"]),
}
"""Each worked example levels.py gives, computed again with the library: (what must hold, the texts the
example must contain as the library writes them: frames byte for byte, numbers to the digits written)."""

NOTHING_TO_COMPUTE = {"13.1": "a slave's counters, named", "16.3": "a flowchart's box", "17.0": "a verdict"}
"""The examples with no number or frame the library could compute, and what they hold instead."""


def test_every_example_of_levels_py_is_checked():
    mine = set(levels.STEPS_AND_EXAMPLES) | set(levels.EXAMPLES) | set(levels.EXAMPLES_REPLACED)
    assert mine == set(CHECKS) | set(NOTHING_TO_COMPUTE)
    assert not set(CHECKS) & set(NOTHING_TO_COMPUTE)


@pytest.mark.parametrize("key", sorted(CHECKS))
def test_the_example_s_numbers_are_the_library_s(key):
    holds, texts = CHECKS[key]()
    example = LINES[key][1]
    assert holds, key
    assert texts and not [text for text in texts if text not in example], \
        f"{key}: not in the example as the library writes it: {[t for t in texts if t not in example]}"


_FRAME = re.compile(r"\b[0-9A-F]{2}(?: [0-9A-F]{2}){5,}\b")


def _reads(data: bytes) -> bool:
    """True if the library reads ``data`` whole: an RTU or Modbus/TCP frame (request or response), a PDU,
    a slave address and a PDU (the bytes a CRC is computed over), or those and their LRC; or a request's
    RTU frame followed by a response's (an adapter's echo, then the answer)."""
    reads = []
    for role in ("request", "response"):
        reads += [lambda role=role: mb.RtuFrame.decode(data, role=role),
                  lambda role=role: mb.TcpFrame.decode(data, role=role),
                  lambda role=role: mb.decode_pdu(data, role),
                  lambda role=role: mb.decode_pdu(data[1:], role)]
        if mb.lrc(data[:-1]) == data[-1]:
            reads.append(lambda role=role: mb.decode_pdu(data[1:-1], role))
    reads += [lambda cut=cut: (mb.RtuFrame.decode(data[:cut], role="request"),
                               mb.RtuFrame.decode(data[cut:], role="response"))
              for cut in range(4, len(data) - 3)]
    for read in reads:
        try:
            read()
        except mb.ModbusError:
            continue
        return True
    return False


DAMAGED = {"03.3": "01 03 00 00 00 01 84 0B", "05.4": "00 01 00 01 00 06 01 03 00 00 00 01"}
"""The worked examples that show a damaged frame on purpose (a CRC, a protocol identifier), by key."""


@pytest.mark.parametrize("key", KEYS)
def test_every_frame_in_an_example_is_whole(key):
    """A run of 6 bytes or more in a worked example (of any exercise) is one the library reads (or the
    start of another run of the same example that it reads: an MBAP header before its frame); the one
    examples that show a damaged frame do so on purpose, and the library refuses those frames."""
    runs = _FRAME.findall(LINES[key][1])
    for run in runs:
        data = mb.parse_hex(run)
        if DAMAGED.get(key) == run:
            assert not _reads(data)
            continue
        whole = _reads(data) or any(other.startswith(run + " ") and _reads(mb.parse_hex(other))
                                    for other in runs)
        assert whole, f"{key}: {run} is nothing the library reads"


def test_the_frame_finder_finds_frames():
    assert _FRAME.findall("it ends 84 0A; 01 03 00 00 00 01 84 0A.") == ["01 03 00 00 00 01 84 0A"]
    assert not _reads(mb.parse_hex("01 03 00 00 00 01 84 0B")) and _reads(mb.parse_hex("01 03 00 00 00 01"))
