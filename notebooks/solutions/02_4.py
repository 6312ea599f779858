# 0x05 = 0000 0101: bit 0 (coil address 0) and bit 2 (coil address 2) are 1.
import modbus_edu as mb
from modbus_edu.exercises import check

response = mb.decode_pdu(bytes([0x01, 0x01, 0x05]), "response")
answer = [address for address, bit in enumerate(response.bits) if bit]
print(answer)   # [0, 2]
check("02.4", answer)
