# ':' + 2 characters per byte (address 05, PDU 03 06 + 6 data bytes, LRC) + CR LF = 1 + 2 x 10 + 2.
import modbus_edu as mb
from modbus_edu.exercises import check

response = mb.ReadHoldingRegistersResponse(registers=[0, 0, 0])
answer = len(mb.AsciiFrame(unit=5, pdu=response).encode())
print(answer)   # 23
check("04.3", answer)
