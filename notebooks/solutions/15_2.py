# What a gateway does to an RTU request: check the CRC and drop it, keep the unit and the PDU, put the MBAP
# header in front (transaction id, protocol id 0, length of unit + PDU), every field big-endian.
import modbus_edu as mb
from modbus_edu.exercises import check


def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    body, crc = frame[:-2], frame[-2:]
    if len(frame) < 4 or mb.crc16(body).to_bytes(2, "little") != crc:
        raise ValueError("CRC mismatch: a gateway does not forward a damaged frame")
    unit, pdu = body[0], body[1:]
    return (transaction_id.to_bytes(2, "big") + b"\x00\x00" + (1 + len(pdu)).to_bytes(2, "big")
            + bytes([unit]) + pdu)


print(rtu_to_tcp(bytes.fromhex("01 03 00 00 00 02 C4 0B"), 1).hex(" "))   # 00 01 00 00 00 06 01 03 00 00 00 02
answer = rtu_to_tcp
check("15.2", answer)
