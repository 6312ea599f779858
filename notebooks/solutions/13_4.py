# The client wrote its id 3 low byte first: 03 00.  Read high byte first (the spec), that is 0x0300 = 768.
import modbus_edu as mb
from modbus_edu.exercises import check

captured = mb.TcpFrame.decode(mb.parse_hex("03 00 00 00 00 06 01 03 00 00 00 01"), role="request")
correct = mb.TcpFrame(transaction_id=3, unit=1, pdu=captured.pdu).encode()
answer = (captured.transaction_id, correct[:2].hex(" ").upper())
print(answer)          # (768, '00 03')
check("13.4", answer)
