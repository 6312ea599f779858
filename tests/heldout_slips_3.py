# ruff: noqa: E501 (the slips' answers and function sources are kept whole, one per entry)
"""A third held-out set of realistic wrong answers ("slips") to the course's exercises.

Written like the first two sets, by someone else again, from the notebooks alone: their prose, their
exercise cells and ``check("NN.M", ...)`` keys, and the library's public API, used to compute the right
answers and to build each wrong one the way a learner with that misconception would (a CRC started at 0,
a frame built with the wrong table, a float decoded in the wrong word order ...). The checkers, their
diagnoses, the catalogue of misconceptions, the hints, the catalogue of slips and the first two held-out
sets' entries were not read, and no slip was run through a checker, nor any checker's verdict seen,
while this set was written. So it measures, a third time, how the checkers meet mistakes they were not
written for.

Each entry: ``key`` (the exercise), ``answer`` (the value, or for a build exercise the function's source
as a learner's cell would hold it), ``kind`` ("value" or "build"), ``slip`` (what the learner did, in
plain words), ``mistake`` (the misconception a teacher would name, one sentence) and ``candidates``:
the catalogue's ids (modbus_edu/exercises/diagnosis, their labels and teaching sentences) that name that
mistake, or ``()`` where no entry does.

The candidates were mapped afterwards by someone else, from each slip's ``slip`` and ``mistake`` words
(with its key and answer) and the catalogue's ids, labels and teaching sentences only, by the second
set's rule: an id is a candidate only where a teacher would agree it names the learner's own mistake
(several where entries overlap), and a slip that only answers another question, gives a partial answer
or a wrong form has none unless an entry names exactly that. No checker was run on the set, no
checker's code or verdict was read while they were mapped, and none was changed after.

The kinds of slip, varied as learners err: off by one (a reference's 1, a fence post, an edge of a
range), the wrong table or function, byte order and word order, a wrong field of a header, hex read as
decimal, a unit (milliseconds for seconds, milliamperes for amperes), the request where the response
was asked, RTU where TCP (and back), a partial answer, the right value in the wrong form (an int where a
string is asked, lowercase hex in an ASCII frame, the instance for the class, a pair in the wrong
order), the answer of a neighbouring exercise, and build functions that fail only on an empty, a long
or an edge input.

tests/test_heldout.py (``test_every_third_heldout_slip_is_wrong``) checks, with no checker involved,
that each answer differs from the right answer the library computes (tests/heldout_right.py), beyond
the precision the exercise asks; for a build slip, that some input the task allows tells it from the
library's function.

Dropped before the set was done, as arguably right: 00.1's ``"0x11"`` (a string, but the right number
spelt in hex), 00.2's list of ints ``[3, 0, 107, 0, 3]`` (the PDU's bytes in another container), 01.1's
and 13.3's answers as digit strings (``"249"``, ``"20"``: the right number as text), 01.3's
``("input registers", "no")`` (free spelling), 02.2's ``3.0``, 03.3's ``0`` (equal to False in Python)
and ``"timeout"`` (it does mean "no answer"), 04.1's ``"7E"`` (the right LRC as hex text), 05.4's
``"length field"``, 06.3's ``87`` (87 whole transactions do fit in one second, and "at most" admits
it), 07.4's function returning the hex text ``"83 02"`` (the right bytes spelt as text), 11.3's URL with
a trailing slash, 12.1's ``"0x96"`` (the right value without the grid's padding), 12.3's ``"01 1b"``
and ``"011B"`` (hex spelling), 13.2's ``135.5`` (no precision is asked, so a rounding may pass),
14.1's ``"0x135"`` (the right value as text), 15.3's hex strings ``"0x0A"``, 16.3's "exchange A and B"
and "reverse the polarity" (the same step as "swap A and B", in other words), and 16.1's map with a
wrong ``type`` of the same width (uint32 for float32), whose plan is the right one, so that no input of
the comparison tells it apart. One build slip was replaced: 17.3's operator allowed function 23
within 0..99. The exercise's rules give an operator 5, 6, 15 and 16 only, but the library's role table,
which the exercise names as the reference, allows function 23 (and, for a viewer, 43 and the other
reading functions): on those requests the stated rules and the library disagree, so the slip could not
be shown wrong, and the test holds 17.3 only on requests where they agree.

The test holds 06.5 against what the library's slave answers (a read of 0 or 126 registers gets
exception 03, where the second set's reference raises) and leaves out of 11.4's inputs the exception
response that ``TcpFrame.decode`` refuses as a request (the task asks to refuse only a wrong protocol id,
a wrong length and a frame too short); for each of the three it checks that a right function passes.
"""

import modbus_edu as mb
from modbus_edu.devices import ArduinoSlave
from modbus_edu.widgets import TestTool

HELDOUT_3: list[dict] = []

h = bytes.fromhex


def value(key: str, answer, slip: str, mistake: str, candidates: tuple[str, ...] = ()) -> None:
    HELDOUT_3.append({"key": key, "answer": answer, "kind": "value", "slip": slip, "mistake": mistake,
                      "candidates": candidates})


def build(key: str, source: str, slip: str, mistake: str, candidates: tuple[str, ...] = ()) -> None:
    HELDOUT_3.append({"key": key, "answer": source, "kind": "build", "slip": slip, "mistake": mistake,
                      "candidates": candidates})


# --- the learner's procedures, with one step changed ------------------------------------------------
def _crc(data: bytes, init: int = 0xFFFF, poly: int = 0xA001) -> int:
    crc = init
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ poly if crc & 1 else crc >> 1
    return crc


def _crc_unreflected(data: bytes) -> int:
    """The polynomial 0x8005 run high bit first, as a generic CRC-16 calculator does."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def _low_first(crc: int) -> bytes:
    return bytes([crc & 0xFF, crc >> 8])


def _high_first(crc: int) -> bytes:
    return bytes([crc >> 8, crc & 0xFF])


def _rtu(unit: int, pdu) -> bytes:
    return mb.RtuFrame(unit, pdu).encode()


def _rtu_raw(body: bytes) -> bytes:
    return body + mb.crc_bytes(body)


def _rtu_crc_swapped(body: bytes) -> bytes:
    return body + _high_first(mb.crc16(body))


def _tcp(tid: int, unit: int, pdu) -> bytes:
    return mb.TcpFrame(tid, unit, pdu).encode()


def _ascii(body: bytes, lrc: int | None = None, end: bytes = b"\r\n", lower: bool = False) -> bytes:
    check = mb.lrc(body) if lrc is None else lrc
    text = (body + bytes([check])).hex().upper()
    return b":" + (text.lower() if lower else text).encode("ascii") + end


def board(*runs: tuple[int, int]) -> ArduinoSlave:
    """A board with each run ``(first reference, count)`` declared, as a learner's loop of ``add`` does."""
    made = ArduinoSlave(unit=1, sketch=False)
    for first, count in runs:
        for reference in range(first, first + count):
            made.add(reference)
    return made


def tool(**changes) -> dict:
    settings = {"role": "rtu_master", "unit": 7, "address": 10, "length": 4, "function": 4, "interval": 0.5}
    settings.update(changes)
    return TestTool(settings.pop("role"), **settings).config()


READ_00_3 = mb.ReadHoldingRegistersRequest(0, 2)
WRITE_03_2 = mb.WriteSingleRegisterRequest(2, 0x1234)
BODY_03_1 = h("11 04 00 08 00 01")
WRITE_05_2 = mb.WriteSingleRegisterRequest(0, 1234)
PDU_11_2 = h("03 00 00 00 03")


# --- 00: welcome --------------------------------------------------------------------------------
value("00.0", "ABCDABCDABC", "gave 11 letters: one question skipped, not marked with ?", "Each of the twelve questions takes one character, a ? where there is no idea.", ())
value("00.0", ..., "ran the cell without replacing the ... placeholder", "An answer must replace the placeholder before it is checked.", ())
value("00.0", "CADDBDCBCCBAE", "typed a thirteenth letter, e, which no question offers", "The answers are a to d or ?, one per question.", ())
value("00.0", "ACBDNCBBDBAA", "wrote N (no idea) where the course asks for ?", "The mark for \"no idea\" is ?, not a letter of one's own.", ())
value("00.0", "1234123412??", "numbered the choices 1 to 4 instead of a to d", "The choices are letters a to d.", ())
value("00.0", "?", "gave a single ? for the whole test", "A ? stands for one question: twelve are asked.", ())

value("00.1", 11, "read the address byte 11 as the decimal number 11", "Frame bytes are hex: 11 is 0x11, seventeen.", ("hex-read-as-decimal",))
value("00.1", 3, "gave the second byte, the function code", "The slave address is the first byte of an RTU frame; the function code follows.", ("another-field",))
value("00.1", 107, "gave the register address field 00 6B", "The first byte addresses the slave; 00 6B is the register address inside the PDU.", ("another-field",))
value("00.1", 0x76, "gave the CRC's first byte", "The frame starts with the slave address; the CRC is at its end.", ("another-field",))
value("00.1", 16, "took 0x11 = 17 and subtracted one, as for register numbers", "Slave addresses are not numbered from 1 like references: the byte is the address.", ())
value("00.1", 0x1103, "read the first two bytes as one 16-bit address", "The slave address is one byte.", ())

value("00.2", "11 03 00 6B 00 03", "kept the unit identifier with the PDU", "The unit id belongs to the MBAP header; the PDU starts at the function code.", ("unit-in-pdu",))
value("00.2", "00 06 11 03 00 6B 00 03", "started after the protocol id: length, unit and PDU", "The MBAP header is 7 bytes; the PDU is what follows it.", ("frame-for-pdu", "unit-in-pdu"))
value("00.2", h("00 07 00 00 00 06 11 03 00 6B 00 03"), "gave the whole Modbus/TCP frame", "The PDU is the frame without its 7-byte MBAP header.", ("frame-for-pdu",))
value("00.2", "03 00 6B 00", "dropped the last byte, counting the length 6 as the PDU's length", "The length field counts the unit id and the PDU: the PDU is length - 1 bytes.", ("mbap-length",))
value("00.2", "03 00 6B 00 03 76 87", "added the CRC of the RTU frame of 00.1", "A PDU carries no CRC, and Modbus/TCP has none at all.", ("frame-for-pdu", "crc-on-tcp"))
value("00.2", "00 00 00 06 11 03", "took the 6 bytes after the transaction id, as the length says", "The length field counts from the unit id, not from the protocol id.", ("mbap-length",))

value("00.3", _rtu_crc_swapped(h("02 03 00 00 00 02")), "put the CRC high byte first", "An RTU frame carries its CRC low byte first.", ("crc-swapped",))
value("00.3", _tcp(1, 2, READ_00_3), "built a Modbus/TCP frame for unit 2", "An RTU frame is address + PDU + CRC, with no MBAP header.", ("tcp-frame-for-rtu",))
value("00.3", _rtu(2, mb.ReadHoldingRegistersRequest(1, 2)), "started at address 1, counting registers from 1", "Addresses in a frame count from 0.", ("one-based-address",))
value("00.3", _rtu(2, mb.ReadInputRegistersRequest(0, 2)), "used function 4", "Holding registers are read with function 3; function 4 reads input registers.", ("holding-for-input",))
value("00.3", READ_00_3.encode(), "gave the PDU alone", "An RTU frame adds the slave address before the PDU and the CRC after it.", ("unit-missing", "crc-forgotten"))
value("00.3", h("02 03 00 00 00 02"), "left out the CRC", "Every RTU frame ends with its two CRC bytes.", ("crc-forgotten",))
value("00.3", _rtu(2, mb.ReadHoldingRegistersRequest(0, 4)), "asked for 4, the number of bytes two registers take", "The quantity counts registers, not bytes.", ("byte-count-for-quantity", "bytes-for-registers"))

