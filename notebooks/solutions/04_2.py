# 44097 = holding register number 4097 = address 4096 = 0x1000; unit 5, function 3, count 2.
import modbus_edu as mb
from modbus_edu.exercises import check

address = mb.parse_reference("44097").address
answer = mb.AsciiFrame(unit=5, pdu=mb.ReadHoldingRegistersRequest(address=address, count=2)).encode()
print(answer)   # b':050310000002E6\r\n', source 004's request
check("04.2", answer)
