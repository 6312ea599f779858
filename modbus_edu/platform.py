"""Where the library runs: a local Python, or a browser (JupyterLite on Pyodide).

In a browser, everything that works on bytes runs (codecs, ``explain``, Master and Slave over the
loopback links, devices, register maps, exercises), but nothing can open a socket: a web page cannot
listen on a port, nor reach a Modbus/TCP device.  Servers, gateways and network links call
:func:`require_sockets` first, so they refuse with a :class:`~modbus_edu.errors.BrowserError` that says
so, instead of failing deep inside the socket module.
"""

from __future__ import annotations

import sys

from .errors import BrowserError

IN_BROWSER = sys.platform == "emscripten"
"""True under Pyodide (JupyterLite): Python compiled to WebAssembly, running in a web page."""

BINDER = "https://mybinder.org/v2/gh/modbus-edu/modbus_edu/main"
"""Where the course runs with a real Python and sockets, with nothing to install."""


def require_sockets(what: str) -> None:
    """Raise :class:`BrowserError` if running in a browser, where ``what`` cannot work."""
    if IN_BROWSER:
        raise BrowserError(
            f"{what} needs a local Python or Binder ({BINDER}): this notebook runs in a web browser, "
            "which cannot listen on a socket or open a TCP/UDP connection to a device")