# --- 01: data model -----------------------------------------------------------------------------
value("01.1", 250, "dropped the prefix 4 but kept 250", "References count from 1: 40250 is address 249.", ("one-based-address",))
value("01.1", 40249, "subtracted one but kept the table prefix", "The prefix 4 names the table and is not part of the address.", ("reference-number",))
value("01.1", 40250, "put the reference number itself in the frame", "The frame carries the address, the reference minus 40001.", ("reference-number",))
value("01.1", 10249, "subtracted 30001, the input registers' offset", "Holding registers start at 40001.", ("holding-for-input",))
value("01.1", 248, "subtracted 40001 and then one more for counting from 0", "Subtracting 40001 already makes the address count from 0.", ("address-one-too-low",))
value("01.1", 0x250, "wrote 250 as hex, since frames are hex", "The address is a number; only its bytes are shown in hex.", ("decimal-written-as-hex",))

value("01.2", "30009", "wrote the address 9 after the prefix, without adding one", "Reference numbers count from 1: address 9 is 30010.", ("zero-based-number",))
value("01.2", "40010", "used the holding registers' prefix", "Input registers carry the prefix 3.", ("holding-for-input",))
value("01.2", "10010", "took \"input\" for the discrete inputs' prefix 1", "Input registers are 3xxxx; 1xxxx are discrete inputs (bits).", ("bit-table-for-register-table",))
value("01.2", "3x0010", "wrote the 4x-style form", "The 5-digit form is asked: 30010.", ())
value("01.2", "30011", "added one twice, once for the reference and once more", "Address 9 plus one is reference 10.", ())
value("01.2", "3010", "wrote four digits, dropping a zero", "The 5-digit form has the prefix and four digits.", ())
value("01.2", 30010, "gave an int where a string is asked", "A reference number is given as text, \"30010\", to keep its leading digits.", ())

value("01.3", ("holding_registers", True), "confused function 4 with function 3", "Function 4 reads input registers; 3 reads holding registers.", ("holding-for-input",))
value("01.3", ("input_registers", True), "thought input registers are written by the master", "Input registers are read-only to a master.", ("holding-for-input",))
value("01.3", ("discrete_inputs", False), "took function 4 for the discrete inputs", "Function 2 reads discrete inputs; 4 reads input registers.", ("bit-table-for-register-table",))
value("01.3", ("holding_registers", False), "named the wrong table but the right rule", "Function 4 reads the input registers.", ("holding-for-input",))
value("01.3", "input_registers", "gave the table alone, not the pair asked", "The answer is a pair: the table and whether a master may write it.", ())
value("01.3", ("coils", True), "left the example's answer", "Function 4 reads input registers, not coils.", ())

value("01.4", 58, "subtracted the ends: 149 - 100 + 309 - 300", "Both ends of a range count: 100 to 149 is 50 registers.", ("range-one-end",))
value("01.4", 59, "counted one range with its ends and the other without", "100 to 149 is 50 registers and 300 to 309 is 10.", ("range-one-end",))
value("01.4", 50, "counted only the first range", "The device implements both ranges.", ("one-range-only",))
value("01.4", 62, "added one to each range's count", "100 to 149 is 50 numbers, not 51.", ("range-one-extra",))
value("01.4", 10, "counted only the second range", "The device implements both ranges.", ("one-range-only",))
value("01.4", 210, "counted from 100 to 309 as one block", "A sparse device has gaps: 150 to 299 are not implemented.", ("dense-for-sparse",))

build("01.5", '''def parse_reference(text):
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no reference 0000")
    return (tables[text[0]], number)
''', "returned the four digits without subtracting one", "The four digits count from 1: 40108 is address 107.", ("one-based-address",))
build("01.5", '''def parse_reference(text):
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    return (tables[text[0]], int(text[1:]) - 1)
''', "forgot to refuse the number 0000", "A reference's four digits start at 0001; 0000 does not exist.", ("invalid-input-accepted",))
build("01.5", '''def parse_reference(text):
    tables = {"0": "coils", "1": "discrete_inputs", "3": "holding_registers", "4": "input_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no reference 0000")
    return (tables[text[0]], number - 1)
''', "swapped the prefixes 3 and 4", "4xxxx are holding registers, 3xxxx input registers.", ("holding-for-input",))
build("01.5", '''def parse_reference(text):
    tables = {"1": "coils", "0": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no reference 0000")
    return (tables[text[0]], number - 1)
''', "swapped the prefixes 0 and 1", "0xxxx are coils, 1xxxx discrete inputs.", ())
build("01.5", '''def parse_reference(text):
    number = int(text) - 40001
    if number < 0:
        raise ValueError("not a reference")
    return ("holding_registers", number)
''', "assumed every reference is a holding register", "The first digit chooses the table.", ())
build("01.5", '''def parse_reference(text):
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:], 16)
    if number == 0:
        raise ValueError("no reference 0000")
    return (tables[text[0]], number - 1)
''', "read the four digits as hex", "Reference numbers are decimal.", ("decimal-written-as-hex",))
build("01.5", '''def parse_reference(text):
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if not 1 <= number < 9999:
        raise ValueError("reference out of range")
    return (tables[text[0]], number - 1)
''', "refused 9999, the last reference of a table", "The four digits run from 0001 to 9999, both ends included.", ())

# --- 02: function codes -------------------------------------------------------------------------
value("02.1", h("06 00 04 01 F4 06 00 05 03 E8"), "wrote two function 6 requests one after the other", "One request writing two registers is function 16.", ())
value("02.1", h("10 00 04 00 02 02 01 F4 03 E8"), "put the quantity 2 in the byte count", "The byte count counts bytes: two registers are 4.", ("byte-count-for-quantity",))
value("02.1", h("10 00 04 00 02 01 F4 03 E8"), "left out the byte count", "Function 16 carries a byte count before the values.", ("byte-count-missing",))
value("02.1", h("10 00 04 00 02 04 F4 01 E8 03"), "wrote each value low byte first", "Registers travel high byte first.", ("field-low-byte-first",))
value("02.1", mb.WriteMultipleRegistersRequest(5, (500, 1000)).encode(), "started at address 5, thinking the first register is 1", "The frame carries the address itself: 4.", ("one-based-address",))
value("02.1", h("10 00 04 00 02 04 05 00 10 00"), "wrote 500 and 1000 as hex digits", "500 is 0x01F4 and 1000 is 0x03E8: the values are numbers, written in hex bytes.", ("decimal-written-as-hex",))
value("02.1", h("0F 00 04 00 02 04 01 F4 03 E8"), "used function 15, write multiple coils", "Function 15 writes coils; 16 writes holding registers.", ("bit-table-for-register-table",))

value("02.2", 2.4, "divided 300 by 125 and stopped", "A number of requests is a whole number: round up.", ())
value("02.2", 2, "rounded 2.4 down", "Two requests read only 250 registers: a third is needed.", ("count-rounded-down",))
value("02.2", 300, "counted one request per register", "One read holding registers request reads up to 125 registers.", ("request-per-register",))
value("02.2", 1, "thought one request reads them all", "A read is limited to 125 registers.", ())
value("02.2", 4, "added one for the fence post, 300 / 125 + 1 rounded up", "ceil(300 / 125) is 3.", ())
value("02.2", 0.15, "used the bit limit, 2000 per read", "2000 is the limit for coils; registers are limited to 125.", ())

value("02.3", h("83 02"), "answered for function 3", "The exception response carries the request's function, 4, plus 0x80.", ())
value("02.3", h("84 01"), "answered illegal function", "The slave has function 4; the address is what it lacks: code 02.", ("illegal-function-for-address", "exception-code-confused"))
value("02.3", h("04 02"), "forgot to add 0x80 to the function code", "An exception response sets the function code's top bit.", ("exception-bit-missing",))
value("02.3", h("84 03"), "answered illegal data value", "An address the slave does not have is code 02.", ("exception-code-confused",))
value("02.3", h("80 02"), "wrote 0x80 alone for the function", "The function code is the request's plus 0x80: 0x84.", ("exception-function-forgotten",))
value("02.3", h("02 84"), "put the exception code first", "The function code comes first in every PDU.", ("function-and-code-swapped",))
value("02.3", _rtu(1, mb.ExceptionResponse(4, 2)), "gave an RTU frame for unit 1", "A PDU has no address and no CRC.", ("frame-for-pdu",))

value("02.4", [1, 3], "numbered the coils from 1", "Coil addresses start at 0: the lowest bit is coil 0.", ("one-based-address",))
value("02.4", [5], "read the data byte 05 as a coil number", "The data byte holds one bit per coil.", ("byte-value-as-coils",))
value("02.4", [5, 7], "read the bits highest first", "The first coil is the lowest bit.", ("bits-from-the-left",))
value("02.4", [0, 1, 2, 3, 4], "read 05 as five coils ON", "05 is a bit pattern, 0000 0101, not a count.", ("byte-value-as-coils",))
value("02.4", [True, False, True, False, False, False, False, False], "gave the bits instead of the addresses ON", "The answer is the list of addresses whose bit is 1.", ())
value("02.4", [0], "read the byte count 01 as the data", "The first data byte after the function is the byte count.", ("another-field",))

build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    return struct.pack(">BHH", 3, address, count)
''', "checked nothing", "A count outside 1..125 or registers past 65535 must be refused.", ("invalid-input-accepted",))
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count < 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHH", 3, address, count)
''', "refused 125, the largest count", "1 to 125 registers are allowed, 125 included.", ())
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count <= 125 or address + count > 65535:
        raise ValueError("bad request")
    return struct.pack(">BHH", 3, address, count)
''', "refused reading the last register, 65535", "address + quantity may be 65536.", ())
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count <= 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack("<BHH", 3, address, count)
''', "packed the fields little-endian", "Every field of a PDU is big-endian.", ("field-low-byte-first",))
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if count > 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHH", 3, address, count)
''', "allowed a count of 0", "A read asks for at least one register.", ("invalid-input-accepted",))
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count <= 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHHB", 3, address, count, 2 * count)
''', "added a byte count, as function 16 has", "A read request is function, address and quantity: 5 bytes.", ())
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count <= 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHH", 4, address, count)
''', "used function 4", "Holding registers are read with function 3.", ("holding-for-input",))
build("02.5", '''import struct

def read_holding_registers_pdu(address, count):
    if not 1 <= count <= 125 or address > 65535:
        raise ValueError("bad request")
    return struct.pack(">BHH", 3, address, count)
