# explain() computes CRC 0x0A84, which goes on the wire low byte first: 84 0A.  The tool sent 0A 84.
import modbus_edu as mb
from modbus_edu.exercises import check

print(mb.explain("01 03 00 00 00 01 0A 84"))
answer = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
print(answer.hex(" ").upper())          # 01 03 00 00 00 01 84 0A
check("13.5", answer)
