# A gateway keeps the unit and the PDU, drops the CRC, and puts an MBAP header in front.
import modbus_edu as mb
from modbus_edu.exercises import check

rtu = mb.RtuFrame.decode(mb.parse_hex("03 03 00 00 00 03 04 29"), role="request")
answer = mb.TcpFrame(transaction_id=7, unit=rtu.unit, pdu=rtu.pdu).encode()
print(answer.hex(" ").upper())          # 00 07 00 00 00 06 03 03 00 00 00 03
check("11.2", answer)
