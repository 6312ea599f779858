# THD_AL1 is at 0x36-0x37, THD_AL2 at 0x38-0x39, THD_AL3 at 0x3A-0x3B: six consecutive registers from 0x36.
from modbus_edu.devices import METER_BY_NAME
from modbus_edu.exercises import check

first = METER_BY_NAME["THD_AL1"].address
answer = (3, first, 6)
print(answer)                                      # (3, 54, 6)
check("10.3", answer)
