# ruff: noqa: E501 (the slips' answers and function sources are kept whole, one per entry)
"""A held-out set of realistic wrong answers ("slips") to the course's exercises.

Each entry is an answer a newcomer plausibly gives to one exercise of notebooks 00 to 17: an
arithmetic or procedure slip (a CRC register started at 0, bytes in the wrong order, hex read as
decimal, an address off by one, a forgotten field, the wrong number of bits per character, ...),
a wrong type or form, a partial answer, or, for a build exercise, the source of a whole function with
one realistic bug. Every wrong value was computed with Python and the library, as a learner with that
misconception would compute it, and differs from the right answer.

The rule this set was written under: it was written from the notebooks alone (their prose, their
exercise cells and the library's public API used to compute right answers), without reading the
checkers, the existing catalogue of wrong answers, the checker tests or the worked solutions, and it
was never tuned against the checkers: no slip was run through a checker while the set was written,
and no answer was changed after the checkers' verdicts were seen. So it measures how well the checkers
name mistakes they were not written for.

One entry was taken out after the first measurement, as not a mistake: 12.1's "0x96", the right
value without leading zeros, which the course's one rule of strictness accepts (spelling is free,
the value is not; the verdict names the usual form).

Each entry: ``key`` (the exercise), ``answer`` (the value, or for a build exercise the function's
source), ``kind`` ("value" or "build"), ``mistake`` (the misconception, one sentence) and
``candidates`` (the catalogue's misconception ids whose description fits the mistake, filled in
afterwards from the catalogue's id list and one-line descriptions only; empty where none fits).
"""

import modbus_edu as mb


def _board(declarations):
    """An ArduinoSlave with holding registers declared as a learner would: (first reference, count)."""
    from modbus_edu.devices import ArduinoSlave

    board = ArduinoSlave(unit=1, sketch=False)
    for first, count in declarations:
        for reference in range(first, first + count):
            board.add(str(reference))
    return board


