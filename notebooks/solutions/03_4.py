# 1 (address) + 1 (function) + 1 (byte count) + 2 x 10 (registers) + 2 (CRC) = 25 = 5 + 2N.
import modbus_edu as mb

response = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 10)).encode()
answer = len(response)
print(answer)   # 25
