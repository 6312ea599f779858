# Try each pause on a loopback wire: the slave answers only when the pause is at most 1.5 characters.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = []
for chars in [1.0, 1.4, 2.0, 3.0, 5.0]:
    link = mb.loopback_serial(mb.Slave(unit=1), baudrate=9600)
    link.faults.insert_gap(at_byte=4, chars=chars, target="request")
    try:
        mb.Master(link, timeout=0.1).read_holding_registers(unit=1, address=0, count=1)
    except mb.ModbusError:
        answer.append(chars)
print(answer)          # [2.0, 3.0, 5.0]
check("08.3", answer)
