# FC 16 from 98, quantity 3: addresses 98, 99, 100. 100 is outside the operator's 0..99: exception 01.
from modbus_edu.exercises import check

answer = 1
check("17.2", answer)
