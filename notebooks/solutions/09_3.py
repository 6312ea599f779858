# The longest loop is 1.65 s x 1.1 = 1.815 s; the reply and its final silence add 13 ms at 9600 baud.
# Any timeout from about 1.83 s works; 2 s is a round number with some margin.
from modbus_edu.devices import loop_time_experiment
from modbus_edu.devices.arduino import SLOW_LOOP
from modbus_edu.exercises import check

answer = 2.0
print(loop_time_experiment([SLOW_LOOP], timeout=answer))     # [(1.65, 1.0)]
check("09.3", answer)
