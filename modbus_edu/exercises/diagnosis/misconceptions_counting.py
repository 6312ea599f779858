"""More of the catalogue's misconceptions: counts, rates, ports, responses, masks and tables.

A frame's length counted from its data alone, a range counted with an extra register, one request per
register, a rate worked out at another baud rate, a figure of the question given for the one asked, a
device server's URL with the Modbus/TCP port, an exception response taken for silence, the OR mask left
out, a dense bank for a sparse one.  The entries register in
:data:`~modbus_edu.exercises.catalogue.CATALOGUE` when :mod:`.misconceptions` imports this module at its
end, so every checker keeps asking ``misconceptions.diagnose`` for them.
"""

from __future__ import annotations

from typing import Any

from ...crc import lrc
from ...pdu import mask_write
from ...values import decode_value
from .catalogue import _entry, _int, _near, _number

# --- lengths of frames ---------------------------------------------------------------------------------

@_entry("data-bytes-only", "only the data bytes counted", "got: a length (int); data: the data bytes it "
        "carries (int)",
        "a length counts every byte it covers, not only the registers' data: the unit, the function code "
        "and the byte count come first (and an RTU frame's CRC last).")
def _data_only(got: Any, data: Any) -> bool:
    return _int(got) and got == data


@_entry("ascii-colon-forgotten", "the ':' left out", "got, expected: an ASCII frame's length in characters",
        "an ASCII frame starts with ':', one character of its own, and it counts in the frame's length.")
