# (8 + 3.5 + 7 + 3.5) = 22 characters x 10 bits / 19200 baud = 11.46 ms per transaction: 87.3 per second.
import modbus_edu as mb
from modbus_edu.exercises import check

link = mb.loopback_serial(mb.Slave(unit=1), baudrate=19200)
mb.Master(link).read_holding_registers(unit=1, address=0, count=1)
answer = 1 / link.clock.now
print(f"{answer:.2f} transactions per second")   # 87.27
check("06.3", answer)
