# MBAP: 00 02 = transaction 2 (big-endian), 00 00 = protocol, 00 06 = length, 01 = unit;
# PDU: 06 = write single register, 00 05 = address 5, 00 63 = value 99.
import modbus_edu as mb

frame = mb.TcpFrame.decode(mb.parse_hex("00 02 00 00 00 06 01 06 00 05 00 63"), role="request")
answer = (frame.transaction_id, frame.pdu.function_code, frame.pdu.address, frame.pdu.value)
print(answer)          # (2, 6, 5, 99)
