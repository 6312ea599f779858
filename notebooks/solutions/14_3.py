# Unit 1 hears every frame on the line. Since the clear, with a good CRC: its two reads, the read for unit 2,
# unit 2's response, and the 0x0B request itself (counted before it is answered). The damaged request has a
# bad CRC: the serial-line guide counts it in 0x0C, not in 0x0B.
from modbus_edu.exercises import check

answer = 2 + 1 + 1 + 1
print(answer)   # 5
check("14.3", answer)
