# ruff: noqa: E501 (the slips' answers and function sources are kept whole, one per entry)
"""A second held-out set of realistic wrong answers ("slips") to the course's exercises.

Written like the first set (tests/heldout_slips.py), by someone else, from the notebooks alone: their
prose, their exercise cells and ``check(...)`` keys, and the library's public API used to compute the
right answers. The checkers, their diagnoses, the catalogue of misconceptions, the first catalogue of
slips and the first held-out set's entries were not read, and no slip was run through a checker while
this set was written. So it measures, a second time, how well the checkers name mistakes they were not
written for.

Each entry: ``key`` (the exercise), ``answer`` (the value, or for a build exercise the function's
source), ``kind`` ("value" or "build"), ``slip`` (what the learner did, in plain words), ``mistake``
(the misconception a teacher would name, one sentence) and ``candidates``: the catalogue's ids
(modbus_edu/exercises/diagnosis, their labels and teaching sentences) that name that mistake, or ``()``
where no entry does. The set was written without the catalogue; the candidates were added afterwards by
someone else, from each slip's ``slip`` and ``mistake`` words and the catalogue's words only, without
running a checker on the set or reading any of its verdicts, and none was changed after. An id is a candidate only where a teacher
would agree it names the learner's own mistake (several where entries overlap); a slip that only answers
another question, gives a partial answer or a wrong form usually has none.

Every answer was computed as a learner with that misconception would compute it, and
tests/test_heldout.py checks that each differs from the right answer computed with the library (for a
build slip: that some input the task allows tells it from the library's function). Before any checker
saw the set, four answers were taken out as arguably right, and one replaced: 00.1's text "11" (it may
mean 0x11), 06.3's 87.2 and 08.2's 47.9 (within the asked precision of 87.27 and 47.99), 06.4's class
name as a string, and 09.3's "2 s" (a right timeout written with its unit), replaced by 1.8. Nothing
was changed after the checkers' verdicts were seen.
"""


import modbus_edu as mb
from modbus_edu.devices import ArduinoSlave
from modbus_edu.widgets import TestTool

HELDOUT_2: list[dict] = []


def value(key: str, answer, slip: str, mistake: str, candidates: tuple[str, ...]) -> None:
    HELDOUT_2.append({"key": key, "answer": answer, "kind": "value", "slip": slip, "mistake": mistake,
                      "candidates": candidates})


def build(key: str, source: str, slip: str, mistake: str, candidates: tuple[str, ...]) -> None:
    HELDOUT_2.append({"key": key, "answer": source, "kind": "build", "slip": slip, "mistake": mistake,
                      "candidates": candidates})


# --- the learner's own arithmetic, with its slips --------------------------------------------------
def crc(data: bytes, start: int = 0xFFFF) -> int:
    """CRC-16/MODBUS as a learner writes it, with the register's start value a parameter."""
    register = start
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register


def crc_unreflected(data: bytes) -> int:
    """The CRC computed high bit first with the polynomial 0x8005, as many CRC calculators do."""
    register = 0xFFFF
    for byte in data:
        register ^= byte << 8
        for _ in range(8):
            register = ((register << 1) ^ 0x8005) & 0xFFFF if register & 0x8000 else (register << 1) & 0xFFFF
    return register


def low_first(value16: int) -> bytes:
    return bytes([value16 & 0xFF, value16 >> 8])


def high_first(value16: int) -> bytes:
    return bytes([value16 >> 8, value16 & 0xFF])


def rtu(body: bytes) -> bytes:
    """Address and PDU with the right CRC, low byte first."""
    return body + low_first(crc(body))


def lrc_of(data: bytes) -> int:
    return (-sum(data)) & 0xFF


def ascii_frame(body: bytes, check: int | None = None) -> str:
    check = lrc_of(body) if check is None else check
    return ":" + body.hex().upper() + f"{check:02X}" + "\r\n"


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def char_time(baud: int, bits: int) -> float:
    return bits / baud


def board(*declarations: tuple[int, int]) -> ArduinoSlave:
    """A board with registers declared by reference number: (first reference, count)."""
    made = ArduinoSlave(unit=1, sketch=False)
    for first, count in declarations:
        for reference in range(first, first + count):
            made.add(str(reference))
    return made


def tool_config(**changes) -> dict:
    settings = {"unit": 7, "address": 10, "length": 4, "function": 4, "interval": 0.5}
    settings.update(changes)
    role = settings.pop("role", "rtu_master")
    return TestTool(role, **settings).config()


# === 00 welcome ===================================================================================
value("00.0", "CADDBDCBCCB", "typed eleven letters for the twelve questions", "one answer per question: a question was skipped instead of answered with ?", ())
value("00.0", "CADDBDCBCCBAB", "typed thirteen letters", "one answer per question: an extra letter was typed", ())
value("00.0", "CADDBDCBCCBE", "used the letter e for 'I do not know'", "only a to d or ? are answers", ())
value("00.0", "AB?C...", "left the example from the comment in place", "the placeholder is not an answer", ())
value("00.0", "342242323321", "numbered the choices 1 to 4 instead of using letters", "answers are letters a to d", ())

value("00.1", 11, "read the first byte 0x11 as the decimal number 11", "hex read as decimal", ("hex-read-as-decimal",))
value("00.1", 3, "gave the function code, the second byte", "wrong field: the function code is not the address", ("another-field",))
value("00.1", 0x6B, "gave the register address in the PDU, 107", "slave address confused with register address", ("another-field",))
value("00.1", 0x1103, "read the first two bytes as one number", "the address is one byte", ())

value("00.2", "11 03 00 6B 00 03", "kept the unit identifier with the PDU", "the unit id belongs to the MBAP header, not the PDU", ("unit-in-pdu",))
value("00.2", "00 00 00 06 11 03 00 6B 00 03", "dropped only the transaction id", "the whole 7-byte MBAP header must come off", ("frame-for-pdu",))
value("00.2", "00 07 00 00 00 06 11 03 00 6B 00 03", "gave the whole frame", "the frame is not the PDU", ("frame-for-pdu",))
value("00.2", "03 00 6B 00", "left out the last byte", "the PDU is function + data, all of it", ())
value("00.2", "03 00 6B 00 03 76 87", "added the RTU CRC of the other example", "a PDU has no checksum; TCP carries none at all", ("crc-on-tcp", "frame-for-pdu"))
value("00.2", b"03006B0003", "gave the hex characters as bytes", "hex text and the bytes it names are not the same bytes", ())

value("00.3", h("02 03 00 00 00 02") + high_first(crc(h("02 03 00 00 00 02"))), "put the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("00.3", h("00 01 00 00 00 06 02 03 00 00 00 02"), "built a Modbus/TCP frame", "RTU frame confused with TCP frame", ("tcp-frame-for-rtu",))
value("00.3", h("02 03 00 00 00 02"), "left out the CRC", "an RTU frame ends with its CRC", ("crc-forgotten",))
value("00.3", rtu(h("02 04 00 00 00 02")), "used function 4", "holding registers are read with function 3", ("holding-for-input",))
value("00.3", rtu(h("02 03 00 01 00 02")), "started at address 1", "addresses count from 0 on the wire", ("one-based-address",))
value("00.3", rtu(h("02 03 00 00 00 04")), "asked for 4 (the bytes of two registers)", "the quantity counts registers, not bytes", ("bytes-for-registers", "byte-count-for-quantity"))
value("00.3", h("02 03 00 00 00 02") + low_first(crc(h("02 03 00 00 00 02"), 0)), "started the CRC register at 0", "the CRC register starts at 0xFFFF", ("crc-initial-zero",))

# === 01 data model ================================================================================
value("01.1", 40250, "gave the reference number itself", "reference number confused with address", ("reference-number",))
value("01.1", 250, "dropped the leading 4 but not the 1-based count", "references count from 1, addresses from 0", ("one-based-address",))
value("01.1", 40249, "subtracted 1 but kept the table digit", "the table prefix is not part of the address", ("reference-number",))
value("01.1", 248, "subtracted 40001 and then 1 again", "off by one twice", ("address-one-too-low",))
value("01.1", (3, 249), "answered with the function code as well", "answered another question: only the address was asked", ())

value("01.2", "30009", "wrote the address after the table digit", "references count from 1, addresses from 0", ("zero-based-number",))
value("01.2", "300010", "wrote the 6-digit form", "the 5-digit form was asked", ())
value("01.2", "40010", "used the holding register prefix", "wrong table prefix: input registers are 3x", ("holding-for-input",))
value("01.2", "10010", "used the discrete input prefix", "wrong table prefix: input registers are 3x", ("bit-table-for-register-table",))
value("01.2", 30010, "gave an int, not a string", "a reference is text with its leading digit", ())
value("01.2", "30011", "added 1 twice", "off by one", ())

value("01.3", ("holding registers", True), "thought function 4 reads holding registers", "function 3 and function 4 swapped", ("holding-for-input",))
value("01.3", ("input registers", True), "thought every register table is writable", "input registers are read-only", ())
value("01.3", ("holding registers", False), "picked the wrong table and said it is read-only", "function 3 and function 4 swapped", ("holding-for-input",))
value("01.3", ("discrete inputs", False), "thought function 4 reads discrete inputs", "function 2 and function 4 confused", ("bit-table-for-register-table",))
value("01.3", "input registers", "gave only the table", "partial answer: the writability is missing", ())

value("01.4", 58, "subtracted the ends of each range without adding 1", "a range's count is last - first + 1", ("range-one-end",))
value("01.4", 59, "added 1 to one range only", "a range's count is last - first + 1", ("range-one-end",))
value("01.4", 210, "counted from 100 to 309 without the gap", "a sparse map has gaps", ("dense-for-sparse",))
value("01.4", 50, "counted the first range only", "partial answer", ("one-range-only",))
value("01.4", 2, "counted the ranges", "answered another question", ())
value("01.4", 62, "counted 51 and 11 (the ends twice)", "off by one", ("range-one-extra",))

build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    return tables[text[0]], int(text[1:])
''', "forgot to subtract 1 (and never raises for 0000)", "references count from 1, addresses from 0", ("one-based-address", "invalid-input-accepted"))
build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "holding_registers", "4": "input_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no element 0")
    return tables[text[0]], number - 1
''', "swapped the 3 and 4 prefixes", "input registers and holding registers swapped", ("holding-for-input",))
build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    return tables[text[0]], int(text[1:]) - 1
''', "did not raise for 0000 (returns address -1)", "reference 0000 does not exist", ("invalid-input-accepted",))
build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"1": "coils", "2": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no element 0")
    return tables[text[0]], number - 1
''', "numbered the tables 1 to 4, so 0xxxx coils fail and 1xxxx are read as coils", "coils are 0x, discrete inputs 1x", ("table-2x",))
build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("no element 0")
    return tables[text[0]], str(number - 1)
