# PF2 is at 0x12-0x13, VL3 at 0x14-0x15, AL3 at 0x16-0x17: six consecutive registers from 0x12.
from modbus_edu.devices import METER_BY_NAME

first = METER_BY_NAME["PF2"].address
answer = (3, first, 6)
print(answer)                                      # (3, 18, 6)
