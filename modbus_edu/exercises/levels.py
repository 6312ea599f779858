"""The hints after the idea, for the exercises whose checkers do not give them all.

Every exercise's hints escalate (:data:`.core.LINES`): its ``hint`` gives the idea; after two wrong tries
:func:`~.core.count_try` adds the next step, after three a worked example of the same idea on other
numbers, never the exercise's own answer.  Most checkers give those levels beside the exercise
(``hint=(idea, step, example)``); this module gives them for the rest, once every checker is registered:

* :data:`STEPS_AND_EXAMPLES`: both levels, for exercises whose checker gives none;
* :data:`EXAMPLES`: the worked example, for exercises whose checker gives the step only;
* :data:`EXAMPLES_REPLACED`: a worked example that replaces a checker's own (00.3's walked through the
  exercise's own request with other numbers: a template to fill in, not an example to learn from).

Each example's numbers and frames are the library's (``tests/test_hint_levels.py`` computes every one of
them again), written for a reader who has never seen Modbus.  :data:`GIVEN_BY_CHECKERS` keeps what the
checkers gave before this module added its levels, so that a level given twice is caught.
"""

from __future__ import annotations

from . import checkers, inventory  # noqa: F401  (every exercise registered first: their levels stand)
from .core import EXERCISES, LINES, line_after_tries