HELDOUT = [
    # ---- notebook 00 ----
    {
        "key": "00.0",
        "kind": "value",
        "answer": "abdc?ab",
        "mistake": "Answers only the questions it could guess and stops, giving 7 letters for 12 questions.",
        "candidates": [],
    },
    {
        "key": "00.0",
        "kind": "value",
        "answer": ["c", "a", "d", "d", "b", "d", "c", "b", "c", "c", "b", "a"],
        "mistake": "Gives a list of letters instead of one string of 12 letters.",
        "candidates": [],
    },
    {
        "key": "00.0",
        "kind": "value",
        "answer": "cadd b dcbc cbae",
        "mistake": "Uses a letter outside a to d (e) and scatters spaces in the answer.",
        "candidates": [],
    },
    {
        "key": "00.0",
        "kind": "value",
        "answer": "312241324321",
        "mistake": "Numbers the choices 1 to 4 instead of writing the letters a to d.",
        "candidates": [],
    },
    {
        "key": "00.1",
        "kind": "value",
        "answer": 11,
        "mistake": "Reads the address byte 11 as the decimal number eleven instead of hex 0x11.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "00.1",
        "kind": "value",
        "answer": 3,
        "mistake": "Takes the function code, the second byte, for the slave address.",
        "candidates": ["another-field"],
    },
    {
        "key": "00.1",
        "kind": "value",
        "answer": 1,
        "mistake": "Answers slave 1 from habit, without reading the first byte of the frame.",
        "candidates": [],
    },
    {
        "key": "00.2",
        "kind": "value",
        "answer": bytes.fromhex("11 03 00 6B 00 03"),
        "mistake": "Includes the unit identifier in the PDU.",
        "candidates": ["unit-in-pdu"],
    },
    {
        "key": "00.2",
        "kind": "value",
        "answer": bytes.fromhex("06 11 03 00 6B 00 03"),
        "mistake": "Counts the PDU from the low byte of the length field on, taking the length and unit with it.",
        "candidates": ["unit-in-pdu"],
    },
    {
        "key": "00.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 06"),
        "mistake": "Gives the MBAP header's first six bytes instead of what follows it.",
        "candidates": ["another-field"],
    },
    {
        "key": "00.2",
        "kind": "value",
        "answer": "03 00 6B 00",
        "mistake": "Drops the last byte of the PDU, taking the count to be one byte.",
        "candidates": [],
    },
    {
        "key": "00.2",
        "kind": "value",
        "answer": "00 07 00 00 00 06 11 03 00 6B 00 03",
        "mistake": "Gives the whole Modbus/TCP frame instead of only the PDU.",
        "candidates": ["frame-for-pdu"],
    },
    {
        "key": "00.3",
        "kind": "value",
        "answer": bytes.fromhex("02 03 00 00 00 02 38 C4"),
        "mistake": "Appends the CRC high byte first.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "00.3",
        "kind": "value",
        "answer": bytes.fromhex("02 03 00 00 00 02"),
        "mistake": "Forgets the CRC at the end of the RTU frame.",
        "candidates": ["crc-forgotten"],
    },
    {
        "key": "00.3",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 00 02 C4 0B"),
        "mistake": "Leaves the slave address at 1 as in the notebook's example.",
        "candidates": [],
    },
    {
        "key": "00.3",
        "kind": "value",
        "answer": bytes.fromhex("02 03 00 01 00 02 95 F8"),
        "mistake": "Puts address 1 in the frame, counting registers from 1.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "00.3",
        "kind": "value",
        "answer": bytes.fromhex("02 04 00 00 00 02 71 F8"),
        "mistake": "Uses function 4 instead of function 3 for holding registers.",
        "candidates": ["holding-for-input"],
    },
    # ---- notebook 01 ----
    {
        "key": "01.1",
        "kind": "value",
        "answer": 250,
        "mistake": "Takes the element number 250 as the address, forgetting that addresses start at 0.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "01.1",
        "kind": "value",
        "answer": 40249,
        "mistake": "Subtracts one but keeps the table prefix 4 in the address.",
        "candidates": ["reference-number"],
    },
    {
        "key": "01.1",
        "kind": "value",
        "answer": 40250,
        "mistake": "Puts the reference number itself in the frame.",
        "candidates": ["reference-number"],
    },
    {
        "key": "01.1",
        "kind": "value",
        "answer": 248,
        "mistake": "Subtracts one twice, once for the prefix digit and once for the 1-based count.",
        "candidates": ["address-one-too-low"],
    },
    {
        "key": "01.1",
        "kind": "value",
        "answer": 585,
        "mistake": "Writes the right digits 249 but as hex 0x249.",
        "candidates": ["decimal-written-as-hex"],
    },
    {
        "key": "01.2",
        "kind": "value",
        "answer": "30009",
        "mistake": "Keeps the address as the element number, forgetting the +1.",
        "candidates": ["zero-based-number"],
    },
    {
        "key": "01.2",
        "kind": "value",
        "answer": "40010",
        "mistake": "Uses the holding-register prefix 4 for an input register.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "01.2",
        "kind": "value",
        "answer": "10010",
        "mistake": "Uses prefix 1 (discrete inputs) for input registers.",
        "candidates": ["bit-table-for-register-table"],
    },
    {
        "key": "01.2",
        "kind": "value",
        "answer": "300010",
        "mistake": "Writes the 6-digit form when the 5-digit one was asked.",
        "candidates": [],
    },
    {
        "key": "01.2",
        "kind": "value",
        "answer": "30011",
        "mistake": "Adds one to the address twice.",
        "candidates": [],
    },
    {
        "key": "01.3",
        "kind": "value",
        "answer": ("input_registers", True),
        "mistake": "Thinks a master may write input registers because they are registers.",
        "candidates": [],
    },
    {
        "key": "01.3",
        "kind": "value",
        "answer": ("holding_registers", True),
        "mistake": "Mixes up function 4 with function 3 (holding registers).",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "01.3",
        "kind": "value",
        "answer": ("discrete_inputs", False),
        "mistake": "Mixes up function 4 with function 2 (discrete inputs).",
        "candidates": ["bit-table-for-register-table"],
    },
    {
        "key": "01.3",
        "kind": "value",
        "answer": ("holding_registers", False),
        "mistake": "Takes function 4 for holding registers and calls them read-only.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "01.3",
        "kind": "value",
        "answer": ("coils", True),
        "mistake": "Counts the four tables from function 1 in the wrong order and lands on coils.",
        "candidates": ["bit-table-for-register-table"],
    },
    {
        "key": "01.4",
        "kind": "value",
        "answer": 58,
        "mistake": "Subtracts the ends of each range (149 - 100 and 309 - 300) without adding one.",
        "candidates": ["range-one-end"],
    },
    {
        "key": "01.4",
        "kind": "value",
        "answer": 59,
        "mistake": "Adds one to the first range's difference but not to the second.",
        "candidates": ["range-one-end"],
    },
    {
        "key": "01.4",
        "kind": "value",
        "answer": 210,
        "mistake": "Counts every register from 100 to 309, gaps included.",
        "candidates": ["dense-for-sparse"],
    },
    {
        "key": "01.4",
        "kind": "value",
        "answer": 2,
        "mistake": "Counts the blocks instead of the registers.",
        "candidates": [],
    },
    {
        "key": "01.4",
        "kind": "value",
        "answer": 61,
        "mistake": "Counts the first range as 51, including both ends and one more.",
        "candidates": ["range-one-extra"],
    },
    {
        "key": "01.5",
        "kind": "build",
        "answer": """\
def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("element 0000 does not exist")
    return (tables[text[0]], number)
""",
        "mistake": "Returns the element number as the address, forgetting to subtract one.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "01.5",
        "kind": "build",
        "answer": """\
def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "input_registers", "3": "discrete_inputs", "4": "holding_registers"}
    number = int(text[1:])
    if number == 0:
        raise ValueError("element 0000 does not exist")
    return (tables[text[0]], number - 1)
""",
        "mistake": "Swaps the prefixes 1 and 3: discrete inputs and input registers.",
        "candidates": ["bit-table-for-register-table"],
    },
    {
        "key": "01.5",
        "kind": "build",
        "answer": """\
def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    return (tables[text[0]], int(text[1:]) - 1)
""",
        "mistake": "Forgets to refuse element 0000 and returns address -1 for it.",
        "candidates": ["invalid-input-accepted"],
    },
    {
        "key": "01.5",
        "kind": "build",
        "answer": """\
def parse_reference(text: str) -> tuple:
    tables = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}
    number = int(text[2:])
    if number == 0:
        raise ValueError("element 0000 does not exist")
    return (tables[text[0]], number - 1)
""",
        "mistake": "Slices the element number from the third character, dropping its first digit.",
        "candidates": [],
    },
    {
        "key": "01.5",
        "kind": "build",
        "answer": """\
def parse_reference(text: str) -> tuple:
    number = int(text)
    table = number // 10000
    address = number % 10000
    if address == 0:
        raise ValueError("element 0000 does not exist")
    names = {0: "coils", 1: "discrete_inputs", 3: "input_registers", 4: "holding_registers"}
    return (names[table], address)
""",
        "mistake": "Splits the number arithmetically but keeps the 1-based element number as the address.",
        "candidates": ["one-based-address"],
    },
    # ---- notebook 02 ----
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("10 00 04 00 02 02 01 F4 03 E8"),
        "mistake": "Writes the byte count as the number of registers (2) instead of the number of bytes (4).",
        "candidates": ["byte-count-for-quantity"],
    },
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("10 00 04 00 02 01 F4 03 E8"),
        "mistake": "Forgets the byte count field of FC16.",
        "candidates": ["byte-count-missing"],
    },
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("10 00 05 00 02 04 01 F4 03 E8"),
        "mistake": "Puts address 5, counting registers from 1.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("10 04 00 02 00 04 F4 01 E8 03"),
        "mistake": "Writes every 16-bit field low byte first.",
        "candidates": ["field-low-byte-first"],
    },
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("06 00 04 01 F4 06 00 05 03 E8"),
        "mistake": "Sends two FC6 writes back to back instead of one FC16 request.",
        "candidates": [],
    },
    {
        "key": "02.1",
        "kind": "value",
        "answer": bytes.fromhex("0F 00 04 00 02 04 01 F4 03 E8"),
        "mistake": "Uses function 15 (write multiple coils) instead of 16.",
        "candidates": ["bit-table-for-register-table"],
    },
    {
        "key": "02.2",
        "kind": "value",
        "answer": 2,
        "mistake": "Divides 300 by the 125-register limit and rounds 2.4 down instead of up.",
        "candidates": ["count-rounded-down"],
    },
    {
        "key": "02.2",
        "kind": "value",
        "answer": 300,
        "mistake": "Reads one register per request.",
        "candidates": ["request-per-register"],
    },
    {
        "key": "02.2",
        "kind": "value",
        "answer": 1,
        "mistake": "Thinks one request can read any number of registers.",
        "candidates": [],
    },
    {
        "key": "02.2",
        "kind": "value",
        "answer": 2.4,
        "mistake": "Divides 300 by 125 without rounding up to whole requests.",
        "candidates": [],
    },
    {
        "key": "02.3",
        "kind": "value",
        "answer": bytes.fromhex("04 02"),
        "mistake": "Leaves the function code as it was, without setting the top bit for an exception.",
        "candidates": ["exception-bit-missing"],
    },
    {
        "key": "02.3",
        "kind": "value",
        "answer": bytes.fromhex("83 02"),
        "mistake": "Answers with function 3's exception code 0x83 although the request was function 4.",
        "candidates": [],
    },
    {
        "key": "02.3",
        "kind": "value",
        "answer": bytes.fromhex("84 01"),
        "mistake": "Gives exception code 01 (illegal function) for an address the slave lacks.",
        "candidates": ["illegal-function-for-address"],
    },
    {
        "key": "02.3",
        "kind": "value",
        "answer": bytes.fromhex("84 03"),
        "mistake": "Gives exception code 03 (illegal data value) for an address the slave lacks.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "02.3",
        "kind": "value",
        "answer": bytes.fromhex("01 84 02 C2 C1"),
        "mistake": "Gives the whole RTU frame instead of the PDU.",
        "candidates": ["frame-for-pdu"],
    },
    {
        "key": "02.4",
        "kind": "value",
        "answer": [1, 3],
        "mistake": "Numbers the coils from 1 instead of from address 0.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "02.4",
        "kind": "value",
        "answer": [5],
        "mistake": "Reads the data byte 05 as the address of one coil.",
        "candidates": ["byte-value-as-coils"],
    },
    {
        "key": "02.4",
        "kind": "value",
        "answer": [0, 1, 2, 3, 4],
        "mistake": "Reads 05 as a count of five coils that are ON.",
        "candidates": ["byte-value-as-coils"],
    },
    {
        "key": "02.4",
        "kind": "value",
        "answer": [5, 7],
        "mistake": "Takes the first coil to be the most significant bit of the byte.",
        "candidates": ["bits-from-the-left"],
    },
    {
        "key": "02.4",
        "kind": "value",
        "answer": [0],
        "mistake": "Takes the byte count 01 for the coil data byte.",
        "candidates": ["another-field"],
    },
    {
        "key": "02.5",
        "kind": "build",
        "answer": """\
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 0 <= count <= 125:
        raise ValueError("count must be 1..125")
    if address + count > 65536:
        raise ValueError("past address 65535")
    return bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
""",
        "mistake": "Lets a count of 0 through: the range check starts at 0 instead of 1.",
        "candidates": ["invalid-input-accepted"],
    },
    {
        "key": "02.5",
        "kind": "build",
        "answer": """\
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 1 <= count <= 125:
        raise ValueError("count must be 1..125")
    if address + count > 65535:
        raise ValueError("past address 65535")
    return bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
""",
        "mistake": "Refuses a read that ends exactly at address 65535: off by one in the end check.",
        "candidates": [],
    },
    {
        "key": "02.5",
        "kind": "build",
        "answer": """\
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 1 <= count <= 125:
        raise ValueError("count must be 1..125")
    if address + count > 65536:
        raise ValueError("past address 65535")
    return bytes([3]) + address.to_bytes(2, "little") + count.to_bytes(2, "little")
""",
        "mistake": "Writes the address and the count low byte first.",
        "candidates": ["field-low-byte-first"],
    },
    {
        "key": "02.5",
        "kind": "build",
        "answer": """\
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 1 <= count <= 2000:
        raise ValueError("count must be 1..2000")
    if address + count > 65536:
        raise ValueError("past address 65535")
    return bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
""",
        "mistake": "Uses the 2000 limit of the bit reads instead of 125 registers.",
        "candidates": ["another-devices-limit", "invalid-input-accepted"],
    },
    {
        "key": "02.5",
        "kind": "build",
        "answer": """\
def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 1 <= count <= 125:
        raise ValueError("count must be 1..125")
    return bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
""",
        "mistake": "Checks the count but not that the registers stay within address 65535.",
        "candidates": ["invalid-input-accepted"],
    },
    # ---- notebook 03 ----
    {
        "key": "03.1",
        "kind": "value",
        "answer": bytes.fromhex("98 B2"),
        "mistake": "Gives the two CRC bytes high byte first.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "03.1",
        "kind": "value",
        "answer": 39090,
        "mistake": "Gives the CRC register value as an int instead of its two bytes in wire order.",
        "candidates": [],
    },
    {
        "key": "03.1",
        "kind": "value",
        "answer": bytes.fromhex("B2 83"),
        "mistake": "Starts the CRC register at 0 instead of 0xFFFF.",
        "candidates": ["crc-initial-zero"],
    },
    {
        "key": "03.1",
        "kind": "value",
        "answer": bytes.fromhex("95 C2"),
        "mistake": "Computes the CRC over the PDU only, leaving out the slave address.",
        "candidates": ["checksum-without-address"],
    },
    {
        "key": "03.1",
        "kind": "value",
        "answer": bytes.fromhex("4D 67"),
        "mistake": "XORs the CRC with 0xFFFF at the end, as some other CRC-16 variants do.",
        "candidates": [],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 02 12 34 7D 25"),
        "mistake": "Appends the CRC high byte first.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 02 34 12 BE C7"),
        "mistake": "Writes the register value 0x1234 low byte first.",
        "candidates": ["field-low-byte-first"],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 02 04 D2 AA 97"),
        "mistake": "Writes the decimal value 1234 instead of hex 0x1234.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 01 12 34 D5 7D"),
        "mistake": "Subtracts one from the address as if it were a 1-based reference number.",
        "candidates": ["address-one-too-low"],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 02 12 34 25 66"),
        "mistake": "Starts the CRC register at 0 instead of 0xFFFF.",
        "candidates": ["crc-initial-zero"],
    },
    {
        "key": "03.2",
        "kind": "value",
        "answer": bytes.fromhex("01 06 00 02 12 34"),
        "mistake": "Forgets the CRC at the end of the frame.",
        "candidates": ["crc-forgotten"],
    },
    {
        "key": "03.3",
        "kind": "value",
        "answer": True,
        "mistake": "Trusts the frame because it looks like the notebook's example, without checking the CRC.",
        "candidates": ["answer-to-damaged-request"],
    },
    {
        "key": "03.3",
        "kind": "value",
        "answer": "yes",
        "mistake": "Says in words that the slave answers, thinking a slave still answers a frame whose CRC "
        "it cannot check.",
        "candidates": ["answer-to-damaged-request"],
    },
    {
        "key": "03.3",
        "kind": "value",
        "answer": "exception",
        "mistake": "Thinks the slave answers a bad CRC with an exception response.",
        "candidates": ["answer-to-damaged-request"],
    },
    {
        "key": "03.4",
        "kind": "value",
        "answer": 25,
        "mistake": "Counts one byte per register: 5 + 20.",
        "candidates": ["register-one-byte"],
    },
    {
        "key": "03.4",
        "kind": "value",
        "answer": 40,
        "mistake": "Counts the register data only, without address, function, byte count and CRC.",
        "candidates": ["data-bytes-only"],
    },
    {
        "key": "03.4",
        "kind": "value",
        "answer": 43,
        "mistake": "Forgets the two CRC bytes: 3 + 40.",
        "candidates": ["crc-forgotten"],
    },
    {
        "key": "03.4",
        "kind": "value",
        "answer": 8,
        "mistake": "Gives the length of the request instead of the response.",
        "candidates": [],
    },
    {
        "key": "03.4",
        "kind": "value",
        "answer": 44,
        "mistake": "Counts 4 bytes of overhead instead of 5.",
        "candidates": [],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0x0000
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
""",
        "mistake": "Starts the CRC register at 0 instead of 0xFFFF.",
        "candidates": ["crc-initial-zero"],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0x8005
            else:
                crc >>= 1
    return crc
""",
        "mistake": "XORs the unreflected polynomial 0x8005 while shifting right.",
        "candidates": ["crc-msb-first"],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data[:-1]:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
""",
        "mistake": "Loops over all bytes but the last.",
        "candidates": [],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(7):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return crc
""",
        "mistake": "Shifts seven times per byte instead of eight.",
        "candidates": [],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            if crc & 1:
                crc = (crc >> 1) ^ 0xA001
            else:
                crc >>= 1
    return ((crc & 0xFF) << 8) | (crc >> 8)
""",
        "mistake": "Swaps the two bytes of the result, returning the wire order instead of the register value.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "03.5",
        "kind": "build",
        "answer": """\
def crc16(data: bytes) -> int:
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc >>= 1
            if crc & 1:
                crc ^= 0xA001
    return crc
""",
        "mistake": "Shifts first and then tests the bit, looking at the wrong bit.",
        "candidates": [],
    },
    # ---- notebook 04 ----
    {
        "key": "04.1",
        "kind": "value",
        "answer": 130,
        "mistake": "Gives the sum of the bytes without taking its two's complement.",
        "candidates": ["lrc-plain-sum"],
    },
    {
        "key": "04.1",
        "kind": "value",
        "answer": 125,
        "mistake": "Takes the one's complement (inverts the bits) and forgets to add one.",
        "candidates": ["lrc-ones-complement"],
    },
    {
        "key": "04.1",
        "kind": "value",
        "answer": -130,
        "mistake": "Negates the sum but does not keep it to 8 bits.",
        "candidates": ["lrc-not-8-bits"],
    },
    {
        "key": "04.1",
        "kind": "value",
        "answer": 382,
        "mistake": "Keeps a ninth bit: 256 - 0x82 + 256.",
        "candidates": ["lrc-not-8-bits"],
    },
    {
        "key": "04.1",
        "kind": "value",
        "answer": 143,
        "mistake": "Leaves the slave address out of the sum.",
        "candidates": ["checksum-without-address"],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": b":050310000002E6",
        "mistake": "Leaves out the CR LF that ends an ASCII frame.",
        "candidates": ["ascii-without-crlf"],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": ":050310010002E5\r\n",
        "mistake": "Starts at address 0x1001 (4097), taking the element number after the prefix as the "
        "address without subtracting one.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": ":0503AC4000020A\r\n",
        "mistake": "Subtracts one from the whole reference number 44097 and sends 44096 (0xAC40) as the address.",
        "candidates": ["reference-number"],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": b":050310000002e6\r\n",
        "mistake": "Writes the LRC in lowercase hex.",
        "candidates": [],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": ":05034096000220\r\n",
        "mistake": "Writes the decimal address 4096 as if its digits were hex.",
        "candidates": ["decimal-written-as-hex"],
    },
    {
        "key": "04.2",
        "kind": "value",
        "answer": ":050410000002E5\r\n",
        "mistake": "Uses function 4 instead of 3 for holding registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "04.3",
        "kind": "value",
        "answer": 21,
        "mistake": "Forgets the CR LF at the end of the frame.",
        "candidates": ["ascii-without-crlf"],
    },
    {
        "key": "04.3",
        "kind": "value",
        "answer": 11,
        "mistake": "Counts the bytes instead of the characters, one character per byte.",
        "candidates": ["rtu-length-for-ascii"],
    },
    {
        "key": "04.3",
        "kind": "value",
        "answer": 22,
        "mistake": "Forgets the ':' at the start.",
        "candidates": ["ascii-colon-forgotten"],
    },
    {
        "key": "04.3",
        "kind": "value",
        "answer": 25,
        "mistake": "Counts the LRC as two bytes, like RTU's CRC.",
        "candidates": ["crc-in-ascii"],
    },
    {
        "key": "04.3",
        "kind": "value",
        "answer": 17,
        "mistake": "Counts one data byte per register instead of two.",
        "candidates": ["register-one-byte"],
    },
    {
        "key": "04.4",
        "kind": "value",
        "answer": bytes.fromhex("05 03 04 FF 06 00 64"),
        "mistake": "Includes the slave address 05 in the PDU.",
        "candidates": ["unit-in-pdu"],
    },
    {
        "key": "04.4",
        "kind": "value",
        "answer": bytes.fromhex("03 04 FF 06 00 64 8B"),
        "mistake": "Keeps the LRC byte at the end of the PDU.",
        "candidates": [],
    },
    {
        "key": "04.4",
        "kind": "value",
        "answer": bytes.fromhex("05 03 04 FF 06 00 64 8B"),
        "mistake": "Gives all the frame's bytes, address and LRC included.",
        "candidates": ["frame-for-pdu"],
    },
    {
        "key": "04.4",
        "kind": "value",
        "answer": bytes.fromhex("30 33 30 34 46 46 30 36 30 30 36 34"),
        "mistake": "Gives the hex characters as ASCII bytes instead of the bytes they stand for.",
        "candidates": [],
    },
    {
        "key": "04.4",
        "kind": "value",
        "answer": bytes.fromhex("03 FF 06 00 64"),
        "mistake": "Drops the byte count, thinking the PDU starts with the data.",
        "candidates": ["byte-count-missing"],
    },
    {
        "key": "04.5",
        "kind": "build",
        "answer": """\
def lrc(data: bytes) -> int:
    return sum(data) & 0xFF
""",
        "mistake": "Returns the 8-bit sum without its two's complement.",
        "candidates": ["lrc-plain-sum"],
    },
    {
        "key": "04.5",
        "kind": "build",
        "answer": """\
def lrc(data: bytes) -> int:
    return (~sum(data)) & 0xFF
""",
        "mistake": "Takes the one's complement and forgets to add one.",
        "candidates": ["lrc-ones-complement"],
    },
    {
        "key": "04.5",
        "kind": "build",
        "answer": """\
def lrc(data: bytes) -> int:
    return 256 - (sum(data) & 0xFF)
""",
        "mistake": "Subtracts from 256 without keeping the result to 8 bits, giving 256 when the sum ends in 00.",
        "candidates": ["lrc-not-8-bits"],
    },
    {
        "key": "04.5",
        "kind": "build",
        "answer": """\
def lrc(data: bytes) -> int:
    return -sum(data)
""",
        "mistake": "Negates the sum but does not keep it to one byte.",
        "candidates": ["lrc-not-8-bits"],
    },
    {
        "key": "04.5",
        "kind": "build",
        "answer": """\
def lrc(data: bytes) -> int:
    text = data.hex().upper()
    return (-sum(text.encode())) & 0xFF
""",
        "mistake": "Sums the ASCII characters of the hex text instead of the bytes.",
        "candidates": ["lrc-of-characters"],
    },
    # ---- notebook 05 ----
    {
        "key": "05.1",
        "kind": "value",
        "answer": 10752,
        "mistake": "Reads the two transaction id bytes low byte first, as 0x2A00.",
        "candidates": ["mbap-little-endian", "field-low-byte-first"],
    },
    {
        "key": "05.1",
        "kind": "value",
        "answer": 17,
        "mistake": "Gives the unit identifier 0x11 instead of the transaction id.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.1",
        "kind": "value",
        "answer": 6,
        "mistake": "Gives the length field instead of the transaction id.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.1",
        "kind": "value",
        "answer": 0,
        "mistake": "Takes the protocol identifier (00 00) for the transaction id.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.2",
        "kind": "value",
        "answer": bytes.fromhex("07 00 00 00 06 00 01 06 00 00 04 D2"),
        "mistake": "Writes the transaction id and the length low byte first.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "05.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 05 01 06 00 00 04 D2"),
        "mistake": "Counts only the PDU in the length field, not the unit identifier.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 06 01 06 00 00 12 34"),
        "mistake": "Writes 1234 as if it were hex 0x1234.",
        "candidates": ["decimal-written-as-hex"],
    },
    {
        "key": "05.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 06 01 06 00 00 04 D2 0B 57"),
        "mistake": "Appends a CRC as in RTU, though Modbus/TCP has none.",
        "candidates": ["crc-on-tcp"],
    },
    {
        "key": "05.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 0C 01 06 00 00 04 D2"),
        "mistake": "Puts the length of the whole frame (12) in the length field.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.3",
        "kind": "value",
        "answer": 22,
        "mistake": "Counts the PDU only, without the unit identifier.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.3",
        "kind": "value",
        "answer": 13,
        "mistake": "Counts one byte per register.",
        "candidates": ["register-one-byte"],
    },
    {
        "key": "05.3",
        "kind": "value",
        "answer": 29,
        "mistake": "Counts the whole frame, the MBAP header included.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.3",
        "kind": "value",
        "answer": 25,
        "mistake": "Counts two CRC bytes as if the response were RTU.",
        "candidates": ["crc-on-tcp"],
    },
    {
        "key": "05.3",
        "kind": "value",
        "answer": 6,
        "mistake": "Copies the length of the request, which is always 6.",
        "candidates": [],
    },
    {
        "key": "05.4",
        "kind": "value",
        "answer": "transaction identifier",
        "mistake": "Thinks 01 18 is a byte-swapped transaction id because notebook 00 drew it low byte first.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.4",
        "kind": "value",
        "answer": "protocol identifier",
        "mistake": "Blames the protocol identifier, reading 00 00 06 00 as one 4-byte field.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.4",
        "kind": "value",
        "answer": "unit identifier",
        "mistake": "Thinks 00 01 after the length is a unit identifier that should be 01 only.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.4",
        "kind": "value",
        "answer": "function code",
        "mistake": "Names a PDU field rather than an MBAP one.",
        "candidates": ["another-field"],
    },
    {
        "key": "05.5",
        "kind": "build",
        "answer": """\
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "big") + bytes(2) + len(pdu).to_bytes(2, "big") + bytes([unit])
""",
        "mistake": "Counts only the PDU in the length field, not the unit byte.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.5",
        "kind": "build",
        "answer": """\
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "little") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit])
""",
        "mistake": "Writes the transaction id low byte first.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "05.5",
        "kind": "build",
        "answer": """\
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "big") + bytes(2) + (len(pdu) + 7).to_bytes(2, "big") + bytes([unit])
""",
        "mistake": "Puts the length of the whole frame, header included, in the length field.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "05.5",
        "kind": "build",
        "answer": """\
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "big") + bytes(1) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit])
""",
        "mistake": "Writes the protocol identifier as one byte, giving a 6-byte header.",
        "candidates": ["field-in-one-byte"],
    },
    {
        "key": "05.5",
        "kind": "build",
        "answer": """\