def _colon(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 1


@_entry("crc-in-ascii", "a 2-byte CRC in an ASCII frame", "got, expected: an ASCII frame's length in "
        "characters",
        "an ASCII frame ends with a 1-byte LRC (two characters), not RTU's 2-byte CRC.")
def _crc_in_ascii(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected + 2


@_entry("rtu-length-for-ascii", "the RTU frame's length for the ASCII one", "got: a length; rtu: the RTU "
        "frame's length in bytes",
        "ASCII writes every byte (address, PDU, LRC) as two characters between ':' and CR LF: about twice "
        "the RTU frame's length.")
def _rtu_for_ascii(got: Any, rtu: Any) -> bool:
    return _int(got) and got == rtu


@_entry("crc-one-byte", "one byte of the CRC", "got: the learner's CRC (bytes or int); crc: the CRC register",
        "a Modbus CRC is 16 bits: two bytes on the wire, its low byte first, then its high byte.")
def _crc_one_byte(got: Any, crc: Any) -> bool:
    halves = (crc & 0xFF, crc >> 8)
    if isinstance(got, (bytes, bytearray)):
        return len(got) == 1 and got[0] in halves
    return _int(got) and got in halves and crc > 0xFF


@_entry("lrc-not-8-bits", "an LRC not kept to 8 bits", "data (bytes), got: the learner's LRC (int)",
        "an LRC is one byte: keep the low 8 bits of the two's complement, (-sum(data)) & 0xFF; 256 for a sum "
        "of 0, or a 16-bit result, is no byte.")
def _lrc_wide(data: Any, got: Any) -> bool:
    return _int(got) and not 0 <= got <= 0xFF and got & 0xFF == lrc(bytes(data))


# --- counts of registers, requests and messages --------------------------------------------------------

@_entry("one-range-only", "only one range counted", "got: a count; ranges: the count of each range",
        "a sparse bank holds every range declared in the table: add the registers of each range.")
def _one_range(got: Any, ranges: Any) -> bool:
    return _int(got) and len(ranges) > 1 and got in ranges


@_entry("range-one-extra", "a range counted with one extra", "got, expected: counts; ranges: how many ranges",
        "last - first + 1 counts both ends once: registers 100 to 149 are 50, not 51.")
def _range_extra(got: Any, expected: Any, ranges: int = 1) -> bool:
    return _int(got) and _int(expected) and got in (expected + ranges, expected + 1)


@_entry("request-per-register", "one request per register", "got: a number of requests; registers: how "
        "many to read",
        "one read request gives a start address and a count, and reads up to mb.MAX_READ_REGISTERS (125) "
        "registers at once.")
def _request_per_register(got: Any, registers: Any) -> bool:
    return _int(got) and got == registers > 1


OTHER_LIMITS = (16, 32, 60, 64, 100)
"""Register limits some devices have, below the standard's 125 per read."""


@_entry("another-devices-limit", "another device's limit for the standard's", "got: a number of requests; "
        "registers: how many; limit: the standard's registers per request",
        "the standard lets one read ask for up to 125 registers (mb.MAX_READ_REGISTERS); some devices accept "
        "fewer, but the question asks for the protocol's limit.")
def _another_limit(got: Any, registers: Any, limit: Any) -> bool:
    right = -(-registers // limit)
    return _int(got) and got != right and got in {-(-registers // other) for other in OTHER_LIMITS}


@_entry("byte-value-as-coils", "a byte's value for its coils", "got: the coils the learner names; data: the "
        "data bytes of a read-bits response",
        "each data byte of a read-bits response holds eight coils, one per bit: 0x05 is 0000 0101, coils 0 "
        "and 2 ON, not coil 5.")
def _byte_value(got: Any, data: Any) -> bool:
    return list(got) == [byte for byte in data if byte]


@_entry("own-frames-counted", "its own responses counted", "got: a message count; with_own: the count with "
        "the node's own responses",
        "the course's slave counts the frames it receives, and its own responses are frames it sends: it "
        "does not count them (the specification leaves this to each device; notebook 14 says so).")
def _own_frames(got: Any, with_own: Any) -> bool:
    return _int(got) and got == with_own


@_entry("count-request-forgotten", "the 0x0B request itself left out", "got, expected: message counts",
        "the request that asks for the count is itself a message the slave received: the course's slave "
        "counts it before it answers (the specification leaves this order to each device).")
def _count_request(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 1


# --- times and rates -----------------------------------------------------------------------------------

@_entry("microseconds-for-milliseconds", "microseconds for milliseconds", "got, expected: a time, expected "
        "in ms",
        "the question asks for milliseconds: 1000 µs make 1 ms, divide by 1000.")
def _us_for_ms(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and got != expected and _near(got / 1000, expected)


@_entry("another-baud-rate", "worked out at another baud rate", "got: a time or rate; other: the same at "
        "another baud rate",
        "a bit lasts 1 / baud s, so every time on the line follows the baud rate: twice the baud rate, half "
        "the time. Work at the rate the question gives.")
def _another_baud(got: Any, other: Any) -> bool:
    return _number(got) and _number(other) and _near(got, other, 0.01)


@_entry("one-register-response", "the response for one register", "got: a time or rate; one: the same for "
        "a read of one register",
        "a read response carries 2 bytes per register, 5 + 2 x N bytes in all: the more registers, the "
        "longer the response.")
def _one_register_response(got: Any, one: Any) -> bool:
    return _number(got) and _number(one) and _near(got, one, 0.01)


@_entry("loop-time-for-timeout", "the loop time alone for the timeout", "got: a timeout (s); loop: the "
        "slave's longest loop (s)",
        "a request waits for the slave's loop to come round and then for the reply to travel: the timeout "
        "covers the longest loop, the reply and a margin.")
def _loop_alone(got: Any, loop: Any) -> bool:
    return _number(got) and _number(loop) and _near(got, loop, 0.03 * loop)


@_entry("timeout-far-too-long", "a timeout far longer than needed", "got: a timeout (s); enough: the "
        "longest a reply can take (s)",
        "each request left unanswered (a missing slave, a damaged frame) costs the whole timeout: keep it a "
        "little above the longest wait a reply can need.")
def _too_long(got: Any, enough: Any) -> bool:
    return _number(got) and _number(enough) and got > 3 * enough


@_entry("given-figure", "a figure of the question for the one it asks", "got: a number; figures: the "
        "figures the question gives or measures, by name",
        "{which} is one of the figures you work from; the answer asked is worked out from them, it is none "
        "of them.")
def _given(got: Any, figures: Any) -> dict | None:
    for which, value in figures.items():
        if _number(got) and _near(got, value, 0.02 * abs(value)):
            return {"which": which}
    return None


# --- ports and checks ----------------------------------------------------------------------------------

@_entry("modbus-tcp-port-for-server", "the Modbus/TCP port for a device server's", "got, expected: TCP "
        "ports (int)",
        "502 is the port of Modbus/TCP; a serial device server carries the serial bytes on a raw-TCP port of "
        "its own (4001 on many), the one its settings give.")
def _port_502(got: Any, expected: Any) -> bool:
    return got == 502 != expected


@_entry("url-not-socket", "not a socket:// URL", "got: the URL the learner wrote (str)",
        "pyserial opens a serial line carried over raw TCP with a socket://host:port URL; a bare host:port "
        "is no URL, pyserial knows no tcp:// at all, and rfc2217:// is another protocol (RFC 2217, serial "
        "port control over Telnet).")
def _not_socket(got: Any) -> bool:
    return isinstance(got, str) and not got.strip().startswith("socket://") and ":" in got


@_entry("url-without-port", "a URL without its port", "got: the URL the learner wrote (str)",
        "a TCP connection needs a port as well as a host, socket://host:port: pyserial has no default port.")
def _without_port(got: Any) -> bool:
    return isinstance(got, str) and got.strip().startswith("socket://") and ":" not in got.strip()[9:]


@_entry("port-out-of-range", "a port past 65535", "got: a TCP port (int)",
        "a TCP port is a 16-bit number: 0 to 65535.")
def _port_range(got: Any) -> bool:
    return _int(got) and not 0 <= got <= 0xFFFF


@_entry("check-ruled-out", "a check the evidence already ruled out", "got: the learner's next check (str); "
        "ruled_out: words of the checks the tests so far ruled out",
        "each test so far ruled a cause out: the next check is the first one on the flowchart that nothing "
        "has ruled out yet.")
def _ruled_out(got: Any, ruled_out: Any) -> bool:
    return isinstance(got, str) and any(word in got.lower() for word in ruled_out)




# --- responses, exceptions and outcomes ----------------------------------------------------------------

@_entry("function-and-code-swapped", "the function and the exception code swapped", "got, expected: "
        "(function, exception code) pairs",
        "an exception response is the function byte (the request's function + 0x80), then the exception "
        "code: 83 02 is function 3, exception code 2.")
def _pair_swapped(got: Any, expected: Any) -> bool:
    return tuple(got) == tuple(expected)[::-1] != tuple(expected)


@_entry("exception-function-forgotten", "0x80 without the function", "got, expected: an exception "
        "response's PDU (bytes)",
        "an exception response's function byte is the request's function code with its top bit set, "
        "function | 0x80 (0x83 for function 3), not 0x80 alone.")
def _function_forgotten(got: Any, expected: Any) -> bool:
    return (len(got) == len(expected) == 2 and got[0] == 0x80 != expected[0] and expected[0] & 0x80
            and got[1] == expected[1])


@_entry("damaged-response-as-silence", "a damaged response taken for silence", "got, expected: what the "
        "master sees (str)",
        "a response damaged on its way still arrives: the master receives its bytes, finds the CRC wrong "
        "and reports a checksum error, not a timeout.")
def _damaged_silence(got: Any, expected: Any) -> bool:
    return (got, expected) == ("timeout", "checksum error")


@_entry("last-transaction-id", "the last request's id for the next one", "got, expected: transaction ids",
        "the course's client (like most) adds 1 to the transaction id for every new request, so the next "
        "request carries the id after the last one sent; the specification only asks that a response "
        "carry its request's id.")
def _last_id(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 1


@_entry("bytes-for-registers", "a byte count for a register count", "got, expected: register counts",
        "a read request counts registers, not bytes: each register is 2 bytes, so 12 bytes are 6 "
        "registers.")
def _bytes_for_registers(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == 2 * expected > 0


@_entry("pause-threshold", "a pause limit other than 1.5 characters", "got, expected: the pauses (in "
        "characters) that break a frame; pauses: all the pauses tried",
        "a pause of more than 1.5 character times inside a frame breaks it: 2 characters break it, 1.4 do "
        "not.")
def _pause_threshold(got: Any, expected: Any, pauses: Any) -> bool:
    got = sorted(float(p) for p in got)
    return got != sorted(expected) and any(got == [p for p in sorted(pauses) if p > limit]
                                           for limit in [0.0, *pauses])


# --- masks ---------------------------------------------------------------------------------------------

@_entry("or-mask-forgotten", "the OR mask left out", "current, and_mask, or_mask, got: ints",
        "FC 22 applies both masks: the AND mask keeps bits, the OR mask sets the others, (current & "
        "and_mask) | (or_mask & ~and_mask); the AND mask alone only clears bits.")
def _or_forgotten(current: Any, and_mask: Any, or_mask: Any, got: Any) -> bool:
    return _int(got) and got == current & and_mask != mask_write(current, and_mask, or_mask)


# --- serial characters and polling ---------------------------------------------------------------------

@_entry("start-stop-forgotten", "8 bits a character", "got, eight_bits: a time, and the same time with 8 "
        "bits a character",
        "each character on a serial line also carries a start bit and a stop bit (and parity if any): 8N1 "
        "is 10 bits a character, not 8.")
def _start_stop(got: Any, eight_bits: Any) -> bool:
    return _number(got) and _number(eight_bits) and _near(got, eight_bits)


@_entry("reply-time-forgotten", "the reply's time forgotten", "got, without: a share, and the same share "
        "without the reply's time",
        "a request is answered in time only if its reply, too, arrives within the timeout: the reply's own "
        "time counts (the share answered is (timeout - reply) / loop time, not timeout / loop time).")
def _reply_forgotten(got: Any, without: Any) -> bool:
    return _number(got) and _number(without) and _near(got, without)


@_entry("missed-for-answered", "the share missed for the share answered", "got, expected: shares 0..1",
        "the question asks for the share answered; 1 minus it is the share missed.")
def _missed(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and 0 < expected < 1 and _near(got, 1 - expected)


@_entry("integer-for-float", "an integer type for a float", "got: the learner's value, registers and order: "
        "the registers that carry a float32, in that word order; or got: the type the learner names (str)",
        "these two registers carry an IEEE 754 float32 (sign, exponent, fraction), not a whole number: "
        "decode them as float32.")
def _integer_for_float(got: Any, registers: Any = None, order: Any = None) -> bool:
    if isinstance(got, str):
        return got.lower().startswith(("int", "uint"))
    return _int(got) and got == decode_value(list(registers), "uint32", order)


@_entry("three-characters-for-t35", "3 characters for t3.5", "got, three: a time, and the same time with "
        "silences of 3 characters",
        "t3.5 is three and a half character times, 3.5 x the bits of a character / baud: rounding it to 3 "
        "makes every silence too short.")
def _three_chars(got: Any, three: Any) -> bool:
    return _number(got) and _number(three) and _near(got, three)


@_entry("result-rounded", "a result rounded inside the function", "got, expected: floats; decimals: the "
        "places the result was rounded to",
        "a function returns the value it decodes, whole; round only where you show it, or every caller "
        "loses the digits it may need.")
def _rounded(got: Any, expected: Any, decimals: int = 2) -> bool:
    return _number(got) and _number(expected) and got != expected and got == round(expected, decimals)


@_entry("field-in-one-byte", "a 2-byte field in one byte", "got, expected: a PDU (bytes)",
        "the address and the count of a request are 16-bit fields, two bytes each, high byte first, even "
        "when the value fits in one byte.")
def _field_one_byte(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(got) == len(expected) - 1 and any(
        expected[i] == 0 and got == expected[:i] + expected[i + 1:] for i in range(1, len(expected)))


@_entry("slave-for-master", "a slave's role for the master's", "got: the role the learner chose (str)",
        "a slave (or server) only answers; the tool that asks, polls and shows the values is the master "
        "(rtu_master) or the client (tcp_client).")
def _slave_for_master(got: Any) -> bool:
    return isinstance(got, str) and got.endswith(("slave", "server"))


@_entry("termination-for-silence", "a missing terminator for a silent meter", "got: the learner's next "
        "check (str)",
        "a missing or extra terminator garbles frames now and then (CRC errors) on long lines; it does not "
        "silence a meter on every setting, and a short bench cable hardly needs one.")
def _termination(got: Any) -> bool:
    return isinstance(got, str) and "terminat" in got.lower()


# --- tables, banks and handlers ------------------------------------------------------------------------

@_entry("bit-table-for-register-table", "a table of bits for a table of registers", "got, expected: table "
        "names",
        "coils (0xxxx) and discrete inputs (1xxxx) hold single bits; holding registers (4xxxx) and input "
        "registers (3xxxx) hold 16-bit words. Function 4 reads input registers, function 2 discrete inputs.")
def _bits_for_words(got: Any, expected: Any) -> bool:
    pairs = ({"discrete_inputs", "input_registers"}, {"coils", "holding_registers"})
    return got != expected and {got, expected} in pairs


@_entry("dense-for-sparse", "a dense bank for a sparse one", "got: the learner's DataBank",
        "a dense bank has every address 0..65535 of every table, so any read succeeds; a sparse bank holds "
        "only the ranges declared, and its slave refuses the others with exception 02.")
def _dense(got: Any) -> bool:
    return getattr(got, "sparse", True) is False


@_entry("slave-subtracts-one", "1 subtracted on the slave's side", "got, expected: the handler's response "
        "and the right one (bytes) to a request for address 0",
        "the address on the wire already counts from 0: the slave uses it as the index into its table, "
        "registers[address], and address 0 is its first register.")
def _slave_minus_one(got: Any, expected: Any) -> bool:
    return (len(got) == 2 and got[0] & 0x80 and got[1] == 2 and len(expected) > 2
            and not expected[0] & 0x80)


@_entry("frame-for-header", "the whole frame for its header", "got, expected: the MBAP header (bytes)",
        "the MBAP header is the first 7 bytes alone (transaction id, protocol id, length, unit); the PDU "
        "comes after it and is not part of it.")
def _frame_for_header(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(expected) == 7 and len(got) > 7 and got[:7] == expected


@_entry("an-order-when-none-fits", "a word order named when none fits", "got: the learner's order; "
        "expected: the orders that fit (empty)",
        "when no word order turns the registers into the value, none is right: return None, not a default "
        "such as ABCD; those registers hold another value or another type.")
def _order_when_none(got: Any, expected: Any) -> bool:
    return not expected and isinstance(got, str) and got.upper() in ("ABCD", "CDAB", "BADC", "DCBA")


# --- found by the procedures (:mod:`.procedures`) ------------------------------------------------------

@_entry("fixed-silence-at-19200", "the fixed 1.75 ms at 19200 baud", "got, fixed: a time at 19200 baud, "
        "and the same time with 1.75 ms silences",
        "the fixed 1.75 ms (and 0.75 ms) replace 3.5 (and 1.5) character times only above 19200 baud; at "
        "19200 baud and below the silences are counted in characters.")
def _fixed_at_19200(got: Any, fixed: Any) -> bool:
    return _number(got) and _number(fixed) and _near(got, fixed)


@_entry("causes-swapped", "two causes swapped", "got, expected: the causes the learner gave two wires",
        "each cause leaves its own trace in the slave's counters and log: a wrong unit id counts requests "
        "for another address (other_unit), a wrong baud rate or parity garbled bytes (checksum_errors), no "
        "slave nothing at all; match each wire's trace to its cause.")
def _causes_swapped(got: Any, expected: Any) -> bool:
    return False  # named by 13.1's checker, which compares the causes wire by wire


@_entry("builtin-for-library-exception", "Python's own exception for the library's", "got: the exception "
        "class the learner names",
        "Python's built-in TimeoutError is not what modbus_edu raises: every error of the library is a "
        "mb.ModbusError subclass, and a request left unanswered raises mb.ModbusTimeoutError.")
def _builtin_for_library(got: Any) -> bool:
    return isinstance(got, type) and got.__module__ == "builtins" and issubclass(got, Exception)


@_entry("word-order-in-specification", "a word order the specification fixes", "got: the learner's belief",
        "the specification defines 16-bit registers only, each high byte first; how a device spreads a "
        "32-bit value over two registers is its own choice, and its datasheet says which.")
def _order_in_spec(got: Any) -> bool:
    return False  # named by the concept inventory's question on word order


@_entry("tcp-frame-for-rtu", "a Modbus/TCP frame for an RTU frame", "got: the learner's frame (bytes)",
        "an RTU frame is the slave address, the PDU and a CRC, low byte first; the MBAP header (transaction "
        "id, protocol id, length, unit) and a frame with no CRC are Modbus/TCP's.")
def _tcp_for_rtu(got: Any) -> bool:
    return False  # named by the RTU frame's procedure, which rebuilds the TCP frame


@_entry("ascii-frame-for-rtu", "an ASCII frame for an RTU frame", "got: the learner's frame (bytes)",
        "an RTU frame carries the bytes themselves and a CRC; ':', hex characters, an LRC and CR LF are "
        "the ASCII mode's.")
def _ascii_for_rtu(got: Any) -> bool:
    return False  # named by the RTU frame's procedure, which rebuilds the ASCII frame


# --- the answer's form and scope (what was asked, not how it is computed) ------------------------------

@_entry("another-form", "the right value in another form", "form: the form the exercise asks for, in words",
        "the value is right; write it as {form}.")
def _another_form(form: Any) -> Any:
    return {"form": form} if isinstance(form, str) and form else None


@_entry("part-of-answer", "part of the answer", "got, expected: the learner's bytes and the asked bytes",
        "your answer is {part}; the exercise asks for {whole}.")
def _part_of_answer(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return 0 < len(got) < len(expected) and got in expected


@_entry("another-question", "the answer to another question", "got, expected: the learner's answer and "
        "what another question (a neighbouring exercise, the request for the response, another mode) asks",
        "reread what the exercise asks for (a request or its response, an RTU or a Modbus/TCP frame, a "
        "whole frame or one of its fields) before working it out.")
def _another_question(got: Any, other: Any) -> bool:
    return got == other and not isinstance(got, bool)

