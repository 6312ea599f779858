# a) unit 5: the gateway asks the bus, nobody answers within its 0.2 s: 0B (target device failed to respond).
# b) unit 0: this gateway has no path for it (a broadcast gets no answer): 0A at once.
# c) unit 2, holding register 10: the pump has only register 0; its exception 02 passes through unchanged.
# d) unit 5 with a client timeout of 0.1 s: the gateway's 0B comes after 0.2 s of bus time, too late.
answer = {"a": 0x0B, "b": 0x0A, "c": 0x02, "d": "timeout"}