''', "returned the address as a string", "an address is a number", ())
build("01.5", '''def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:4])
    if number == 0:
        raise ValueError("no element 0")
    return tables[text[0]], number - 1
''', "sliced three digits instead of four", "off by one in the slice: the number has four digits", ())

# === 02 function codes ============================================================================
value("02.1", "10 00 05 00 02 04 01 F4 03 E8", "started at address 5", "off by one: the first address is 4", ())
value("02.1", "10 00 04 00 02 02 01 F4 03 E8", "wrote the byte count as the number of registers", "the byte count counts bytes: 2 per register", ("byte-count-for-quantity",))
value("02.1", "10 00 04 00 02 04 F4 01 E8 03", "wrote the values low byte first", "registers go high byte first", ("field-low-byte-first",))
value("02.1", "16 00 04 00 02 04 01 F4 03 E8", "wrote function 16 as the byte 0x16", "decimal read as hex: function 16 is 0x10", ("decimal-written-as-hex",))
value("02.1", "10 00 04 00 02 01 F4 03 E8", "left out the byte count", "FC16 carries a byte count before the values", ("byte-count-missing",))
value("02.1", "10 00 04 00 04 04 01 F4 03 E8", "gave the quantity in bytes", "the quantity counts registers", ("bytes-for-registers", "byte-count-for-quantity"))
value("02.1", "01 10 00 04 00 02 04 01 F4 03 E8", "put a slave address in front", "the PDU has no address", ("unit-in-pdu", "frame-for-pdu"))

value("02.2", 2, "thought 150 registers fit in one request", "the limit per read is 125 registers", ())
value("02.2", 2.4, "divided 300 by 125 and did not round up", "a number of requests is a whole number, rounded up", ("count-rounded-down",))
value("02.2", 300, "one request per register", "one request reads up to 125 registers", ("request-per-register",))
value("02.2", 1, "thought one request reads any number", "the limit per read is 125 registers", ())
value("02.2", 4, "took 100 registers per request", "the limit per read is 125 registers", ("another-devices-limit",))

value("02.3", "83 02", "used function 3's exception code", "the exception function is the request's function + 0x80", ())
value("02.3", "04 02", "did not set the top bit", "the exception function is the request's function + 0x80", ("exception-bit-missing",))
value("02.3", "84 01", "answered illegal function", "the function exists; the address does not: code 02", ("illegal-function-for-address",))
value("02.3", "84", "left out the exception code", "partial answer: the code follows the function", ())
value("02.3", "01 84 02", "put a slave address in front", "the PDU has no address", ("unit-in-pdu", "frame-for-pdu"))
value("02.3", "84 03", "answered illegal data value", "a missing address is code 02", ("exception-code-confused",))

value("02.4", [1, 3], "counted the coils from 1", "addresses count from 0", ("one-based-address",))
value("02.4", [5], "read the data byte as a coil number", "a byte of coils is 8 bits", ("byte-value-as-coils",))
value("02.4", [5, 7], "read the bits most significant first", "the first coil is the lowest bit", ("bits-from-the-left",))
value("02.4", [0], "read the byte count 01 as the data", "wrong field: the byte count comes before the data", ("another-field",))
value("02.4", [2], "only saw the higher bit", "partial answer", ())

build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count < 1 or count > 126:
        raise ValueError("count")
    if address + count > 65536:
        raise ValueError("address")
    return struct.pack(">BHH", 3, address, count)
''', "allowed 126 registers", "the read limit is 125 registers", ("invalid-input-accepted",))
build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count < 1:
        raise ValueError("count")
    return struct.pack(">BHH", 3, address, count)
''', "checked only the lower end of the count", "the read limit is 125 registers, and the address space ends", ("invalid-input-accepted",))
build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count < 1 or count > 125:
        raise ValueError("count")
    if address + count > 65535:
        raise ValueError("address")
    return struct.pack(">BHH", 3, address, count)
''', "refused a read that ends at the last register 65535", "off by one: address + count may be 65536", ())
build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count < 1 or count > 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack("<BHH", 3, address, count)
''', "packed little-endian", "multi-byte fields are big-endian", ("field-low-byte-first",))
build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count < 1 or count > 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHH", 4, address, count)
''', "used function 4", "holding registers are read with function 3", ("holding-for-input",))
build("02.5", '''import struct
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if count > 125 or address + count > 65536:
        raise ValueError("bad request")
    return struct.pack(">BHH", 3, address, count)
''', "accepted a count of 0", "a read asks for at least one register", ("invalid-input-accepted",))

# === 03 RTU and CRC ===============================================================================
_Q31 = h("11 04 00 08 00 01")
value("03.1", high_first(crc(_Q31)), "gave the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("03.1", low_first(crc(_Q31, 0)), "started the CRC register at 0", "the CRC register starts at 0xFFFF", ("crc-initial-zero",))
value("03.1", low_first(crc_unreflected(_Q31)), "used a calculator's CRC-16 with the polynomial 0x8005, high bit first", "the Modbus CRC is reflected: 0xA001, shifted right", ("crc-msb-first",))
value("03.1", low_first(crc(_Q31[1:])), "computed the CRC over the PDU only", "the RTU CRC covers the address too", ("checksum-without-address",))
value("03.1", _Q31 + low_first(crc(_Q31)), "gave the whole frame", "answered another question: only the two CRC bytes were asked", ())
value("03.1", crc(_Q31), "gave the register value as one int", "the wire order is two bytes, low first", ())
value("03.1", low_first(crc(bytes([11, 4, 0, 8, 0, 1]))), "read 11 as decimal eleven", "hex read as decimal", ("hex-read-as-decimal",))

_Q32 = h("01 06 00 02 12 34")
value("03.2", _Q32 + high_first(crc(_Q32)), "put the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("03.2", rtu(h("01 06 00 01 12 34")), "wrote address 1 for 'address 2'", "the address is already the wire address", ("address-one-too-low", "slave-subtracts-one"))
value("03.2", rtu(h("01 06 00 02 34 12")), "wrote the value low byte first", "registers go high byte first", ("field-low-byte-first",))
value("03.2", rtu(h("01 10 00 02 00 01 02 12 34")), "used function 16", "function 6 was asked", ())
value("03.2", _Q32, "left out the CRC", "an RTU frame ends with its CRC", ("crc-forgotten",))
value("03.2", _Q32 + low_first(crc(_Q32, 0)), "started the CRC register at 0", "the CRC register starts at 0xFFFF", ("crc-initial-zero",))
value("03.2", rtu(h("01 06 00 02 04 D2")), "wrote 1234 in decimal instead of 0x1234", "hex read as decimal", ("hex-read-as-decimal",))

value("03.3", True, "thought the slave answers any frame addressed to it", "a frame with a bad CRC is dropped in silence", ("answer-to-damaged-request",))
value("03.3", 1, "answered 1 for yes", "a frame with a bad CRC is dropped in silence", ("answer-to-damaged-request",))
value("03.3", "yes", "answered yes", "a frame with a bad CRC is dropped in silence", ("answer-to-damaged-request",))
value("03.3", "True", "typed the word True in quotes", "a frame with a bad CRC is dropped in silence", ("answer-to-damaged-request",))
value("03.3", "the CRC is wrong", "gave the reason instead of the answer", "answered another question", ())

value("03.4", 40, "counted the data bytes only", "the response has address, function, byte count and CRC too", ("data-bytes-only",))
value("03.4", 43, "forgot the CRC", "an RTU response ends with its CRC", ("crc-forgotten",))
value("03.4", 8, "gave the request's length", "answered another question: the response's length", ())
value("03.4", 25, "counted one byte per register", "a register is two bytes", ("register-one-byte",))
value("03.4", 44, "forgot the byte count", "an FC3 response is 5 + 2N bytes", ("byte-count-missing",))
value("03.4", 85, "counted four bytes per register", "a register is two bytes", ())

build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "started the register at 0", "the CRC register starts at 0xFFFF", ("crc-initial-zero",))
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            if crc & 0x8000:
                crc = ((crc << 1) ^ 0x8005) & 0xFFFF
            else:
                crc = (crc << 1) & 0xFFFF
    return crc
''', "shifted left with the polynomial 0x8005", "the Modbus CRC is reflected: 0xA001, shifted right", ("crc-msb-first",))
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(7):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "shifted seven times per byte", "eight shifts per byte", ())
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return ((crc & 0xFF) << 8) | (crc >> 8)
''', "swapped the bytes of the result for the wire", "the register value is asked; the swap is for the wire only", ("crc-swapped",))
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc >>= 1
            if crc & 1:
                crc ^= 0xA001
    return crc
