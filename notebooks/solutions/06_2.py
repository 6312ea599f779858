# The slave implements function 5, but its sparse bank has no coils: exception 02, illegal data address.
import modbus_edu as mb
from modbus_edu.exercises import check

bank = mb.DataBank(sparse=True)
bank.holding_registers.declare(0, 20)
master = mb.Master(mb.loopback_serial(mb.Slave(unit=1, bank=bank)))
try:
    master.write_single_coil(unit=1, address=0, value=True)
except mb.ModbusExceptionError as error:
    print(error)
    answer = error.code   # 2
check("06.2", answer)
