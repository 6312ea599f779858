# The twelve answers, each one idea the course teaches (notebook 17 asks them again, in another order):
#  1 C  Modbus fixes the byte order in a register, not the order of two registers
#  2 A  every MBAP field goes high byte first: 10 is 00 0A
#  3 D  40001 is reference number 1, address 0: the 4 never travels
#  4 D  register 10, counted from 1, is address 9
#  5 B  on the wire the CRC goes low byte first: 37 4B
#  6 D  Modbus/TCP has no CRC: TCP checks every byte
#  7 C  a slave says nothing to a request with a wrong CRC
#  8 B  a missing address is exception 02
#  9 C  the MBAP length counts the unit and the PDU: 1 + 5 = 6
# 10 C  3.5 character times of silence end an RTU frame
# 11 B  a pause of more than 1.5 character times breaks a frame: the slave drops it
# 12 A  an exception response sets the top bit: 03 becomes 83
from modbus_edu.exercises import check

answer = "CADDBDCBCCBA"
check("00.0", answer)