''', "shifted before looking at the bit that falls out", "XOR 0xA001 when the bit shifted out is 1", ())
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc ^ 0xFFFF
''', "inverted the result at the end", "the Modbus CRC has no final XOR", ())
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for i in range(len(data) - 1):
        crc ^= data[i]
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "stopped the loop one byte early", "off by one: every byte goes into the CRC", ())
build("03.5", '''def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data[:255]:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
''', "only read the first 255 bytes, as many as a frame can hold", "the CRC of any data was asked, not only of a frame", ())

# === 04 ASCII and LRC =============================================================================
value("04.1", 0x82, "gave the sum without negating it", "the LRC is the two's complement of the sum", ("lrc-plain-sum",))
value("04.1", 0x7D, "inverted the sum without adding 1", "the two's complement adds 1 after inverting", ("lrc-ones-complement",))
value("04.1", -0x82, "negated the sum without keeping 8 bits", "the LRC is one byte: keep the low 8 bits", ("lrc-not-8-bits",))
value("04.1", lrc_of(b"1103006B0003"), "summed the hex characters", "the LRC sums the bytes, not the characters", ("lrc-of-characters",))
value("04.1", 0xE7, "swapped the two hex digits", "a byte's digits, high first", ())
value("04.1", lrc_of(bytes([11, 3, 0, 6, 0, 3])), "read the bytes as decimal and 6B as 6", "hex read as decimal", ("hex-read-as-decimal",))

value("04.2", ascii_frame(h("05 03 10 01 00 02")), "took 44097 as address 4097", "references count from 1, addresses from 0", ("one-based-address",))
value("04.2", ascii_frame(h("05 03 10 00 00 02"))[:-2], "left out CR LF", "an ASCII frame ends with CR LF", ("ascii-without-crlf",))
value("04.2", ascii_frame(h("05 03 10 00 00 02"), lrc_of(b"050310000002")), "computed the LRC over the characters", "the LRC sums the bytes, not the characters", ("lrc-of-characters",))
value("04.2", ":050310000002" + low_first(crc(h("05 03 10 00 00 02"))).hex().upper() + "\r\n", "used the RTU CRC instead of an LRC", "an ASCII frame ends with an LRC", ("crc-in-ascii",))
value("04.2", ascii_frame(h("05 04 10 00 00 02")), "used function 4", "4xxxx registers are read with function 3", ("holding-for-input",))
value("04.2", ascii_frame(h("05 03 10 00 00 04")), "asked for 4 (the bytes of two registers)", "the quantity counts registers, not bytes", ("bytes-for-registers", "byte-count-for-quantity"))
value("04.2", ascii_frame(h("05 03 10 00 00 02"))[1:], "left out the colon", "an ASCII frame starts with ':'", ("ascii-colon-forgotten",))
value("04.2", ascii_frame(h("05 03 10 00 00 02"))[:-2] + "\n\r", "wrote LF before CR", "an ASCII frame ends with CR then LF", ())

value("04.3", 20, "counted only the hex characters", "the colon and CR LF are characters too", ("ascii-colon-forgotten", "ascii-without-crlf"))
value("04.3", 21, "counted the colon but not CR LF", "CR LF end the frame", ("ascii-without-crlf",))
value("04.3", 22, "counted CR LF as one character", "CR and LF are two characters", ())
value("04.3", 25, "counted an RTU CRC of two bytes", "an ASCII frame ends with a one-byte LRC", ("crc-in-ascii",))
value("04.3", 10, "counted bytes, not characters", "each byte is two hex characters", ("rtu-length-for-ascii",))

value("04.4", "05 03 04 FF 06 00 64", "kept the slave address", "the PDU starts at the function code", ("frame-for-pdu", "unit-in-pdu"))
value("04.4", "03 04 FF 06 00 64 8B", "kept the LRC", "the PDU carries no checksum", ("frame-for-pdu",))
value("04.4", b"0304FF060064", "gave the characters as bytes", "the characters are hex for the bytes", ())
value("04.4", "03 FF 06 00 64", "left out the byte count", "the byte count is part of the PDU", ("byte-count-missing",))
value("04.4", "FF 06 00 64", "gave only the register data", "the PDU starts at the function code", ("function-code-missing", "byte-count-missing"))
value("04.4", "03 04 06 FF 64 00", "swapped the bytes of each register", "registers go high byte first", ("field-low-byte-first",))

build("04.5", '''def lrc(data: bytes) -> int:
    return sum(data) & 0xFF
''', "returned the sum", "the LRC is the two's complement of the sum", ("lrc-plain-sum",))
build("04.5", '''def lrc(data: bytes) -> int:
    return -sum(data)
''', "negated the sum and did not keep 8 bits", "the LRC is one byte: keep the low 8 bits", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data: bytes) -> int:
    return ~sum(data) & 0xFF
''', "inverted the sum without adding 1", "the two's complement adds 1 after inverting", ("lrc-ones-complement",))
build("04.5", '''def lrc(data: bytes) -> int:
    return 0x100 - (sum(data) & 0xFF)
''', "subtracted from 0x100 without masking the result", "the LRC of a sum that is a multiple of 256 is 0, not 256", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data: bytes) -> int:
    return (0x100 - sum(data)) if sum(data) < 0x100 else 0
''', "only handled sums below 256", "the sum is taken modulo 256", ("lrc-not-8-bits",))
build("04.5", '''def lrc(data: bytes) -> int:
    return (-sum(data.hex().upper().encode())) & 0xFF
''', "summed the hex characters", "the LRC sums the bytes, not the characters", ("lrc-of-characters",))

