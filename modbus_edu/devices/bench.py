"""The bench meter: a single-phase energy meter that behaves on the bench as real ones do (notebook 16).

A first real device rarely answers at once.  :class:`BenchMeter` is a :class:`~modbus_edu.slave.Slave`
with what makes a real meter hard to reach, so each branch of a troubleshooting flowchart can be tried
without hardware:

* **its own line settings**, set on its front panel (:meth:`BenchMeter.set_menu`: address, baud rate,
  parity).  A loopback wire reads them (``serial_settings``): a master at another baud rate or parity
  puts characters on the line that the meter's UART assembles wrongly, its CRC check fails, and it stays
  silent (:func:`~modbus_edu.links.wire.uart_receive`).  The factory setting is even parity, which a
  master that assumes 8N1 never meets;
* **a slow first answer**: after power-up it answers its first request ``wake_time`` seconds late
  (0.8 s by default; the datasheet says "up to 1 s"), so a master with a short timeout fails once and
  then succeeds; :meth:`BenchMeter.power_cycle` makes the next answer slow again;
* **a sparse map**: only the registers of its datasheet exist; any other address is answered with
  exception 02, and any function but 04 with exception 01.

The wiring faults belong to the wire, not to the meter: A and B swapped is
``link.faults.swap_ab(unit)``, an adapter that echoes the request is ``link.faults.echo = True``
(:mod:`modbus_edu.links.faults`).

:data:`DATASHEET` is the excerpt of its manual that notebook 16's worksheet starts from; the map it
describes ships as ``maps/bench_meter.csv`` (reference numbers, loaded with ``numbering="reference"``).
"""

from __future__ import annotations

from importlib import resources
from typing import Any

from ..datamodel import DataBank
from ..errors import ConfigError, shown
from ..master import _check_seconds
from ..pdu import ExceptionCode, ExceptionResponse, FunctionCode, Pdu
from ..registermap import RegisterMap, load_map
from ..slave import Slave

__all__ = ["BENCH_BAUDRATES", "BENCH_VALUES", "DATASHEET", "BenchMeter", "bench_map", "bench_map_path"]

DATASHEET = """\
SPM-1 single-phase energy meter - Modbus RTU (excerpt of the manual)

Terminals   9: A    10: B    11: GND (common)
Settings    front panel, menu Set > Comm:
            Addr  1 ... 247                default 1
            bAud  2400 4800 9600 19200      default 9600
            PAr   nonE  EvEn  odd          default EvEn   (one stop bit)
            The first answer after power-up may take up to 1 s.

Input registers, read with function code 04. Each value is a 32-bit IEEE 754
floating-point number in two registers, low word first.

  Register   Parameter                Unit
  30001      Voltage                  V
  30007      Current                  A
  30013      Active power             W
  30071      Frequency                Hz
  30073      Import active energy     kWh
"""
"""The datasheet excerpt of the bench meter, as notebook 16's worksheet prints it."""

BENCH_BAUDRATES = (2400, 4800, 9600, 19200)
"""The baud rates the meter's menu offers."""

BENCH_VALUES = {"voltage": 229.6, "current": 4.82, "active_power": 1062.4, "frequency": 50.0,
                "import_energy": 1532.7}
"""What the meter measures on the bench: mains voltage and frequency, a kettle-sized load."""

_PARITIES = {"N": "N", "E": "E", "O": "O", "NONE": "N", "EVEN": "E", "ODD": "O"}


def bench_map_path() -> Any:
    """The bench meter's register map file (``maps/bench_meter.csv``, reference numbers)."""
    return resources.files("modbus_edu.devices") / "maps" / "bench_meter.csv"


def bench_map() -> RegisterMap:
    """The bench meter's register map, loaded with ``numbering="reference"`` (30001 is address 0)."""
    return load_map(bench_map_path(), numbering="reference")


