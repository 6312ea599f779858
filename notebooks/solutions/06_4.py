# No slave 2 on the line: nobody answers, so the master waits its timeout out.
import modbus_edu as mb

master = mb.Master(mb.loopback_serial(mb.Slave(unit=1)), timeout=0.5)
try:
    master.read_holding_registers(unit=2, address=0, count=1)
except mb.ModbusError as error:
    print(error)
    answer = type(error)   # mb.ModbusTimeoutError
