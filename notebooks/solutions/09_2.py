# Register 150 is reference 40150 (address 149); declare every number from 150 to 175 and 200 to 225.
from modbus_edu.devices import ArduinoSlave
from modbus_edu.exercises import check

board = ArduinoSlave(unit=1, sketch=False)
for number in [*range(150, 176), *range(200, 226)]:
    board.add(40000 + number)
print(board.bank)                   # 52 holding registers, nothing else
answer = board
check("09.2", answer)