''', "checked the start address but not the last register", "Every register read must exist: address + quantity at most 65536.", ("first-address-only", "invalid-input-accepted"))

# --- 03: RTU and CRC ----------------------------------------------------------------------------
value("03.1", _high_first(mb.crc16(BODY_03_1)), "gave the CRC high byte first", "The CRC goes on the wire low byte first.", ("crc-swapped",))
value("03.1", _low_first(_crc(BODY_03_1, init=0)), "started the CRC register at 0", "CRC-16/MODBUS starts at 0xFFFF.", ("crc-initial-zero",))
value("03.1", _low_first(mb.crc16(BODY_03_1[1:])), "computed the CRC over the PDU only", "The CRC covers the slave address too.", ("checksum-without-address",))
value("03.1", _rtu(17, mb.ReadInputRegistersRequest(8, 1)), "gave the whole frame", "Only the two CRC bytes are asked.", ())
value("03.1", mb.crc16(BODY_03_1), "gave the register value as an int", "The bytes in wire order are asked, not the 16-bit number.", ())
value("03.1", _low_first(_crc_unreflected(BODY_03_1)), "ran the polynomial 0x8005 high bit first, as a generic calculator does", "CRC-16/MODBUS is reflected: 0xA001, low bit first.", ("crc-msb-first",))
value("03.1", mb.crc_bytes(h("11 03 00 08 00 01")), "computed the CRC of a function 3 request", "The frame reads an input register: function 4.", ("holding-for-input",))

value("03.2", _rtu(1, mb.WriteSingleRegisterRequest(2, 0x3412)), "wrote the value low byte first", "Registers travel high byte first: 12 34.", ("field-low-byte-first",))
value("03.2", _rtu_crc_swapped(h("01 06 00 02 12 34")), "put the CRC high byte first", "An RTU frame carries its CRC low byte first.", ("crc-swapped",))
value("03.2", _rtu(1, mb.WriteSingleRegisterRequest(1, 0x1234)), "wrote to address 1, counting registers from 1", "The frame carries the address itself: 2.", ("address-one-too-low",))
value("03.2", _rtu(1, mb.WriteSingleRegisterRequest(2, 1234)), "wrote 1234 decimal for 0x1234", "0x1234 is 4660; its bytes are 12 34.", ("hex-read-as-decimal",))
value("03.2", _rtu(1, mb.WriteMultipleRegistersRequest(2, (0x1234,))), "used function 16", "The exercise asks for function 6, write single register.", ())
value("03.2", h("01 06 00 02 12 34"), "left out the CRC", "A complete RTU frame ends with its CRC.", ("crc-forgotten",))
value("03.2", _tcp(1, 1, WRITE_03_2), "built a Modbus/TCP frame", "An RTU frame is address + PDU + CRC.", ("tcp-frame-for-rtu",))

value("03.3", True, "thought the slave answers as the bytes look right", "The CRC is wrong (86 for 87): the slave drops the frame silently.", ("answer-to-damaged-request",))
value("03.3", 1, "answered 1 for yes", "The CRC does not match: the slave does not answer.", ("answer-to-damaged-request",))
value("03.3", "yes", "answered yes in words", "A wrong CRC gets no answer at all.", ("answer-to-damaged-request",))
value("03.3", "exception", "thought the slave answers with an exception", "A slave never answers a frame whose CRC fails: not even an exception.", ("answer-to-damaged-request",))
value("03.3", "it answers with a CRC error", "thought the slave reports the CRC error", "Modbus has no CRC-error response: the slave is silent.", ("answer-to-damaged-request",))

value("03.4", 25, "counted one byte per register", "A register is two bytes: 5 + 2 x 20.", ("register-one-byte",))
value("03.4", 43, "left out the CRC", "The response ends with two CRC bytes: 5 + 2N.", ("crc-forgotten",))
value("03.4", 8, "gave the request's length", "The master waits for the response.", ())
value("03.4", 40, "counted the data only", "The response adds address, function, byte count and CRC.", ("data-bytes-only",))
value("03.4", 49, "counted a Modbus/TCP response, MBAP included", "The question is about RTU: 5 + 2N.", ("tcp-frame-for-rtu",))
value("03.4", 44, "counted 4 + 2N", "Address, function, byte count and two CRC bytes: 5 + 2N.", ())

build("03.5", '''def crc16(data):
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "started the register at 0", "CRC-16/MODBUS starts at 0xFFFF.", ("crc-initial-zero",))
build("03.5", '''def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0x8005
            else:
                crc >>= 1
    return crc
''', "XORed the polynomial 0x8005 while shifting right", "Shifting right needs the reflected polynomial 0xA001.", ("crc-msb-first",))
build("03.5", '''def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(7):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "shifted seven times per byte", "Each byte takes eight shifts, one per bit.", ())
build("03.5", '''def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return ((crc & 0xFF) << 8) | (crc >> 8)
''', "swapped the bytes before returning, for the wire", "The register value is asked; the swap happens only when the bytes are sent.", ("crc-swapped",))
build("03.5", '''def crc16(data):
    crc = 0xFFFF
    for i in range(len(data) - 1):
        crc ^= data[i]
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "stopped the loop one byte early", "Every byte of the data goes into the CRC.", ())
build("03.5", '''def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc >>= 1
            if crc & 1:
                crc ^= 0xA001
    return crc
''', "tested the low bit after the shift instead of before", "The bit that falls out decides the XOR: test it before shifting.", ())
build("03.5", '''def crc16(data):
    if len(data) > 256:
        raise ValueError("a Modbus frame is at most 256 bytes")
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "refused data longer than an RTU frame", "The task asks for the CRC of any data, whatever its length.", ())
build("03.5", '''def crc16(data):
    if not data:
        raise ValueError("no data")
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "refused empty data", "The CRC of no bytes is the start value, 0xFFFF.", ())

# --- 04: ASCII and LRC --------------------------------------------------------------------------
value("04.1", 0x82, "gave the sum without the two's complement", "The LRC is the two's complement of the 8-bit sum.", ("lrc-plain-sum",))
value("04.1", 0x7D, "took the one's complement (inverted the bits)", "Two's complement: invert and add one.", ("lrc-ones-complement",))
value("04.1", -0x82, "negated the sum without keeping 8 bits", "The LRC is one byte: (-sum) & 0xFF.", ("lrc-not-8-bits",))
value("04.1", 0x8F, "left the address 0x11 out of the sum", "The LRC covers the address and the PDU.", ("checksum-without-address",))
value("04.1", (-sum(b"1103006B0003")) & 0xFF, "summed the hex characters", "The LRC sums the bytes, not their ASCII characters.", ("lrc-of-characters",))
value("04.1", 0x126, "wrote 126 (the decimal LRC) as 0x126", "0x7E is 126: the number is the same, its digits are not.", ("decimal-written-as-hex",))

value("04.2", _ascii(h("05 03 10 00 00 02"), lower=True), "wrote the hex characters in lowercase", "An ASCII frame's hex digits are uppercase.", ())
value("04.2", _ascii(h("05 03 10 01 00 02")), "used address 4097, 44098 - 40001 misread as 44097 - 40000", "44097 is address 4096, 0x1000.", ("one-based-address",))
value("04.2", _ascii(h("05 03 10 00 00 02"), end=b""), "left out CR LF", "An ASCII frame ends with CR LF.", ("ascii-without-crlf",))
value("04.2", _ascii(h("05 03 10 00 00 02"), end=b"\n"), "ended the frame with LF only", "The end is CR LF, two characters.", ("ascii-without-crlf",))
value("04.2", _ascii(h("05 04 10 00 00 02")), "used function 4", "Holding registers are read with function 3.", ("holding-for-input",))
value("04.2", _ascii(h("05 03 40 96 00 02")), "wrote the decimal address 4096 as hex digits", "4096 is 0x1000.", ("decimal-written-as-hex",))
value("04.2", b":050310000002" + mb.crc_bytes(h("05 03 10 00 00 02")).hex().upper().encode() + b"\r\n", "put the CRC where the LRC goes", "ASCII frames carry an LRC, not the RTU CRC.", ("crc-in-ascii",))
value("04.2", _ascii(h("05 03 10 00 00 02"))[1:], "left out the colon", "Every ASCII frame starts with ':'.", ("ascii-colon-forgotten",))

value("04.3", 21, "forgot CR LF", "The count goes to the CR LF included.", ("ascii-without-crlf",))
value("04.3", 22, "counted CR LF as one character", "CR and LF are two characters.", ("ascii-without-crlf",))
value("04.3", 25, "counted a two-byte CRC", "ASCII carries a one-byte LRC.", ("crc-in-ascii",))
value("04.3", 11, "counted the RTU response's bytes", "In ASCII each byte becomes two characters, plus ':' and CR LF.", ("rtu-length-for-ascii",))
value("04.3", 20, "counted the hex characters only", "The ':' and CR LF count too.", ("ascii-colon-forgotten", "ascii-without-crlf"))
value("04.3", 13, "counted one character per byte, plus ':' and CR LF", "Each byte is written as two hex characters.", ("rtu-length-for-ascii",))

value("04.4", h("05 03 04 FF 06 00 64"), "kept the address", "The PDU starts at the function code.", ("unit-in-pdu",))
value("04.4", h("03 04 FF 06 00 64 8B"), "kept the LRC", "The LRC belongs to the ASCII frame, not to the PDU.", ("frame-for-pdu",))
value("04.4", b"0304FF060064", "gave the characters instead of the bytes", "Each pair of hex characters is one byte.", ())
value("04.4", h("03 FF 06 00 64"), "dropped the byte count", "The byte count is part of the response PDU.", ("byte-count-missing",))
value("04.4", h("FF 06 00 64"), "gave only the register data", "The PDU starts with the function code and the byte count.", ("function-code-missing",))
value("04.4", h("05 03 04 FF 06 00 64 8B"), "gave every byte of the frame", "The gateway forwards the PDU, without address and LRC.", ("frame-for-pdu",))
value("04.4", [0xFF06, 0x0064], "gave the register values", "The PDU's bytes are asked, function code first.", ())

build("04.5", '''def lrc(data):
    return -sum(data)
''', "negated the sum without keeping one byte", "The LRC is an 8-bit value: (-sum) & 0xFF.", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data):
    return ~sum(data) & 0xFF
''', "inverted the sum (one's complement)", "Two's complement: invert and add one.", ("lrc-ones-complement",))
build("04.5", '''def lrc(data):
    return 256 - (sum(data) & 0xFF)
''', "subtracted from 256 without a final mask", "When the sum is a multiple of 256 the LRC is 0, not 256.", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data):
    return -sum(data.hex().upper().encode()) & 0xFF
''', "summed the hex characters", "The LRC sums the bytes, not their ASCII characters.", ("lrc-of-characters",))
build("04.5", '''def lrc(data):
    return 0x100 - sum(data)
''', "subtracted the whole sum from 0x100", "The sum is kept to 8 bits first: it fails once the bytes add up past 256.", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data):
    x = 0
    for b in data:
        x ^= b
    return -x & 0xFF
''', "XORed the bytes instead of adding them", "The LRC adds the bytes; XOR is another check.", ())
build("04.5", '''def lrc(data):
    return sum(data) & 0xFF
''', "returned the sum itself", "The LRC is the two's complement of the sum.", ("lrc-plain-sum",))

# --- 05: TCP and MBAP ---------------------------------------------------------------------------
value("05.1", 0x2A00, "read the transaction id low byte first", "MBAP fields are big-endian: 00 2A is 42.", ("mbap-little-endian",))
value("05.1", 0, "gave the protocol identifier", "The transaction id is the first two bytes.", ("another-field",))
value("05.1", 6, "gave the length field", "The transaction id is the first two bytes.", ("another-field",))
value("05.1", 17, "gave the unit identifier", "The transaction id is the first two bytes.", ("another-field",))
value("05.1", 107, "gave the register address", "The transaction id is in the MBAP header, not the PDU.", ("another-field",))
value("05.1", 2, "read the digits of 2A", "0x2A is a hex number, 42.", ("hex-read-as-decimal",))

value("05.2", h("07 00 00 00 00 06 01 06 00 00 04 D2"), "wrote the transaction id low byte first", "MBAP fields are big-endian.", ("mbap-little-endian",))
value("05.2", h("00 07 00 00 00 05 01 06 00 00 04 D2"), "counted the PDU only in the length", "The length counts the unit id and the PDU.", ("mbap-length",))
value("05.2", h("00 07 00 00 00 0C 01 06 00 00 04 D2"), "counted the whole frame in the length", "The length counts what follows it.", ("mbap-length",))
value("05.2", h("00 07 00 00 00 06 01 06 00 00 12 34"), "wrote 1234 as the hex digits 12 34", "1234 is 0x04D2.", ("decimal-written-as-hex",))
value("05.2", _tcp(7, 1, WRITE_05_2) + mb.crc_bytes(h("01 06 00 00 04 D2")), "added a CRC, as in RTU", "Modbus/TCP carries no CRC.", ("crc-on-tcp",))
value("05.2", _rtu(1, WRITE_05_2), "built an RTU frame", "A Modbus/TCP frame is the MBAP header and the PDU.", ("crc-on-tcp",))
value("05.2", _tcp(7, 1, mb.WriteSingleRegisterRequest(1, 1234)), "wrote to address 1", "Addresses count from 0.", ("one-based-address",))

value("05.3", 22, "forgot the unit identifier", "The length counts the unit id too.", ("mbap-length",))
value("05.3", 20, "counted the data only", "The length counts unit, function, byte count and data.", ("data-bytes-only", "mbap-length"))
value("05.3", 29, "counted the whole frame", "The length counts what follows it: unit id and PDU.", ("mbap-length",))
value("05.3", 6, "gave the request's length", "The response's length is asked.", ())
value("05.3", 13, "counted one byte per register", "A register is two bytes.", ("register-one-byte",))
value("05.3", 25, "added two CRC bytes", "Modbus/TCP has no CRC.", ("crc-on-tcp",))

value("05.4", "protocol identifier", "left the example's answer", "The protocol id is 00 00, right; the length is 06 00.", ())
value("05.4", "transaction identifier", "blamed the transaction id", "01 18 is a valid transaction id; the length is written low byte first.", ())
value("05.4", "unit identifier", "blamed the unit id", "Unit 1 is fine; the length field reads 0x0600.", ())
value("05.4", "function code", "blamed the PDU", "The PDU is fine; the MBAP length is wrong.", ())
value("05.4", "PDU", "named the PDU, not a field", "The length field, 06 00, is the wrong one.", ())
value("05.4", "byte count", "named a field requests do not have", "The MBAP length is the wrong field.", ())

build("05.5", '''def mbap_header(tid, unit, pdu):
    return tid.to_bytes(2, "big") + bytes([0, 0]) + len(pdu).to_bytes(2, "big") + bytes([unit])