STEPS_AND_EXAMPLES: dict[str, tuple[str, str]] = {
    "00.0": (
        "write one letter per question, in the order of the questions, 12 in all: a, b, c or d, or ? where "
        "you have no idea; capitals or not and spaces do not matter. A dict {question number: letter} works "
        "too.",
        "for a quiz of 4 questions where you think b, then c, then have no idea, then a: \"BC?A\", or "
        "{1: \"b\", 2: \"c\", 3: \"?\", 4: \"a\"}."),
    "00.1": (
        "take the frame's first byte (the two characters before the first space) and turn it from "
        "hexadecimal into a number: the first digit times 16 plus the second, or int(\"..\", 16) in Python.",
        "the frame 1F 03 00 00 00 01 87 B4 starts with 1F: 1 x 16 + 15 (F) = 31, so it is for slave 31; "
        "mb.RtuFrame.decode(mb.parse_hex(\"1F 03 00 00 00 01 87 B4\")).unit says the same."),
    "00.2": (
        "count off the first 7 bytes (transaction 2, protocol 2, length 2, unit 1) and keep everything after "
        "them; mb.TcpFrame.decode(mb.parse_hex(\"...\")).pdu.encode() gives the same bytes.",
        "in 00 01 00 00 00 06 05 04 00 0A 00 02 the header is 00 01 00 00 00 06 05 and the PDU is "
        "04 00 0A 00 02: function 4 (read input registers), address 10, count 2."),
    "01.1": (
        "drop the leading 4 (it only names the table), read the four digits left as a number, and subtract "
        "one: the frame counts from 0, the manual from 1.",
        "holding register 40017: 0017 is 17, and 17 - 1 = 16 is the address in the frame "
        "(mb.parse_reference(\"40017\").address)."),
    "01.2": (
        "add one to the address, write the result with four digits (leading zeros), and put the table's "
        "digit in front: five characters in all.",
        "holding register address 41: 41 + 1 = 42, with four digits 0042, after the holding registers' "
        "prefix 4: \"40042\" (mb.format_reference(\"holding_registers\", 41))."),
    "01.3": (
        "mb.table_kind(4) names the table; for the second half, look for a write function that reaches the "
        "same table (notebook 02's list of function codes): if there is none, a master may not write it.",
        "function 3 reads holding registers (mb.table_kind(3)), and function 6 writes one "
        "(mb.table_kind(6) is the same table): (\"holding_registers\", True)."),
    "01.5": (
        "split the text: its first character picks the table from a dict such as {\"0\": \"coils\", ...}, "
        "int() of the other four is the number; return the table and the number minus 1, and raise an error "
        "when that number is 0 or the first digit names no table.",
        "\"10020\": the first digit 1 is the discrete inputs, 0020 is 20, so (\"discrete_inputs\", 19); "
        "\"30000\" has the number 0, so mb.parse_reference raises mb.ReferenceNumberError for it."),
    "02.2": (
        "divide the number of registers by mb.MAX_READ_REGISTERS (125) and round up: a request that reads "
        "fewer than 125 still counts as one (math.ceil does the rounding up).",
        "500 registers: 500 / 125 = 4 exactly, so 4 requests; 130 registers: 130 / 125 = 1.04, rounded up "
        "to 2 requests (125, then 5)."),
    "02.3": (
        "two bytes: first the request's function code plus 0x80, then the exception code whose name in "
        "mb.ExceptionCode says the address is missing (list(mb.ExceptionCode) shows each code and its name).",
        "a slave refuses a write of a single coil (function 05) whose value is neither ON nor OFF: "
        "0x05 + 0x80 = 0x85, and ILLEGAL_DATA_VALUE is 03, so the PDU is 85 03 "
        "(mb.ExceptionResponse(5, 3).encode())."),
    "02.4": (
        "write the data byte in binary with 8 digits (f\"{0x05:08b}\" in Python) and read it from the right: "
        "the rightmost digit is coil 0, the next one coil 1, and so on; a 1 is ON.",
        "the response PDU 01 01 0A: 0x0A is 0000 1010 in binary; read from the right, coils 1 and 3 are ON "
        "(mb.ReadCoilsResponse.decode(mb.parse_hex(\"01 01 0A\")).bits)."),
    "03.3": (
        "compute mb.crc16 over all bytes but the last two, split it into its low and high byte, and compare "
        "them, low byte first, with the frame's last two bytes; mb.explain(mb.parse_hex(\"...\")) does both.",
        "01 03 00 00 00 01 84 0B: the CRC of 01 03 00 00 00 01 is 0x0A84, so the frame must end 84 0A; it "
        "ends 84 0B, the slave finds a damaged frame and stays silent."),
    "03.4": (
        "add the parts of the response for 20 registers: 1 byte of slave address, 1 of function code, 1 of "
        "byte count, 2 bytes per register, and the 2 bytes of the CRC.",
        "for 4 registers: 1 + 1 + 1 + 8 + 2 = 13 bytes; len(mb.RtuFrame(unit=1, "
        "pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 4)).encode()) is 13 too."),
    "05.1": (
        "read the frame's first two bytes as one number, the first one high: first x 256 + second, each "
        "turned from hexadecimal (int(\"..\", 16)).",
        "01 0C 00 00 00 06 01 03 00 00 00 01 has 01 0C there: 1 x 256 + 12 = 268 "
        "(mb.TcpFrame.decode(...).transaction_id)."),
    "05.3": (
        "list what follows the length field in the response: the unit (1 byte), the function code (1), the "
        "byte count (1), and 2 bytes per register read; add them.",
        "a response with 4 registers: 1 + 1 + 1 + 8 = 11 = 0x0B, so the frame is 00 01 00 00 00 0B 01 03 08 "
        "00 00 00 00 00 00 00 00 (mb.TcpFrame(transaction_id=1, unit=1, "
        "pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 4)).encode())."),
    "06.1": (
        "count characters: a read request is 8 bytes, an FC3 response 5 + 2 per register; add 3.5 characters "
        "of silence after each; a character is 10 bits at 8N1 and a bit lasts 1/9600 s; x 1000 for "
        "milliseconds.",
        "2 registers at 19200 baud 8N1: 8 + 3.5 + 9 + 3.5 = 24 characters = 240 bits; 240 / 19200 = "
        "0.0125 s = 12.50 ms (mb.SerialTiming(baudrate=19200).transaction_time(8, 9))."),
    "06.5": (
        "start from the function code, the PDU's first byte. For 3: address and count are int.from_bytes "
        "of the next two pairs of bytes "
        "(\"big\"); check the count (1..125), then that address + count stays inside the list; answer the "
        "function, the byte count (2 per register), then each register as 2 bytes, high first. For 6: store "
        "the value at the address (if it exists) and answer with the request.",
        "registers [10, 20, 30]: 03 00 01 00 02 (2 registers from address 1) is answered 03 04 00 14 00 1E; "
        "03 00 02 00 02 runs past the end: 83 02; 06 00 00 01 F4 stores 500 at address 0 and is answered "
        "06 00 00 01 F4."),
    "07.1": (
        "look at the second byte, the function code: 0x80 or more is an exception; subtract 0x80 for the "
        "request's function; the byte after it is the exception code (the last two bytes are the CRC).",
        "05 84 03 42 C0: 0x84 - 0x80 = 4 (read input registers), refused with code 03 (illegal data value): "
        "(4, 3)."),
    "07.3": (
        "for each situation ask in turn: did the slave get a whole request for its own unit (if not, it says "
        "nothing)? Did its answer arrive whole, from the unit asked? Is the answer a refusal?",
        "other situations: a write to a holding register the slave has is valid (the echo of the request); "
        "a request with function 0x41, which the slave does not implement, gets exception 01; an answer "
        "that arrives after the master's timeout counts as a timeout."),
    "07.4": (
        "return two bytes, bytes([...]): the function code with its top bit set (| 0x80, or + 128), then the "
        "code as it is; no slave address and no CRC: those belong to the frame, not the PDU.",
        "function 16 refused with code 4: 0x10 | 0x80 = 0x90, so 90 04 "
        "(mb.ExceptionResponse(16, 4).encode())."),
    "08.3": (
        "compare each pause with the limit of 1.5 character times: up to it the frame stays whole, above it "
        "the frame is broken; or try each on a loopback wire with link.faults.insert_gap(at_byte=4, "
        "chars=..., target=\"request\") before a read, and keep those that end in a timeout.",
        "at 19200 baud with the pauses [0.5, 1.2, 1.6, 4.0]: 1.6 and 4.0 are more than 1.5 and leave the "
        "request unanswered; 0.5 and 1.2 do not."),
    "08.4": (
        "three lines: the bits of one character (1 start, 8 data, 1 more unless parity is \"N\", then the "
        "stop bits), the seconds of one character (bits / baudrate), then t3.5 (3.5 characters up to 19200 "
        "baud, 0.00175 s above); return the request's and response's characters plus two t3.5.",
        "38400 baud 8E1, 8 and 7 bytes: 11 bits, 0.2865 ms a character; above 19200 baud t3.5 is 1.75 ms: "
        "15 x 0.2865 + 2 x 1.75 = 7.797 ms, 0.007797 s (mb.SerialTiming(baudrate=38400, "
        "parity=\"E\").transaction_time(8, 7))."),
    "09.3": (
        "work out the longest wait: the longest loop, SLOW_LOOP x 1.1, plus the reply, reply_time(9 + 3.5); "
        "take a timeout a little above it, then run loop_time_experiment([SLOW_LOOP], timeout=...) and see "
        "that every request is answered (1.0).",
        "a 0.8 s loop that varies by up to 10%, with the 13 ms reply: the longest wait is 0.88 + 0.013 = "
        "0.893 s, so a timeout of 0.9 s copes: loop_time_experiment([0.8], timeout=0.9) gives [(0.8, 1.0)]."),
    "10.3": (
        "print METER_BY_NAME[name].address for the three names; the request starts at the lowest address, "
        "and its count runs to the end of the last value, each value two registers.",
        "VL1 and AL1 at addresses 0 and 2, two registers each: one request from 0 to the end of AL1, "
        "(3, 0, 4)."),
    "10.4": (
        "turn each register into its two bytes, high first (value.to_bytes(2, \"big\")); name them after "
        "the order's letters (register 0 holds the first two); put them in the order A B C D, then "
        "struct.unpack(\">f\", ...)[0].",
        "pi as a float32 is the bytes 40 49 0F DB (A B C D): in ABCD the registers are [0x4049, 0x0FDB], in "
        "CDAB [0x0FDB, 0x4049], in BADC [0x4940, 0xDB0F], in DCBA [0xDB0F, 0x4940]; each decodes to "
        "3.1415927."),
    "11.3": (
        "write the scheme socket://, then the server's IP address, a colon and the TCP port; nothing after "
        "the port.",
        "a device server at 10.0.0.7 carrying its line on TCP port 950: \"socket://10.0.0.7:950\"."),
    "12.4": (
        "one field at a time with value.to_bytes(size, \"big\"): the MBAP's three 2-byte fields (the "
        "transaction id, 0, the length) and the unit's 1 byte, then the PDU's function (1 byte) and its two "
        "2-byte fields; join them with +. A read request's length is the same whatever its numbers.",
        "transaction 300, unit 7, 5 registers from address 1000: 01 2C 00 00 00 06 07 03 03 E8 00 05."),
    "13.1": (
        "read the poll's output wire by wire: a wire that prints no \"slave counters\" line has no slave "
        "listening; for the two others, see which count is 3 (other_unit or checksum_errors) and whether "
        "\"slave received\" shows the bytes of the monitor or others.",
        "after two polls, a slave whose counters show other_unit 2 and whose log holds the monitor's bytes "
        "heard two whole requests, both for another address; one with checksum_errors 2 and other bytes in "
        "its log assembled something else than was sent."),
    "13.2": (
        "take the two registers read and decode them twice, mb.decode_value(registers, \"uint32\", \"ABCD\") "
        "and with \"CDAB\"; divide each by 1000 (mA to A) and keep the one a current sensor could measure.",
        "the registers [0x0001, 0x86A0]: ABCD gives 0x000186A0 = 100000 mA = 100.0 A; CDAB gives "
        "0x86A00001 = 2258632705 mA, over two million amperes: not a current, so the order is ABCD there."),
    "13.5": (
        "compute mb.crc16 over the frame without its last two bytes, write it as 4 hex digits, and compare "
        "them with the last two bytes the tool sends: the tool kept the calculator's order (high byte "
        "first); the wire wants the low byte first.",
        "for 02 06 00 01 00 0A the CRC is 0x3E58: a calculator shows 3E58, and the frame ends 58 3E: "
        "02 06 00 01 00 0A 58 3E."),
    "15.1": (
        "add the characters (the request, 3.5 of silence, the response, 3.5 more), multiply by the bits of "
        "one character (start, 8 data, parity, stop), divide by 19200 bits a second and multiply by 1000.",
        "one register at 9600 baud 8O1 (odd parity, also 11 bits): 8 + 3.5 + 7 + 3.5 = 22 characters x 11 "
        "bits = 242 bits; 242 / 9600 = 25.21 ms (mb.SerialTiming(baudrate=9600, "
        "parity=\"O\").transaction_time(8, 7))."),
    "15.2": (
        "split the frame into its body (all but the last two bytes) and its CRC; compare the CRC with "
        "mb.crc16(body) written low byte first (.to_bytes(2, \"little\")) and raise an error if they differ; "
        "the body is already the unit and the PDU, so the length field is len(body).",
        "the RTU frame 05 06 00 01 00 64 D8 65 with transaction id 1 becomes 00 01 00 00 00 06 05 06 00 01 "
        "00 64; the same frame ending D8 66 raises."),
    "15.3": (
        "for each case ask who answers, and when: the gateway itself (no path to that unit: 0A; the bus "
        "silent for its 0.2 s: 0B), the unit (its own exception passes through unchanged), or nobody before "
        "the client's own timeout runs out.",
        "the client reads holding register 9999 of unit 2, the pump, which has no such register: the pump "
        "answers exception 02, and the gateway hands the client 02 as it is, not 0B."),
    "16.3": (
        "go along the timeout row from the left and cross off each box that one of the colleague's facts "
        "rules out (the LED, the wires, the scan, the menu); the first box still standing is the next check.",
        "a meter whose adapter's TX LED stays dark at every request: nothing has left the computer, so the "
        "first box, the port, is not ruled out: check the port's name and the dialout group."),
    "16.4": (
        "two cases: the first len(sent) bytes of received are exactly sent, and the answer is the rest of "
        "received (a slice); otherwise raise an error, such as a mb.ModbusError subclass.",
        "sent 01 03 00 00 00 01 84 0A, received 01 03 00 00 00 01 84 0A 01 03 02 00 2A 39 9B: the first 8 "
        "bytes are the echo and 01 03 02 00 2A 39 9B is the answer; received 01 03 02 00 2A 39 9B alone (no "
        "echo) raises."),
    "17.0": (
        "the verdict lists each question still wrong with the idea it stands for: go back to the notebook "
        "that teaches that idea, rethink only those questions and keep the other letters.",
        "\"10 of 12 right; look again at question 4 (...), 9 (...)\": keep the ten letters that were right, "
        "change the fourth and the ninth, and check again."),
    "17.1": (
        "skip the 7 bytes of the MBAP header; the PDU is 06, then the address (2 bytes), then the value (2 "
        "bytes): read the last two bytes as one number, the first one high (first x 256 + second).",
        "00 03 00 00 00 06 01 06 00 01 03 E8 writes 0x03E8 = 3 x 256 + 232 = 1000 into address 1."),
}
"""Exercise key -> (the next step, a worked example on other numbers), for exercises whose checker gives
neither."""

