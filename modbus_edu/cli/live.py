"""The polling engine of ``poll`` and its two views: a live table refreshed in place (rich) on a terminal,
and plain lines anywhere else (a pipe, a file, a log).

A :class:`Block` is one read request (function, address, count) and the values cut out of its registers
(:class:`Cell`: a display format, a scale and a unit, or a register map's point). :class:`Poller` asks
every block once per cycle and keeps, per block, the last status and response time and the count of
each kind of failure; the views only show what it holds.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, TextIO

from rich.table import Table

from ..codes import _hex
from ..errors import ConfigError, ModbusError, ModbusExceptionError, ModbusTimeoutError
from ..registermap import Point
from ..values import TYPES, decode_value, format_registers
from .common import _one_line

_READERS = {1: "read_coils", 2: "read_discrete_inputs", 3: "read_holding_registers",
            4: "read_input_registers"}
_PLAIN_FORMATS = ("hex", "binary", "unsigned", "signed", "ascii_char", "ascii_value")
_PREFIX = {1: "0", 2: "1", 3: "4", 4: "3"}


def format_width(fmt: str) -> int:
    """Registers per value of a display format: 1, or 2/4 for the wide types (``float64_ABCD``: 4)."""
    kind = fmt.lower().rpartition("_")[0]
    return TYPES[kind].registers if kind in TYPES else 1


def _number(value: float | int) -> str:
    return f"{value:.10g}" if isinstance(value, float) else str(value)


@dataclass
class Cell:
    """One value of a block: ``offset`` registers (or bits) into it, ``width`` long."""

    label: str
    offset: int
    width: int = 1
    fmt: str = "unsigned"
    scale: float = 1.0
    unit: str = ""
    point: Point | None = None

    def text(self, function: int, values: Sequence[Any]) -> str:
        """The value as shown: bits 1/0; registers in the display format, scaled if asked."""
        part = list(values[self.offset : self.offset + self.width])
        if function in (1, 2):
            return "1" if part[0] else "0"
        if self.point is not None:
            return _number(self.point.decode(part))
        if self.fmt in _PLAIN_FORMATS:
            if self.scale == 1 or self.fmt not in ("unsigned", "signed"):
                return format_registers(part, self.fmt)[0]
            raw = decode_value(part, "int16" if self.fmt == "signed" else "uint16")
            return _number(raw * self.scale)
        if self.scale == 1:
            return format_registers(part, self.fmt)[0]
        type_, _, order = self.fmt.rpartition("_")
        return _number(decode_value(part, type_, order) * self.scale)


@dataclass
class Block:
    """One read request of a poll and what became of it."""

    function: int
    address: int
    count: int
    cells: list[Cell]
    values: list[Any] = field(default_factory=list)
    status: str = "-"
    note: str = ""
    seconds: float | None = None
    ok: int = 0
    timeouts: int = 0
    exceptions: int = 0
    errors: int = 0

    @property
    def title(self) -> str:
        last = self.address + self.count - 1
        ref = f" ({_PREFIX[self.function]}x{self.address + 1:04d})" if self.address < 65535 else ""
        return f"FC {self.function} {self.address}..{last}{ref}"


def plain_block(function: int, address: int, count: int, fmt: str, scale: float = 1.0,
                unit: str = "") -> Block:
    """A block of ``count`` registers (or bits) read as ``fmt``: one cell per value, labelled by address."""
    width = 1 if function in (1, 2) else format_width(fmt)
    if count < width:
        raise ConfigError(f"--format {fmt} needs {width} registers per value, but --count {count} reads "
                          f"{count}: use --count {width} (or a multiple)")
    if count % width:
        raise ConfigError(f"--format {fmt} takes {width} registers per value: --count {count} leaves "
                          f"{count % width} over; use --count {count - count % width} or "
                          f"{count - count % width + width}")
    cells = [Cell(str(address + i), i, width, fmt, scale, unit) for i in range(0, count, width)]
    return Block(function, address, count, cells)


def map_blocks(register_map: Any, max_gap: int = 0) -> list[Block]:
    """The blocks that read a register map: its planned requests, one cell per point, named."""
    blocks = []
    for poll in register_map.plan(max_gap):
        cells = [Cell(p.name, p.address - poll.address, p.count, p.type, p.scale, p.unit, p)
                 for p in poll.points]
        blocks.append(Block(poll.function, poll.address, poll.count, cells))
    return blocks


class Poller:
    """Ask every block once per :meth:`cycle` through ``master``, keeping each one's last state."""

    def __init__(self, master: Any, unit: int, blocks: list[Block]) -> None:
        self.master = master
        self.unit = unit
        self.blocks = blocks
        self.cycles = 0
        self.started = time.monotonic()

    def cycle(self) -> list[Block]:
        self.cycles += 1
        for block in self.blocks:
            read = getattr(self.master, _READERS[block.function])
            begin = time.monotonic()
            try:
                block.values = read(unit=self.unit, address=block.address, count=block.count)
            except ModbusTimeoutError as exc:
                block.status, block.note, block.values = "timeout", _one_line(exc), []
                block.timeouts += 1
            except ModbusExceptionError as exc:
                block.status, block.note, block.values = f"exception {exc.code:02X}", exc.meaning, []
                block.exceptions += 1
            except ModbusError as exc:
                if isinstance(exc, ConfigError):
                    raise
                block.status, block.note, block.values = "error", _one_line(exc), []
                block.errors += 1
            else:
                block.status, block.note = "ok", ""
                block.ok += 1
            block.seconds = time.monotonic() - begin
        return self.blocks

    def rate(self) -> float:
        """Polls (cycles) per second since the start."""
        elapsed = time.monotonic() - self.started
        return self.cycles / elapsed if elapsed > 0 else 0.0

    def texts(self) -> list[tuple[Block, Cell, str]]:
        """Every cell with its text ('' where its block failed this cycle)."""
        return [(b, c, c.text(b.function, b.values) if b.values else "")
                for b in self.blocks for c in b.cells]


