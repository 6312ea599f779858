# A Modbus/TCP read request: the MBAP header (tid, protocol 0, length 6, unit) and the FC3 PDU.
from modbus_edu.exercises import check


def read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    pdu = bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")
    return tid.to_bytes(2, "big") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu


print(read_request(280, 1, 0, 1).hex(" ").upper())   # 01 18 00 00 00 06 01 03 00 00 00 01
answer = read_request
check("12.4", answer)
