# The same twelve questions as 00.0, in notebook 17's order; the answers, each with its idea:
#  1 C  the MBAP length counts the unit and the PDU: 1 + 5 = 6
#  2 C  a slave says nothing to a request with a wrong CRC
#  3 B  on the wire the CRC goes low byte first: 37 4B
#  4 D  Modbus/TCP has no CRC: TCP checks every byte
#  5 C  3.5 character times of silence end an RTU frame
#  6 A  every MBAP field goes high byte first: 10 is 00 0A
#  7 A  an exception response sets the top bit: 03 becomes 83
#  8 B  a missing address is exception 02
#  9 D  40001 is reference number 1, address 0: the 4 never travels
# 10 C  Modbus fixes the byte order in a register, not the order of two registers
# 11 D  register 10, counted from 1, is address 9
# 12 B  a pause of more than 1.5 character times breaks a frame: the slave drops it
from modbus_edu.exercises import check

answer = "CCBDCAABDCDB"
check("17.0", answer)