# === 05 TCP and MBAP ==============================================================================
value("05.1", 0x2A00, "read the two bytes low first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("05.1", 6, "gave the length field", "wrong field: the transaction id is the first two bytes", ("another-field",))
value("05.1", 17, "gave the unit identifier", "wrong field: the transaction id is the first two bytes", ("another-field",))
value("05.1", 0, "gave the protocol identifier", "wrong field: the transaction id is the first two bytes", ("another-field",))
value("05.1", 2, "read 2A as the digit 2", "hex read as decimal", ("hex-read-as-decimal",))

value("05.2", h("07 00 00 00 00 06 01 06 00 00 04 D2"), "wrote the transaction id low byte first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("05.2", h("00 07 00 00 00 05 01 06 00 00 04 D2"), "counted the PDU only in the length", "the length counts the unit id and the PDU", ("mbap-length",))
value("05.2", h("00 07 00 00 00 0C 01 06 00 00 04 D2"), "counted the whole frame in the length", "the length counts the bytes after it", ("mbap-length",))
value("05.2", h("00 07 00 00 00 06 01 06 00 00 D2 04"), "wrote the value low byte first", "registers go high byte first", ("field-low-byte-first",))
value("05.2", h("00 07 00 00 00 06 01 06 00 00 04 D2") + low_first(crc(h("01 06 00 00 04 D2"))), "added an RTU CRC", "Modbus/TCP carries no CRC", ("crc-on-tcp",))
value("05.2", h("00 07 00 00 00 05 06 00 00 04 D2"), "left out the unit identifier", "the MBAP header ends with the unit id", ("unit-missing",))
value("05.2", h("00 07 00 00 00 06 01 06 00 00 12 34"), "wrote 1234 as the bytes 12 34", "decimal written as hex", ("decimal-written-as-hex",))

value("05.3", 22, "counted the PDU only", "the length counts the unit id and the PDU", ("mbap-length",))
value("05.3", 29, "counted the whole frame", "the length counts the bytes after it", ("mbap-length",))
value("05.3", 20, "counted the register data only", "the length counts the unit id and the PDU", ("mbap-length", "data-bytes-only"))
value("05.3", 13, "counted one byte per register", "a register is two bytes", ("register-one-byte",))
value("05.3", 6, "gave the request's length", "answered another question: the response's length", ())
value("05.3", 23 + 2, "added a CRC", "Modbus/TCP carries no CRC", ("crc-on-tcp",))

value("05.4", "protocol identifier", "copied the example field", "the protocol identifier 00 00 is right; the length 06 00 is not", ())
value("05.4", "transaction identifier", "blamed the transaction id", "the server echoes any transaction id", ())
value("05.4", "unit identifier", "blamed the unit id", "the unit id 01 is fine", ())
value("05.4", "function code", "named a PDU field", "the function code is not in the MBAP header", ())
value("05.4", "byte order", "named a property, not a field", "answered another question: which field", ())

build("05.5", '''import struct
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu), unit)
''', "counted the PDU only in the length", "the length counts the unit id and the PDU", ("mbap-length",))
build("05.5", '''import struct
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu) + 7, unit)
''', "counted the whole header in the length", "the length counts the bytes after it", ("mbap-length",))
build("05.5", '''import struct
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack("<HHHB", tid, 0, len(pdu) + 1, unit)
''', "packed little-endian", "MBAP fields are big-endian", ("mbap-little-endian",))
build("05.5", '''def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return bytes([0, tid & 0xFF, 0, 0, 0, len(pdu) + 1, unit])
''', "wrote only the low byte of the transaction id", "the transaction id is two bytes", ("field-in-one-byte",))
build("05.5", '''import struct
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHH", tid, 0, len(pdu) + 1)
''', "left out the unit identifier", "the MBAP header ends with the unit id", ("unit-missing",))
build("05.5", '''import struct
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", tid, 1, len(pdu) + 1, unit)
''', "set the protocol identifier to 1", "Modbus is protocol 0", ())

# === 06 master and slave ==========================================================================
_C96 = 10 / 9600 * 1000  # ms per 8N1 character at 9600
value("06.1", round(40 * 10 / 19200 * 1000, 2), "used 19200 baud", "the baud rate given was 9600", ("another-baud-rate",))
value("06.1", 22.92, "gave the one-register time of the notebook", "answered another question: 10 registers", ("one-register-response",))
value("06.1", round(33 * _C96, 2), "left out the two silences", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
value("06.1", round(40 * 11 / 9600 * 1000, 2), "counted 11 bits per character", "8N1 is 10 bits per character", ())
value("06.1", round(36.5 * _C96, 2), "counted one silence only", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
value("06.1", round(40 * _C96 / 1000, 5), "gave seconds", "the unit asked is milliseconds", ("seconds-for-milliseconds",))
value("06.1", round(30 * _C96, 2), "took the response as 5 + N bytes", "a register is two bytes", ("register-one-byte",))

value("06.2", 1, "answered illegal function", "the slave knows function 5; the coil is missing: code 02", ("illegal-function-for-address",))
value("06.2", 3, "answered illegal data value", "a missing address is code 02", ("exception-code-confused",))
value("06.2", 4, "answered slave device failure", "a missing address is code 02", ("exception-code-confused",))
value("06.2", 0x85, "gave the exception function code", "answered another question: the code, not the function", ("exception-function-for-code",))
value("06.2", "timeout", "thought the slave stays silent", "a slave that cannot do a request answers with an exception", ("refusal-unanswered",))

value("06.3", 43.6, "gave the 9600-baud figure", "the baud rate given was 19200", ("another-baud-rate",))
value("06.3", round(1 / (22 * 11 / 19200), 1), "counted 11 bits per character", "8N1 is 10 bits per character", ())
value("06.3", round(1 / (15 * 10 / 19200), 1), "left out the silences", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
value("06.3", round(22 * 10 / 19200, 4), "gave the time of one transaction in seconds", "answered another question: transactions per second", ("time-for-rate",))
value("06.3", round(1 / (15 * 10 / 19200 + 2 * 0.00175), 1), "used the fixed 1.75 ms silences at 19200", "the fixed values apply above 19200 baud", ("fixed-silence-at-19200",))

value("06.4", mb.CrcError, "thought the master sees a CRC error", "a damaged request is dropped by the slave: the master times out", ("answer-to-damaged-request",))
value("06.4", mb.ModbusExceptionError, "thought the slave answers with an exception", "a damaged request gets silence, not an exception", ("answer-to-damaged-request",))
value("06.4", mb.ModbusTimeoutError("no answer"), "gave an instance of the right class", "the class was asked, not an instance", ())
value("06.4", TimeoutError, "gave Python's built-in TimeoutError", "the library's own error class was asked", ("builtin-for-library-exception",))
value("06.4", mb.ChecksumError, "gave the general checksum error", "a damaged request is dropped by the slave: the master times out", ("answer-to-damaged-request",))
value("06.4", mb.FrameLengthError, "thought the frame comes back short", "a damaged request gets silence", ("answer-to-damaged-request",))

build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers) + 1:
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "range check off by one (allows one register past the end)", "the last address is len - 1", ("invalid-input-accepted", "refusal-unanswered"))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "little") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "sent the registers low byte first", "registers go high byte first", ("field-low-byte-first",))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, count]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "wrote the register count as the byte count", "the byte count counts bytes: 2 per register", ("byte-count-for-quantity",))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([3, 3])
        if address + count > len(registers):
            return bytes([3, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([6, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "answered exceptions without the top bit", "the exception function is the request's function + 0x80", ("exception-bit-missing",))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if address + count > len(registers):
            return bytes([0x83, 2])
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "checked the address before the count", "a count outside 1..125 is code 03 whatever the address", ("exception-code-confused",))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    return pdu
''', "echoed the write without storing the value", "a write changes the register before it is echoed", ("write-not-stored",))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address > len(registers):
        return bytes([0x86, 2])
    if address < len(registers):
        registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu
''', "let a write at address len(registers) through", "the last address is len - 1", ("invalid-input-accepted", "refusal-unanswered"))
build("06.5", '''def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if count < 1 or count > 125:
            return bytes([0x83, 3])
        if address + count > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = int.from_bytes(pdu[3:5], "big")
    return pdu[:3]
''', "echoed the function and address only", "a write single register echoes the whole request", ())

# === 07 exceptions and errors =====================================================================
value("07.1", (0x83, 2), "gave the response's function code", "the request's function is the code without the top bit", ("exception-code-as-function",))
value("07.1", (83, 2), "read 83 as decimal", "hex read as decimal, and the top bit kept", ("hex-read-as-decimal", "exception-code-as-function"))
value("07.1", (3, 0xC1), "took the first CRC byte as the code", "wrong field: the code follows the function", ("another-field",))
value("07.1", (17, 3), "shifted every field by one", "wrong field: the first byte is the address", ("another-field",))
value("07.1", (2, 3), "swapped the pair", "the pair is (function, code)", ("function-and-code-swapped",))
value("07.1", (3, 2, 17), "added the slave address", "partial answer plus an extra field", ())

value("07.2", rtu(h("11 83 02")), "used function 3's exception", "the exception function is the request's function + 0x80", ())
value("07.2", rtu(h("11 81 01")), "answered illegal function", "a missing address is code 02", ("illegal-function-for-address",))
value("07.2", h("11 81 02"), "left out the CRC", "an RTU frame ends with its CRC", ("crc-forgotten",))
value("07.2", h("11 81 02") + high_first(crc(h("11 81 02"))), "put the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("07.2", rtu(h("11 01 02")), "did not set the top bit", "the exception function is the request's function + 0x80", ("exception-bit-missing",))
value("07.2", rtu(h("17 81 02")), "wrote slave 17 as the byte 0x17", "decimal written as hex", ("decimal-written-as-hex",))
value("07.2", h("81 02"), "gave the PDU only", "the frame was asked: address, PDU, CRC", ("unit-missing", "crc-forgotten"))

_RIGHT_073 = {"request for a unit nobody has": "timeout", "one bit flipped in the request": "timeout",
              "one bit flipped in the response": "checksum error", "read of an address the slave does not have": "exception",
              "response carries another unit id": "mismatch"}
value("07.3", {**_RIGHT_073, "one bit flipped in the request": "checksum error"}, "thought the master sees the damaged request's CRC", "a damaged request gets silence: the slave drops it", ("answer-to-damaged-request",))
value("07.3", {**_RIGHT_073, "response carries another unit id": "timeout"}, "thought another unit's answer counts as silence", "a response from another unit is a mismatch", ())
value("07.3", {**_RIGHT_073, "request for a unit nobody has": "exception"}, "thought someone answers for a missing unit", "nobody answers a unit nobody has", ("answer-to-another-unit",))
value("07.3", {**_RIGHT_073, "read of an address the slave does not have": "timeout"}, "thought a slave stays silent for a missing address", "a missing address earns exception 02", ("refusal-unanswered",))
value("07.3", {k: v for k, v in _RIGHT_073.items() if k != "response carries another unit id"}, "left one situation out", "partial answer", ())
value("07.3", {**_RIGHT_073, "one bit flipped in the response": "timeout"}, "thought a damaged response is ignored like silence", "a damaged response is a checksum error", ("damaged-response-as-silence",))
value("07.3", {**_RIGHT_073, "one bit flipped in the request": "checksum error", "one bit flipped in the response": "timeout"}, "swapped the request and response cases", "who checks the CRC: the slave for requests, the master for responses", ("answer-to-damaged-request", "damaged-response-as-silence"))

build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return bytes([function, code])
''', "did not set the top bit", "the exception function is the request's function + 0x80", ("exception-bit-missing",))
build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return bytes([function + 80, code])
''', "added decimal 80", "0x80 is 128", ("hex-read-as-decimal",))
build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return bytes([code, function | 0x80])
''', "put the code first", "the function comes first, then the code", ("function-and-code-swapped",))
build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return bytes([function | 0x80])
''', "left out the code", "partial answer: the code follows the function", ())
build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return f"{function | 0x80:02X} {code:02X}"
''', "returned hex text", "bytes were asked", ())
build("07.4", '''def exception_response(function: int, code: int) -> bytes:
    return bytes([0x80, function, code])
