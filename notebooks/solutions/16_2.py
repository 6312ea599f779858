# 30001 -> address 0, 30007 -> 6, 30013 -> 12, 30071 and 30073 -> 70..73 (neighbours: one request).
# Each float32 takes two registers. Unit 1 (the meter's factory Addr), function 04, CRC low byte first.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = [mb.RtuFrame(unit=1, pdu=mb.ReadInputRegistersRequest(address=address, count=count)).encode()
          for address, count in [(0, 2), (6, 2), (12, 2), (70, 4)]]
for frame in answer:
    print(frame.hex(" ").upper())
check("16.2", answer)