def stats_line(stats: Any, poller: Poller | None = None) -> str:
    latencies = list(getattr(stats, "latencies", []) or [])
    parts = [
        f"requests {stats.requests}",
        f"valid {stats.valid_responses}",
        f"timeouts {stats.timeouts}",
        f"checksum errors {stats.checksum_errors}",
        f"exceptions {stats.exceptions}",
    ]
    if latencies:
        avg = sum(latencies) / len(latencies) * 1000
        parts.append(f"latency avg {avg:.1f} ms, max {max(latencies) * 1000:.1f} ms")
    if poller is not None and poller.cycles > 1:
        parts.append(f"{poller.rate():.1f} polls/s")
    return "stats: " + ", ".join(parts)


def line_of(poller: Poller, stream: TextIO) -> None:
    """The lines view: one line per poll with every value; a failed block's own line."""
    n = poller.cycles
    shown = []
    for block in poller.blocks:
        if block.status != "ok":
            what = block.status if block.status != "error" else "error"
            note = block.note
            print(f"#{n} {what}: {note}", file=stream)
            continue
        for cell in block.cells:
            text = cell.text(block.function, block.values)
            if cell.point is not None:
                shown.append(f"{cell.label}={text}{' ' + cell.unit if cell.unit else ''}")
            else:
                shown.append(f"[{cell.label}] {text}{' ' + cell.unit if cell.unit else ''}")
    if shown:
        print(f"#{n} " + "  ".join(shown), file=stream)


def table_of(poller: Poller, unit: int, where: str) -> Any:
    """The live view: a rich Table of every value (name, raw registers, value, status, time), with the
    statistics of each block and of the whole poll under it."""
    stats = poller.master.stats
    table = Table(title=f"unit {unit} on {where}: poll {poller.cycles}, {poller.rate():.1f} polls/s",
                  caption=stats_line(stats, poller), title_justify="left", caption_justify="left")
    for name, justify in (("name", "left"), ("raw", "left"), ("value", "right"), ("unit", "left"),
                          ("status", "left"), ("ms", "right"), ("block", "left"),
                          ("ok/timeouts/exceptions/errors", "right")):
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    for block in poller.blocks:
        ms = f"{block.seconds * 1000:.1f}" if block.seconds is not None else ""
        style = "green" if block.status == "ok" else "red"
        counts = f"{block.ok}/{block.timeouts}/{block.exceptions}/{block.errors}"
        for cell in block.cells:
            if block.values:
                part = block.values[cell.offset : cell.offset + cell.width]
                raw = " ".join("1" if v else "0" for v in part) if block.function in (1, 2) else \
                    _hex(b"".join(int(v).to_bytes(2, "big") for v in part))
                value = cell.text(block.function, block.values)
            else:
                raw, value = "", ""
            table.add_row(cell.label, raw, value, cell.unit, f"[{style}]{block.status}[/{style}]", ms,
                          block.title, counts)
    return table