EXAMPLES: dict[str, str] = {
    "06.2": "a request with function 0x41, which this slave does not implement: the master raises "
            "mb.ModbusExceptionError, and its .code is 1 (ILLEGAL_FUNCTION).",
    "06.4": "flip one bit of the response instead (target='response'): the slave did answer, the master's "
            "own CRC check fails, and it raises mb.CrcError, a mb.ChecksumError.",
    "11.1": "00 05 00 00 00 06 01 06 00 03 00 64: transaction 5, function 6, address 3, value 0x0064 = 100: "
            "(5, 6, 3, 100).",
}
"""Exercise key -> a worked example on other numbers, for exercises whose checker gives the step only."""

EXAMPLES_REPLACED: dict[str, str] = {
    "00.3": "another request in the same envelope: slave 9, write the value 500 into holding register 5 "
            "(function 6): the unit 09, then the PDU 06 00 05 01 F4, then the CRC of those six bytes, "
            "0x9498, low byte first: 09 06 00 05 01 F4 98 94 (mb.RtuFrame(unit=9, "
            "pdu=mb.WriteSingleRegisterRequest(address=5, value=500)).encode()).",
}
"""Exercise key -> a worked example that replaces its checker's own."""

GIVEN_BY_CHECKERS: dict[str, tuple[str, ...]] = {key: LINES.get(key, ()) for key in EXERCISES}
"""The levels each exercise had from its checker, before this module added its own."""


def give_levels() -> None:
    """Give every exercise of the tables above its two levels (:func:`~.core.line_after_tries`)."""
    for key, (step, example) in STEPS_AND_EXAMPLES.items():
        line_after_tries(key, step, example)
    for key, example in EXAMPLES.items():
        line_after_tries(key, GIVEN_BY_CHECKERS[key][0], example)
    for key, example in EXAMPLES_REPLACED.items():
        line_after_tries(key, GIVEN_BY_CHECKERS[key][0], example)


give_levels()
