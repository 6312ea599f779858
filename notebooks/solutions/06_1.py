# FC3 for 10 registers: request 8 bytes, response 5 + 2 x 10 = 25 bytes.
# (8 + 3.5 + 25 + 3.5) characters x 10 bits / 9600 baud = 41.67 ms.  Measured on a loopback line:
import modbus_edu as mb
from modbus_edu.exercises import check

link = mb.loopback_serial(mb.Slave(unit=1), baudrate=9600)
master = mb.Master(link)
master.read_holding_registers(unit=1, address=0, count=10)
answer = link.clock.now * 1000
print(f"{answer:.2f} ms")   # 41.67 ms
check("06.1", answer)
