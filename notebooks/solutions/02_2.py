# One request reads at most 125 registers: 125 + 125 + 50 = 300, so three requests.
import math

import modbus_edu as mb
from modbus_edu.exercises import check

answer = math.ceil(300 / mb.MAX_READ_REGISTERS)
print(answer)   # 3
check("02.2", answer)
