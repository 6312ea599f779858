"""The mutants of the worked solutions that no checker can refuse, because they are not wrong.

Keyed by exercise, then by the mutant's name (``"<line of the solution> | <change>"``, as
:func:`.mutate.mutants` names it), each with the one reason it behaves like the solution on every input
the exercise allows.  Every other mutant must be refused by the exercise's checker
(``tests/test_checker_mutants.py``).
"""

_ILLEGAL_FUNCTION = "return bytes([function | 0x80, 1])                    # illegal function"
_ONLY_3_AND_6 = "the exercise sends function 3 or 6 only: the solution's answer to any other is never asked"

EQUIVALENT: dict[str, dict[str, str]] = {
    "01.5": {
        "if not 1 <= number <= 9999: | `9999` -> `10000`":
            "four digits never make a number above 9999",
    },
    "02.5": {
        "if not 0 <= address or address + count > 65536: | `0` -> `-1`":
            "(-1).to_bytes(2, 'big') raises OverflowError: address -1 is refused either way",
    },
    "05.5": {
        'return tid.to_bytes(2, "big") + (0).to_bytes(2, "big") + (len(pdu) + 1).to_bytes(2, "big") '
        '+ bytes([unit]) | `\'big\'` -> `\'little\'` #3':
            "the protocol id 0 is 00 00 in either byte order",
    },
    "06.5": {
        f"{_ILLEGAL_FUNCTION} | `|` -> `&`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | `1` -> `2`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | `1` -> `0`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | `0x80` -> `0x81`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | `0x80` -> `0x7F`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | `0x80` -> `0x40`": _ONLY_3_AND_6,
        f"{_ILLEGAL_FUNCTION} | line dropped": _ONLY_3_AND_6,
        'count = int.from_bytes(pdu[3:5], "big") | `5` -> `6`':
            "an FC3 request PDU is 5 bytes: pdu[3:6] is pdu[3:5]",
        'registers[address] = int.from_bytes(pdu[3:5], "big") | `5` -> `6`':
            "an FC6 request PDU is 5 bytes: pdu[3:6] is pdu[3:5]",
    },
    "10.4": {
        'return struct.unpack(">f", abcd)[0] | `0` -> `-1`':
            "struct.unpack gives a tuple of one float: [0] and [-1] are the same item",
    },
    "11.4": {
        'protocol = int.from_bytes(frame[2:4], "big") | `\'big\'` -> `\'little\'`':
            "the protocol id is only compared with 0 (and returned once it is 0): 0 in either byte order",
        'protocol = int.from_bytes(frame[2:4], "big") | `4` -> `5`':
            "byte 4, the length's high byte, is 0 in any frame the library takes (a length is at most 254); "
            "a frame with more is refused by the library and by the mutant alike",
        'length = int.from_bytes(frame[4:6], "big") | `4` -> `3`':
            "byte 3, the protocol id's low byte, is 0 once the protocol check (made first) has passed",
    },
    "13.7": {
        "return None | line dropped": "a function that ends without return returns None",
    },
}
