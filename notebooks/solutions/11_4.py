# The MBAP header's fields, big-endian, and the PDU after them; the length must fit the frame.
from modbus_edu.exercises import check


def split_mbap(frame: bytes) -> tuple:
    tid = int.from_bytes(frame[0:2], "big")
    protocol = int.from_bytes(frame[2:4], "big")
    length = int.from_bytes(frame[4:6], "big")
    if protocol != 0 or length != len(frame) - 6 or len(frame) < 8:
        raise ValueError(f"not a Modbus/TCP frame: protocol {protocol}, length {length}, {len(frame)} bytes")
    return tid, protocol, length, frame[6], frame[7:]


print(split_mbap(bytes.fromhex("01 18 00 00 00 06 01 03 00 00 00 01")))
answer = split_mbap
check("11.4", answer)
