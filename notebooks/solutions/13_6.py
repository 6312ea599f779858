# About 45% of the requests are answered; fraction ~ (timeout - reply) / loop time, so the loop is about
# 0.987 / 0.45 = 2.2 s: more than twice the master's timeout.  Fixes: a faster loop on the slave (no
# delay()), or a master timeout above the longest loop (about 2.5 s here).
import modbus_edu as mb
from modbus_edu.exercises import lab
from modbus_edu.exercises import check

poller = mb.Master(lab("slow slave"), timeout=1.0)
outcomes = poller.poll(interval=5.0, polls=300, function=4, unit=1, address=0, quantity=2)
fraction = poller.stats.valid_responses / poller.stats.requests
answer = (1.0 - 0.013) / fraction
print(f"{fraction:.0%} answered: loop time about {answer:.2f} s")
check("13.6", answer)
