# Timeout row of the flowchart: the port works (TX LED), A, B and common are connected, the scan tried every
# setting and every unit, the menu matches the script. What is left is which way round A and B go.
from modbus_edu.exercises import check

answer = "swap A and B"
check("16.3", answer)