def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "little") + bytes([unit])
""",
        "mistake": "Writes the length field low byte first.",
        "candidates": ["mbap-little-endian"],
    },
    # ---- notebook 06 ----
    {
        "key": "06.1",
        "kind": "value",
        "answer": 34.38,
        "mistake": "Leaves out both 3.5-character silences.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "06.1",
        "kind": "value",
        "answer": 31.25,
        "mistake": "Counts one byte per register in the response (5 + 10 bytes).",
        "candidates": ["register-one-byte"],
    },
    {
        "key": "06.1",
        "kind": "value",
        "answer": 45.83,
        "mistake": "Counts 11 bits per character although 8N1 has 10.",
        "candidates": [],
    },
    {
        "key": "06.1",
        "kind": "value",
        "answer": 38.02,
        "mistake": "Counts the silence after the request but not the one after the response.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "06.1",
        "kind": "value",
        "answer": 0.04167,
        "mistake": "Gives the time in seconds instead of milliseconds.",
        "candidates": ["seconds-for-milliseconds"],
    },
    {
        "key": "06.2",
        "kind": "value",
        "answer": 1,
        "mistake": "Thinks a device without coils refuses the whole function as illegal.",
        "candidates": ["illegal-function-for-address"],
    },
    {
        "key": "06.2",
        "kind": "value",
        "answer": 3,
        "mistake": "Thinks the value True is what the slave cannot accept.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "06.2",
        "kind": "value",
        "answer": 4,
        "mistake": "Expects a slave device failure when it has no coils.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "06.2",
        "kind": "value",
        "answer": 130,
        "mistake": "Gives the exception response's function byte pattern (0x80 + 2) instead of the code.",
        "candidates": ["exception-function-for-code"],
    },
    {
        "key": "06.2",
        "kind": "value",
        "answer": "timeout",
        "mistake": "Thinks a slave stays silent when it has nothing at the address.",
        "candidates": ["refusal-unanswered"],
    },
    {
        "key": "06.3",
        "kind": "value",
        "answer": 43.6,
        "mistake": "Uses 9600 baud, the notebook's example, instead of 19200.",
        "candidates": ["another-baud-rate"],
    },
    {
        "key": "06.3",
        "kind": "value",
        "answer": 79.3,
        "mistake": "Counts 11 bits per character for 8N1.",
        "candidates": [],
    },
    {
        "key": "06.3",
        "kind": "value",
        "answer": 128.0,
        "mistake": "Leaves out the two 3.5-character silences.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "06.3",
        "kind": "value",
        "answer": 88.4,
        "mistake": "Uses the fixed 1.75 ms silence, which applies only above 19200 baud.",
        "candidates": [],
    },
    {
        "key": "06.3",
        "kind": "value",
        "answer": 240.0,
        "mistake": "Divides the characters per second by the request's 8 bytes, forgetting the response and "
        "the silences.",
        "candidates": [],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": mb.CrcError,
        "mistake": "Thinks the master sees a CRC error when the request, not the response, is damaged.",
        "candidates": [],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": mb.ModbusTimeoutError("no answer"),
        "mistake": "Gives an instance of the error instead of the class itself.",
        "candidates": [],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": "ModbusTimeoutError",
        "mistake": "Gives the class's name as a string instead of the class.",
        "candidates": [],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": mb.ModbusExceptionError,
        "mistake": "Thinks the slave answers a damaged request with an exception response.",
        "candidates": ["answer-to-damaged-request"],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": mb.ModbusError,
        "mistake": "Gives the base class of every library error instead of the specific one.",
        "candidates": [],
    },
    {
        "key": "06.4",
        "kind": "value",
        "answer": mb.ChecksumError,
        "mistake": "Picks the general checksum error, thinking the master learns of the bad CRC.",
        "candidates": [],
    },
    {
        "key": "06.5",
        "kind": "build",
        "answer": """\