''', "put 0x80 as its own byte before the function", "the top bit is set in the function byte itself", ())

# === 08 serial timing =============================================================================
value("08.1", round(3.5 * 10 / 4800, 6), "counted 10 bits per character", "a character with parity is 11 bits", ("parity-bit-forgotten",))
value("08.1", 0.00175, "used the fixed 1.75 ms", "the fixed values apply above 19200 baud", ("fixed-silence-at-19200",))
value("08.1", round(3.5 * 11 / 4800 * 1000, 3), "gave milliseconds", "the unit asked is seconds", ("milliseconds-for-seconds",))
value("08.1", round(11 / 4800, 6), "gave one character time", "the silence is 3.5 characters", ("one-character-for-t35",))
value("08.1", round(1.5 * 11 / 4800, 6), "gave the 1.5-character gap", "the end of a frame is 3.5 characters, 1.5 is the gap inside", ("t15-for-t35",))
value("08.1", round(3.5 * 12 / 4800, 6), "counted 12 bits (parity and two stop bits)", "8E1 has one stop bit: 11 bits", ())

_C192 = 10 / 19200
value("08.2", round(1 / (40 * 10 / 9600), 1), "used 9600 baud", "the baud rate given was 19200", ("another-baud-rate",))
value("08.2", 87.3, "gave the one-register figure", "answered another question: 10 registers", ("one-register-response",))
value("08.2", round(1 / (33 * _C192 + 2 * 0.00175), 1), "used the fixed 1.75 ms silences at 19200", "the fixed values apply above 19200 baud", ("fixed-silence-at-19200",))
value("08.2", round(1 / (33 * _C192), 1), "left out the silences", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
value("08.2", round(1 / (30 * _C192), 1), "took the response as 5 + N bytes", "a register is two bytes", ("register-one-byte",))

value("08.3", [5.0], "thought only a full 3.5-character silence breaks a frame", "a gap of more than 1.5 characters inside a frame breaks it", ("t15-forgotten",))
value("08.3", [3.0, 5.0], "took the limit as 2 characters or more, exclusive", "a gap of more than 1.5 characters breaks the frame", ("pause-threshold",))
value("08.3", [1.4, 2.0, 3.0, 5.0], "thought any gap over one character breaks it", "the limit is 1.5 characters", ("pause-threshold",))
value("08.3", [2.0, 3.0], "thought a 5-character pause makes two frames and both are answered", "the pieces of a split request are not a request", ())
value("08.3", [1.0, 1.4], "inverted the question", "answered another question: the pauses that are harmless", ())
value("08.3", [], "thought the slave waits for the rest", "a gap of more than 1.5 characters inside a frame breaks it", ("t15-forgotten",))

build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    char = 10 / baudrate
    return (request_bytes + 3.5 + response_bytes + 3.5) * char
''', "counted 10 bits whatever the parity and stop bits", "a character is start + 8 + parity + stop bits", ("parity-bit-forgotten",))
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    return (request_bytes + response_bytes) * char + 2 * 0.00175
''', "used the fixed 1.75 ms silence at every baud rate", "the fixed values apply above 19200 baud only", ("fixed-silence-at-19200",))
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    return (request_bytes + 3.5 + response_bytes + 3.5) * char
''', "forgot the fixed silence above 19200 baud", "above 19200 baud t3.5 is a fixed 1.75 ms", ("fixed-silence-ignored",))
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    silence = 0.00175 if baudrate >= 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * silence
''', "applied the fixed value at 19200 baud already", "the fixed values apply above 19200 baud, not at it", ("fixed-silence-at-19200",))
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    silence = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + silence
''', "counted one silence per transaction", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (2 if parity != "N" else 0) + stopbits
    char = bits / baudrate
    silence = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * silence
''', "counted two parity bits", "parity is one bit", ())
build("08.4", '''def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    silence = 0.00175 if baudrate > 19200 else 3.5 * char
    return ((request_bytes + response_bytes) * char + 2 * silence) * 1000
''', "returned milliseconds", "the unit asked is seconds", ("milliseconds-for-seconds",))

# === 09 Arduino slave =============================================================================
value("09.1", (3, 9), "used function 3", "input registers are read with function 4", ("holding-for-input",))
value("09.1", (4, 10), "kept the 1-based number", "references count from 1, addresses from 0", ("one-based-address",))
value("09.1", (4, 30009), "kept the table digit in the address", "the table prefix is not part of the address", ("reference-number",))
value("09.1", (9, 4), "swapped the pair", "the pair is (function, address)", ())
value("09.1", (4, 10009), "dropped only the 3", "the table prefix and the 1-based count both go", ("one-based-address",))

value("09.2", board((40150, 25), (40200, 25)), "declared 25 registers per range (150 to 174)", "a range's count is last - first + 1", ("range-one-end",))
value("09.2", board((40151, 26), (40201, 26)), "added 1 to each register number", "register 150 is reference 40150", ())
value("09.2", board((30150, 26), (30200, 26)), "declared input registers", "wrong table prefix: holding registers are 4x", ("holding-for-input",))
value("09.2", board((40150, 26)), "declared the first range only", "partial answer", ("one-range-only",))
value("09.2", board((40150, 76)), "declared 150 to 225 in one run", "a sparse map has gaps", ("dense-for-sparse",))
value("09.2", board((40149, 26), (40199, 26)), "subtracted 1 from each register number", "register 150 is reference 40150", ())

value("09.3", 1.0, "kept the default timeout of 1 s", "a timeout shorter than the loop misses requests", ())
value("09.3", 1.65, "took the nominal loop time", "loops vary by up to 10%, and the reply takes time", ("loop-time-for-timeout",))
value("09.3", 1.5, "rounded the loop time down", "a timeout shorter than the loop misses requests", ("loop-time-for-timeout",))
value("09.3", 2.6, "added a generous margin", "the task caps the timeout at 2.5 s", ("timeout-far-too-long",))
value("09.3", 5.0, "picked a timeout far longer than needed", "the task caps the timeout at 2.5 s", ("timeout-far-too-long",))
value("09.3", 1.8, "added the 10% to the loop and rounded down", "the longest loop is 1.815 s, and the reply takes time too", ("loop-time-for-timeout",))

build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return min(1.0, timeout / loop_time)
''', "ignored the reply time", "the reply takes part of the timeout", ("reply-time-forgotten",))
build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return (timeout - reply) / loop_time
''', "did not clamp the fraction to 0..1", "a fraction is at most 1 and at least 0", ("fraction-unclamped",))
build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return min(1.0, (timeout - reply) / loop_time)
''', "clamped at 1 but not at 0", "a fraction is at least 0", ("fraction-unclamped",))
build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(1.0, timeout / (loop_time + reply)))
''', "added the reply to the loop instead of taking it from the timeout", "the reply takes part of the timeout", ("reply-time-forgotten",))
build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(100.0, 100 * (timeout - reply) / loop_time))
''', "returned a percentage", "a fraction was asked", ("percentage-for-fraction",))
build("09.4", '''def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(1.0, 1 - (timeout - reply) / loop_time))
''', "returned the missed fraction", "answered another question: the share missed", ("missed-for-answered",))

# === 10 power meter ===============================================================================
value("10.1", 4105, "gave the raw register value", "the meter sends volts x 10: scale it", ("raw-for-scaled",))
value("10.1", 41.05, "divided by 100", "the voltage scale is x 10", ("scale-wrong",))
value("10.1", (0x1009 << 16) / 10, "read the registers low word first", "this meter sends the high word first (ABCD)", ("word-order",))
value("10.1", 100.9, "read the hex digits 1009 as decimal", "hex read as decimal", ("hex-read-as-decimal",))
value("10.1", 410.0, "rounded to whole volts", "one decimal was asked", ())

value("10.2", [0x6884, 0x0004], "put the low word first", "this meter sends the high word first (ABCD)", ("word-order",))
value("10.2", [0, 2889], "scaled by 10 like a voltage", "currents are sent in mA", ("current-not-in-milliamperes", "scale-wrong"))
value("10.2", [288900], "gave the 32-bit value as one number", "two registers were asked", ())
value("10.2", [4, 6884], "wrote the hex digits as a decimal number", "hex read as decimal", ("hex-read-as-decimal",))
value("10.2", [0, 28890], "scaled by 100", "currents are sent in mA", ("current-not-in-milliamperes", "scale-wrong"))

value("10.3", (3, 54, 3), "counted three values, not six registers", "a 32-bit value takes two registers", ("one-register-for-32-bits",))
value("10.3", (4, 54, 6), "used function 4", "this meter's map is read with function 3", ("holding-for-input",))
value("10.3", (3, 55, 6), "started one register late", "addresses count from 0", ("one-based-address",))
value("10.3", (3, 40055, 6), "gave a reference number as the address", "reference number confused with address", ("reference-number",))
value("10.3", (3, 54, 12), "counted bytes", "the quantity counts registers", ("bytes-for-registers",))
value("10.3", (3, 48, 12), "read the voltage THDs too", "answered a wider question: only the three current THDs", ())

build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    raw = registers[0].to_bytes(2, "big") + registers[1].to_bytes(2, "big")
    return struct.unpack(">f", raw)[0]
''', "ignored the order", "the word order is the device's choice: decode each one", ("word-order", "word-order-in-specification"))
build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    raw = {"ABCD": a + b, "CDAB": b + a, "BADC": b[::-1] + a[::-1], "DCBA": a[::-1] + b[::-1]}[order]
    return struct.unpack(">f", raw)[0]
''', "swapped the BADC and DCBA rules", "BADC swaps bytes in each register; DCBA reverses all four", ("word-order",))
build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    if order in ("CDAB", "DCBA"):
        a, b = b, a
    return struct.unpack(">f", a + b)[0]