''', "counted the PDU only in the length", "The length counts the unit id and the PDU.", ("mbap-length",))
build("05.5", '''def mbap_header(tid, unit, pdu):
    return tid.to_bytes(2, "big") + bytes([0, 0, 0, 6, unit])
''', "wrote the length 6 for every PDU", "The length depends on the PDU: 1 + len(pdu).", ("mbap-length",))
build("05.5", '''import struct

def mbap_header(tid, unit, pdu):
    return struct.pack("<HHHB", tid, 0, len(pdu) + 1, unit)
''', "packed the header little-endian", "Every MBAP field is big-endian.", ("mbap-little-endian",))
build("05.5", '''def mbap_header(tid, unit, pdu):
    return tid.to_bytes(2, "big") + bytes([0, 0]) + (len(pdu) + 7).to_bytes(2, "big") + bytes([unit])
''', "counted the whole header in the length", "The length counts what follows it.", ("mbap-length",))
build("05.5", '''def mbap_header(tid, unit, pdu):
    return bytes([0, tid & 0xFF, 0, 0, 0, len(pdu) + 1, unit])
''', "wrote the transaction id as one byte", "The transaction id takes two bytes: 280 is 01 18.", ("field-in-one-byte",))
build("05.5", '''def mbap_header(tid, unit, pdu):
    return tid.to_bytes(2, "big") + bytes([0, 0]) + (len(pdu) + 1).to_bytes(2, "big")
''', "left out the unit identifier", "The MBAP header ends with the unit id: 7 bytes.", ("unit-missing",))
build("05.5", '''def mbap_header(tid, unit, pdu):
    return tid.to_bytes(2, "big") + bytes([0, 0]) + (len(pdu) + 1).to_bytes(2, "little") + bytes([unit])
''', "wrote the length low byte first", "The length is big-endian, like every MBAP field.", ("mbap-little-endian",))

# --- 06: master and slave -----------------------------------------------------------------------
value("06.1", 34.375, "left out the two 3.5-character silences", "A transaction is request, t3.5, response, t3.5.", ("silences-forgotten",))
value("06.1", 38.02, "counted one silence only", "Both frames are followed by 3.5 characters of silence.", ("silences-forgotten",))
value("06.1", 31.25, "counted one byte per register in the response", "The FC3 response is 5 + 2N bytes.", ("register-one-byte",))
value("06.1", 45.83, "used 11 bits per character", "8N1 is 10 bits: start, 8 data, stop.", ())
value("06.1", 0.0417, "gave seconds", "Milliseconds are asked.", ("seconds-for-milliseconds",))
value("06.1", 22.92, "gave the one-register figure of the notebook", "Ten registers make the response 25 bytes.", ("one-register-response",))
value("06.1", 33.33, "used 8 bits per character", "A character is 10 bits on the line: start and stop bits count.", ("start-stop-forgotten",))

value("06.2", 1, "answered illegal function", "The slave knows function 5; coil 0 does not exist: code 02.", ("illegal-function-for-address", "exception-code-confused"))
value("06.2", 3, "answered illegal data value", "An address the slave lacks is code 02.", ("exception-code-confused",))
value("06.2", 4, "answered slave device failure", "A missing coil is code 02, illegal data address.", ("exception-code-confused",))
value("06.2", 0x82, "gave the exception function code of a read", "The exception code, 02, is asked.", ("exception-function-for-code",))
value("06.2", 0x85, "gave the exception response's function code", "The code after the function is asked: 02.", ("exception-function-for-code",))
value("06.2", 0, "thought the write succeeds", "The slave has no coils: it refuses.", ("refusal-unanswered",))

value("06.3", 43.6, "used the 9600-baud figure", "At 19200 baud every time halves: about 87.3.", ("another-baud-rate",))
value("06.3", 128.0, "left out the silences", "Each transaction includes two 3.5-character silences.", ("silences-forgotten",))
value("06.3", 79.3, "used 11 bits per character", "8N1 is 10 bits.", ())
value("06.3", 174.5, "counted the request or the response only", "A transaction is both frames and both silences.", ())
value("06.3", 0.0115, "gave the seconds one transaction takes", "Transactions per second are asked.", ("time-for-rate",))
value("06.3", 11.46, "gave the milliseconds one transaction takes", "Transactions per second are asked.", ("time-for-rate",))
value("06.3", 88.4, "used the fixed 1.75 ms silence at 19200 baud", "The fixed values apply only above 19200 baud.", ("fixed-silence-at-19200",))

value("06.4", mb.CrcError, "thought a damaged request shows as a CRC error", "The slave drops a damaged request silently: the master times out.", ("answer-to-damaged-request",))
value("06.4", mb.ModbusTimeoutError("no answer"), "gave an instance of the class", "The class itself is asked, not an error made from it.", ())
value("06.4", mb.ModbusExceptionError, "thought the slave answers with an exception", "A slave never answers a frame whose CRC fails.", ("answer-to-damaged-request",))
value("06.4", mb.TransactionMismatchError, "thought the flipped bit makes the answer another unit's", "No answer comes back at all.", ("answer-to-damaged-request",))
value("06.4", TimeoutError, "gave Python's built-in TimeoutError", "The library raises its own ModbusTimeoutError.", ("builtin-for-library-exception",))
value("06.4", mb.ModbusError, "gave the base class", "The specific class is asked: ModbusTimeoutError.", ())
value("06.4", mb.FrameLengthError, "thought the damaged request comes back short", "Nothing comes back: a timeout.", ("answer-to-damaged-request",))

_HANDLE_OK = '''    if pdu[0] == 3:
        address, count = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, 2 * count]) + data
    address, value = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = value
    return pdu
'''
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("if address + count > len(registers)", "if address + count >= len(registers)"), "refused a read that ends on the last register", "A read may end at the last register: address + count <= len.", ())
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("        if not 1 <= count <= 125:\n            return bytes([0x83, 3])\n", ""), "did not check the read count", "A count outside 1..125 gets exception 03.", ("invalid-input-accepted",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace('r.to_bytes(2, "big")', 'r.to_bytes(2, "little")'), "sent the registers low byte first", "Registers travel high byte first.", ("field-low-byte-first",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("    registers[address] = value\n", ""), "echoed the write without storing it", "A write single register stores the value, then echoes the request.", ("write-not-stored",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("bytes([3, 2 * count])", "bytes([3, count])"), "put the register count in the byte count", "The byte count is twice the number of registers.", ("byte-count-for-quantity",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("bytes([0x83, 2])", "bytes([3, 2])").replace("bytes([0x83, 3])", "bytes([3, 3])").replace("bytes([0x86, 2])", "bytes([6, 2])"), "left the function code as it was in exception responses", "An exception response adds 0x80 to the function code.", ("exception-bit-missing",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("if address >= len(registers)", "if address > len(registers)"), "let a write reach one past the last register", "The last register is len - 1: address len does not exist.", ("invalid-input-accepted",))
build("06.5", "def handle(registers, pdu):\n" + _HANDLE_OK.replace("        if not 1 <= count <= 125:\n            return bytes([0x83, 3])\n        if address + count > len(registers):\n            return bytes([0x83, 2])\n",
                                                             "        if address + count > len(registers):\n            return bytes([0x83, 2])\n        if not 1 <= count <= 125:\n            return bytes([0x83, 3])\n"), "checked the address before the count", "The quantity is checked first: a count of 0 is exception 03 wherever it starts.", ("exception-code-confused",))

# --- 07: exceptions and errors ------------------------------------------------------------------
value("07.1", (0x83, 2), "gave the response's function code", "The request's function is 0x83 - 0x80 = 3.", ("exception-code-as-function",))
value("07.1", (83, 2), "read 83 as the decimal function 83", "0x83 is function 3 with the exception bit.", ("hex-read-as-decimal",))
value("07.1", (2, 3), "gave the pair in the wrong order", "The pair is (function, code): (3, 2).", ("function-and-code-swapped",))
value("07.1", (17, 3), "took the address for the function and the function for the code", "The first byte is the slave address.", ("another-field",))
value("07.1", (3, 0xC1), "took the CRC's first byte for the exception code", "The exception code is the byte after the function.", ("another-field",))
value("07.1", (3,), "gave only the function", "A pair is asked: the function and the code.", ())

value("07.2", _rtu(17, mb.ExceptionResponse(1, 1)), "answered illegal function", "The slave has function 1; the coil is what it lacks: code 02.", ("illegal-function-for-address", "exception-code-confused"))
value("07.2", _rtu(17, mb.ExceptionResponse(3, 2)), "used function 3, as in 07.1", "The request was read coils, function 1: 0x81.", ())
value("07.2", _rtu_raw(h("11 01 02")), "did not add 0x80 to the function", "An exception response sets the function's top bit: 0x81.", ("exception-bit-missing",))
value("07.2", _rtu_crc_swapped(h("11 81 02")), "put the CRC high byte first", "An RTU frame carries its CRC low byte first.", ("crc-swapped",))
value("07.2", h("81 02"), "gave the PDU only", "The exact RTU frame is asked: address, PDU and CRC.", ("unit-missing", "crc-forgotten"))
value("07.2", h("11 81 02"), "left out the CRC", "Every RTU frame ends with its CRC.", ("crc-forgotten",))
value("07.2", _rtu(0x17, mb.ExceptionResponse(1, 2)), "wrote slave 17 as the byte 0x17", "17 decimal is the byte 0x11.", ("decimal-written-as-hex",))

_RIGHT_07_3 = {"request for a unit nobody has": "timeout", "one bit flipped in the request": "timeout",
               "one bit flipped in the response": "checksum error",
               "read of an address the slave does not have": "exception",
               "response carries another unit id": "mismatch"}
value("07.3", {**_RIGHT_07_3, "one bit flipped in the request": "checksum error"}, "thought the master sees a damaged request as a checksum error", "The slave drops a damaged request: the master times out.", ("answer-to-damaged-request",))
value("07.3", {**_RIGHT_07_3, "one bit flipped in the response": "timeout"}, "thought a damaged response is lost", "The response arrives, and its CRC fails at the master.", ("damaged-response-as-silence",))
value("07.3", {**_RIGHT_07_3, "request for a unit nobody has": "exception"}, "thought someone refuses a unit nobody has", "On a serial line nobody answers: a timeout.", ("answer-to-another-unit",))
value("07.3", {**_RIGHT_07_3, "read of an address the slave does not have": "timeout"}, "thought the slave stays silent on a missing address", "It answers exception 02.", ("refusal-unanswered",))
value("07.3", {**_RIGHT_07_3, "response carries another unit id": "valid"}, "thought the master takes any answer", "A response from another unit does not match the request.", ())
value("07.3", {**_RIGHT_07_3, "one bit flipped in the request": "exception"}, "thought a damaged request earns illegal data value", "A damaged request is dropped, not refused.", ("answer-to-damaged-request",))
value("07.3", {k: v for k, v in _RIGHT_07_3.items() if k != "response carries another unit id"}, "left one situation out", "Every situation must be answered.", ())

build("07.4", '''def exception_response(function, code):
    return bytes([0x80, function, code])
