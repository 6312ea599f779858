# Three polls use 280, 281 and 282; the next request carries 283 = 0x011B, written high byte first.
from modbus_edu.widgets import TestTool
from modbus_edu.exercises import check

server = TestTool("tcp_server", unit=1, length=1)
client = TestTool("tcp_client", partner=server, unit=1, length=1, transaction_id=280)
client.run_polls(3)
tid = client.transaction_id.value
answer = (tid, tid.to_bytes(2, "big").hex(" ").upper())
print(answer)          # (283, '01 1B')
check("12.3", answer)
