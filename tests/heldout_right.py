# ruff: noqa: E501 (the probe lists are kept one per exercise)
"""The right answers to the course's exercises, computed with the library's public API, and for each
build exercise the library's function and inputs the task allows: what tests/test_heldout.py holds the
second held-out set (tests/heldout_slips_2.py) against, so that every slip in it is shown to be wrong.

``RIGHT[key]`` is the right value; ``ACCEPTS[key]`` a predicate for the exercises whose right answers are
many (a pretest, a range, free words); ``REFERENCE[key]`` is ``(function, probes, compare)`` for a build
exercise: a slip is wrong when, on some probe, its result (or its raising) differs from the library's.
"""

import math

import modbus_edu as mb
from modbus_edu.devices import METER_BY_NAME, ArduinoSlave
from modbus_edu.devices.arduino import expected_answered_fraction, reply_time
from modbus_edu.links.echo import strip_echo
from modbus_edu.security import course_roles
from modbus_edu.widgets import TestTool

h = bytes.fromhex


def _rtu(unit, pdu):
    return mb.RtuFrame(unit, pdu).encode()


def _tcp(tid, unit, pdu):
    return mb.TcpFrame(tid, unit, pdu).encode()


def _slave_with_twenty():
    bank = mb.DataBank(sparse=True)
    bank.holding_registers.declare(0, 20)
    return mb.Slave(unit=1, bank=bank)


def _code_for_coil_write() -> int:
    answer = _slave_with_twenty().handle_pdu(mb.WriteSingleCoilRequest(0, True))
    return answer.code


def _operator_fc16_at_98() -> int:
    decision = course_roles().decide(mb.WriteMultipleRegistersRequest(98, (1, 2, 3)).encode(), "operator")
    return 0 if decision.allowed else decision.response[1]


_LOOP_13_6 = (1.0 - reply_time(9 + 3.5)) / (132 / 300)

