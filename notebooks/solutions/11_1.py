# MBAP: 00 2A = transaction 42 (big-endian), 00 00 = protocol, 00 06 = length, 11 = unit 17;
# PDU: 06 = write single register, 00 10 = address 16, 01 F4 = value 500.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.TcpFrame.decode(mb.parse_hex("00 2A 00 00 00 06 11 06 00 10 01 F4"), role="request")
answer = (frame.transaction_id, frame.pdu.function_code, frame.pdu.address, frame.pdu.value)
print(answer)          # (42, 6, 16, 500)
check("11.1", answer)