class BenchMeter(Slave):
    """``BenchMeter(address=1, baudrate=9600, parity="E", wake_time=0.8)``: see the module's documentation.

    The front-panel settings are attributes (``address``, ``baudrate``, ``parity``); change them with
    :meth:`set_menu`, as on the device.  ``values`` (engineering values by point name) defaults to
    :data:`BENCH_VALUES`.
    """

    FUNCTIONS = frozenset({int(FunctionCode.READ_INPUT_REGISTERS)})
    """The function codes the meter answers; anything else gets exception 01."""

    def __init__(self, address: int = 1, baudrate: int = 9600, parity: str = "E", *, wake_time: float = 0.8,
                 values: dict[str, float] | None = None, name: str = "bench meter") -> None:
        super().__init__(1, DataBank(sparse=True), name=name,
                         identity={0: "SPM", 1: "SPM-1", 2: "1.0"})
        self.map = bench_map()
        """The meter's register map (:func:`bench_map`)."""
        for point in self.map:
            self.bank.input_registers.declare(point.address, point.count)
        self.map.store(self.bank, dict(BENCH_VALUES if values is None else values))
        self.address, self.baudrate, self.parity = 1, 9600, "E"
        self.set_menu(address=address, baudrate=baudrate, parity=parity)
        self.wake_time = _check_seconds("wake_time", wake_time)
        """Seconds the first answer after power-up comes late."""
        self.awake = False
        """False until the meter has answered once since power-up."""

    def __repr__(self) -> str:
        return (f"<BenchMeter Addr {self.address}, bAud {self.baudrate}, PAr {self.parity} "
                f"{self.counters.as_dict()}>")

    def set_menu(self, *, address: int | None = None, baudrate: int | None = None,
                 parity: str | None = None) -> None:
        """Change the front-panel settings: ``address`` 1..247, ``baudrate`` one of
        :data:`BENCH_BAUDRATES`, ``parity`` ``"N"``/``"E"``/``"O"`` (or ``"none"``, ``"even"``, ``"odd"``)."""
        if address is not None:
            if isinstance(address, bool) or not isinstance(address, int) or not 1 <= address <= 247:
                raise ConfigError(f"the meter's Addr menu offers 1 ... 247, got {shown(address)}")
            self.address = self.unit = address
        if baudrate is not None:
            if baudrate not in BENCH_BAUDRATES or isinstance(baudrate, bool):
                raise ConfigError(f"the meter's bAud menu offers {', '.join(map(str, BENCH_BAUDRATES))}, "
                                  f"got {shown(baudrate)}")
            self.baudrate = int(baudrate)
        if parity is not None:
            key = str(parity).upper()
            if key not in _PARITIES:
                raise ConfigError(f"the meter's PAr menu offers nonE, EvEn and odd, got {shown(parity)}")
            self.parity = _PARITIES[key]

    @property
    def serial_settings(self) -> dict[str, Any]:
        """The line settings of the menu, read by a loopback wire: ``{"baudrate": 9600, "parity": "E",
        "stopbits": 1}``."""
        return {"baudrate": self.baudrate, "parity": self.parity, "stopbits": 1}

    def power_cycle(self) -> None:
        """Switch the meter off and on: its next answer is slow again."""
        self.awake = False

    def response_delay(self, arrival_time: float) -> float:
        """The first answer after power-up comes ``wake_time`` late; then ``processing_time``."""
        if not self.awake:
            self.awake = True
            return self.wake_time + self.processing_time
        return self.processing_time

    def process(self, request: Pdu) -> Pdu:
        """Function 04 goes to the bank (addresses off the map: exception 02); anything else: 01."""
        function = getattr(request, "function_code", 0)
        if getattr(request, "role", None) == "request" and function not in self.FUNCTIONS:
            return ExceptionResponse(function, int(ExceptionCode.ILLEGAL_FUNCTION))
        return super().process(request)


# --- the troubleshooting flowchart -----------------------------------------------------------------
TROUBLESHOOTING: dict[str, tuple[tuple[str, str], ...]] = {
    "timeout\n(no answer at all)": (
        ("port", "the right port?\nlist_ports, dialout"),
        ("wiring", "A, B and common\n(0 V) connected?"),
        ("A/B", "swap A and B\n(harmless)"),
        ("settings", "baud, parity as\nthe meter's menu?"),
        ("first answer", "just switched on?\ntimeout 1 s,\nor retries=1"),
        ("unit", "unit = the\nmeter's Addr?"),
    ),
    "exception 02\n(illegal data address)": (
        ("numbering", "30001 is address 0:\n1-based? reference?"),
        ("table", "input (FC 4) or\nholding (FC 3)?"),
    ),
    "absurd values": (
        ("word order", "low word first?\nCDAB vs ABCD"),
        ("scale", "x10, x100, mA?\ntype int/float?"),
    ),
    "CRC errors": (
        ("baud", "baud rate as\nthe meter's?"),
        ("parity", "parity and\nstop bits?"),
        ("noise", "termination,\ncommon, cable"),
    ),
    "a bad response that\nis your own request": (
        ("echo", "adapter echo on?\nswitch it off, or\nstrip_echo"),
    ),
}
"""The bench's troubleshooting flowchart: each symptom and the checks to make, in order ((name, what
to look at) pairs).  :func:`troubleshooting_figure` draws it."""


def troubleshooting_figure():
    """Draw :data:`TROUBLESHOOTING` as a flowchart (one row per symptom, checks left to right).

    Returns the matplotlib figure (the course's width, :mod:`modbus_edu.plotstyle`)."""
    # matplotlib (the course extra) only when the figure is drawn: plotstyle imports it at its top
    from matplotlib.patches import FancyBboxPatch

    from ..plotstyle import figure

    rows = list(TROUBLESHOOTING.items())
    columns = 1 + max(len(checks) for _, checks in rows)
    fig, ax = figure(height=0.95 * len(rows) + 0.4)
    ax.set_xlim(-0.05, columns - 0.1)
    ax.set_ylim(-len(rows) + 0.35, 0.75)
    ax.axis("off")
    ax.set_title("What to check, symptom by symptom (left to right; stop when it answers)", loc="left")
    width, height = 0.88, 0.74

    def box(x: float, y: float, text: str, colour: str, bold: bool = False) -> None:
        ax.add_patch(FancyBboxPatch((x, y - height / 2), width, height, boxstyle="round,pad=0.02",
                                    facecolor=colour, edgecolor="#444444", linewidth=1.0))
        ax.text(x + width / 2, y, text, ha="center", va="center", fontsize=7.5,
                fontweight="bold" if bold else "normal")

    for row, (symptom, checks) in enumerate(rows):
        y = -row
        box(0, y, symptom, "#f4c7c3", bold=True)
        for column, (name, hint) in enumerate(checks, start=1):
            box(column, y, f"{name}\n{hint}", "#d9ead3")
            ax.annotate("", xy=(column, y), xytext=(column - 1 + width, y),
                        arrowprops={"arrowstyle": "->", "color": "#444444"})
    return fig
