# Input registers are read with function 4; the rest are the device and polling parameters.
from modbus_edu.widgets import TestTool
from modbus_edu.exercises import check

answer = TestTool("rtu_master", unit=7, function=4, address=10, length=4, interval=0.5)
check("12.2", answer)
