# 00 07 | 00 00 | 00 06 | 01 | 06 | 00 0A | 01 F4: write single register 10, value 0x01F4.
from modbus_edu.exercises import check

answer = 0x01F4
check("17.1", answer)
