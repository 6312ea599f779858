# 1 (address) + 1 (function) + 1 (byte count) + 2 x 20 (registers) + 2 (CRC) = 45 = 5 + 2N.
import modbus_edu as mb
from modbus_edu.exercises import check

response = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 20)).encode()
answer = len(response)
print(answer)   # 45
check("03.4", answer)