RIGHT = {
    "00.1": 0x11,
    "00.2": h("03 00 6B 00 03"),
    "00.3": _rtu(2, mb.ReadHoldingRegistersRequest(0, 2)),
    "01.1": mb.parse_reference("40250").address,
    "01.2": mb.format_reference("input_registers", 9),
    "01.3": ("input_registers", False),
    "01.4": 50 + 10,
    "02.1": mb.WriteMultipleRegistersRequest(4, (500, 1000)).encode(),
    "02.2": math.ceil(300 / mb.MAX_READ_REGISTERS),
    "02.3": mb.ExceptionResponse(4, 2).encode(),
    "02.4": [i for i, bit in enumerate(mb.ReadCoilsResponse.decode(h("01 01 05")).bits) if bit],
    "03.1": mb.crc_bytes(h("11 04 00 08 00 01")),
    "03.2": _rtu(1, mb.WriteSingleRegisterRequest(2, 0x1234)),
    "03.3": False,
    "03.4": len(_rtu(1, mb.ReadHoldingRegistersResponse(tuple(range(20))))),
    "04.1": mb.lrc(h("11 03 00 6B 00 03")),
    "04.2": mb.AsciiFrame(5, mb.ReadHoldingRegistersRequest(mb.parse_reference("44097").address, 2)).encode(),
    "04.3": len(mb.AsciiFrame(5, mb.ReadHoldingRegistersResponse((1, 2, 3))).encode()),
    "04.4": mb.AsciiFrame.decode(b":050304FF0600648B\r\n", "response").pdu.encode(),
    "05.1": mb.TcpFrame.decode(h("00 2A 00 00 00 06 11 03 00 6B 00 03")).transaction_id,
    "05.2": _tcp(7, 1, mb.WriteSingleRegisterRequest(0, 1234)),
    "05.3": len(_tcp(1, 1, mb.ReadHoldingRegistersResponse(tuple(range(10))))) - 6,
    "05.4": "length",
    "06.1": mb.SerialTiming(9600).transaction_time(8, 5 + 2 * 10) * 1000,
    "06.2": _code_for_coil_write(),
    "06.3": 1 / mb.SerialTiming(19200).transaction_time(8, 7),
    "06.4": mb.ModbusTimeoutError,
    "07.1": (3, 2),
    "07.2": _rtu(17, mb.ExceptionResponse(1, 2)),
    "07.3": {"request for a unit nobody has": "timeout", "one bit flipped in the request": "timeout",
             "one bit flipped in the response": "checksum error",
             "read of an address the slave does not have": "exception",
             "response carries another unit id": "mismatch"},
    "08.1": 3.5 * mb.character_time(4800, "E", 1),
    "08.2": 1 / mb.SerialTiming(19200).transaction_time(8, 5 + 2 * 10),
    "08.3": [2.0, 3.0, 5.0],
    "09.1": (4, mb.parse_reference("30010").address),
    "10.1": mb.decode_value([0x0000, 0x1009], "uint32", "ABCD") / METER_BY_NAME["VL2"].scale,
    "10.2": mb.encode_value(288900, "uint32", "ABCD"),
    "10.3": (3, METER_BY_NAME["THD_AL1"].address, 6),
    "11.1": (42, 6, 16, 500),
    "11.2": _tcp(7, 3, mb.RtuFrame.decode(h("03 03 00 00 00 03 04 29")).pdu),
    "11.3": "socket://192.168.1.60:4001",
    "12.1": mb.format_registers([100 + 5 * 10], "hex")[0],
    "12.2": TestTool("rtu_master", unit=7, address=10, length=4, function=4, interval=0.5).config(),
    "12.3": (283, "01 1B"),
    "13.1": {"A": "wrong unit id", "B": "no slave on the line", "C": "wrong baud rate or parity"},
    "13.2": ("CDAB", mb.decode_value([0x1175, 0x0002], "uint32", "CDAB") / 1000),
    "13.3": mb.parse_reference("40021").address,
    "13.4": (0x0300, "00 03"),
    "13.5": _rtu(1, mb.ReadHoldingRegistersRequest(0, 1)),
    "14.1": mb.pdu.mask_write(0x00A5, 0x000F, 0x0130),
    "14.3": 5,  # measured: two slaves on a 19200-baud loopback line, the master's sequence as the task says
    "15.1": mb.SerialTiming(19200, "E", 1).transaction_time(8, 5 + 2 * 2) * 1000,
    "15.3": {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"},
    "16.2": [_rtu(1, mb.ReadInputRegistersRequest(a, c)) for a, c in ((0, 2), (6, 2), (12, 2), (70, 4))],
    "17.0": "CCBDCAABDCDB",
    "17.1": mb.decode_pdu(h("06 00 0A 01 F4"), "request").value,
    "17.2": _operator_fc16_at_98(),
}
RIGHT_MAP_16_1 = """name,table,address,type,order,scale,unit
voltage,input,30001,float32,CDAB,1,V
current,input,30007,float32,CDAB,1,A
power,input,30013,float32,CDAB,1,W
frequency,input,30071,float32,CDAB,1,Hz
energy,input,30073,float32,CDAB,1,kWh
"""


def _declared_holding(board: ArduinoSlave) -> frozenset:
    table = board.bank.table("holding_registers")
    return frozenset(a for a in range(0, 400) if table.is_declared(a))


def _plan(text: str):
    try:
        return [(p.function, p.address, p.count, p.points) for p in mb.load_map(text, numbering="reference").plan()]
    except mb.ModbusError as error:
        return type(error)


ACCEPTS = {
    # a pretest: any twelve answers a to d or ?
    "00.0": lambda a: isinstance(a, str) and len(a) == 12 and all(c in "abcd?" for c in a.lower()),
    # a timeout at least the longest loop and the reply, at most 2.5 s
    "09.3": lambda a: isinstance(a, (int, float)) and 1.65 * 1.1 + reply_time(8 + 3.5) <= a <= 2.5,
    # the registers declared: 150-175 and 200-225
    "09.2": lambda a: _declared_holding(a) == frozenset(range(149, 175)) | frozenset(range(199, 225)),
    # within 25% of the loop time the figures give
    "13.6": lambda a: isinstance(a, (int, float)) and abs(a - _LOOP_13_6) <= 0.25 * _LOOP_13_6,
    "16.1": lambda a: isinstance(a, str) and _plan(a) == _plan(RIGHT_MAP_16_1),
    # the flowchart's next check after port, wiring and settings is swapping A and B
    "16.3": lambda a: isinstance(a, str) and "swap" in a.lower(),
}


def _outcome(function, args):
    """A function's result on ``args``, or "raises" (any exception, as a learner's check may raise any)."""
    try:
        return function(*args)
    except Exception:  # noqa: BLE001 (the learner's function may raise anything: only that it raised counts)
        return "raises"


def _ref_parse(text):
    r = mb.parse_reference(text)
    return (r.kind, r.address)


def _ref_handle(registers, pdu):
    bank = mb.DataBank(sparse=True)
    bank.holding_registers.declare(0, len(registers))
    bank.holding_registers.write(0, list(registers))
    answer = mb.Slave(unit=1, bank=bank).handle_pdu(mb.decode_pdu(pdu, "request")).encode()
    return answer, bank.holding_registers.read(0, len(registers))


def _learner_handle(function):
    def run(registers, pdu):
        mine = list(registers)
        answer = function(mine, pdu)
        return answer, mine
    return run


def _ref_split(frame):
    decoded = mb.TcpFrame.decode(frame)
    return (decoded.transaction_id, decoded.protocol_id, len(frame) - 6, decoded.unit, frame[7:])


def _ref_rtu_to_tcp(frame, tid):
    decoded = mb.RtuFrame.decode(frame)
    return mb.TcpFrame(tid, decoded.unit, decoded.pdu).encode()


def _fits(registers, expected):
    return [o for o in mb.ORDERS
            if math.isclose(mb.decode_value(registers, "float32", o), expected, rel_tol=1e-6, abs_tol=1e-9)]


def _ref_decide(pdu, role):
    decision = course_roles().decide(pdu, role)
    return None if decision.allowed else decision.response


_REQUEST = h("01 03 00 00 00 01 84 0A")
_WRITE = _rtu(1, mb.WriteSingleRegisterRequest(1, 7))
_REGS = [10, 20, 30, 40, 50]
_FLOATS = [(mb.encode_value(v, "float32", o), v) for v in (403.6000061035156, 100000.0, -12.25, 0.5)
           for o in mb.ORDERS]

# (library function, probe argument tuples, how the learner's function is run)
REFERENCE = {
    "01.5": (_ref_parse, [("40108",), ("00001",), ("10001",), ("30001",), ("49999",), ("40000",), ("00000",)], None),
    "02.5": (lambda a, c: mb.ReadHoldingRegistersRequest(a, c).encode(),
             [(107, 3), (0, 1), (0, 125), (0, 126), (0, 0), (65535, 1), (65535, 2), (65411, 125), (0x1234, 2)], None),
    "03.5": (mb.crc16, [(b"",), (b"\x00",), (b"123456789",), (h("11 03 00 6B 00 03"),), (bytes(range(256)) * 2,)], None),
    "04.5": (mb.lrc, [(b"",), (h("05 06 10 01 02 00"),), (b"\x80\x80",), (bytes(range(256)),), (b"\xff",)], None),
    "05.5": (lambda t, u, p: _tcp(t, u, mb.decode_pdu(p, "request"))[:7],
             [(280, 1, h("03 00 00 00 01")), (0, 255, h("03 00 00 00 01")), (65535, 0, h("10 00 01 00 02 04 00 01 00 02"))], None),
    "06.5": (_ref_handle, [(_REGS, h(p)) for p in ("03 00 00 00 05", "03 00 01 00 04", "03 00 00 00 06", "03 00 04 00 01",
                                                     "03 00 05 00 01", "03 00 00 00 00", "03 00 00 00 7E", "03 00 0A 00 00",
                                                     "06 00 04 12 34", "06 00 05 00 01", "06 00 00 00 07")], _learner_handle),
    "07.4": (lambda f, c: mb.ExceptionResponse(f, c).encode(), [(3, 2), (1, 1), (16, 4), (43, 11)], None),
    "08.4": (lambda b, p, s, q, r: mb.SerialTiming(b, p, s).transaction_time(q, r),
             [(9600, "N", 1, 8, 7), (4800, "E", 1, 8, 9), (19200, "N", 1, 8, 7), (38400, "N", 1, 8, 7),
              (115200, "O", 2, 8, 25), (9600, "N", 2, 8, 7)], None),
    "09.4": (expected_answered_fraction, [(1.65, 1.0, 0.013), (0.01, 1.0, 0.013), (1.0, 0.005, 0.013), (2.0, 1.0, 0.0),
                                          (0.5, 1.0, 0.1)], None),
    "10.4": (lambda r, o: mb.decode_value(r, "float32", o), [(r, o) for o in mb.ORDERS for r, _ in _FLOATS[:4]]
             + [([0xCCCD, 0x43C9], "CDAB")], None),
    "11.4": (_ref_split, [(h("01 18 00 00 00 06 01 03 00 00 00 01"),), (h("00 01 00 01 00 06 01 03 00 00 00 01"),),
                          (h("00 01 00 00 00 07 01 03 00 00 00 01"),), (h("00 01 00 00 00 01 01"),),
                          (h("FF 00 00 00 00 03 11 83 02"),)], None),
    "12.4": (lambda t, u, a, c: _tcp(t, u, mb.ReadHoldingRegistersRequest(a, c)),
             [(280, 1, 0, 1), (1, 255, 65535, 1), (65535, 0, 0, 125), (300, 1, 0, 60)], None),
    "13.7": (_fits, [(r, v) for r, v in _FLOATS] + [(_FLOATS[0][0], 999.0), ([0xCCCD, 0x43C9], 403.6)], "order"),
    "14.2": (mb.pdu.mask_write, [(0x12, 0xF2, 0x25), (0xA5, 0x0F, 0x130), (0xFFFF, 0, 0xFFFF), (0x1234, 0xFF00, 0x00FF),
                                 (0xABCD, 0x0F0F, 0xFFFF)], None),
    "15.2": (_ref_rtu_to_tcp, [(_REQUEST, 280), (_REQUEST, 7), (_REQUEST[:-1] + b"\x00", 1),
                               (_rtu(247, mb.ReadHoldingRegistersRequest(5, 2)), 0x1234)], None),
    "16.4": (strip_echo, [(_REQUEST, _REQUEST + h("01 03 02 00 2A 38 5B")), (_REQUEST, h("01 03 02 00 2A 38 5B")),
                          (_REQUEST, _REQUEST[:-1] + h("0B 01 03 02 00 2A 38 5B")), (_WRITE, _WRITE + _WRITE),
                          (_REQUEST, _REQUEST), (_REQUEST, h("00") + _REQUEST + h("01 03 02 00 2A 38 5B"))], None),
    "17.3": (_ref_decide, [(mb.decode_pdu(h(p), "request").encode(), role)
                           for p in ("03 00 00 00 01", "06 00 63 00 01", "06 00 64 00 01", "10 00 62 00 03 06 00 01 00 02 00 03",
                                     "10 00 61 00 03 06 00 01 00 02 00 03", "0F 00 5A 00 0A 02 FF 03", "05 01 00 FF 00",
                                     "2B 0E 01 00", "17 00 00 00 01 00 00 00 01 02 00 07")
                           for role in ("viewer", "operator", "engineer", "guest")], None),
}

# the precision each numeric answer is asked to (a slip must be further from the exact value than that)
TOLERANCE = {"06.1": 0.01, "06.3": 0.1, "08.1": 1e-6, "08.2": 0.1, "15.1": 0.01, "10.1": 0.1}
