# pyserial carries a serial line over raw TCP with its socket:// URL handler.
from modbus_edu.exercises import check

answer = "socket://192.168.1.60:4001"
check("11.3", answer)
