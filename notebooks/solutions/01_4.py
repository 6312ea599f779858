# Declare numbers 100-149 and 300-309 (addresses 99-148 and 299-308) in a sparse bank and count them.
import modbus_edu as mb
from modbus_edu.exercises import check

bank = mb.DataBank(sparse=True)
bank.holding_registers.declare(99, 50)    # numbers 100..149: 149 - 100 + 1 = 50 registers
bank.holding_registers.declare(299, 10)   # numbers 300..309: 10 registers
answer = len(bank.holding_registers)
print(answer)   # 60
check("01.4", answer)
