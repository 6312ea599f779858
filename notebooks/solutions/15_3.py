# a) unit 248: reserved on a serial line, so this gateway has no path to it: 0A at once.
# b) the meter's cable is off: the gateway asks the bus, nobody answers within its 0.2 s: 0B.
# c) an unknown function code: exception 01 (illegal function), passed on unchanged.
# d) the gateway's 0B comes after 0.2 s, but this client gave up after 0.1 s: it sees a timeout.
from modbus_edu.exercises import check

answer = {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"}
check("15.3", answer)
