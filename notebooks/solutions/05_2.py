# MBAP: transaction 00 07, protocol 00 00, length 00 06 (unit + 5-byte PDU), unit 01; PDU 06 00 00 04 D2.
import modbus_edu as mb
from modbus_edu.exercises import check

pdu = mb.WriteSingleRegisterRequest(address=0, value=1234)
answer = mb.TcpFrame(transaction_id=7, unit=1, pdu=pdu).encode()
print(answer.hex(" ").upper())   # 00 07 00 00 00 06 01 06 00 00 04 D2
check("05.2", answer)
