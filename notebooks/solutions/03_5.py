# The bitwise CRC-16/MODBUS: the register starts at 0xFFFF; each byte is XORed into its low end, then
# eight shifts to the right, XORing the reflected polynomial 0xA001 whenever a 1 falls out.
from modbus_edu.exercises import check


def crc16(data: bytes) -> int:
    register = 0xFFFF
    for byte in data:
        register ^= byte
        for _ in range(8):
            if register & 1:
                register = (register >> 1) ^ 0xA001
            else:
                register >>= 1
    return register


print(hex(crc16(b"123456789")))   # 0x4b37, the check value of CRC-16/MODBUS
answer = crc16
check("03.5", answer)