def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([0x83, 0x03])
        if address + count > len(registers):
            return bytes([0x83, 0x02])
        data = b"".join(v.to_bytes(2, "big") for v in registers[address:address + count])
        return bytes([3, count]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([0x86, 0x02])
        registers[address] = int.from_bytes(pdu[3:5], "big")
        return pdu
""",
        "mistake": "Puts the register count in the byte count field instead of the number of bytes.",
        "candidates": ["byte-count-for-quantity"],
    },
    {
        "key": "06.5",
        "kind": "build",
        "answer": """\
def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([0x83, 0x03])
        if address + count >= len(registers):
            return bytes([0x83, 0x02])
        data = b"".join(v.to_bytes(2, "big") for v in registers[address:address + count])
        return bytes([3, 2 * count]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([0x86, 0x02])
        registers[address] = int.from_bytes(pdu[3:5], "big")
        return pdu
""",
        "mistake": "Refuses a read that ends at the last register: off by one in the address check.",
        "candidates": [],
    },
    {
        "key": "06.5",
        "kind": "build",
        "answer": """\
def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if address + count > len(registers):
            return bytes([0x83, 0x02])
        if not 1 <= count <= 125:
            return bytes([0x83, 0x03])
        data = b"".join(v.to_bytes(2, "big") for v in registers[address:address + count])
        return bytes([3, 2 * count]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([0x86, 0x02])
        registers[address] = int.from_bytes(pdu[3:5], "big")
        return pdu
""",
        "mistake": "Checks the address before the count, so a bad count past the end gets 02 instead of 03.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "06.5",
        "kind": "build",
        "answer": """\
def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([3, 0x03])
        if address + count > len(registers):
            return bytes([3, 0x02])
        data = b"".join(v.to_bytes(2, "big") for v in registers[address:address + count])
        return bytes([3, 2 * count]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([6, 0x02])
        registers[address] = int.from_bytes(pdu[3:5], "big")
        return pdu
""",
        "mistake": "Forgets to set the top bit of the function code in an exception response.",
        "candidates": ["exception-bit-missing"],
    },
    {
        "key": "06.5",
        "kind": "build",
        "answer": """\
def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([0x83, 0x03])
        if address + count > len(registers):
            return bytes([0x83, 0x02])
        data = b"".join(v.to_bytes(2, "big") for v in registers[address:address + count])
        return bytes([3, 2 * count]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([0x86, 0x02])
        return pdu
""",
        "mistake": "Echoes a write without storing the value.",
        "candidates": ["write-not-stored"],
    },
    # ---- notebook 07 ----
    {
        "key": "07.1",
        "kind": "value",
        "answer": (131, 2),
        "mistake": "Gives the function byte as received, 0x83, without clearing the exception bit.",
        "candidates": ["exception-code-as-function"],
    },
    {
        "key": "07.1",
        "kind": "value",
        "answer": (17, 2),
        "mistake": "Takes the first byte, the slave address 0x11, for the function code.",
        "candidates": ["another-field"],
    },
    {
        "key": "07.1",
        "kind": "value",
        "answer": (2, 3),
        "mistake": "Swaps the two numbers of the pair.",
        "candidates": ["function-and-code-swapped"],
    },
    {
        "key": "07.1",
        "kind": "value",
        "answer": (83, 2),
        "mistake": "Reads 0x83 as decimal 83.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "07.1",
        "kind": "value",
        "answer": (3, 193),
        "mistake": "Takes the first CRC byte for the exception code.",
        "candidates": ["another-field"],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 81 02 54 C0"),
        "mistake": "Appends the CRC high byte first.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 01 02 A1 94"),
        "mistake": "Keeps function code 01 without setting the exception bit.",
        "candidates": ["exception-bit-missing"],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 83 02 C1 34"),
        "mistake": "Uses 0x83, the exception function code of the notebook's FC3 example, for a coil read.",
        "candidates": [],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 81 02"),
        "mistake": "Forgets the CRC.",
        "candidates": ["crc-forgotten"],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 81 01 80 55"),
        "mistake": "Answers exception 01 (illegal function) for a missing address.",
        "candidates": ["illegal-function-for-address"],
    },
    {
        "key": "07.2",
        "kind": "value",
        "answer": bytes.fromhex("11 81 02 B1 94"),
        "mistake": "Starts the CRC register at 0 instead of 0xFFFF.",
        "candidates": ["crc-initial-zero"],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "timeout",
            "one bit flipped in the request": "checksum error",
            "one bit flipped in the response": "checksum error",
            "read of an address the slave does not have": "exception",
            "response carries another unit id": "mismatch",
        },
        "mistake": "Thinks a damaged request makes the master report a checksum error, as a damaged response "
        "does.",
        "candidates": [],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "exception",
            "one bit flipped in the request": "timeout",
            "one bit flipped in the response": "checksum error",
            "read of an address the slave does not have": "exception",
            "response carries another unit id": "mismatch",
        },
        "mistake": "Thinks someone answers a request for a missing unit with an exception.",
        "candidates": ["answer-to-another-unit"],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "timeout",
            "one bit flipped in the request": "timeout",
            "one bit flipped in the response": "checksum error",
            "read of an address the slave does not have": "timeout",
            "response carries another unit id": "mismatch",
        },
        "mistake": "Thinks a slave stays silent when it lacks the address, instead of answering exception 02.",
        "candidates": ["refusal-unanswered"],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "timeout",
            "one bit flipped in the request": "timeout",
            "one bit flipped in the response": "checksum error",
            "read of an address the slave does not have": "exception",
            "response carries another unit id": "valid",
        },
        "mistake": "Accepts a response from another unit because its CRC is good.",
        "candidates": [],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "timeout",
            "one bit flipped in the request": "exception",
            "one bit flipped in the response": "exception",
            "read of an address the slave does not have": "exception",
            "response carries another unit id": "mismatch",
        },
        "mistake": "Thinks any damaged frame makes the slave send an exception.",
        "candidates": ["answer-to-damaged-request"],
    },
    {
        "key": "07.3",
        "kind": "value",
        "answer": {
            "request for a unit nobody has": "timeout",
            "one bit flipped in the request": "timeout",
            "one bit flipped in the response": "checksum error",
            "read of an address the slave does not have": "exception",
        },
        "mistake": "Leaves out the situation it is unsure of.",
        "candidates": [],
    },
    {
        "key": "07.4",
        "kind": "build",
        "answer": """\
def exception_response(function: int, code: int) -> bytes:
    return bytes([function, code])
""",
        "mistake": "Forgets to set the top bit of the function code.",
        "candidates": ["exception-bit-missing"],
    },
    {
        "key": "07.4",
        "kind": "build",
        "answer": """\
def exception_response(function: int, code: int) -> bytes:
    return bytes([function | 0x80])
""",
        "mistake": "Sends only the function code with its top bit set, without the exception code.",
        "candidates": [],
    },
    {
        "key": "07.4",
        "kind": "build",
        "answer": """\
def exception_response(function: int, code: int) -> bytes:
    return bytes([code | 0x80, function])
""",
        "mistake": "Puts the exception code first and the function second.",
        "candidates": ["function-and-code-swapped"],
    },
    {
        "key": "07.4",
        "kind": "build",
        "answer": """\
def exception_response(function: int, code: int) -> bytes:
    return bytes([function | 0x80]) + code.to_bytes(2, "big")
""",
        "mistake": "Writes the exception code as a 16-bit field.",
        "candidates": [],
    },
    {
        "key": "07.4",
        "kind": "build",
        "answer": """\
def exception_response(function: int, code: int) -> bytes:
    return bytes([0x80, function, code])
""",
        "mistake": "Sends 0x80 as its own byte in front of the function code.",
        "candidates": [],
    },
    # ---- notebook 08 ----
    {
        "key": "08.1",
        "kind": "value",
        "answer": 0.007292,
        "mistake": "Counts 10 bits per character, forgetting the parity bit.",
        "candidates": ["parity-bit-forgotten"],
    },
    {
        "key": "08.1",
        "kind": "value",
        "answer": 0.00175,
        "mistake": "Uses the fixed 1.75 ms, which applies only above 19200 baud.",
        "candidates": [],
    },
    {
        "key": "08.1",
        "kind": "value",
        "answer": 8.020833,
        "mistake": "Gives the silence in milliseconds instead of seconds.",
        "candidates": ["milliseconds-for-seconds"],
    },
    {
        "key": "08.1",
        "kind": "value",
        "answer": 0.003438,
        "mistake": "Gives t1.5, the gap that breaks a frame, instead of t3.5.",
        "candidates": ["t15-for-t35"],
    },
    {
        "key": "08.1",
        "kind": "value",
        "answer": 0.002292,
        "mistake": "Gives one character time instead of 3.5.",
        "candidates": ["one-character-for-t35"],
    },
    {
        "key": "08.2",
        "kind": "value",
        "answer": 43.6,
        "mistake": "Counts 11 bits per character for 8N1.",
        "candidates": [],
    },
    {
        "key": "08.2",
        "kind": "value",
        "answer": 64.0,
        "mistake": "Counts one byte per register in the response.",
        "candidates": ["register-one-byte"],
    },
    {
        "key": "08.2",
        "kind": "value",
        "answer": 58.2,
        "mistake": "Leaves out the two 3.5-character silences.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "08.2",
        "kind": "value",
        "answer": 48.3,
        "mistake": "Uses the fixed 1.75 ms silences, which apply only above 19200 baud.",
        "candidates": [],
    },
    {
        "key": "08.2",
        "kind": "value",
        "answer": 52.6,
        "mistake": "Counts only the silence after the request.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "08.3",
        "kind": "value",
        "answer": [5.0],
        "mistake": "Thinks only a pause longer than t3.5 breaks a request.",
        "candidates": ["t15-forgotten"],
    },
    {
        "key": "08.3",
        "kind": "value",
        "answer": [2.0, 3.0],
        "mistake": "Thinks a pause longer than t3.5 just splits the request and the slave still answers.",
        "candidates": [],
    },
    {
        "key": "08.3",
        "kind": "value",
        "answer": [1.4, 2.0, 3.0, 5.0],
        "mistake": "Rounds 1.4 up and treats it as more than t1.5.",
        "candidates": ["pause-threshold"],
    },
    {
        "key": "08.3",
        "kind": "value",
        "answer": [1.0, 1.4, 2.0, 3.0, 5.0],
        "mistake": "Thinks any pause inside a frame breaks it.",
        "candidates": ["pause-threshold"],
    },
    {
        "key": "08.3",
        "kind": "value",
        "answer": [3.0, 5.0],
        "mistake": "Takes the limit to be 2 character times instead of 1.5.",
        "candidates": ["pause-threshold"],
    },
    {
        "key": "08.4",
        "kind": "build",
        "answer": """\
def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    char = 10 / baudrate
    t35 = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * t35
""",
        "mistake": "Always counts 10 bits per character, whatever the parity and stop bits.",
        "candidates": ["parity-bit-forgotten"],
    },
    {
        "key": "08.4",
        "kind": "build",
        "answer": """\
def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    return (request_bytes + response_bytes + 2 * 3.5) * char
""",
        "mistake": "Scales t3.5 with the character time at every baud rate, ignoring the fixed 1.75 ms above "
        "19200.",
        "candidates": ["fixed-silence-ignored"],
    },
    {
        "key": "08.4",
        "kind": "build",
        "answer": """\
def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    t35 = 0.00175 if baudrate >= 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * t35
""",
        "mistake": "Uses the fixed 1.75 ms from 19200 baud on, instead of only above it.",
        "candidates": [],
    },
    {
        "key": "08.4",
        "kind": "build",
        "answer": """\
def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    char = bits / baudrate
    t35 = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + t35
""",
        "mistake": "Counts only one t3.5 silence.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "08.4",
        "kind": "build",
        "answer": """\
def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (1 if parity == "E" else 0) + stopbits
    char = bits / baudrate
    t35 = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request_bytes + response_bytes) * char + 2 * t35
""",
        "mistake": "Adds a parity bit for even parity only, forgetting odd.",
        "candidates": ["parity-bit-forgotten"],
    },
    # ---- notebook 09 ----
    {
        "key": "09.1",
        "kind": "value",
        "answer": (4, 10),
        "mistake": "Takes the element number 10 as the address, forgetting the -1.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "09.1",
        "kind": "value",
        "answer": (3, 9),
        "mistake": "Uses function 3 (holding registers) for an input register.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "09.1",
        "kind": "value",
        "answer": (4, 30009),
        "mistake": "Subtracts one but keeps the table prefix in the address.",
        "candidates": ["reference-number"],
    },
    {
        "key": "09.1",
        "kind": "value",
        "answer": (4, 30010),
        "mistake": "Puts the reference number itself in the frame.",
        "candidates": ["reference-number"],
    },
    {
        "key": "09.1",
        "kind": "value",
        "answer": (3, 10),
        "mistake": "Uses function 3 and forgets the -1.",
        "candidates": ["holding-for-input", "one-based-address"],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(40150, 25), (40200, 25)]),
        "mistake": "Stops each range one short (range(150, 175)), leaving out registers 175 and 225.",
        "candidates": ["range-one-end"],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(40151, 26), (40201, 26)]),
        "mistake": "Adds one to every reference number, as if 40150 were address 150.",
        "candidates": [],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(40149, 26), (40199, 26)]),
        "mistake": "Subtracts one from the reference numbers as if add() took addresses.",
        "candidates": ["slave-subtracts-one", "address-one-too-low"],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(30150, 26), (30200, 26)]),
        "mistake": "Declares input registers (3xxxx) instead of holding registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(40150, 1), (40175, 1), (40200, 1), (40225, 1)]),
        "mistake": "Declares only the first and last register of each range.",
        "candidates": [],
    },
    {
        "key": "09.2",
        "kind": "value",
        "answer": _board([(40150, 76)]),
        "mistake": "Declares one block from 150 to 225, filling the gap between the two ranges.",
        "candidates": ["dense-for-sparse"],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 1.65,
        "mistake": "Sets the timeout to the loop time, forgetting the 10% variation and the reply's time.",
        "candidates": ["loop-time-for-timeout"],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 1.0,
        "mistake": "Keeps the usual 1 s timeout.",
        "candidates": [],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 1.8,
        "mistake": "Allows for the loop's 10% but rounds 1.815 s down and forgets the reply.",
        "candidates": ["reply-time-forgotten"],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 3.3,
        "mistake": "Doubles the loop time to be safe, longer than allowed.",
        "candidates": ["timeout-far-too-long"],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 1650,
        "mistake": "Gives the loop time in milliseconds.",
        "candidates": ["milliseconds-for-seconds"],
    },
    {
        "key": "09.3",
        "kind": "value",
        "answer": 1.5,
        "mistake": "Takes the loop's shortest time, 10% below 1.65 s, instead of the longest.",
        "candidates": [],
    },
    {
        "key": "09.4",
        "kind": "build",
        "answer": """\
def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return min(1.0, timeout / loop_time)
""",
        "mistake": "Ignores the reply's time: timeout / loop time.",
        "candidates": ["reply-time-forgotten"],
    },
    {
        "key": "09.4",
        "kind": "build",
        "answer": """\
def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return (timeout - reply) / loop_time
""",
        "mistake": "Forgets to cap the fraction at 1 and at 0.",
        "candidates": ["fraction-unclamped"],
    },
    {
        "key": "09.4",
        "kind": "build",
        "answer": """\
def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return min(1.0, (timeout - reply) / loop_time)
""",
        "mistake": "Caps the fraction at 1 but lets it go negative when the reply is longer than the timeout.",
        "candidates": ["fraction-unclamped"],
    },
    {
        "key": "09.4",
        "kind": "build",
        "answer": """\
def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(1.0, (timeout + reply) / loop_time))
""",
        "mistake": "Adds the reply's time to the timeout instead of subtracting it.",
        "candidates": [],
    },
    {
        "key": "09.4",
        "kind": "build",
        "answer": """\
def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(1.0, (timeout - reply) / (loop_time + reply)))
""",
        "mistake": "Adds the reply's time to the loop time in the denominator.",
        "candidates": [],
    },
    # ---- notebook 10 ----
    {
        "key": "10.1",
        "kind": "value",
        "answer": 4105,
        "mistake": "Forgets to divide by 10 (the map's V x 10).",
        "candidates": ["raw-for-scaled"],
    },
    {
        "key": "10.1",
        "kind": "value",
        "answer": 41.05,
        "mistake": "Divides by 100 instead of 10.",
        "candidates": ["scale-wrong"],
    },
    {
        "key": "10.1",
        "kind": "value",
        "answer": 26902528.0,
        "mistake": "Decodes the pair low word first (CDAB).",
        "candidates": ["word-order"],
    },
    {
        "key": "10.1",
        "kind": "value",
        "answer": 100.9,
        "mistake": "Reads the hex register 0x1009 as the decimal digits 1009, then divides by 10.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "10.1",
        "kind": "value",
        "answer": 41050,
        "mistake": "Multiplies by the scale instead of dividing.",
        "candidates": ["scale-wrong"],
    },
    {
        "key": "10.2",
        "kind": "value",
        "answer": [26756, 4],
        "mistake": "Puts the low word first.",
        "candidates": ["word-order"],
    },
    {
        "key": "10.2",
        "kind": "value",
        "answer": [0, 2889],
        "mistake": "Scales the current by 10, like the voltages, instead of in milliamperes.",
        "candidates": ["current-not-in-milliamperes", "scale-wrong"],
    },
    {
        "key": "10.2",
        "kind": "value",
        "answer": [4, 6884],
        "mistake": "Writes the hex digits of the low word 0x6884 as a decimal number.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "10.2",
        "kind": "value",
        "answer": [1024, 33896],
        "mistake": "Swaps the bytes inside each register as well.",
        "candidates": ["word-order"],
    },
    {
        "key": "10.2",
        "kind": "value",
        "answer": [4, 26760],
        "mistake": "Splits the value by 65535 instead of 65536.",
        "candidates": [],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (3, 54, 3),
        "mistake": "Counts one register per value instead of two.",
        "candidates": ["one-register-for-32-bits"],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (3, 55, 6),
        "mistake": "Adds one to the address, as for a reference number.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (4, 54, 6),
        "mistake": "Uses function 4 (input registers) for the meter's holding registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (3, 36, 6),
        "mistake": "Reads the map's hex address 36 as decimal.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (3, 54, 5),
        "mistake": "Counts from the first register of THD_AL1 to the first register of THD_AL3, both included.",
        "candidates": ["range-one-end"],
    },
    {
        "key": "10.3",
        "kind": "value",
        "answer": (3, "40055", 6),
        "mistake": "Puts the reference number 40055 in the request instead of the address.",
        "candidates": ["reference-number"],
    },
    {
        "key": "10.4",
        "kind": "build",
        "answer": """\
import struct

def decode_float32(registers: list, order: str) -> float:
    a, b = registers
    raw = a.to_bytes(2, "big") + b.to_bytes(2, "big")
    if order == "CDAB":
        raw = raw[::-1]
    elif order == "BADC":
        raw = bytes([raw[1], raw[0], raw[3], raw[2]])
    elif order == "DCBA":
        raw = raw[2:] + raw[:2]
    return struct.unpack(">f", raw)[0]
""",
        "mistake": "Reverses all four bytes for CDAB and only swaps the words for DCBA.",
        "candidates": ["word-order"],
    },
    {
        "key": "10.4",
        "kind": "build",
        "answer": """\
import struct

def decode_float32(registers: list, order: str) -> float:
    a, b = registers
    raw = a.to_bytes(2, "big") + b.to_bytes(2, "big")
    if order == "CDAB":
        raw = raw[2:] + raw[:2]
    elif order == "BADC":
        raw = raw[::-1]
    elif order == "DCBA":
        raw = bytes([raw[1], raw[0], raw[3], raw[2]])
    return struct.unpack(">f", raw)[0]
""",
        "mistake": "Mixes up BADC and DCBA: reverses all four bytes for BADC and swaps within each register "
        "for DCBA.",
        "candidates": ["word-order"],
    },
    {
        "key": "10.4",
        "kind": "build",
        "answer": """\
import struct

def decode_float32(registers: list, order: str) -> float:
    a, b = registers
    raw = a.to_bytes(2, "big") + b.to_bytes(2, "big")
    if order == "CDAB":
        raw = raw[2:] + raw[:2]
    elif order == "BADC":
        raw = bytes([raw[1], raw[0], raw[3], raw[2]])
    elif order == "DCBA":
        raw = raw[::-1]
    return struct.unpack("<f", raw)[0]
""",
        "mistake": "Unpacks the four bytes little-endian ('<f') after putting them in order.",
        "candidates": ["word-order"],
    },
    {
        "key": "10.4",
        "kind": "build",
        "answer": """\
import struct

def decode_float32(registers: list, order: str) -> float:
    a, b = registers
    raw = a.to_bytes(2, "big") + b.to_bytes(2, "big")
    if order == "ABCD":
        raw = raw[2:] + raw[:2]
    elif order == "BADC":
        raw = bytes([raw[1], raw[0], raw[3], raw[2]])
    elif order == "DCBA":
        raw = raw[::-1]
    return struct.unpack(">f", raw)[0]
""",
        "mistake": "Swaps the words for ABCD instead of for CDAB.",
        "candidates": ["word-order"],
    },
    # ---- notebook 11 ----
    {
        "key": "11.1",
        "kind": "value",
        "answer": (10752, 6, 4096, 62465),
        "mistake": "Reads every 16-bit field low byte first.",
        "candidates": ["field-low-byte-first", "mbap-little-endian"],
    },
    {
        "key": "11.1",
        "kind": "value",
        "answer": (42, 6, 10, 500),
        "mistake": "Reads the address bytes 00 10 as decimal 10.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "11.1",
        "kind": "value",
        "answer": (42, 6, 17, 500),
        "mistake": "Adds one to the address, as for a reference number.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "11.1",
        "kind": "value",
        "answer": (17, 6, 16, 500),
        "mistake": "Gives the unit identifier instead of the transaction id.",
        "candidates": ["another-field"],
    },
    {
        "key": "11.1",
        "kind": "value",
        "answer": (42, 17, 6, 16),
        "mistake": "Reads the frame one field late, starting at the unit identifier.",
        "candidates": ["another-field"],
    },
    {
        "key": "11.1",
        "kind": "value",
        "answer": (42, 6, 16, 1),
        "mistake": "Takes only the high byte 01 of the value.",
        "candidates": ["field-in-one-byte"],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 08 03 03 00 00 00 03 04 29"),
        "mistake": "Keeps the RTU CRC behind the PDU and counts it in the length.",
        "candidates": ["crc-on-tcp", "mbap-length"],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 06 03 03 00 00 00 03 04 29"),
        "mistake": "Keeps the RTU CRC behind the PDU.",
        "candidates": ["crc-on-tcp"],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 05 03 03 00 00 00 03"),
        "mistake": "Counts only the PDU in the length field, not the unit.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("07 00 00 00 06 00 03 03 00 00 00 03"),
        "mistake": "Writes the transaction id and the length low byte first.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 06 01 03 00 00 00 03"),
        "mistake": "Sets the unit identifier to 1 instead of keeping the RTU address 3.",
        "candidates": [],
    },
    {
        "key": "11.2",
        "kind": "value",
        "answer": bytes.fromhex("00 07 00 00 00 05 03 00 00 00 03"),
        "mistake": "Drops the unit byte, thinking the IP address replaces it.",
        "candidates": ["unit-missing"],
    },
    {
        "key": "11.3",
        "kind": "value",
        "answer": "tcp://192.168.1.60:4001",
        "mistake": "Writes tcp:// as the scheme instead of pyserial's socket://.",
        "candidates": ["url-not-socket"],
    },
    {
        "key": "11.3",
        "kind": "value",
        "answer": "192.168.1.60:4001",
        "mistake": "Leaves out the URL scheme.",
        "candidates": ["url-not-socket"],
    },
    {
        "key": "11.3",
        "kind": "value",
        "answer": "socket://192.168.1.60:502",
        "mistake": "Uses the Modbus/TCP port 502 instead of the device server's port 4001.",
        "candidates": ["modbus-tcp-port-for-server"],
    },
    {
        "key": "11.3",
        "kind": "value",
        "answer": "socket://192.168.1.60",
        "mistake": "Leaves out the port.",
        "candidates": ["url-without-port"],
    },
    {
        "key": "11.3",
        "kind": "value",
        "answer": "rfc2217://192.168.1.60:4001",
        "mistake": "Uses the RFC 2217 scheme for a raw TCP port.",
        "candidates": ["url-not-socket"],
    },
    {
        "key": "11.4",
        "kind": "build",
        "answer": """\
def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    return (tid, protocol, length, frame[6], frame[7:])
""",
        "mistake": "Never checks the length field against the frame.",
        "candidates": ["invalid-input-accepted"],
    },
    {
        "key": "11.4",
        "kind": "build",
        "answer": """\
def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    pdu = frame[7:]
    if length != len(pdu):
        raise ValueError("the length field does not match the frame")
    return (tid, protocol, length, frame[6], pdu)
""",
        "mistake": "Compares the length field with the PDU alone, forgetting that it counts the unit byte.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "11.4",
        "kind": "build",
        "answer": """\
def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "little")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if length != len(frame) - 6:
        raise ValueError("the length field does not match the frame")
    return (tid, protocol, length, frame[6], frame[7:])
""",
        "mistake": "Reads the transaction id low byte first.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "11.4",
        "kind": "build",
        "answer": """\
def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if length != len(frame) - 6:
        raise ValueError("the length field does not match the frame")
    return (tid, protocol, length, frame[6], frame[6:])
""",
        "mistake": "Cuts the PDU one byte early, so it starts with the unit.",
        "candidates": ["unit-in-pdu"],
    },
    # ---- notebook 12 ----
    {
        "key": "12.1",
        "kind": "value",
        "answer": "0x0150",
        "mistake": "Writes the decimal value 150 with a 0x in front, without converting it.",
        "candidates": ["decimal-written-as-hex"],
    },
    {
        "key": "12.1",
        "kind": "value",
        "answer": "0x008C",
        "mistake": "Counts addresses from 1 and takes the fifth value, 140.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "12.1",
        "kind": "value",
        "answer": "0x00A0",
        "mistake": "Starts the increments at address 0 with 110, giving 160 at address 5.",
        "candidates": [],
    },
    {
        "key": "12.1",
        "kind": "value",
        "answer": "150",
        "mistake": "Gives the decimal value, not the hex display.",
        "candidates": [],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_master",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 1.0,
            "unit": 7,
            "address": 10,
            "length": 4,
            "function": 3,
            "transaction_id": 1,
            "interval": 0.5,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Leaves the function at 3, reading holding registers instead of input registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_master",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 1.0,
            "unit": 7,
            "address": 9,
            "length": 4,
            "function": 4,
            "transaction_id": 1,
            "interval": 0.5,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Subtracts one from the address as if 10 were a reference number.",
        "candidates": ["address-one-too-low"],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_master",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 1.0,
            "unit": 7,
            "address": 10,
            "length": 4,
            "function": 4,
            "transaction_id": 1,
            "interval": 500,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Gives the poll interval in milliseconds.",
        "candidates": ["milliseconds-for-seconds"],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_slave",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 1.0,
            "unit": 7,
            "address": 10,
            "length": 4,
            "function": 4,
            "transaction_id": 1,
            "interval": 0.5,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Makes the tool a slave, the side that answers, to test a device.",
        "candidates": ["slave-for-master"],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_master",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 1.0,
            "unit": 1,
            "address": 10,
            "length": 4,
            "function": 4,
            "transaction_id": 1,
            "interval": 0.5,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Leaves the unit at the default 1.",
        "candidates": [],
    },
    {
        "key": "12.2",
        "kind": "value",
        "answer": {
            "role": "rtu_master",
            "name": "",
            "connection": "loopback",
            "url": "loop://",
            "baudrate": 9600,
            "parity": "N",
            "stopbits": 1,
            "host": "127.0.0.1",
            "port": 5020,
            "timeout": 0.5,
            "unit": 7,
            "address": 10,
            "length": 4,
            "function": 4,
            "transaction_id": 1,
            "interval": 1.0,
            "continuous": True,
            "display": "unsigned",
            "fill_start": 0,
            "fill_increment": True,
            "fill_step": 1,
            "auto_interval": 1.0,
            "newest_on_top": True,
            "seed": 0,
        },
        "mistake": "Puts the 0.5 s into the timeout instead of the poll interval.",
        "candidates": [],
    },
    {
        "key": "12.3",
        "kind": "value",
        "answer": (282, "01 1A"),
        "mistake": "Gives the id of the third poll instead of the next request.",
        "candidates": ["last-transaction-id"],
    },
    {
        "key": "12.3",
        "kind": "value",
        "answer": (283, "1B 01"),
        "mistake": "Writes the transaction id low byte first, like the published test tool.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "12.3",
        "kind": "value",
        "answer": (281, "01 19"),
        "mistake": "Thinks the first of the three polls already used 281.",
        "candidates": [],
    },
    {
        "key": "12.3",
        "kind": "value",
        "answer": (283, "00 00"),
        "mistake": "Gives the protocol identifier's bytes instead of the transaction id's.",
        "candidates": ["another-field"],
    },
    {
        "key": "12.3",
        "kind": "value",
        "answer": (283, "01 83"),
        "mistake": "Writes the decimal digits of 283 into the low byte.",
        "candidates": ["decimal-written-as-hex"],
    },
    {
        "key": "12.4",
        "kind": "build",
        "answer": """\
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    pdu = bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    return tid.to_bytes(2, "little") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Writes the transaction id low byte first, as the published test tool does.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "12.4",
        "kind": "build",
        "answer": """\
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    pdu = bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    return tid.to_bytes(2, "big") + bytes(2) + len(pdu).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Counts only the PDU in the length field.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "12.4",
        "kind": "build",
        "answer": """\
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    pdu = bytes([4]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    return tid.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Uses function 4 (input registers) instead of 3.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "12.4",
        "kind": "build",
        "answer": """\
def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    pdu = bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    return tid.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + pdu
""",
        "mistake": "Leaves out the unit byte but still counts it in the length.",
        "candidates": ["unit-missing"],
    },
    # ---- notebook 13 ----
    {
        "key": "13.1",
        "kind": "value",
        "answer": {"A": "wrong baud rate or parity", "B": "no slave on the line", "C": "wrong unit id"},
        "mistake": "Swaps A and C: takes the slave whose log shows the right bytes for the misconfigured one.",
        "candidates": [],
    },
    {
        "key": "13.1",
        "kind": "value",
        "answer": {"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"},
        "mistake": "Thinks a wire whose slave ignored every frame has no slave, and that B's silence is a "
        "unit mismatch.",
        "candidates": [],
    },
    {
        "key": "13.1",
        "kind": "value",
        "answer": {"A": "wrong unit id", "B": "wrong baud rate or parity", "C": "no slave on the line"},
        "mistake": "Reads C's checksum errors as noise on an empty line and blames B's settings.",
        "candidates": [],
    },
    {
        "key": "13.1",
        "kind": "value",
        "answer": {"A": "wrong unit id", "B": "no slave on the line", "C": "wrong unit id"},
        "mistake": "Sees frames C's slave did not answer and calls it a wrong unit id too.",
        "candidates": [],
    },
    {
        "key": "13.1",
        "kind": "value",
        "answer": {"A": "wrong unit id", "C": "wrong baud rate or parity"},
        "mistake": "Leaves out the wire with nothing on it.",
        "candidates": [],
    },
    {
        "key": "13.2",
        "kind": "value",
        "answer": ("ABCD", 292880.386),
        "mistake": "Keeps the colleague's high-word-first decoding.",
        "candidates": ["word-order"],
    },
    {
        "key": "13.2",
        "kind": "value",
        "answer": ("CDAB", 135541),
        "mistake": "Decodes low word first but forgets to turn milliamperes into amperes.",
        "candidates": ["milliamperes-for-amperes"],
    },
    {
        "key": "13.2",
        "kind": "value",
        "answer": ("CDAB", 0.135541),
        "mistake": "Divides by 1000 twice.",
        "candidates": ["scale-wrong"],
    },
    {
        "key": "13.2",
        "kind": "value",
        "answer": ("DCBA", 33584.401),
        "mistake": "Swaps the bytes inside the registers as well as the words.",
        "candidates": ["word-order"],
    },
    {
        "key": "13.2",
        "kind": "value",
        "answer": ("BADC", 1964048.896),
        "mistake": "Swaps the bytes inside each register instead of the two words.",
        "candidates": ["word-order"],
    },
    {
        "key": "13.3",
        "kind": "value",
        "answer": 21,
        "mistake": "Drops the prefix but keeps the element number as the address.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "13.3",
        "kind": "value",
        "answer": 40020,
        "mistake": "Subtracts one but keeps the prefix.",
        "candidates": ["reference-number"],
    },
    {
        "key": "13.3",
        "kind": "value",
        "answer": 22,
        "mistake": "Thinks the script read the register before, and moves the other way.",
        "candidates": [],
    },
    {
        "key": "13.3",
        "kind": "value",
        "answer": 19,
        "mistake": "Subtracts one from the wrong address 21 and then one more.",
        "candidates": ["address-one-too-low"],
    },
    {
        "key": "13.3",
        "kind": "value",
        "answer": 40021,
        "mistake": "Puts the reference number in the request.",
        "candidates": ["reference-number"],
    },
    {
        "key": "13.4",
        "kind": "value",
        "answer": (3, "00 03"),
        "mistake": "Gives the id the client meant, not the one a server reads from 03 00.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "13.4",
        "kind": "value",
        "answer": (768, "03 00"),
        "mistake": "Reads the id right but copies the same low-byte-first bytes as the fix.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "13.4",
        "kind": "value",
        "answer": (3, "03 00"),
        "mistake": "Trusts the client's own numbering and its byte order.",
        "candidates": ["mbap-little-endian"],
    },
    {
        "key": "13.4",
        "kind": "value",
        "answer": (300, "00 03"),
        "mistake": "Reads the hex bytes 03 00 as the decimal number 300.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "13.4",
        "kind": "value",
        "answer": (768, "00 3"),
        "mistake": "Writes the low byte with one hex digit.",
        "candidates": [],
    },
    {
        "key": "13.5",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 00 01 0A 84"),
        "mistake": "Finds nothing wrong and sends the frame unchanged.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "13.5",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 00 01"),
        "mistake": "Drops the CRC, thinking the slave computes it.",
        "candidates": ["crc-forgotten"],
    },
    {
        "key": "13.5",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 00 01 84 11"),
        "mistake": "Recomputes the CRC with the register started at 0.",
        "candidates": ["crc-initial-zero"],
    },
    {
        "key": "13.5",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 00 01 A1 C0"),
        "mistake": "Recomputes the CRC over the PDU only, without the slave address.",
        "candidates": ["checksum-without-address"],
    },
    {
        "key": "13.5",
        "kind": "value",
        "answer": bytes.fromhex("01 03 00 00 01 00 84 0A"),
        "mistake": "Swaps the bytes of the count field as well as the CRC.",
        "candidates": ["field-low-byte-first"],
    },
    {
        "key": "13.6",
        "kind": "value",
        "answer": 0.44,
        "mistake": "Gives the fraction answered instead of the loop time.",
        "candidates": [],
    },
    {
        "key": "13.6",
        "kind": "value",
        "answer": 2243,
        "mistake": "Gives the loop time in milliseconds.",
        "candidates": ["milliseconds-for-seconds"],
    },
    {
        "key": "13.6",
        "kind": "value",
        "answer": 0.56,
        "mistake": "Gives the fraction of timeouts.",
        "candidates": [],
    },
    {
        "key": "13.6",
        "kind": "value",
        "answer": 1.0,
        "mistake": "Takes the loop time to be the master's timeout.",
        "candidates": ["given-figure"],
    },
    {
        "key": "13.6",
        "kind": "value",
        "answer": 0.79,
        "mistake": "Divides the answered polls by the timed-out ones.",
        "candidates": [],
    },
    {
        "key": "13.7",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def find_order(registers: list, expected: float):
    for order in ("ABCD", "CDAB"):
        if abs(mb.decode_value(registers, "float32", order) - expected) <= 0.01 * abs(expected) + 1e-6:
            return order
    return None
""",
        "mistake": "Tries only the two word orders and never the byte-swapped ones.",
        "candidates": [],
    },
    {
        "key": "13.7",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "uint32", order) - expected) <= 0.01 * abs(expected) + 1e-6:
            return order
    return None
""",
        "mistake": "Decodes the registers as an unsigned integer instead of a float32.",
        "candidates": ["integer-for-float"],
    },
    {
        "key": "13.7",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if abs(mb.decode_value(registers, "float32", order) - expected) <= 0.01 * abs(expected) + 1e-6:
            return order
    return "ABCD"
""",
        "mistake": "Returns ABCD as a default when no order fits, instead of None.",
        "candidates": ["an-order-when-none-fits"],
    },
    {
        "key": "13.7",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if mb.decode_value(registers, "float32", order) == expected:
            return order
    return None
""",
        "mistake": "Compares the decoded float32 with the displayed value by exact equality, so 403.6000061 "
        "never equals 403.6.",
        "candidates": ["float-compared-exactly"],
    },
    # ---- notebook 14 ----
    {
        "key": "14.1",
        "kind": "value",
        "answer": 32,
        "mistake": "Uses the OR mask as a second AND mask.",
        "candidates": [],
    },
    {
        "key": "14.1",
        "kind": "value",
        "answer": 5,
        "mistake": "Applies the AND mask and forgets the OR mask.",
        "candidates": ["or-mask-forgotten"],
    },
    {
        "key": "14.1",
        "kind": "value",
        "answer": 437,
        "mistake": "Applies the OR mask and forgets the AND mask.",
        "candidates": ["mask-write-or"],
    },
    {
        "key": "14.1",
        "kind": "value",
        "answer": 160,
        "mistake": "Reads the AND mask backwards: a 1 marks a bit to replace.",
        "candidates": ["mask-roles-swapped"],
    },
    {
        "key": "14.1",
        "kind": "value",
        "answer": 319,
        "mistake": "Combines the two masks and ignores the register's value.",
        "candidates": [],
    },
    {
        "key": "14.1",
        "kind": "value",
        "answer": 135,
        "mistake": "Writes the hex result 0x135 as decimal 135.",
        "candidates": ["hex-read-as-decimal"],
    },
    {
        "key": "14.2",
        "kind": "build",
        "answer": """\
def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & and_mask) | or_mask
""",
        "mistake": "ORs the whole OR mask in, without masking it with NOT and_mask.",
        "candidates": ["mask-write-or"],
    },
    {
        "key": "14.2",
        "kind": "build",
        "answer": """\
def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current | or_mask) & and_mask
""",
        "mistake": "Applies the OR mask first and the AND mask last.",
        "candidates": [],
    },
    {
        "key": "14.2",
        "kind": "build",
        "answer": """\
def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & ~and_mask & 0xFFFF) | (or_mask & and_mask)
""",
        "mistake": "Reads the AND mask backwards: a 1 marks a bit to replace.",
        "candidates": ["mask-roles-swapped"],
    },
    {
        "key": "14.2",
        "kind": "build",
        "answer": """\
def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & and_mask) | (or_mask & ~current & 0xFFFF)
""",
        "mistake": "Masks the OR mask with NOT current instead of NOT and_mask.",
        "candidates": [],
    },
    {
        "key": "14.3",
        "kind": "value",
        "answer": 4,
        "mistake": "Forgets that the 0x0B request being answered counts too.",
        "candidates": ["count-request-forgotten"],
    },
    {
        "key": "14.3",
        "kind": "value",
        "answer": 3,
        "mistake": "Counts only the requests addressed to unit 1.",
        "candidates": ["others-not-heard"],
    },
    {
        "key": "14.3",
        "kind": "value",
        "answer": 6,
        "mistake": "Counts the request whose bit was flipped, though its CRC is bad.",
        "candidates": ["damaged-message-counted"],
    },
    {
        "key": "14.3",
        "kind": "value",
        "answer": 7,
        "mistake": "Counts unit 1's own two responses as messages it heard.",
        "candidates": ["own-frames-counted"],
    },
    {
        "key": "14.3",
        "kind": "value",
        "answer": 2,
        "mistake": "Counts only unit 1's two good reads.",
        "candidates": ["others-not-heard", "count-request-forgotten"],
    },
    # ---- notebook 15 ----
    {
        "key": "15.1",
        "kind": "value",
        "answer": 12.5,
        "mistake": "Counts 10 bits per character, forgetting the parity bit.",
        "candidates": ["parity-bit-forgotten"],
    },
    {
        "key": "15.1",
        "kind": "value",
        "answer": 13.24,
        "mistake": "Uses the fixed 1.75 ms silences, which apply only above 19200 baud.",
        "candidates": [],
    },
    {
        "key": "15.1",
        "kind": "value",
        "answer": 12.6,
        "mistake": "Takes the one-register response of 7 bytes instead of 9.",
        "candidates": ["one-register-response"],
    },
    {
        "key": "15.1",
        "kind": "value",
        "answer": 11.74,
        "mistake": "Stops at the end of the response, leaving out the final silence.",
        "candidates": ["silences-forgotten"],
    },
    {
        "key": "15.1",
        "kind": "value",
        "answer": 0.01375,
        "mistake": "Gives seconds instead of milliseconds.",
        "candidates": ["seconds-for-milliseconds"],
    },
    {
        "key": "15.2",
        "kind": "build",
        "answer": """\
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    unit, pdu = frame[0], frame[1:-2]
    return transaction_id.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Drops the CRC without checking it, forwarding damaged frames.",
        "candidates": ["invalid-input-accepted"],
    },
    {
        "key": "15.2",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    if mb.crc16(frame[:-2]) != int.from_bytes(frame[-2:], "big"):
        raise ValueError("bad CRC")
    unit, pdu = frame[0], frame[1:-2]
    return transaction_id.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Reads the CRC on the wire high byte first, so it refuses good frames.",
        "candidates": ["crc-swapped"],
    },
    {
        "key": "15.2",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    if mb.crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("bad CRC")
    unit, pdu = frame[0], frame[1:]
    return transaction_id.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Checks the CRC but keeps it behind the PDU.",
        "candidates": ["crc-on-tcp"],
    },
    {
        "key": "15.2",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    if mb.crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("bad CRC")
    unit, pdu = frame[0], frame[1:-2]
    return transaction_id.to_bytes(2, "big") + bytes(2) + len(pdu).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Counts only the PDU in the length field.",
        "candidates": ["mbap-length"],
    },
    {
        "key": "15.2",
        "kind": "build",
        "answer": """\
import modbus_edu as mb

def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    if mb.crc16(frame[1:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ValueError("bad CRC")
    unit, pdu = frame[0], frame[1:-2]
    return transaction_id.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu
""",
        "mistake": "Computes the CRC over the PDU without the unit byte, so it refuses good frames.",
        "candidates": ["checksum-without-address"],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": 11, "b": 11, "c": 1, "d": "timeout"},
        "mistake": "Thinks the gateway asks the bus for unit 248 and waits, answering 0B.",
        "candidates": ["gateway-codes-swapped"],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": 10, "b": "timeout", "c": 1, "d": "timeout"},
        "mistake": "Thinks a client behind a gateway times out when the device is disconnected.",
        "candidates": ["gateway-silence"],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": 10, "b": 10, "c": 1, "d": "timeout"},
        "mistake": "Takes a cable that came off for a path that is unavailable (0A).",
        "candidates": ["gateway-codes-swapped"],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": 10, "b": 11, "c": "timeout", "d": "timeout"},
        "mistake": "Thinks a device stays silent for a function it does not implement.",
        "candidates": ["refusal-unanswered"],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": 10, "b": 11, "c": 1, "d": 11},
        "mistake": "Forgets that the client gives up at 0.1 s, before the gateway's 0B comes.",
        "candidates": [],
    },
    {
        "key": "15.3",
        "kind": "value",
        "answer": {"a": "timeout", "b": 11, "c": 1, "d": "timeout"},
        "mistake": "Thinks nobody answers a reserved unit id, so the client times out.",
        "candidates": ["gateway-silence"],
    },
    # ---- notebook 16 ----
    {
        "key": "16.1",
        "kind": "value",
        "answer": "name,table,address,type,order,scale,unit\nvoltage,input,30001,float32,ABCD,1,V\ncurrent,input,30007,float32,ABCD,1,A\nactive_power,input,30013,float32,ABCD,1,W\nfrequency,input,30071,float32,ABCD,1,Hz\nimport_energy,input,30073,float32,ABCD,1,kWh\n",
        "mistake": "Writes ABCD, the common order, though the datasheet says low word first.",
        "candidates": ["word-order"],
    },
    {
        "key": "16.1",
        "kind": "value",
        "answer": "name,table,address,type,order,scale,unit\nvoltage,holding,30001,float32,CDAB,1,V\ncurrent,holding,30007,float32,CDAB,1,A\nactive_power,holding,30013,float32,CDAB,1,W\nfrequency,holding,30071,float32,CDAB,1,Hz\nimport_energy,holding,30073,float32,CDAB,1,kWh\n",
        "mistake": "Marks the values as holding registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "16.1",
        "kind": "value",
        "answer": "name,table,address,type,order,scale,unit\nvoltage,input,0,float32,CDAB,1,V\ncurrent,input,6,float32,CDAB,1,A\nactive_power,input,12,float32,CDAB,1,W\nfrequency,input,70,float32,CDAB,1,Hz\nimport_energy,input,72,float32,CDAB,1,kWh\n",
        "mistake": "Converts the numbers to addresses in the file that should keep the datasheet's numbers.",
        "candidates": ["zero-based-number"],
    },
    {
        "key": "16.1",
        "kind": "value",
        "answer": "name,table,address,type,order,scale,unit\nvoltage,input,30001,uint32,CDAB,1,V\ncurrent,input,30007,uint32,CDAB,1,A\nactive_power,input,30013,uint32,CDAB,1,W\nfrequency,input,30071,uint32,CDAB,1,Hz\nimport_energy,input,30073,uint32,CDAB,1,kWh\n",
        "mistake": "Writes the 32-bit values as integers instead of floats.",
        "candidates": ["integer-for-float"],
    },
    {
        "key": "16.1",
        "kind": "value",
        "answer": "name,table,address,type,order,scale,unit\nVoltage,input,30001,float32,CDAB,1,V\nCurrent,input,30007,float32,CDAB,1,A\nActive power,input,30013,float32,CDAB,1,W\nFrequency,input,30071,float32,CDAB,1,Hz\nImport active energy,input,30073,float32,CDAB,1,kWh\n",
        "mistake": "Copies the datasheet's parameter names, spaces included, as the names.",
        "candidates": [],
    },
    {
        "key": "16.1",
        "kind": "value",
        "answer": "voltage,input,30001,float32,CDAB,1,V\ncurrent,input,30007,float32,CDAB,1,A\nactive_power,input,30013,float32,CDAB,1,W\nfrequency,input,30071,float32,CDAB,1,Hz\nimport_energy,input,30073,float32,CDAB,1,kWh\n",
        "mistake": "Leaves out the header row.",
        "candidates": [],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [
            bytes.fromhex("01 03 00 00 00 02 C4 0B"),
            bytes.fromhex("01 03 00 06 00 02 24 0A"),
            bytes.fromhex("01 03 00 0C 00 02 04 08"),
            bytes.fromhex("01 03 00 46 00 04 A5 DC"),
        ],
        "mistake": "Uses function 3 for input registers.",
        "candidates": ["holding-for-input"],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [
            bytes.fromhex("01 04 00 00 00 02 71 CB"),
            bytes.fromhex("01 04 00 06 00 02 91 CA"),
            bytes.fromhex("01 04 00 0C 00 02 B1 C8"),
            bytes.fromhex("01 04 00 46 00 02 90 1E"),
            bytes.fromhex("01 04 00 48 00 02 F1 DD"),
        ],
        "mistake": "Sends one request per value instead of joining the two neighbours at 70 and 72.",
        "candidates": ["request-per-register"],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [
            bytes.fromhex("01 04 00 01 00 02 20 0B"),
            bytes.fromhex("01 04 00 07 00 02 C0 0A"),
            bytes.fromhex("01 04 00 0D 00 02 E0 08"),
            bytes.fromhex("01 04 00 47 00 04 41 DC"),
        ],
        "mistake": "Takes the element numbers after the prefix as the addresses.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [bytes.fromhex("01 04 00 00 00 4A 71 FD")],
        "mistake": "Reads everything from 0 to 73 in one request, across the registers the meter does not list.",
        "candidates": ["dense-for-sparse"],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [
            bytes.fromhex("01 04 00 00 00 01 31 CA"),
            bytes.fromhex("01 04 00 06 00 01 D1 CB"),
            bytes.fromhex("01 04 00 0C 00 01 F1 C9"),
            bytes.fromhex("01 04 00 46 00 02 90 1E"),
        ],
        "mistake": "Reads one register per value, forgetting that a float32 takes two.",
        "candidates": ["one-register-for-32-bits"],
    },
    {
        "key": "16.2",
        "kind": "value",
        "answer": [
            bytes.fromhex("04 00 00 00 02"),
            bytes.fromhex("04 00 06 00 02"),
            bytes.fromhex("04 00 0C 00 02"),
            bytes.fromhex("04 00 46 00 04"),
        ],
        "mistake": "Gives the PDUs instead of the RTU frames.",
        "candidates": [],
    },
    {
        "key": "16.3",
        "kind": "value",
        "answer": "check the baud rate and parity",
        "mistake": "Goes back to the settings, which the scan already covered.",
        "candidates": ["check-ruled-out"],
    },
    {
        "key": "16.3",
        "kind": "value",
        "answer": "the unit address",
        "mistake": "Checks the unit, which the scan of 1 to 247 already covered.",
        "candidates": ["check-ruled-out"],
    },
    {
        "key": "16.3",
        "kind": "value",
        "answer": "termination resistors",
        "mistake": "Jumps to termination, a cure for CRC errors, not for silence.",
        "candidates": ["termination-for-silence"],
    },
    {
        "key": "16.3",
        "kind": "value",
        "answer": "a longer timeout",
        "mistake": "Tries a longer timeout before the cheap check of the wiring's polarity.",
        "candidates": [],
    },
    {
        "key": "16.3",
        "kind": "value",
        "answer": "the port and permissions",
        "mistake": "Checks the port, though the TX LED shows the requests leave.",
        "candidates": ["check-ruled-out"],
    },
    {
        "key": "16.4",
        "kind": "build",
        "answer": """\
def strip_echo(sent: bytes, received: bytes) -> bytes:
    return received[len(sent):]
""",
        "mistake": "Cuts off as many bytes as were sent without checking that they are the echo.",
        "candidates": ["echo-unchecked"],
    },
    {
        "key": "16.4",
        "kind": "build",
        "answer": """\
def strip_echo(sent: bytes, received: bytes) -> bytes:
    if received[:1] != sent[:1]:
        raise ValueError("no echo")
    return received[len(sent):]
""",
        "mistake": "Checks only the first byte of the echo.",
        "candidates": ["echo-unchecked"],
    },
    {
        "key": "16.4",
        "kind": "build",
        "answer": """\
def strip_echo(sent: bytes, received: bytes) -> bytes:
    if sent not in received:
        raise ValueError("no echo")
    return received.replace(sent, b"", 1)
""",
        "mistake": "Looks for the request anywhere in what came back instead of at its start.",
        "candidates": [],
    },
    {
        "key": "16.4",
        "kind": "build",
        "answer": """\
def strip_echo(sent: bytes, received: bytes) -> bytes:
    if not received.startswith(sent):
        raise ValueError("no echo")
    return received[len(sent) + 1:]
""",
        "mistake": "Cuts one byte too many after the echo.",
        "candidates": [],
    },
    {
        "key": "16.4",
        "kind": "build",
        "answer": """\
def strip_echo(sent: bytes, received: bytes) -> bytes:
    if received[:len(sent)] != sent[:len(received)]:
        raise ValueError("no echo")
    return received[len(sent):]
""",
        "mistake": "Accepts a received run shorter than the request when what there is matches.",
        "candidates": [],
    },
    # ---- notebook 17 ----
    {
        "key": "17.0",
        "kind": "value",
        "answer": "caddbdcbccba",
        "mistake": "Copies the right answers in notebook 00's order, though notebook 17 asks them in another "
        "order.",
        "candidates": [],
    },
    {
        "key": "17.0",
        "kind": "value",
        "answer": "acbdcaabdcdb",
        "mistake": "Takes the MBAP length to count the PDU only (5).",
        "candidates": ["mbap-length"],
    },
    {
        "key": "17.0",
        "kind": "value",
        "answer": "ccadcbabdcdb",
        "mistake": "Thinks the CRC goes high byte first and the transaction id low byte first.",
        "candidates": ["crc-swapped", "mbap-little-endian"],
    },
    {
        "key": "17.0",
        "kind": "value",
        "answer": "ccbdcaabccab",
        "mistake": "Takes reference numbers as addresses: 40001 is address 1 and register 10 is address 10.",
        "candidates": ["one-based-address"],
    },
    {
        "key": "17.0",
        "kind": "value",
        "answer": "ccbddaabdcda",
        "mistake": "Mixes up t1.5 and t3.5, and thinks a 2-character pause is harmless.",
        "candidates": ["t15-for-t35", "pause-threshold"],
    },
    {
        "key": "17.0",
        "kind": "value",
        "answer": "CABDCAABDADB",
        "mistake": "Thinks a bad CRC gets exception 03 and that the specification fixes the word order.",
        "candidates": ["answer-to-damaged-request", "word-order"],
    },
    {
        "key": "17.1",
        "kind": "value",
        "answer": 10,
        "mistake": "Gives the register address instead of the value.",
        "candidates": ["another-field"],
    },
    {
        "key": "17.1",
        "kind": "value",
        "answer": 62465,
        "mistake": "Reads the value's two bytes low byte first.",
        "candidates": ["field-low-byte-first"],
    },
    {
        "key": "17.1",
        "kind": "value",
        "answer": 6,
        "mistake": "Gives the function code.",
        "candidates": ["another-field"],
    },
    {
        "key": "17.1",
        "kind": "value",
        "answer": 7,
        "mistake": "Gives the transaction id.",
        "candidates": ["another-field"],
    },
    {
        "key": "17.1",
        "kind": "value",
        "answer": 1,
        "mistake": "Takes the high byte 01 of the value for the whole value.",
        "candidates": ["field-in-one-byte"],
    },
    {
        "key": "17.2",
        "kind": "value",
        "answer": 0,
        "mistake": "Checks only the starting address 98, not the last register written (100).",
        "candidates": ["first-address-only"],
    },
    {
        "key": "17.2",
        "kind": "value",
        "answer": 2,
        "mistake": "Answers illegal data address for a write outside the allowed range.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "17.2",
        "kind": "value",
        "answer": 129,
        "mistake": "Gives the exception response's function byte pattern instead of the code.",
        "candidates": ["exception-function-for-code"],
    },
    {
        "key": "17.2",
        "kind": "value",
        "answer": 144,
        "mistake": "Gives the exception function code 0x90 (16 + 0x80) instead of the exception code.",
        "candidates": ["exception-function-for-code"],
    },
    {
        "key": "17.2",
        "kind": "value",
        "answer": 3,
        "mistake": "Answers illegal data value because the quantity runs past the limit.",
        "candidates": ["exception-code-confused"],
    },
    {
        "key": "17.3",
        "kind": "build",
        "answer": """\
def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        return None if address <= 99 else refuse
    return refuse
""",
        "mistake": "Checks only the starting address of a multiple write, not the last address written.",
        "candidates": ["first-address-only"],
    },
    {
        "key": "17.3",
        "kind": "build",
        "answer": """\
def decide(pdu: bytes, role: str) -> bytes | None:
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
        return None if last <= 99 else refuse
    return refuse
""",
        "mistake": "Takes address + quantity as the last address written, one past the real last one.",
        "candidates": ["range-one-extra"],
    },
    {
        "key": "17.3",
        "kind": "build",
        "answer": """\
def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([0x81, 0x01])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        return None if last <= 99 else refuse
    return refuse
""",
        "mistake": "Always answers with function byte 0x81 instead of the request's function with the top "
        "bit set.",
        "candidates": [],
    },
    {
        "key": "17.3",
        "kind": "build",
        "answer": """\
def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x01])
    if role in ("viewer", "operator") and function in (1, 2, 3, 4):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        return None if last <= 99 else refuse
    if role == "viewer" or role == "operator":
        return refuse
    return None
""",
        "mistake": "Lets every role it does not know through, as if it were an engineer.",
        "candidates": [],
    },
    {
        "key": "17.3",
        "kind": "build",
        "answer": """\
def decide(pdu: bytes, role: str) -> bytes | None:
    function = pdu[0]
    refuse = bytes([function | 0x80, 0x02])
    if role == "engineer":
        return None
    if function in (1, 2, 3, 4) and role in ("viewer", "operator"):
        return None
    if role == "operator" and function in (5, 6, 15, 16):
        address = int.from_bytes(pdu[1:3], "big")
        last = address
        if function in (15, 16):
            last = address + int.from_bytes(pdu[3:5], "big") - 1
        return None if last <= 99 else refuse
    return refuse
""",
        "mistake": "Refuses with exception 02 (illegal data address) instead of 01.",
        "candidates": ["exception-code-confused"],
    },
]