''', "wrote 0x80 as a byte of its own", "0x80 is added to the function code: one byte.", ())
build("07.4", '''def exception_response(function, code):
    return bytes([function, code])
''', "forgot the exception bit", "An exception response's function code is the request's plus 0x80.", ("exception-bit-missing",))
build("07.4", '''def exception_response(function, code):
    return bytes([function + 80, code])
''', "added decimal 80", "The exception bit is 0x80, 128.", ("hex-read-as-decimal",))
build("07.4", '''def exception_response(function, code):
    return bytes([1, function | 0x80, code])
''', "put a unit address in front", "The PDU starts at the function code.", ("unit-in-pdu",))
build("07.4", '''def exception_response(function, code):
    return bytes([code, function | 0x80])
''', "put the code before the function", "The function code comes first.", ("function-and-code-swapped",))
build("07.4", '''def exception_response(function, code):
    return bytes([function | 0x80, int(str(code), 16)])
''', "wrote the code's decimal digits as hex", "Code 11 is the byte 0x0B.", ("decimal-written-as-hex",))

# --- 08: serial timing --------------------------------------------------------------------------
value("08.1", 3.5 * 10 / 4800, "counted 10 bits per character", "8E1 has a parity bit: 11 bits.", ("parity-bit-forgotten",))
value("08.1", 3.5 * 11 / 4800 * 1000, "gave milliseconds", "Seconds are asked.", ("milliseconds-for-seconds",))
value("08.1", 11 / 4800, "gave one character time", "A frame ends after 3.5 character times.", ("one-character-for-t35",))
value("08.1", 1.5 * 11 / 4800, "used the 1.5-character gap", "1.5 characters break a frame; 3.5 end it.", ("t15-for-t35",))
value("08.1", 0.00175, "used the fixed 1.75 ms", "The fixed value applies only above 19200 baud.", ("fixed-silence-at-19200",))
value("08.1", 0.008, "rounded to three decimals", "Six decimals are asked: 0.008021.", ())
value("08.1", 3.5 * 12 / 4800, "counted two stop bits as well as the parity bit", "8E1 has one stop bit: 11 bits.", ())

value("08.2", 87.3, "used one register, as in 06.3", "Ten registers make the response 25 bytes.", ("one-register-response",))
value("08.2", 64.0, "left out the silences", "Each transaction includes two 3.5-character silences.", ("silences-forgotten",))
value("08.2", 24.0, "used 9600 baud", "The line runs at 19200 baud.", ("another-baud-rate",))
value("08.2", 43.6, "used 11 bits per character", "8N1 is 10 bits.", ())
value("08.2", 0.0208, "gave the seconds per transaction", "Transactions per second are asked.", ("time-for-rate",))
value("08.2", 20.83, "gave the milliseconds per transaction", "Transactions per second are asked.", ("time-for-rate",))
value("08.2", 48.34, "used the fixed 1.75 ms silence at 19200 baud", "The fixed values apply only above 19200 baud.", ("fixed-silence-at-19200",))

value("08.3", [5.0], "thought only a pause longer than 3.5 breaks the request", "A gap of more than 1.5 characters already breaks a frame.", ("t15-forgotten",))
value("08.3", [3.0, 5.0], "put the limit at 2 characters", "Any gap over 1.5 characters breaks the frame.", ("pause-threshold",))
value("08.3", [1.4, 2.0, 3.0, 5.0], "counted 1.4 as too long", "Gaps up to 1.5 characters are allowed.", ("pause-threshold",))
value("08.3", [2.0, 3.0], "thought a pause of 5 ends the frame and the slave answers its first half", "Both halves fail their CRC: nothing is answered.", ("answer-to-damaged-request",))
value("08.3", [1.0, 1.4], "reversed the rule", "Short gaps are allowed; long ones break the frame.", ())
value("08.3", [], "thought the slave waits for the rest", "A gap over 1.5 characters breaks an RTU frame.", ("t15-forgotten",))
value("08.3", [1.0, 1.4, 2.0, 3.0, 5.0], "thought any pause breaks the frame", "Gaps up to 1.5 characters are allowed.", ("pause-threshold",))

_TT = '''def transaction_time(baudrate, parity, stopbits, request_bytes, response_bytes):
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    t35 = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * t35
'''
build("08.4", _TT.replace('bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits', "bits = 10"), "counted 10 bits per character for every setting", "Parity and stop bits change the character's length.", ("parity-bit-forgotten",))
build("08.4", _TT.replace("0.00175 if baudrate > 19200 else 3.5 * char", "3.5 * char"), "used 3.5 characters at every baud rate", "Above 19200 baud the silence is a fixed 1.75 ms.", ("fixed-silence-ignored",))
build("08.4", _TT.replace("baudrate > 19200", "baudrate >= 19200"), "applied the fixed 1.75 ms already at 19200 baud", "The fixed values start above 19200 baud.", ("fixed-silence-at-19200",))
build("08.4", _TT.replace("+ 2 * t35", "+ t35"), "counted one silence", "A transaction is request, t3.5, response, t3.5.", ("silences-forgotten",))
build("08.4", _TT.replace('(0 if parity == "N" else 1)', "1"), "counted a parity bit for N too", "No parity means no parity bit.", ())
build("08.4", _TT.replace("+ stopbits", "+ 1"), "counted one stop bit always", "Two stop bits make the character 11 bits.", ())
build("08.4", _TT.replace("return (request_bytes + response_bytes) * char + 2 * t35", "return ((request_bytes + response_bytes) * char + 2 * t35) * 1000"), "returned milliseconds", "Seconds are asked.", ("milliseconds-for-seconds",))

# --- 09: an Arduino slave -----------------------------------------------------------------------
value("09.1", (3, 9), "used function 3", "Input registers are read with function 4.", ("holding-for-input",))
value("09.1", (4, 10), "kept the reference's count from 1", "30010 is address 9.", ("one-based-address",))
value("09.1", (4, 30009), "kept the table prefix", "The address has no prefix: 9.", ("reference-number",))
value("09.1", (3, 10), "used function 3 and address 10", "Function 4, address 9.", ("holding-for-input", "one-based-address"))
value("09.1", (9, 4), "gave the pair in the wrong order", "The pair is (function, address).", ())
value("09.1", (2, 9), "took an input register for a discrete input", "Function 2 reads discrete inputs; 4 reads input registers.", ("bit-table-for-register-table",))

value("09.2", board((40150, 25), (40200, 25)), "counted 150 to 175 as 25 registers", "Both ends count: 150 to 175 is 26 registers.", ("range-one-end",))
value("09.2", board((40149, 26), (40199, 26)), "subtracted one from the reference numbers", "add() takes reference numbers: register 150 is 40150.", ())
value("09.2", board((40151, 26), (40201, 26)), "added one to the reference numbers", "Register 150 is reference 40150.", ())
value("09.2", board((30150, 26), (30200, 26)), "declared input registers", "Holding registers are 4xxxx.", ("holding-for-input",))
value("09.2", board((40150, 76)), "filled the gap, declaring 150 to 225", "A sparse map leaves 176 to 199 out.", ("dense-for-sparse",))
value("09.2", board((40150, 26)), "declared only the first range", "Both ranges are used.", ("one-range-only",))
value("09.2", board((40150, 27), (40200, 27)), "went one past each range", "175 and 225 are the last registers.", ("range-one-extra",))

value("09.3", 1.65, "gave the loop time itself", "Loops vary by up to 10%, and the reply takes time: at least 1.83 s.", ("loop-time-for-timeout",))
value("09.3", 1.0, "kept the default timeout", "A 1.65 s loop needs a longer timeout.", ())
value("09.3", 1.8, "allowed for the 10% but rounded below it", "1.65 x 1.1 is 1.815, plus the reply.", ())
value("09.3", 3.0, "gave a generous timeout", "At most 2.5 s is asked.", ("timeout-far-too-long",))
value("09.3", 1650, "gave milliseconds", "Seconds are asked.", ("milliseconds-for-seconds",))
value("09.3", 2.6, "added a 1 s margin to the slowest loop", "At most 2.5 s is asked.", ("timeout-far-too-long",))
value("09.3", 1.7, "allowed a little for the reply, not for the 10%", "Loops vary by up to 10%: 1.815 s plus the reply.", ("loop-time-for-timeout",))

_AF = '''def answered_fraction(loop_time, timeout, reply):
    return max(0.0, min(1.0, (timeout - reply) / loop_time))
'''
build("09.4", _AF.replace("(timeout - reply)", "timeout"), "forgot the reply's time", "The reply must arrive within the timeout: (timeout - reply) / loop.", ("reply-time-forgotten",))
build("09.4", _AF.replace("max(0.0, min(1.0, (timeout - reply) / loop_time))", "max(0.0, (timeout - reply) / loop_time)"), "did not cap the fraction at 1", "A fast loop answers every request: at most 1.", ("fraction-unclamped",))
build("09.4", _AF.replace("max(0.0, min(1.0, (timeout - reply) / loop_time))", "min(1.0, (timeout - reply) / loop_time)"), "did not floor the fraction at 0", "A timeout shorter than the reply answers nothing: 0, not negative.", ("fraction-unclamped",))
build("09.4", _AF.replace("(timeout - reply)", "(timeout + reply)"), "added the reply's time", "The reply uses part of the timeout.", ("reply-time-forgotten",))
build("09.4", _AF.replace("(timeout - reply) / loop_time", "loop_time / (timeout - reply)"), "divided the other way", "The fraction is the timeout's share of a loop.", ())
build("09.4", _AF.replace("max(0.0, min(1.0, (timeout - reply) / loop_time))", "1 - max(0.0, min(1.0, (timeout - reply) / loop_time))"), "returned the fraction missed", "The fraction answered is asked.", ("missed-for-answered",))

# --- 10: a power meter --------------------------------------------------------------------------
value("10.1", 4105, "left out the scale", "VL2 is volts x 10: 410.5 V.", ("raw-for-scaled",))
value("10.1", 41.05, "divided by 100", "VL2's scale is x 10.", ("scale-wrong",))
value("10.1", mb.decode_value([0x0000, 0x1009], "uint32", "CDAB") / 10, "read the registers low word first", "This meter sends the high word first (ABCD).", ("word-order",))
value("10.1", 0, "read only the first register", "VL2 is a 32-bit value in two registers.", ("one-register-for-32-bits",))
value("10.1", 100.9, "read 1009 as decimal", "0x1009 is 4105.", ("hex-read-as-decimal",))
value("10.1", 0x37F5 / 10, "took the CRC for the value", "The value is in the data bytes, before the CRC.", ("another-field",))

value("10.2", [26756, 4], "sent the low word first", "This meter sends the high word first.", ("word-order",))
value("10.2", [0, 2889], "scaled by 10 instead of milliamperes", "AL1 is in mA: 288900.", ("scale-wrong", "current-not-in-milliamperes"))
value("10.2", [0x0400, 0x8468], "swapped the bytes in each register", "Each register is sent high byte first.", ("word-order", "field-low-byte-first"))
value("10.2", [288900], "gave one register", "A 32-bit value takes two registers.", ("one-register-for-32-bits",))
value("10.2", [0, 28890], "scaled by 100", "AL1 is in mA: 288900.", ("scale-wrong", "current-not-in-milliamperes"))
value("10.2", mb.encode_value(288900.0, "float32", "ABCD"), "encoded a float32", "This meter sends an unsigned 32-bit integer.", ())

value("10.3", (3, 54, 3), "counted three values, not six registers", "Each value takes two registers: 6.", ("one-register-for-32-bits",))
value("10.3", (4, 54, 6), "used function 4", "This meter's map is read with FC3.", ("holding-for-input",))
value("10.3", (3, 55, 6), "added one to the address", "The map gives the address as it goes in the frame.", ("one-based-address",))
value("10.3", (3, 54, 2), "read THD_AL1 only", "The three currents' THD are asked.", ())
value("10.3", (3, 54, 5), "counted the last register one short", "Three 2-register values are 6 registers.", ("range-one-end",))
value("10.3", (3, 0x54, 6), "read the address 54 as hex", "The address is 54, 0x36.", ("decimal-written-as-hex",))

_DF = '''import struct