''', "treated DCBA like CDAB (swapped words only)", "DCBA also swaps the bytes of each register", ("word-order",))
build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    raw = {"ABCD": a + b, "CDAB": b + a, "BADC": a[::-1] + b[::-1], "DCBA": b[::-1] + a[::-1]}[order]
    return round(struct.unpack(">f", raw)[0], 1)
''', "rounded to one decimal inside the function", "decoding gives the float as it is; rounding is for display", ("result-rounded",))
build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    raw = {"ABCD": a + b, "CDAB": b + a, "BADC": a[::-1] + b[::-1], "DCBA": b[::-1] + a[::-1]}[order]
    return struct.unpack("<f", raw)[0]
''', "unpacked little-endian", "ABCD is big-endian: '>f'", ("word-order",))
build("10.4", '''import struct
def decode_float32(registers: list, order: str) -> float:
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    raw = {"ABCD": a + b, "CDAB": b + a, "BADC": a[::-1] + b[::-1], "DCBA": b[::-1] + a[::-1]}[order]
    return struct.unpack(">i", raw)[0]
''', "unpacked as an integer", "the four bytes are an IEEE 754 float", ("integer-for-float",))

# === 11 real sockets ==============================================================================
value("11.1", (0x2A00, 6, 16, 500), "read the transaction id low byte first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("11.1", (42, 6, 10, 500), "read the address 0x10 as decimal 10", "hex read as decimal", ("hex-read-as-decimal",))
value("11.1", (42, 6, 16, 0xF401), "read the value low byte first", "registers go high byte first", ("field-low-byte-first",))
value("11.1", (42, 17, 6, 16), "took the unit id as the function", "wrong field: the unit id sits between the length and the function", ("another-field",))
value("11.1", (6, 6, 16, 500), "took the length as the transaction id", "wrong field: the transaction id is the first two bytes", ("another-field",))
value("11.1", (42, 6, 16, 1), "read only the high byte of the value", "a register is two bytes", ("register-one-byte",))

value("11.2", h("00 07 00 00 00 06 03 03 00 00 00 03 04 29"), "kept the CRC", "Modbus/TCP carries no CRC: drop it", ("crc-on-tcp",))
value("11.2", h("00 07 00 00 00 08 03 03 00 00 00 03 04 29"), "kept the CRC and counted it in the length", "Modbus/TCP carries no CRC: drop it", ("crc-on-tcp",))
value("11.2", h("07 00 00 00 00 06 03 03 00 00 00 03"), "wrote the transaction id low byte first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("11.2", h("00 07 00 00 00 05 03 03 00 00 00 03"), "counted the PDU only in the length", "the length counts the unit id and the PDU", ("mbap-length",))
value("11.2", h("00 07 00 00 00 05 03 00 00 00 03"), "dropped the slave address", "the slave address becomes the unit id", ("unit-missing",))
value("11.2", h("00 07 00 00 00 06 FF 03 00 00 00 03"), "put unit 255 for a TCP device", "behind a gateway the unit id is the slave address", ())

value("11.3", "tcp://192.168.1.60:4001", "wrote tcp://", "pyserial's raw TCP URL is socket://", ("url-not-socket",))
value("11.3", "192.168.1.60:4001", "left out the scheme", "a serial_link URL needs its scheme", ("url-not-socket",))
value("11.3", "socket://192.168.1.60:502", "used the Modbus/TCP port", "the device server's port is 4001", ("modbus-tcp-port-for-server",))
value("11.3", "rfc2217://192.168.1.60:4001", "picked RFC 2217", "raw TCP mode is socket://", ("url-not-socket",))
value("11.3", "socket://192.168.1.60", "left out the port", "the port is part of the URL", ("url-without-port",))
value("11.3", "socket://192.168.1.60/4001", "separated the port with a slash", "host and port are joined by a colon", ())

build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if length != len(frame) - 6 or len(frame) < 8:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[7:]
''', "did not check the protocol identifier", "Modbus is protocol 0: any other is refused", ("invalid-input-accepted",))
build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or len(frame) < 8:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[7:]
''', "did not check the length field", "the length must match the bytes that follow it", ("invalid-input-accepted",))
build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or length != len(frame) - 7 or len(frame) < 8:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[7:]
''', "compared the length with the PDU only", "the length counts the unit id and the PDU", ("mbap-length",))
build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "little")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or length != len(frame) - 6 or len(frame) < 8:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[7:]
''', "read the transaction id little-endian", "MBAP fields are big-endian", ("mbap-little-endian",))
build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or length != len(frame) - 6 or len(frame) < 7:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[7:]
''', "accepted a 7-byte frame with no function code", "a frame must hold at least a function code", ("invalid-input-accepted",))
build("11.4", '''def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or length != len(frame) - 6 or len(frame) < 8:
        raise ValueError("bad frame")
    return tid, protocol, length, frame[6], frame[6:]
''', "kept the unit id in the PDU", "the PDU starts at the function code", ("unit-in-pdu",))

# === 12 test tool =================================================================================
value("12.1", "0x008C", "read address 4", "off by one: address 5 is the sixth register", ("one-based-address",))
value("12.1", "0x00A0", "counted address 5 as the fifth step after the first value plus one", "off by one: address 0 holds the first value", ())
value("12.1", "150", "gave the unsigned display", "the hex display was asked", ())
value("12.1", "0x0150", "wrote the decimal digits of 150 after 0x", "decimal written as hex", ("decimal-written-as-hex",))
value("12.1", "0x0064", "gave the first value", "answered another question: address 5", ())

value("12.2", tool_config(function=3), "read holding registers", "input registers are read with function 4", ("holding-for-input",))
value("12.2", tool_config(unit=1), "left the unit at 1", "the device is unit 7", ())
value("12.2", tool_config(address=9), "subtracted 1 from the address", "the address is already the wire address", ("address-one-too-low", "slave-subtracts-one"))
value("12.2", tool_config(interval=500), "gave the interval in milliseconds", "the interval is in seconds", ("milliseconds-for-seconds",))
value("12.2", tool_config(length=8), "gave the length in bytes", "the length counts registers", ("bytes-for-registers",))
value("12.2", tool_config(role="rtu_slave"), "made a slave tool", "to test a device, the tool is the master", ("slave-for-master",))

