"""The page's side of :func:`~modbus_edu.links.browser_serial.browser_serial`: a small anywidget whose
JavaScript (``webserial_port.js``, beside this file) owns the browser's serial port.

It holds no protocol: it asks for a port on a click (``navigator.serial.requestPort()``), opens it with
the line settings, sends every burst of bytes it reads to the kernel as a message, and writes the bytes
the kernel sends. Without Web Serial (Firefox, Safari) it shows :data:`NO_WEB_SERIAL`, one line.

anywidget and traitlets are loaded on first use (they come with the ``course`` extra and are pure
Python, so the widget works in JupyterLite too); ``import modbus_edu`` does not load them.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..errors import ConfigError, MissingDependencyError, require
from .wire import SerialTiming

__all__ = ["NO_WEB_SERIAL", "PARITY_NAMES", "make_port", "port_class"]

NO_WEB_SERIAL = ("This browser has no Web Serial, so a notebook cannot reach a device on this computer's "
                 "serial port from here: open it in Chrome or Edge (on a desktop). The rest of the notebook "
                 "runs as it is.")
"""The one line a browser without ``navigator.serial`` shows (and a request there raises)."""

PARITY_NAMES = {"N": "none", "E": "even", "O": "odd"}
"""Modbus's parity letters in the words of the Web Serial API's ``SerialOptions.parity``."""

SCRIPT = Path(__file__).with_name("webserial_port.js")


@functools.cache
def port_class() -> type:
    """The widget's class (made on first use: anywidget is imported only then)."""
    anywidget = require("anywidget", "the browser's serial port (mb.browser_serial)")
    traitlets = require("traitlets", "the browser's serial port (mb.browser_serial)")

    class WebSerialPort(anywidget.AnyWidget):
        """A *choose serial port* button; the port it opens is read and written for the kernel."""

        _esm = SCRIPT.read_text(encoding="utf-8")
        baudrate = traitlets.Int(9600).tag(sync=True)
        parity = traitlets.Unicode("even").tag(sync=True)
        stopbits = traitlets.Int(1).tag(sync=True)
        databits = traitlets.Int(8).tag(sync=True)
        status = traitlets.Unicode("").tag(sync=True)
        """What the page says of its port, in one line (set by the page)."""
        no_web_serial = traitlets.Unicode(NO_WEB_SERIAL).tag(sync=True)
        choose_clicks = traitlets.Int(0).tag(sync=True)
        """Clicks on *choose serial port* (the page's views tell its port owner this way)."""

        def __init__(self, **kwargs: Any) -> None:
            super().__init__(**kwargs)
            self._listeners: list[Callable[[dict[str, Any]], None]] = []
            self.on_msg(self._from_page)

        def listen(self, callback: Callable[[dict[str, Any]], None]) -> None:
            """Hand every message of the page to ``callback`` (the link's ``deliver``)."""
            self._listeners.append(callback)

        def _from_page(self, _widget: Any, content: Any, _buffers: Any) -> None:
            for callback in list(self._listeners):
                callback(content)

        def write(self, data: bytes) -> None:
            """Ask the page to write ``data`` to the port."""
            self.send({"type": "write", "hex": bytes(data).hex()})

        def close(self) -> None:
            """Ask the page to close the port."""
            self.send({"type": "close"})

        def __repr__(self) -> str:
            settings = f"{self.baudrate} baud {self.databits}{self.parity[0].upper()}{self.stopbits}"
            return f"WebSerialPort({settings}: {self.status or 'no port chosen'})"

    return WebSerialPort


def make_port(timing: SerialTiming) -> Any:
    """The widget for a line with these settings; the Web Serial API knows 7 or 8 data bits and 1 or 2
    stop bits only."""
    if timing.stopbits not in (1, 2):
        raise ConfigError(f"the browser's serial port has 1 or 2 stop bits, not {timing.stopbits}")
    if timing.bytesize not in (7, 8):
        raise ConfigError(f"the browser's serial port has 7 or 8 data bits, not {timing.bytesize}")
    try:
        cls = port_class()
    except MissingDependencyError as exc:  # no anywidget here: say so on every request, go on
        return NoWidget(str(exc))
    return cls(baudrate=int(timing.baudrate), parity=PARITY_NAMES[timing.parity],
               stopbits=int(timing.stopbits), databits=int(timing.bytesize))


class NoWidget:
    """The page's side where the widget cannot be made (anywidget is not installed): no port can be
    chosen, and each request says why in one line, so that a notebook prints it and goes on."""

    def __init__(self, reason: str) -> None:
        self.reason = reason

    def listen(self, callback: Callable[[dict[str, Any]], None]) -> None:
        callback({"type": "error", "reason": self.reason})

    def write(self, data: bytes) -> None:  # pragma: no cover - the link never writes without an open port
        raise ConfigError(self.reason)

    def close(self) -> None:
        """Nothing to close."""
