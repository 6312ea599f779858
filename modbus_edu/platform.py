"""Where the library runs: a local Python, or a browser (JupyterLite on Pyodide).

In a browser, everything that works on bytes runs (codecs, ``explain``, Master and Slave over the
loopback links, devices, register maps, exercises), but nothing can open a socket: a web page cannot
listen on a port, nor reach a Modbus/TCP device.  Servers, gateways and network links call
:func:`require_sockets` first, so they refuse with a :class:`~modbus_edu.errors.BrowserError` that says
so, instead of failing deep inside the socket module.
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType

from .errors import BrowserError, MissingDependencyError, require

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


def require_plotting(what: str = "This notebook") -> ModuleType:
    """Return matplotlib, or raise :class:`~modbus_edu.errors.MissingDependencyError` saying in one line
    what needs it and where it runs: in a browser, a copy of the course that carries no matplotlib (the
    offline site); elsewhere, the course's extra to install."""
    try:
        return importlib.import_module("matplotlib")
    except ImportError:
        if IN_BROWSER:
            raise MissingDependencyError(
                f"{what} draws with matplotlib, which this copy of the course does not carry (it runs "
                f"offline, in a web browser): open it on a local Python or on Binder ({BINDER})") from None
        return require("matplotlib", what)
