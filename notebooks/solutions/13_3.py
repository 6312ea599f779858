# 4 = holding registers; number 21 is address 20 (numbers start at 1, addresses at 0).
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.parse_reference("40021").address
print(answer)          # 20
check("13.3", answer)