value("12.3", (283, "1B 01"), "wrote the id low byte first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("12.3", (282, "01 1A"), "counted 280 + 2 for the third request as the next", "off by one: after 280, 281, 282 comes 283", ("last-transaction-id",))
value("12.3", (284, "01 1C"), "counted 280 + 4", "off by one", ())
value("12.3", (283, "01 18"), "kept the first request's bytes", "the two bytes carry the new id", ())
value("12.3", (280, "01 18"), "thought the id never changes", "a client counts its transactions", ("last-transaction-id",))
value("12.3", (283, "02 83"), "wrote the decimal digits as bytes", "decimal written as hex", ("decimal-written-as-hex",))

build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack(">HHHBBHH", tid, 0, 5, unit, 3, address, count)
''', "counted the PDU only in the length", "the length counts the unit id and the PDU", ("mbap-length",))
build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack("<HHHBBHH", tid, 0, 6, unit, 3, address, count)
''', "packed little-endian", "multi-byte fields are big-endian", ("mbap-little-endian", "field-low-byte-first"))
build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack(">HHHBHH", tid, 0, 6, 3, address, count)
''', "left out the unit id", "the MBAP header ends with the unit id", ("unit-missing",))
build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack(">HHHBBHH", tid, 0, 6, unit, 4, address, count)
''', "used function 4", "holding registers are read with function 3", ("holding-for-input",))
build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack(">HHHBBHH", tid & 0xFF, 0, 6, unit, 3, address, count)
''', "kept only the low byte of the transaction id", "the transaction id is two bytes", ("field-in-one-byte",))
build("12.4", '''import struct
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return struct.pack(">HHHBBHH", tid, 0, 6, unit, 3, address, count * 2)
''', "asked for the count in bytes", "the quantity counts registers", ("bytes-for-registers",))

# === 13 troubleshooting ===========================================================================
value("13.1", {"A": "wrong baud rate or parity", "B": "no slave on the line", "C": "wrong unit id"}, "swapped A and C", "other_unit counts frames for another address; checksum errors come from the wrong line settings", ("causes-swapped",))
value("13.1", {"A": "wrong unit id", "B": "wrong baud rate or parity", "C": "no slave on the line"}, "swapped B and C", "a wire with no slave shows no counters at all", ("causes-swapped",))
value("13.1", {"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"}, "swapped A and B", "a slave that counts other_unit is on the line", ("causes-swapped",))
value("13.1", {"A": "wrong unit id", "C": "wrong baud rate or parity"}, "left B out", "partial answer", ())
value("13.1", {"A": "wrong unit id", "B": "no slave on the line", "C": "no slave on the line"}, "thought a slave that hears garbage is as good as absent", "a slave with checksum errors is there, set to other line settings", ("causes-swapped",))

value("13.2", ("ABCD", 292880.386), "kept the colleague's decoding", "an absurd value points at the word order", ("word-order",))
value("13.2", ("CDAB", 135541), "gave milliamperes", "the unit asked is amperes", ("milliamperes-for-amperes",))
value("13.2", ("CDAB", 0.135541), "divided by a million", "milliamperes to amperes is / 1000", ("scale-wrong",))
value("13.2", ("CDAB", 292880.386), "named the order but kept the old value", "the value must be decoded in that order", ())
value("13.2", ("ABCD", 135.541), "gave the right value with the wrong order's name", "low word first is CDAB", ("word-order",))

value("13.3", 21, "kept the script's address", "references count from 1, addresses from 0", ("one-based-address",))
value("13.3", 40020, "kept the table digit", "the table prefix is not part of the address", ("reference-number",))
value("13.3", 19, "subtracted 1 from 20 again", "off by one", ("address-one-too-low",))
value("13.3", 22, "added 1", "references count from 1, addresses from 0", ())
value("13.3", 40021, "gave the reference number", "reference number confused with address", ("reference-number",))

value("13.4", (3, "00 03"), "read the id as the client meant it", "MBAP fields are big-endian: 03 00 is 768", ("mbap-little-endian",))
value("13.4", (768, "03 00"), "kept the client's bytes", "the request should carry 3 high byte first", ("mbap-little-endian",))
value("13.4", (3, "03 00"), "read little-endian and kept the bytes", "MBAP fields are big-endian", ("mbap-little-endian",))
value("13.4", (0x30, "00 03"), "read 03 00 as the digits 30", "hex read as decimal", ("hex-read-as-decimal",))
value("13.4", (768, "00 00"), "took the protocol id bytes", "wrong field", ("another-field",))

value("13.5", h("01 03 00 00 00 01 0A 84"), "gave the frame unchanged", "the CRC bytes are the wrong way round", ("crc-swapped",))
value("13.5", h("01 03 00 00 00 01") + low_first(crc(h("03 00 00 00 01"))), "recomputed the CRC over the PDU only", "the RTU CRC covers the address too", ("checksum-without-address",))
value("13.5", h("01 03 00 00 00 01") + low_first(crc(h("01 03 00 00 00 01"), 0)), "recomputed the CRC from 0", "the CRC register starts at 0xFFFF", ("crc-initial-zero",))
value("13.5", h("01 03 00 00 00 01"), "dropped the CRC", "an RTU frame ends with its CRC", ("crc-forgotten",))
value("13.5", h("84 0A"), "gave only the CRC", "partial answer: the whole frame was asked", ())
value("13.5", h("01 03 00 00 00 01 84 0A 0A 84"), "added the right CRC after the wrong one", "an RTU frame has one CRC", ())

value("13.6", 0.44, "gave the answered fraction", "answered another question: the loop time", ("given-figure",))
value("13.6", 0.56, "gave the missed fraction", "answered another question: the loop time", ())
value("13.6", 1.0, "gave the timeout", "the loop time is (timeout - reply) / fraction", ("given-figure",))
value("13.6", 5.0, "gave the interval between requests", "the loop time is (timeout - reply) / fraction", ("given-figure",))
value("13.6", 2243.0, "gave milliseconds", "the unit asked is seconds", ("milliseconds-for-seconds",))
value("13.6", 0.44 * 1.0, "multiplied the fraction by the timeout", "the loop time is (timeout - reply) / fraction", ())

build("13.7", '''import modbus_edu as mb
def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if mb.decode_value(registers, "float32", order) == expected:
            return order
    return None
''', "compared floats with ==", "a float32 is never exactly the decimal shown: compare with a tolerance", ("float-compared-exactly",))
build("13.7", '''import modbus_edu as mb
def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "float32", order) - expected) < 0.01:
            return order
    return "ABCD"
''', "returned ABCD when no order fits", "None was asked when no order fits", ("an-order-when-none-fits",))
build("13.7", '''import modbus_edu as mb
def find_order(registers: list, expected: float):
    fits = []
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "float32", order) - expected) < 0.01:
            fits.append(order)
    return fits
''', "returned the list of orders", "one order was asked", ())
build("13.7", '''import modbus_edu as mb
def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "float32", order) - expected) < 1000:
            return order
    return None
''', "used a tolerance far too wide", "the tolerance must tell the orders apart", ())
build("13.7", '''import struct
def find_order(registers: list, expected: float):
    a, b = registers[0].to_bytes(2, "big"), registers[1].to_bytes(2, "big")
    for order, raw in (("ABCD", a + b), ("CDAB", b + a), ("BADC", a[::-1] + b[::-1]), ("DCBA", a[::-1] + b[::-1])):
        if abs(struct.unpack(">f", raw)[0] - expected) < 0.01:
            return order
    return None
''', "built DCBA the same as BADC", "DCBA reverses all four bytes", ("word-order",))
build("13.7", '''import modbus_edu as mb
def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "float32", order) - expected) < 0.01:
            return order
    raise ValueError("no order fits")
''', "raised when no order fits", "None was asked when no order fits", ())

# === 14 beyond eight functions ====================================================================
value("14.1", 0x00A5 | 0x0130, "ORed the OR mask in and ignored the AND mask", "FC 22 keeps only the bits of the AND mask", ("mask-write-or",))
value("14.1", 0x00A5 & 0x000F, "applied the AND mask only", "then the OR mask sets bits outside the AND mask", ("or-mask-forgotten",))
value("14.1", 0x0130, "gave the OR mask", "the register keeps its bits inside the AND mask", ())
value("14.1", (0x00A5 & 0x0130) | 0x000F, "swapped the two masks", "AND mask first, OR mask second", ("mask-roles-swapped",))
value("14.1", 0x00A5 & ~0x000F & 0xFFFF, "cleared the bits of the AND mask instead of keeping them", "the AND mask keeps the bits where it has 1s", ("mask-roles-swapped",))
value("14.1", 135, "read the hex result 0x0135 as decimal", "hex read as decimal", ("hex-read-as-decimal",))

build("14.2", '''def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & and_mask) | or_mask
''', "ORed the whole OR mask in", "OR mask bits only where the AND mask is 0", ("mask-write-or",))
build("14.2", '''def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current | or_mask) & and_mask
''', "ORed first, then ANDed", "(current AND and) OR (or AND NOT and)", ())
build("14.2", '''def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & and_mask) | (or_mask & and_mask)
''', "forgot the NOT", "OR mask bits only where the AND mask is 0", ("mask-write-or",))
build("14.2", '''def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & ~and_mask) | (or_mask & and_mask)
''', "inverted the roles of the AND mask", "the AND mask keeps the bits where it has 1s", ("mask-roles-swapped",))
build("14.2", '''def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return ((current & and_mask) | (or_mask & ~and_mask)) & 0xFF
''', "kept 8 bits", "registers are 16 bits", ())

value("14.3", 6, "counted the clear request too", "the clear resets the counter after the request is counted", ())
value("14.3", 4, "forgot the 0x0B request being answered", "the course's slave counts the request it answers", ("count-request-forgotten",))
value("14.3", 3, "counted only unit 1's own requests", "the course's slave counts every good frame on the line", ("others-not-heard",))
value("14.3", 7, "counted the clear request and the damaged one", "a frame with a bad CRC is not a message", ("damaged-message-counted",))
value("14.3", 2, "counted only the two reads of unit 1", "the course's slave counts every good frame on the line", ("others-not-heard",))

# === 15 gateways and converters ===================================================================
_C192E = 11 / 19200 * 1000  # ms per 8E1 character at 19200
value("15.1", round(24 * 10 / 19200 * 1000, 2), "counted 10 bits per character", "a character with parity is 11 bits", ("parity-bit-forgotten",))
value("15.1", round(24 * 11 / 9600 * 1000, 2), "used 9600 baud", "the baud rate given was 19200", ("another-baud-rate",))
value("15.1", round(17 * _C192E, 2), "left out the silences", "each frame is followed by 3.5 characters of silence", ("silences-forgotten",))
value("15.1", round(17 * _C192E + 2 * 1.75, 2), "used the fixed 1.75 ms silences at 19200", "the fixed values apply above 19200 baud", ("fixed-silence-at-19200",))
value("15.1", round(22 * _C192E, 2), "took the response as 5 + N bytes", "a register is two bytes", ("register-one-byte",))
value("15.1", round(24 * _C192E / 1000, 5), "gave seconds", "the unit asked is milliseconds", ("seconds-for-milliseconds",))

build("15.2", '''import struct
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    return struct.pack(">HHH", transaction_id, 0, len(body)) + body
''', "did not check the CRC", "a gateway does not forward a damaged frame", ("invalid-input-accepted",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    if mb.crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("CRC error")
    return struct.pack(">HHH", transaction_id, 0, len(frame)) + frame
''', "kept the CRC", "Modbus/TCP carries no CRC: drop it", ("crc-on-tcp",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    if mb.crc16(body) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("CRC error")
    return struct.pack(">HHH", transaction_id, 0, len(body) - 1) + body
''', "counted the PDU only in the length", "the length counts the unit id and the PDU", ("mbap-length",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    if mb.crc16(body) != int.from_bytes(frame[-2:], "big"):
        raise ValueError("CRC error")
    return struct.pack(">HHH", transaction_id, 0, len(body)) + body
''', "read the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    if mb.crc16(body) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("CRC error")
    return struct.pack("<HHH", transaction_id, 0, len(body)) + body
''', "packed the header little-endian", "MBAP fields are big-endian", ("mbap-little-endian",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    if mb.crc16(body) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("CRC error")
    return struct.pack(">HHH", transaction_id, 0, len(body) - 1) + body[1:]
''', "dropped the unit with the CRC", "the slave address becomes the unit id", ("unit-missing",))
build("15.2", '''import struct
import modbus_edu as mb
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body = frame[:-2]
    if mb.crc16(body) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("CRC error")
    return struct.pack(">HHH", transaction_id & 0xFF, 0, len(body)) + body
''', "kept only the low byte of the transaction id", "the transaction id is two bytes", ("field-in-one-byte",))

