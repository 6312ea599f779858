# The LRC: the two's complement of the 8-bit sum of the bytes (unit and PDU, not the characters).
from modbus_edu.exercises import check


def lrc(data: bytes) -> int:
    return (-sum(data)) & 0xFF


print(hex(lrc(bytes.fromhex("05 06 10 01 02 00"))))   # 0xe2, as in the Inst Tools ASCII article
answer = lrc
check("04.5", answer)
