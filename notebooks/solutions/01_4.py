# Declare numbers 150-175 and 200-225 (addresses 149-174 and 199-224) in a sparse bank and count them.
import modbus_edu as mb

bank = mb.DataBank(sparse=True)
bank.holding_registers.declare(149, 26)   # numbers 150..175: 175 - 150 + 1 = 26 registers
bank.holding_registers.declare(199, 26)   # numbers 200..225
answer = len(bank.holding_registers)
print(answer)   # 52
