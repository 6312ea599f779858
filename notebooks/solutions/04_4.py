# ':' | 05 address | 03 04 FF 06 00 64 the PDU | 8B the LRC | CR LF
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.AsciiFrame.decode(mb.parse_hex(":050304FF0600648B"), role="response")
answer = frame.pdu.encode()
print(answer.hex(" ").upper())   # 03 04 FF 06 00 64
check("04.4", answer)