def decode_float32(registers, order):
    a, b = registers
    raw = struct.pack(">HH", a, b)
    if order == "ABCD":
        data = raw
    elif order == "CDAB":
        data = raw[2:] + raw[:2]
    elif order == "BADC":
        data = bytes([raw[1], raw[0], raw[3], raw[2]])
    else:
        data = raw[::-1]
    return struct.unpack(">f", data)[0]
'''
build("10.4", '''import struct

def decode_float32(registers, order):
    return struct.unpack(">f", struct.pack(">HH", *registers))[0]
''', "ignored the order", "The word order decides which bytes are the value's high half.", ("word-order",))
build("10.4", _DF.replace('order == "CDAB"', 'order == "XXXX"').replace('order == "BADC"', 'order in ("BADC", "CDAB")'), "took CDAB for a swap of the bytes in each register", "CDAB swaps the registers; BADC swaps the bytes in each.", ("word-order",))
build("10.4", _DF.replace('order == "CDAB"', 'order in ("CDAB", "DCBA")'), "treated DCBA like CDAB", "DCBA reverses all four bytes.", ("word-order",))
build("10.4", _DF.replace('data = raw\n', 'data = raw[::-1]\n', 1), "read ABCD little-endian", "ABCD is the most significant byte first.", ("word-order",))
build("10.4", _DF.replace('return struct.unpack(">f", data)[0]', 'return round(struct.unpack(">f", data)[0], 1)'), "rounded the value to one decimal", "The function returns the float32 as decoded.", ("result-rounded",))
build("10.4", _DF.replace('struct.pack(">HH", a, b)', 'struct.pack("<HH", a, b)'), "packed each register low byte first", "A register's bytes are high byte first.", ("word-order", "field-low-byte-first"))
build("10.4", '''import struct

def decode_float32(registers, order):
    a, b = registers
    if order == "ABCD":
        return struct.unpack(">f", struct.pack(">HH", a, b))[0]
    if order == "CDAB":
        return struct.unpack(">f", struct.pack(">HH", b, a))[0]
    return None
''', "handled only ABCD and CDAB", "Four word orders are asked.", ())

# --- 11: real sockets ---------------------------------------------------------------------------
value("11.1", (42, 6, 10, 500), "read the address byte 10 as decimal", "00 10 is address 16.", ("hex-read-as-decimal",))
value("11.1", (42, 6, 16, 0xF401), "read the value low byte first", "01 F4 is 500.", ("field-low-byte-first",))
value("11.1", (42, 17, 16, 500), "took the unit id for the function", "The function code follows the unit id: 6.", ("another-field",))
value("11.1", (42, 6, 17, 500), "added one to the address", "The frame carries the address: 16.", ("one-based-address",))
value("11.1", (42, 6, 16), "left out the value", "Four ints are asked.", ())
value("11.1", (6, 16, 500, 42), "put the transaction id last", "The order asked is (transaction_id, function, address, value).", ())

value("11.2", _tcp(7, 3, mb.decode_pdu(PDU_11_2, "request")) + h("04 29"), "kept the RTU CRC", "Modbus/TCP carries no CRC: the gateway drops it.", ("crc-on-tcp",))
value("11.2", _tcp(7, 1, mb.decode_pdu(PDU_11_2, "request")), "used unit 1", "The RTU address 3 becomes the unit id.", ())
value("11.2", h("00 07 00 00 00 08 03 03 00 00 00 03"), "counted the CRC in the length", "The length counts the unit id and the PDU: 6.", ("mbap-length", "crc-on-tcp"))
value("11.2", h("07 00 00 00 00 06 03 03 00 00 00 03"), "wrote the transaction id low byte first", "MBAP fields are big-endian.", ("mbap-little-endian",))
value("11.2", h("00 07 00 00 00 05 03 00 00 00 03"), "left out the unit id", "The MBAP header ends with the unit id.", ("unit-missing",))
value("11.2", h("03 03 00 00 00 03 04 29"), "forwarded the RTU frame unchanged", "The gateway rewraps the PDU in an MBAP header.", ("crc-on-tcp",))
value("11.2", _tcp(1, 3, mb.decode_pdu(PDU_11_2, "request")), "used transaction id 1", "The task gives transaction id 7.", ())

value("11.3", "tcp://192.168.1.60:4001", "used tcp:// for a raw TCP port", "pyserial names a raw TCP port socket://.", ("url-not-socket",))
value("11.3", "192.168.1.60:4001", "gave the address without a scheme", "serial_link takes a URL: socket://host:port.", ("url-not-socket",))
value("11.3", "socket://192.168.1.60:502", "used Modbus/TCP's port", "The device server carries the line on port 4001.", ("modbus-tcp-port-for-server",))
value("11.3", "rfc2217://192.168.1.60:4001", "used the RFC 2217 scheme", "Raw TCP mode is socket://; rfc2217:// is the Telnet-based protocol.", ("url-not-socket",))
value("11.3", "socket://192.168.1.60", "left out the port", "The URL needs the port, 4001.", ("url-without-port",))
value("11.3", "http://192.168.1.60:4001", "used a web URL", "A raw serial line over TCP is socket://.", ("url-not-socket",))

_SPLIT = '''def split_mbap(frame):
    if len(frame) < 8:
        raise ValueError("too short")
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0:
        raise ValueError("protocol")
    if length != len(frame) - 6:
        raise ValueError("length")
    return (tid, protocol, length, frame[6], frame[7:])
'''
build("11.4", _SPLIT.replace('    if protocol != 0:\n        raise ValueError("protocol")\n', ""), "did not check the protocol id", "A protocol id other than 0 is not Modbus: refuse it.", ("invalid-input-accepted",))
build("11.4", _SPLIT.replace('    if length != len(frame) - 6:\n        raise ValueError("length")\n', ""), "did not check the length", "A length that does not match the frame is refused.", ("invalid-input-accepted",))
build("11.4", _SPLIT.replace("return (tid, protocol, length,", "return (tid, protocol, length - 1,"), "returned the PDU's length", "The length field's value is asked: unit id and PDU.", ("mbap-length",))
build("11.4", _SPLIT.replace('"big"', '"little"'), "read the fields little-endian", "MBAP fields are big-endian.", ("mbap-little-endian",))
build("11.4", _SPLIT.replace("if len(frame) < 8:", "if len(frame) < 7:"), "allowed a frame with no function code", "A frame needs at least a function code after the unit id.", ("invalid-input-accepted",))
build("11.4", _SPLIT.replace("frame[6], frame[7:])", "frame[6], frame[6:])"), "kept the unit id in the PDU", "The PDU starts after the unit id.", ("unit-in-pdu",))
build("11.4", _SPLIT.replace("return (tid, protocol, length, frame[6], frame[7:])", "return (tid, length, frame[6], frame[7:])"), "left the protocol id out of the result", "Five fields are asked.", ())

# --- 12: the test tool --------------------------------------------------------------------------
value("12.1", "0x0064", "gave address 0's value", "Address 5 holds 100 + 5 x 10 = 150.", ())
value("12.1", "0x00A0", "counted address 5 as the sixth increment", "Address 0 holds 100; address 5 holds 150.", ())
value("12.1", "150", "gave the decimal text", "The grid shows hex: 0x0096.", ())
value("12.1", "0x0150", "wrote the decimal digits after 0x", "150 is 0x96.", ("decimal-written-as-hex",))
value("12.1", "0x0069", "used an increment of 1", "The increment is 10: 150.", ())
value("12.1", 0x0096, "gave the number, not the text", "The text the grid shows is asked: a string.", ())

value("12.2", tool(function=3), "read holding registers", "Input registers are read with function 4.", ("holding-for-input",))
value("12.2", tool(unit=10, address=7), "swapped the unit and the address", "Unit 7, address 10.", ())
value("12.2", tool(address=11), "started at address 11, counting from 1", "The address is 10.", ("one-based-address",))
value("12.2", tool(interval=500), "gave the interval in milliseconds", "The interval is in seconds: 0.5.", ("milliseconds-for-seconds",))
value("12.2", tool(role="tcp_client"), "chose a TCP client", "A master on the serial line: rtu_master.", ())
value("12.2", tool(role="rtu_slave"), "chose a slave tool", "To test a device the tool asks: a master.", ("slave-for-master",))
value("12.2", tool(interval=2), "gave the polls per second", "The interval is the time between polls: 0.5 s.", ())

value("12.3", (284, "01 1C"), "counted one too many", "280, 281, 282 were sent: the next is 283.", ())
value("12.3", (282, "01 1A"), "gave the third poll's id", "The next request after three polls is asked.", ("last-transaction-id",))
value("12.3", (283, "1B 01"), "wrote the id low byte first", "The transaction id is big-endian: 01 1B.", ("mbap-little-endian",))
value("12.3", (283, "02 83"), "wrote the decimal digits as bytes", "283 is 0x011B.", ("decimal-written-as-hex",))
value("12.3", (281, "01 19"), "took the next id after the first poll", "Three polls used 280, 281 and 282.", ())
value("12.3", 283, "gave the id alone", "A pair is asked: the id and its two bytes.", ())

_RR = '''def read_request(tid, unit, address, count):
    return (tid.to_bytes(2, "big") + bytes([0, 0, 0, 6, unit, 3])
            + address.to_bytes(2, "big") + count.to_bytes(2, "big"))
