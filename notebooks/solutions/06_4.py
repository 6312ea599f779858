# A damaged request: the slave's CRC check fails, it stays silent, and the master waits its timeout out.
import modbus_edu as mb
from modbus_edu.exercises import check

link = mb.loopback_serial(mb.Slave(unit=1))
link.faults.flip_bits(1, target="request")
try:
    mb.Master(link, timeout=0.5).read_holding_registers(unit=1, address=0, count=1)
except mb.ModbusError as error:
    print(error)
    answer = type(error)   # mb.ModbusTimeoutError
check("06.4", answer)
