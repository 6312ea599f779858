"""The far end of the page's stand-in serial port: a WebSocket on 127.0.0.1, a pty, and pymodbus's RTU
server on the pty's other end, answering at the line's baud rate.

    python serial_bridge.py --baud 9600 --parity E --transcript bridge.jsonl

prints ``READY <port>`` once the WebSocket (``ws://127.0.0.1:<port>/serial``) and the slave are up. What
the page writes goes into the pty at once; what the slave answers comes back to the page one byte per
character time (start bit, 8 data bits, parity, stop bits at the baud rate), as a line at that speed
delivers it (the pty's own end opens without parity: a Linux pty refuses the parity bit). Every byte
each way is written to the transcript (seconds since start, direction, hex). A new page connection
replaces the previous one (a port chosen again). Ends on SIGTERM, or after ``--lifetime`` seconds at
the latest.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import signal
import time
import tty

from pymodbus.framer import FramerType
from pymodbus.server import ModbusSerialServer
from pymodbus.simulator import DataType, SimData, SimDevice
from tornado.httpserver import HTTPServer
from tornado.netutil import bind_sockets
from tornado.web import Application
from tornado.websocket import WebSocketHandler

REGISTERS = [100 + i for i in range(20)]
"""What unit 1's holding registers 0..19 hold when the bridge starts."""


class Bridge:
    def __init__(self, baud: int, parity: str, transcript: str) -> None:
        self.char_time = (1 + 8 + (0 if parity == "N" else 1) + 1) / baud
        self.master_fd, self.slave_fd = os.openpty()
        tty.setraw(self.slave_fd)
        self.tty = os.ttyname(self.slave_fd)
        self.page: WebSocketHandler | None = None
        self.start = time.monotonic()
        self.out = open(transcript, "a", buffering=1)  # noqa: SIM115 - closed by the process's end
        self.line: asyncio.Queue[bytes] = asyncio.Queue()

    def log(self, direction: str, data: bytes, **extra: object) -> None:
        self.out.write(json.dumps({"t": round(time.monotonic() - self.start, 6), "dir": direction,
                                   "hex": data.hex(" "), **extra}) + "\n")

    def from_page(self, data: bytes) -> None:
        self.log("page->slave", data)
        os.write(self.master_fd, data)

    def from_slave(self) -> None:
        try:
            data = os.read(self.master_fd, 4096)
        except OSError:
            return
        for byte in data:
            self.line.put_nowait(bytes([byte]))

    async def pace(self) -> None:
        """The slave's bytes to the page one after another, each at least a character time after the
        one before (a busy machine may stretch a gap, never shorten it), as the line carries them."""
        loop = asyncio.get_running_loop()
        last = 0.0
        while True:
            byte = await self.line.get()
            due = last + self.char_time
            if due > loop.time():
                await asyncio.sleep(due - loop.time())
            self.to_page(byte)
            last = loop.time()

    def to_page(self, data: bytes) -> None:
        self.log("slave->page", data)
        if self.page is not None:
            self.page.write_message(data, binary=True)


def handler(bridge: Bridge) -> type[WebSocketHandler]:
    class Serial(WebSocketHandler):
        def check_origin(self, origin: str) -> bool:
            return origin.startswith(("http://127.0.0.1:", "http://localhost:"))

        def open(self) -> None:
            if bridge.page is not None:
                bridge.page.close()
            bridge.page = self
            bridge.log("open", b"", settings=dict(self.request.query_arguments and {
                k: v[0].decode() for k, v in self.request.query_arguments.items()}))

        def on_message(self, message: str | bytes) -> None:
            if isinstance(message, bytes):
                bridge.from_page(message)

        def on_close(self) -> None:
            if bridge.page is self:
                bridge.page = None
            bridge.log("close", b"")

    return Serial


async def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--baud", type=int, default=9600)
    parser.add_argument("--parity", default="E")
    parser.add_argument("--transcript", required=True)
    parser.add_argument("--lifetime", type=float, default=600.0)
    args = parser.parse_args()
    bridge = Bridge(args.baud, args.parity, args.transcript)
    device = SimDevice(id=1, simdata=[SimData(0, values=REGISTERS, datatype=DataType.REGISTERS)])
    # a Linux pty refuses a parity bit (tcsetattr: EINVAL): the slave's end opens without one, and the
    # bridge paces its answers at the page's character time (11 bits at 8E1) all the same
    server = ModbusSerialServer(device, framer=FramerType.RTU, port=bridge.tty, baudrate=args.baud,
                                parity="N", stopbits=1, bytesize=8)
    await server.serve_forever(background=True)
    loop = asyncio.get_running_loop()
    loop.add_reader(bridge.master_fd, bridge.from_slave)
    pacer = asyncio.create_task(bridge.pace())
    sockets = bind_sockets(0, "127.0.0.1")
    HTTPServer(Application([(r"/serial", handler(bridge))])).add_sockets(sockets)
    done = asyncio.Event()
    loop.add_signal_handler(signal.SIGTERM, done.set)
    print(f"READY {sockets[0].getsockname()[1]} {bridge.tty}", flush=True)
    try:
        await asyncio.wait_for(done.wait(), args.lifetime)
    except TimeoutError:
        pass
    pacer.cancel()
    await server.shutdown()


if __name__ == "__main__":
    asyncio.run(main())