'''
build("12.4", _RR.replace('tid.to_bytes(2, "big")', "bytes([0, tid & 0xFF])"), "wrote the transaction id as one byte", "The transaction id takes two bytes: 280 is 01 18.", ("field-in-one-byte",))
build("12.4", _RR.replace('tid.to_bytes(2, "big")', 'tid.to_bytes(2, "little")'), "wrote the transaction id low byte first", "MBAP fields are big-endian.", ("mbap-little-endian",))
build("12.4", _RR.replace("0, 0, 0, 6, unit", "0, 0, 0, 5, unit"), "counted the PDU only in the length", "The length counts the unit id and the PDU: 6.", ("mbap-length",))
build("12.4", '''def read_request(tid, unit, address, count):
    body = bytes([unit, 3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    crc = 0xFFFF
    for b in body:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return tid.to_bytes(2, "big") + bytes([0, 0, 0, 6]) + body + crc.to_bytes(2, "little")
''', "added a CRC", "Modbus/TCP carries no CRC.", ("crc-on-tcp",))
build("12.4", _RR.replace("bytes([0, 0, 0, 6, unit, 3])", "bytes([0, 0, 0, 5, 3])"), "left out the unit id", "The MBAP header ends with the unit id.", ("unit-missing",))
build("12.4", _RR.replace("unit, 3]", "unit, 4]"), "used function 4", "Holding registers are read with function 3.", ("holding-for-input",))
build("12.4", _RR.replace('address.to_bytes(2, "big")', '(address + 1).to_bytes(2, "big")'), "added one to the address", "The frame carries the address itself.", ("one-based-address",))

# --- 13: troubleshooting ------------------------------------------------------------------------
_RIGHT_13_1 = {"A": "wrong unit id", "B": "no slave on the line", "C": "wrong baud rate or parity"}
value("13.1", {"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"}, "swapped A and B", "A's slave heard every request for another unit; B has no slave at all.", ("causes-swapped",))
value("13.1", {"A": "wrong baud rate or parity", "B": "no slave on the line", "C": "wrong unit id"}, "swapped A and C", "C's slave assembled other bytes, failing their CRC: another baud rate.", ("causes-swapped",))
value("13.1", {"A": "wrong unit id", "B": "wrong baud rate or parity", "C": "no slave on the line"}, "swapped B and C", "B lists no slave; C's slave counted checksum errors.", ("causes-swapped",))
value("13.1", {"A": "no slave on the line", "B": "wrong baud rate or parity", "C": "wrong unit id"}, "rotated the three", "A counted other_unit, B has none, C counted checksum errors.", ("causes-swapped",))
value("13.1", {"A": "wrong baud rate or parity", "B": "wrong unit id", "C": "no slave on the line"}, "rotated the three the other way", "A counted other_unit, B has none, C counted checksum errors.", ("causes-swapped",))
value("13.1", {"A": "wrong unit id", "C": "wrong baud rate or parity"}, "left out the wire with no slave", "All three wires must be named.", ())

value("13.2", ("CDAB", 135541), "left the value in milliamperes", "The sensor sends mA: 135.541 A.", ("milliamperes-for-amperes",))
value("13.2", ("ABCD", 292880.386), "kept the colleague's order", "High word first gives an impossible current: the sensor is CDAB.", ("word-order",))
value("13.2", ("DCBA", 135.541), "named the order DCBA", "The registers are swapped, the bytes in each are not: CDAB.", ("word-order",))
value("13.2", ("CDAB", 0.135541), "divided by a million", "mA to A is / 1000.", ("scale-wrong",))
value("13.2", ("BADC", mb.decode_value([0x1175, 0x0002], "uint32", "BADC") / 1000), "swapped the bytes in each register", "CDAB swaps the registers, not the bytes.", ("word-order",))
value("13.2", (135.541, "CDAB"), "gave the pair in the wrong order", "The pair is (order, current).", ())
value("13.2", ("CDAB", mb.decode_value([0x1175, 0x0002], "float32", "CDAB")), "decoded a float32", "The sensor sends an unsigned 32-bit integer.", ())

value("13.3", 21, "kept the reference's count from 1", "40021 is address 20.", ("one-based-address",))
value("13.3", 40020, "kept the table prefix", "The address has no prefix: 20.", ("reference-number",))
value("13.3", 19, "subtracted one from the script's 20 again", "40021 - 40001 = 20.", ("address-one-too-low",))
value("13.3", 40021, "gave the reference number", "The frame carries the address: 20.", ("reference-number",))
value("13.3", 0x20, "wrote 20 as hex", "The address is the number 20.", ("decimal-written-as-hex",))
value("13.3", 22, "moved the wrong way", "The script read one register too far: the address is 20.", ())

value("13.4", (3, "00 03"), "gave the client's number as the server's reading", "The server reads 03 00 as 768.", ("mbap-little-endian",))
value("13.4", (0x0300, "03 00"), "kept the captured bytes", "Transaction 3 is 00 03, high byte first.", ("mbap-little-endian",))
value("13.4", (3, "03 00"), "read and wrote it little-endian", "MBAP fields are big-endian.", ("mbap-little-endian",))
value("13.4", (300, "00 03"), "read 03 00 as decimal 300", "0x0300 is 768.", ("hex-read-as-decimal",))
value("13.4", (0x0300, "00 04"), "gave the next transaction's bytes", "The client's third request is 3: 00 03.", ())
value("13.4", (0x0300,), "gave the id alone", "A pair is asked.", ())

value("13.5", h("01 03 00 00 00 01 0A 84"), "sent the frame unchanged", "The CRC is written high byte first: swap it.", ("crc-swapped",))
value("13.5", h("01 03 00 00 00 01"), "dropped the CRC", "An RTU frame needs its CRC, low byte first: 84 0A.", ("crc-forgotten",))
value("13.5", _tcp(1, 1, mb.ReadHoldingRegistersRequest(0, 1)), "built a Modbus/TCP frame", "The slave is on a serial line: RTU.", ("tcp-frame-for-rtu",))
value("13.5", h("03 00 00 00 01"), "gave the PDU", "The whole frame is asked.", ("unit-missing", "crc-forgotten"))
value("13.5", _rtu(1, mb.ReadHoldingRegistersRequest(1, 1)), "changed the address to 1", "The address was right; the CRC's byte order was wrong.", ())
value("13.5", h("01 03 00 00 00 01") + _low_first(_crc(h("01 03 00 00 00 01"), init=0)), "recomputed the CRC from 0", "CRC-16/MODBUS starts at 0xFFFF.", ("crc-initial-zero",))

value("13.6", 0.44, "gave the fraction answered", "The loop time is (timeout - reply) / fraction: about 2.2 s.", ("given-figure",))
value("13.6", 2243, "gave milliseconds", "Seconds are asked.", ("milliseconds-for-seconds",))
value("13.6", 5.0 / (132 / 300), "used the 5 s interval as the timeout", "The master's timeout is 1 s.", ())
value("13.6", 1.0, "gave the timeout", "The loop time is the timeout divided by the fraction.", ("given-figure",))
value("13.6", 0.56, "gave the fraction of timeouts", "The loop time is (timeout - reply) / fraction answered.", ())
value("13.6", 0.013, "gave the reply time", "The loop time is asked.", ("given-figure",))
value("13.6", (1.0 - 0.013) * (132 / 300), "multiplied by the fraction", "Divide by the fraction: about 2.2 s.", ())

_FO = '''import math
import struct

def find_order(registers, expected):
    a, b = registers
    raw = struct.pack(">HH", a, b)
    variants = {"ABCD": raw, "CDAB": raw[2:] + raw[:2], "BADC": bytes([raw[1], raw[0], raw[3], raw[2]]), "DCBA": raw[::-1]}
    for order, data in variants.items():
        if math.isclose(struct.unpack(">f", data)[0], expected, rel_tol=1e-6):
            return order
    return None
'''
build("13.7", _FO.replace("math.isclose(struct.unpack(\">f\", data)[0], expected, rel_tol=1e-6)", "struct.unpack(\">f\", data)[0] == expected"), "compared floats with ==", "A float32 is not exactly the decimal shown: compare with a tolerance.", ("float-compared-exactly",))
build("13.7", _FO.replace(', "BADC": bytes([raw[1], raw[0], raw[3], raw[2]]), "DCBA": raw[::-1]', ""), "tried only ABCD and CDAB", "Four orders exist.", ())
build("13.7", _FO.replace("    return None\n", '    return "ABCD"\n'), "returned ABCD when nothing fits", "None is asked when no order fits.", ("an-order-when-none-fits",))
build("13.7", _FO.replace("            return order\n    return None\n", "            found.append(order)\n    return found\n").replace("    for order", "    found = []\n    for order"), "returned a list of orders", "One order is asked, or None.", ())
build("13.7", _FO.replace('struct.unpack(">f", data)[0]', 'struct.unpack(">I", data)[0]'), "decoded a uint32", "The registers hold a float32.", ("integer-for-float",))
build("13.7", _FO.replace("math.isclose(struct.unpack(\">f\", data)[0], expected, rel_tol=1e-6)", "abs(struct.unpack(\">f\", data)[0] - expected) < 1"), "compared within 1 unit", "An absolute tolerance of 1 takes tiny values for 0.5: use a relative one.", ("float-compared-exactly",))
build("13.7", _FO.replace("            return order\n", "            return struct.unpack(\">f\", data)[0]\n"), "returned the value", "The order is asked.", ())

# --- 14: beyond eight functions -----------------------------------------------------------------
value("14.1", 0x05, "applied the AND mask only", "The OR mask's bits outside the AND mask are set too.", ("or-mask-forgotten",))
value("14.1", 0x1B5, "applied the OR mask only", "The AND mask clears bits first.", ("mask-write-or",))
value("14.1", 0x1B0, "kept the bits the AND mask clears", "AND keeps the bits where the mask is 1.", ("mask-roles-swapped",))
value("14.1", 135, "wrote the hex digits 135 as decimal", "The result is 0x135, 309.", ("hex-read-as-decimal",))
value("14.1", 0x20, "ANDed the register with the OR mask", "(current AND and_mask) OR (or_mask AND NOT and_mask).", ("mask-roles-swapped",))
value("14.1", 0xA5, "thought the register does not change", "FC 22 changes the register.", ())

build("14.2", '''def mask_write(current, and_mask, or_mask):
    return (current & and_mask) | or_mask
''', "ORed the whole OR mask", "Only the OR mask's bits outside the AND mask are set.", ("mask-write-or",))
build("14.2", '''def mask_write(current, and_mask, or_mask):
    return (current | or_mask) & and_mask
''', "ORed before ANDing", "AND first, then OR the mask's bits outside the AND mask.", ())
build("14.2", '''def mask_write(current, and_mask, or_mask):
    return (current & ~and_mask) | (or_mask & and_mask)
''', "swapped the roles of the two masks' bits", "AND keeps the bits where the AND mask is 1.", ("mask-roles-swapped",))
build("14.2", '''def mask_write(current, and_mask, or_mask):
    return (current & and_mask) | (or_mask & ~and_mask & 0xFF)
''', "kept only 8 bits of the complement", "Registers are 16 bits: NOT and_mask is & 0xFFFF.", ())
build("14.2", '''def mask_write(current, and_mask, or_mask):
    return current & and_mask
''', "applied the AND mask only", "The OR mask sets bits too.", ("or-mask-forgotten",))
build("14.2", '''def mask_write(current, and_mask, or_mask):
    return current ^ ((current ^ or_mask) & and_mask)
''', "took the bits from the OR mask where the AND mask is 1", "Bits where the AND mask is 0 come from the OR mask.", ("mask-roles-swapped", "mask-write-or"))

value("14.3", 6, "counted the damaged request too", "A frame with a bad CRC is not counted as a bus message.", ("damaged-message-counted",))
value("14.3", 4, "left out the 0x0B request being answered", "The course's slave counts the request it answers.", ("count-request-forgotten",))
value("14.3", 3, "counted only the requests to unit 1", "The course's slave counts every frame with a good CRC, other units' too.", ("others-not-heard",))
value("14.3", 7, "counted unit 1's own responses", "A slave receives other frames; it sends its own responses.", ("own-frames-counted",))
value("14.3", 2, "counted only the two reads", "Unit 2's request and response and the 0x0B request count too.", ("others-not-heard", "count-request-forgotten"))
value("14.3", 8, "counted every frame on the line", "Its own responses and the damaged request are not counted.", ("own-frames-counted", "damaged-message-counted"))

# --- 15: gateways and converters ----------------------------------------------------------------
value("15.1", 12.5, "counted 10 bits per character", "8E1 is 11 bits.", ("parity-bit-forgotten",))
value("15.1", 9.74, "left out the silences", "A transaction is request, t3.5, response, t3.5.", ("silences-forgotten",))
value("15.1", 13.24, "used the fixed 1.75 ms at 19200 baud", "The fixed values apply only above 19200 baud.", ("fixed-silence-at-19200",))
value("15.1", 12.6, "counted one byte per register", "The response is 5 + 2 x 2 = 9 bytes.", ("register-one-byte",))
value("15.1", 0.01375, "gave seconds", "Milliseconds are asked.", ("seconds-for-milliseconds",))
value("15.1", 27.5, "used 9600 baud", "The bus runs at 19200 baud.", ("another-baud-rate",))
value("15.1", 11.74, "counted one silence", "Both frames are followed by 3.5 characters.", ("silences-forgotten",))

_RT = '''def rtu_to_tcp(frame, transaction_id):
    body, crc = frame[:-2], frame[-2:]
    c = 0xFFFF
    for b in body:
        c ^= b
        for _ in range(8):
            c = (c >> 1) ^ 0xA001 if c & 1 else c >> 1
    if c.to_bytes(2, "little") != crc:
        raise ValueError("CRC")
    return transaction_id.to_bytes(2, "big") + bytes([0, 0]) + len(body).to_bytes(2, "big") + body
'''
build("15.2", _RT.replace('    if c.to_bytes(2, "little") != crc:\n        raise ValueError("CRC")\n', ""), "did not check the CRC", "A gateway does not forward a damaged frame.", ("invalid-input-accepted",))
build("15.2", _RT.replace("len(body).to_bytes(2, \"big\") + body", "len(frame).to_bytes(2, \"big\") + frame"), "kept the CRC", "The CRC is dropped.", ("crc-on-tcp",))
build("15.2", _RT.replace("len(body).to_bytes", "(len(body) - 1).to_bytes"), "counted the PDU only in the length", "The length counts the unit id and the PDU.", ("mbap-length",))
build("15.2", _RT.replace('transaction_id.to_bytes(2, "big")', 'transaction_id.to_bytes(2, "little")'), "wrote the transaction id low byte first", "MBAP fields are big-endian.", ("mbap-little-endian",))
build("15.2", _RT.replace("len(body).to_bytes", "len(frame).to_bytes"), "counted the CRC in the length", "The length counts the unit id and the PDU, without the CRC.", ("mbap-length",))
build("15.2", _RT.replace('c.to_bytes(2, "little") != crc', 'c.to_bytes(2, "big") != crc'), "checked the CRC high byte first", "The CRC arrives low byte first.", ("crc-swapped",))
build("15.2", _RT.replace('transaction_id.to_bytes(2, "big")', "bytes([0, transaction_id & 0xFF])"), "wrote the transaction id as one byte", "The transaction id takes two bytes.", ("field-in-one-byte",))

_RIGHT_15_3 = {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"}
value("15.3", {**_RIGHT_15_3, "a": 0x0B}, "thought unit 248 stays silent", "Unit 248 is reserved: the gateway has no path, 0A.", ("gateway-codes-swapped",))
value("15.3", {**_RIGHT_15_3, "b": "timeout"}, "thought the client times out on the silent meter", "The gateway answers 0B after its 0.2 s.", ("gateway-silence",))
value("15.3", {**_RIGHT_15_3, "c": "timeout"}, "thought the meter ignores an unknown function", "The meter answers exception 01, and the gateway passes it on.", ("refusal-unanswered",))
value("15.3", {**_RIGHT_15_3, "c": 0x0B}, "thought the gateway refuses it", "The gateway forwards it; the meter answers 01.", ())
value("15.3", {**_RIGHT_15_3, "d": 0x0B}, "thought the impatient client gets 0B", "Its 0.1 s end before the gateway's 0.2 s: a timeout.", ())
value("15.3", {**_RIGHT_15_3, "a": "timeout"}, "thought no one answers unit 248", "The gateway answers 0A: no path.", ("gateway-silence",))
value("15.3", {**_RIGHT_15_3, "b": 0x0A}, "swapped 0A and 0B for the silent meter", "0B: the target did not respond; 0A: no path.", ("gateway-codes-swapped",))

# --- 16: a first real device --------------------------------------------------------------------
_MAP = """name,table,address,type,order,scale,unit
voltage,input,30001,float32,CDAB,1,V
current,input,30007,float32,CDAB,1,A
power,input,30013,float32,CDAB,1,W
frequency,input,30071,float32,CDAB,1,Hz
energy,input,30073,float32,CDAB,1,kWh
"""
value("16.1", _MAP.replace("input,", "holding,"), "wrote the table as holding", "30001-style numbers are input registers.", ("holding-for-input",))
value("16.1", _MAP.replace(",30001,", ",0,").replace(",30007,", ",6,").replace(",30013,", ",12,").replace(",30071,", ",70,").replace(",30073,", ",72,"), "wrote the addresses instead of the datasheet's numbers", "The file keeps the datasheet's numbers; load_map turns them into addresses.", ())
value("16.1", _MAP.replace("30071", "30070"), "wrote the frequency one number early", "The datasheet lists it at 30071.", ())
value("16.1", "\n".join(_MAP.splitlines()[:-1]) + "\n", "left out the energy row", "Every value of the table gets a row.", ())
value("16.1", _MAP.replace("float32", "int16"), "wrote the values as 16-bit integers", "The meter sends float32 in two registers.", ("one-register-for-32-bits", "integer-for-float"))
value("16.1", _MAP.split("\n", 1)[1], "left out the header row", "A map file starts with its header.", ())
value("16.1", _MAP.replace(",30001,", ",30000,").replace(",30007,", ",30006,").replace(",30013,", ",30012,").replace(",30071,", ",30070,").replace(",30073,", ",30072,"), "subtracted one from each number", "The file keeps the datasheet's numbers as they are.", ())

_PLAN = ((0, 2), (6, 2), (12, 2), (70, 4))
value("16.2", [_rtu(1, mb.ReadHoldingRegistersRequest(a, c)) for a, c in _PLAN], "read with function 3", "The meter's values are input registers: function 4.", ("holding-for-input",))
value("16.2", [_rtu(1, mb.ReadInputRegistersRequest(0, 74))], "read everything in one request", "The plan never reads a register the device does not list.", ("dense-for-sparse",))
value("16.2", [_rtu(1, mb.ReadInputRegistersRequest(a + 1, c)) for a, c in _PLAN], "kept the numbers' count from 1", "30001 is address 0.", ("one-based-address",))
value("16.2", [_rtu(1, mb.ReadInputRegistersRequest(a, c)) for a, c in ((0, 2), (6, 2), (12, 2), (70, 2), (72, 2))], "read frequency and energy apart", "Neighbouring values share one request.", ())
value("16.2", [_rtu_crc_swapped(bytes([1]) + mb.ReadInputRegistersRequest(a, c).encode()) for a, c in _PLAN], "put each CRC high byte first", "An RTU frame carries its CRC low byte first.", ("crc-swapped",))
value("16.2", [bytes([1]) + mb.ReadInputRegistersRequest(a, c).encode() for a, c in _PLAN], "left out the CRCs", "An RTU frame ends with its CRC.", ("crc-forgotten",))
value("16.2", [_rtu(1, mb.ReadInputRegistersRequest(a, c)) for a, c in reversed(_PLAN)], "listed the frames last first", "The order in which they are sent is asked: lowest address first.", ())

value("16.3", "check the termination resistor", "went to termination", "Silence with every setting right points next at A and B swapped.", ("termination-for-silence",))
value("16.3", "the baud rate and parity", "went back to the settings", "The menu and the scan ruled the settings out: swap A and B.", ("check-ruled-out",))
value("16.3", "the unit address", "went back to the address", "The scan found no unit: swap A and B.", ("check-ruled-out",))
value("16.3", "bias resistors", "went to biasing", "Next on the flowchart is swapping A and B.", ())
value("16.3", "the adapter's echo", "went to echo", "Echo brings your own request back; silence here points at A and B.", ())
value("16.3", "the common wire", "went back to the common", "The common is connected: swap A and B.", ("check-ruled-out",))

_SE = '''def strip_echo(sent, received):
    if len(received) < len(sent) or received[:len(sent)] != sent:
        raise ValueError("no echo")
    return received[len(sent):]
'''
build("16.4", '''def strip_echo(sent, received):
    return received[len(sent):]
''', "did not check the echo", "A missing or damaged echo is an error.", ("echo-unchecked",))
build("16.4", '''def strip_echo(sent, received):
    if sent not in received:
        raise ValueError("no echo")
    return received.replace(sent, b"")
''', "removed every copy of the request", "Only the echo at the start is taken off; a write's answer repeats the request.", ())
build("16.4", '''def strip_echo(sent, received):
    i = received.find(sent)
    if i < 0:
        raise ValueError("no echo")
    return received[i + len(sent):]
''', "looked for the echo anywhere", "The echo must be the first bytes received.", ("echo-unchecked",))
build("16.4", _SE.replace("    return received[len(sent):]", '    if len(received) == len(sent):\n        raise ValueError("no answer")\n    return received[len(sent):]'), "refused an echo with nothing after it", "Only the echo is checked: the answer may be empty.", ())
build("16.4", _SE.replace("received[:len(sent)] != sent", "received[:2] != sent[:2]"), "compared only the first two bytes", "A damaged echo must be refused: compare every byte.", ("echo-unchecked",))
build("16.4", _SE.replace("return received[len(sent):]", "return received[len(sent) + 1:]"), "cut one byte too many", "The answer starts right after the echo.", ())
build("16.4", _SE.replace('raise ValueError("no echo")', "return None"), "returned None instead of raising", "A missing echo raises an error.", ("echo-unchecked",))

# --- 17: captures and security ------------------------------------------------------------------
value("17.1", 10, "gave the address", "The value is the last two bytes, 01 F4.", ("another-field",))
value("17.1", 0xF401, "read the value low byte first", "01 F4 is 500.", ("field-low-byte-first",))
value("17.1", 6, "gave the function code", "The value is 01 F4: 500.", ("another-field",))
value("17.1", 0xF4, "read only the last byte", "The value is two bytes: 500.", ("register-one-byte",))
value("17.1", 7, "gave the transaction id", "The value is the last two bytes.", ("another-field",))
value("17.1", 1, "read only the byte 01", "The value is 01 F4: 500.", ("register-one-byte",))

value("17.2", 0, "checked only the start address", "98, 99 and 100 are written: 100 is outside 0..99.", ("first-address-only",))
value("17.2", 2, "answered illegal data address", "A refused request gets exception 01.", ("exception-code-confused", "illegal-function-for-address"))
value("17.2", 3, "answered illegal data value", "A refused request gets exception 01.", ("exception-code-confused",))
value("17.2", 0x90, "gave the exception function code", "The exception code is asked: 01.", ("exception-function-for-code",))
value("17.2", "refused", "answered in words", "The exception code is asked: 1.", ())
value("17.2", True, "answered True for refused", "0 or the exception code is asked.", ())

_DEC = '''def decide(pdu, role):
    function = pdu[0]
    refused = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if role in ("viewer", "operator") and 1 <= function <= 4:
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        quantity = int.from_bytes(pdu[3:5], "big") if function in (15, 16) else 1
        if address + quantity - 1 <= 99:
            return None
    return refused
'''
build("17.3", _DEC.replace("if address + quantity - 1 <= 99:", "if address <= 99:"), "checked only the start address", "Every address written must be within 0..99.", ("first-address-only",))
build("17.3", _DEC.replace("if address + quantity - 1 <= 99:", "if address + quantity <= 99:"), "refused a write that ends at 99", "The last address written is address + quantity - 1.", ())
build("17.3", _DEC.replace("0x01", "0x02"), "answered exception 02", "A refused request gets exception 01.", ("exception-code-confused", "illegal-function-for-address"))
build("17.3", _DEC.replace('if role in ("viewer", "operator") and 1 <= function <= 4', "if 1 <= function <= 4"), "let any other role read", "Any role not listed may do nothing.", ())
build("17.3", _DEC.replace('if role == "operator" and function in', 'if role in ("viewer", "operator") and function in'), "let a viewer write within 0..99 like an operator", "A viewer may only read: functions 1-4.", ())
build("17.3", _DEC.replace("bytes([function | 0x80, 0x01])", "bytes([function, 0x01])"), "forgot the exception bit", "The refusal's function code is the request's plus 0x80.", ("exception-bit-missing",))

value("17.0", "ACBDCAABDCDB", "answered 5 for the length field", "The length counts the unit id and the PDU: 6.", ("mbap-length",))
value("17.0", "CCADCAABDCDB", "put the CRC high byte first", "0x4B37 goes on the wire as 37 4B.", ("crc-swapped",))
value("17.0", "CCBDCBABDCDB", "wrote the transaction id low byte first", "10 is 00 0A, high byte first.", ("mbap-little-endian",))
value("17.0", "CCBDCAABCCDB", "took 40001 for address 1", "40001 is address 0.", ("one-based-address",))
value("17.0", "CCBDCAABDCAB", "put register 10 at address 10", "Numbered from 1, register 10 is address 9.", ("one-based-address",))
value("17.0", "CCBDCAABDCDD", "thought the slave answers the first half", "A gap of 2 characters drops the frame: no answer.", ("t15-forgotten", "answer-to-damaged-request"))
value("17.0", "CADDBDCBCCBA", "gave notebook 00's right answers in notebook 00's order", "Notebook 17 asks the questions in another order.", ())
value("17.0", "CCBDCAABDCD", "answered 11 questions", "Twelve answers are asked.", ())