_RIGHT_153 = {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"}
value("15.3", {**_RIGHT_153, "a": "timeout"}, "thought the gateway stays silent for unit 248", "a gateway answers 0A when it has no path", ("gateway-silence",))
value("15.3", {**_RIGHT_153, "b": "timeout"}, "thought the client times out on a silent meter", "the gateway answers 0B for a silent unit", ("gateway-silence",))
value("15.3", {**_RIGHT_153, "c": 0x0B}, "thought the meter stays silent for an unknown function", "the meter answers 01 for a function it does not implement", ("refusal-unanswered",))
value("15.3", {**_RIGHT_153, "d": 0x0B}, "thought the short-timeout client gets the gateway's 0B", "the client gives up after 0.1 s, before the gateway's 0.2 s", ())
value("15.3", {**_RIGHT_153, "b": 0x0A}, "answered 0A for the loose cable", "0A is no path; 0B a unit that did not answer", ("gateway-codes-swapped",))
value("15.3", {**_RIGHT_153, "a": 0x0B, "b": 0x0A}, "swapped 0A and 0B", "0A is no path; 0B a unit that did not answer", ("gateway-codes-swapped",))

# === 16 first real device =========================================================================
_MAP_HEAD = "name,table,address,type,order,scale,unit\n"
_MAP_ROWS = [("voltage", 30001, "V"), ("current", 30007, "A"), ("power", 30013, "W"), ("frequency", 30071, "Hz"), ("energy", 30073, "kWh")]


def map_text(rows=_MAP_ROWS, table="input", type_="float32", order="CDAB", scale="1", shift=0) -> str:
    return _MAP_HEAD + "".join(f"{name},{table},{number + shift},{type_},{order},{scale},{unit}\n" for name, number, unit in rows)


value("16.1", map_text(order="ABCD"), "wrote the word order as ABCD", "the datasheet says low word first: CDAB", ("word-order",))
value("16.1", map_text(shift=-30001), "wrote addresses (0, 6, 12, ...) where the file keeps the datasheet's numbers", "reference numbers and addresses mixed in one file", ())
value("16.1", map_text(table="holding"), "put the values in the holding table", "30001-style numbers are input registers (FC 4)", ("holding-for-input",))
value("16.1", map_text(type_="uint32"), "typed the values as uint32", "the datasheet says 32-bit float", ("integer-for-float",))
value("16.1", map_text(rows=_MAP_ROWS[:3] + _MAP_ROWS[4:]), "left out the frequency", "partial answer: one row per value", ())
value("16.1", map_text(shift=1), "added 1 to every number", "the file keeps the datasheet's numbers as they are", ())

_PLAN = [(0, 2), (6, 2), (12, 2), (70, 4)]


def frames(plan, function=4, unit=1, crc_high=False) -> list[bytes]:
    made = []
    for address, count in plan:
        body = bytes([unit, function]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
        made.append(body + (high_first(crc(body)) if crc_high else low_first(crc(body))))
    return made


value("16.2", frames([(0, 2), (6, 2), (12, 2), (70, 2), (72, 2)]), "sent one request per value", "neighbouring values share one request", ("request-per-register",))
value("16.2", frames(_PLAN, function=3), "used function 3", "input registers are read with function 4", ("holding-for-input",))
value("16.2", frames([(1, 2), (7, 2), (13, 2), (71, 4)]), "used the 1-based numbers as addresses", "references count from 1, addresses from 0", ("one-based-address",))
value("16.2", frames([(0, 76)]), "read everything in one request", "a request must not cross registers the device does not list", ("dense-for-sparse",))
value("16.2", frames(_PLAN, crc_high=True), "put each CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("16.2", frames(_PLAN[:3]), "left out the last request", "partial answer", ())
value("16.2", [f[1:-2] for f in frames(_PLAN)], "gave the PDUs", "RTU frames were asked: address, PDU, CRC", ("unit-missing", "crc-forgotten"))

value("16.3", "check the baud rate and parity", "went back to the line settings", "the settings were already checked: next on the row is A/B", ("check-ruled-out",))
value("16.3", "check the unit id", "went to the unit", "the scan of every unit found nothing", ("check-ruled-out",))
value("16.3", "increase the timeout", "blamed a slow first answer", "a scan at every setting rules that out; A/B comes before it", ("check-ruled-out",))
value("16.3", "check the port", "went back to the first step", "the TX LED shows the port is right", ("check-ruled-out",))
value("16.3", "check the word order", "picked a check from the absurd-values row", "silence is not an absurd value", ())
value("16.3", "turn on the adapter echo", "picked the echo check", "an echo is a bad response, not silence", ())

build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    return received[len(sent):]
''', "never checked the echo", "a missing or damaged echo must raise", ("echo-unchecked",))
build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    if received[:1] != sent[:1]:
        raise ValueError("no echo")
    return received[len(sent):]
''', "checked only the first byte", "every byte of the echo must match", ("echo-unchecked",))
build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    if sent not in received:
        raise ValueError("no echo")
    return received.replace(sent, b"", 1)
''', "looked for the request anywhere in the bytes", "the echo comes first", ("echo-unchecked",))
build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    if received.startswith(sent):
        return received[len(sent):]
    return received
''', "passed the bytes through when there is no echo", "a missing echo must raise", ("echo-unchecked",))
build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    if not received.startswith(sent):
        raise ValueError("no echo")
    return received[len(sent) + 1:]
''', "cut one byte too many", "off by one: the answer starts right after the echo", ())
build("16.4", '''def strip_echo(sent: bytes, received: bytes) -> bytes:
    if not received.startswith(sent):
        raise ValueError("no echo")
    return received.replace(sent, b"")
''', "removed every copy of the request", "only the echo at the start comes off", ())

# === 17 captures and security =====================================================================
value("17.0", "CADDBDCBCCBA", "answered in notebook 00's order", "the questions come in another order here", ())
value("17.0", "ACBDCAABDCDB", "took the length as the PDU's 5 bytes", "the MBAP length counts the unit id and the PDU", ("mbap-length",))
value("17.0", "CCBDCBABDCDB", "wrote the transaction id low byte first", "MBAP fields are big-endian", ("mbap-little-endian",))
value("17.0", "CCADCAABDCDB", "put the CRC high byte first", "the RTU CRC goes low byte first", ("crc-swapped",))
value("17.0", "CCBDCAABACDB", "took 40001 as the address", "reference number confused with address", ("reference-number",))
value("17.0", "CCBDCAABDCDA", "thought a 2-character pause is harmless", "a gap of more than 1.5 characters breaks the frame", ("pause-threshold", "t15-forgotten"))
value("17.0", "CCBDCAABDCD", "typed eleven letters", "one answer per question", ())

value("17.1", 10, "gave the address", "wrong field: the value follows the address", ("another-field",))
value("17.1", 0xF401, "read the value low byte first", "registers go high byte first", ("field-low-byte-first",))
value("17.1", 6, "gave the function code", "wrong field", ("another-field",))
value("17.1", 0xF4, "read only the last byte", "a register is two bytes", ("register-one-byte",))
value("17.1", 1, "read only the high byte of the value", "a register is two bytes", ("register-one-byte",))

value("17.2", 0, "checked only the first address", "every address written must be within 0..99: 98, 99 and 100", ("first-address-only",))
value("17.2", 2, "answered illegal data address", "a refused role gets exception 01", ("exception-code-confused",))
value("17.2", 3, "answered illegal data value", "a refused role gets exception 01", ("exception-code-confused",))
value("17.2", 0x90, "gave the exception function code", "answered another question: the code", ("exception-function-for-code",))
value("17.2", 0x81, "set the top bit on the code", "the code is 01; the top bit is on the function", ("top-bit-on-code",))
value("17.2", "refused", "answered in words", "the exception code was asked", ())

build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        if address <= 99:
            return None
    return refuse
''', "checked only the first address of a multiple write", "every address written must be within 0..99", ("first-address-only",))
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big")
        if last <= 99:
            return None
    return refuse
''', "took address + quantity as the last address", "off by one: the last address is address + quantity - 1", ())
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "little")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "little") - 1
        if last <= 99:
            return None
    return refuse
''', "read the address and quantity little-endian", "multi-byte fields are big-endian", ("field-low-byte-first",))
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role in ("engineer", None, ""):
        return None
    if function in (1, 2, 3, 4):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        if last <= 99:
            return None
    return refuse
''', "let any role read", "an unknown role may do nothing", ())
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4, 5, 6) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address + int.from_bytes(pdu[3:5], "big") - 1
        if last <= 99:
            return None
    return refuse
''', "let the viewer and the operator write single values anywhere", "a viewer reads only; an operator writes only within 0..99", ())
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function + 0x80, 0x02])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        if last <= 99:
            return None
    return refuse
''', "refused with exception 02", "a refused role gets exception 01", ("exception-code-confused",))
build("17.3", '''def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer" and function <= 24:
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        if last <= 99:
            return None
    return refuse
''', "let the engineer use only the functions up to 24", "an engineer may use everything", ())
