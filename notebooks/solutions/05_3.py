# unit (1) + function (1) + byte count (1) + 10 registers x 2 bytes = 23.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.TcpFrame(transaction_id=1, unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 10))
wire = frame.encode()
answer = int.from_bytes(wire[4:6], "big")
print(answer)   # 23
check("05.3", answer)
