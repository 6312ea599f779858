# Poll each wire and ask the slave what it saw (the monitor shows the same good request on every wire):
#  - other_unit climbs: the slave hears requests for another address -> wrong unit id;
#  - checksum_errors climb: its receiver, set to another baud rate, assembles other bytes than those
#    sent (slave.log shows them), so the CRC never matches -> wrong baud rate or parity;
#  - no slave at all on the wire, nothing counted -> no slave on the line (off, or not connected).
import modbus_edu as mb
from modbus_edu.exercises import lab
from modbus_edu.exercises import check

answer = {}
for name, wire in lab("silent").items():
    mb.Master(wire, timeout=0.2).poll(polls=3, function=3, unit=1, address=0, quantity=1)
    if not wire.slaves:
        answer[name] = "no slave on the line"
    elif wire.slaves[0].counters.other_unit:
        answer[name] = "wrong unit id"
    else:
        answer[name] = "wrong baud rate or parity"
print(answer)
check("13.1", answer)
