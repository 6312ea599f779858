# pyserial carries a serial line over raw TCP with its socket:// URL handler.
answer = "socket://192.168.1.60:4001"
