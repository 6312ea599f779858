# Address 5 holds 100 + 5 x 10 = 150 = 0x0096.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.format_registers([100 + 5 * 10], "hex")[0]
print(answer)          # 0x0096
check("12.1", answer)
