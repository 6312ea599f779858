"""Register maps: a device's datasheet table as a file, typed points, and the poll planner.

A register map file is CSV with a header row and these columns (``order``, ``scale``, ``unit`` optional)::

    name,table,address,type,order,scale,unit
    voltage_l1,input,0,float32,CDAB,1,V

* ``table`` is ``holding`` (read with FC 3) or ``input`` (FC 4);
* ``address`` is the protocol address (0-based), as it goes on the wire. A datasheet that numbers
  registers from 1 (or as reference numbers 30001/40001) is converted with ``numbering="1-based"``
  (or ``"reference"``) when loading: the file keeps the datasheet's numbers, the map holds addresses.
  A file says how it numbers in a line before its header, ``# numbering: reference`` (or ``0-based``,
  ``1-based``), so that no reader has to guess; a file that does not say, and whose addresses look
  like reference numbers (30001 in the input table), is refused rather than read from address 30001;
* ``type`` and ``order`` are those of :mod:`modbus_edu.values` (``uint16`` ... ``float64``,
  ``ABCD`` ``CDAB`` ``BADC`` ``DCBA``); ``scale`` multiplies the raw value (0.1 for "x10" values).

:func:`plan_polls` groups the points of one table into the fewest legal requests: at most 125
registers each (the spec's limit for FC 3 and FC 4), never across a point, and never across a gap
longer than ``max_gap`` registers (a device may answer 02 illegal data address for registers it does
not have, so by default no gap is read at all).

Every load error is a :class:`RegisterMapError`: one line naming the file's line and the column.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from .errors import ModbusError, shown
from .values import ORDERS, TYPES, decode_value, encode_value, register_count

__all__ = [
    "MAX_READ_REGISTERS",
    "Point",
    "Poll",
    "RegisterMap",
    "RegisterMapError",
    "datasheet_to_address",
    "NUMBERINGS",
    "load_map",
    "plan_polls",
]

#: The most registers one FC 3 or FC 4 request may ask for (the spec's 0x007D).
MAX_READ_REGISTERS = 125

_TABLES = {"holding": 3, "input": 4}
_COLUMNS = ("name", "table", "address", "type", "order", "scale", "unit")
_REQUIRED = ("name", "table", "address", "type")
#: The longest field a register map may hold (a name, a unit, a number): a datasheet never needs more.
MAX_FIELD = 200
#: The largest register map file read (65536 registers x 2 tables fit in a few MB).
MAX_FILE_BYTES = 8 * 1024 * 1024
#: A scale is a finite, non-zero factor between these sizes (0.001 for "x1000", 1000 for kilo-units).
SCALE_RANGE = (1e-9, 1e9)


class RegisterMapError(ModbusError):
    """A register map file or point is wrong: the message names the line and the column."""


@dataclass(frozen=True)
class Point:
    """One named value of a device: where it lives (``table``, ``address``) and how to read it."""

    name: str
    table: str
    address: int
    type: str = "uint16"
    order: str = "ABCD"
    scale: float = 1.0
    unit: str = ""

    @property
    def count(self) -> int:
        """How many registers the point occupies."""
        return register_count(self.type)

    @property
    def function(self) -> int:
        """The function code that reads it: 3 (holding registers) or 4 (input registers)."""
        return _TABLES[self.table]

    def __post_init__(self) -> None:
        check_scale(self.scale, f"point {shown(self.name)}")

    def decode(self, registers: Sequence[int]) -> float | int:
        """The value in engineering units from the point's own registers."""
        raw = decode_value(registers, self.type, self.order)
        return raw if self.scale == 1 else raw * self.scale


@dataclass(frozen=True)
class Poll:
    """One request of a plan: function 3 or 4, a start ``address``, a ``count`` and the points it covers."""

    function: int
    address: int
    count: int
    points: tuple[Point, ...]


def check_scale(scale: object, where: str) -> float:
    """``scale`` as a float, or a RegisterMapError: 0, inf, nan, subnormal or absurd sizes are refused."""
    low, high = SCALE_RANGE
    if isinstance(scale, bool) or not isinstance(scale, (int, float)):
        raise RegisterMapError(f"{where}: scale {shown(scale)} is not a number")
    try:
        value = float(scale)
    except OverflowError:
        value = float("inf")
    if value != value or not low <= abs(value) <= high:
        raise RegisterMapError(
            f"{where}: scale {shown(scale)} must be a finite, non-zero number between {low:g} and "
            f"{high:g} in size (0.1 for a value sent x10, 1000 for one sent in kilo-units)"
        )
    return value


def _decode_text(data: bytes, where: str) -> str:
    """A register map file's bytes as text: UTF-8, with or without a byte-order mark; anything else is
    refused by name (a spreadsheet's "Unicode text" is UTF-16, an old one's CSV is often latin-1)."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise RegisterMapError(
            f"{where}: the file is UTF-16 (it starts with the byte-order mark {data[:2].hex(' ').upper()}); "
            f"save it as 'CSV UTF-8'"
        )
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    nul = data.find(b"\x00")
    if nul >= 0:
        raise RegisterMapError(
            f"{where}: byte {nul} is 00: this is a binary file or UTF-16 text, not a CSV register map "
            f"(save it as 'CSV UTF-8')"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RegisterMapError(
            f"{where}: byte {exc.start} is {data[exc.start]:02X}, which is not UTF-8 (the file may be "
            f"latin-1 or Windows-1252); save it as 'CSV UTF-8'"
        ) from None


def datasheet_to_address(number: int, numbering: str = "1-based") -> int:
    """The protocol address of a datasheet's register number.

    ``numbering``: ``"0-based"`` (the datasheet already gives addresses), ``"1-based"`` (register 1
    is address 0), or ``"reference"`` (30001/40001 style: 40001 is address 0, 400001 likewise).
    """
    if isinstance(number, bool) or not isinstance(number, int):
        raise RegisterMapError(f"register number must be an int, got {shown(number)}")
    if numbering == "0-based":
        address = number
    elif numbering == "1-based":
        address = number - 1
    elif numbering == "reference":
        if 30001 <= number <= 39999 or 40001 <= number <= 49999:
            address = number % 10000 - 1
        elif 300001 <= number <= 365536 or 400001 <= number <= 465536:
            address = number % 100000 - 1
        else:
            raise RegisterMapError(
                f"reference number {number} is not a 3x/4x register (30001-39999, 40001-49999 "
                f"or six digits 300001-465536)"
            )
    else:
        raise RegisterMapError(
            f"unknown numbering {shown(numbering)}: expected '0-based', '1-based' or 'reference'"
        )
    if not 0 <= address <= 65535:
        raise RegisterMapError(
            f"register number {shown(number)} ({numbering}) gives address {shown(address)}, outside 0..65535"
        )
    return address


class RegisterMap:
    """A device description: its points by name, in file order."""

    def __init__(self, points: Iterable[Point], name: str = "") -> None:
        self.name = name
        self.points: dict[str, Point] = {}
        for p in points:
            if p.name in self.points:
                raise RegisterMapError(f"{name or 'map'}: point {shown(p.name)} is defined twice")
            self.points[p.name] = p
        _check_overlaps(self.points.values(), name or "map")

    def __getitem__(self, name: str) -> Point:
        try:
            return self.points[name]
        except KeyError:
            raise RegisterMapError(
                f"no point named {shown(name)} in {self.name or 'the map'}: it has {', '.join(self.points)}"
            ) from None

    def __iter__(self):
        return iter(self.points.values())

    def __len__(self) -> int:
        return len(self.points)

    def store(self, bank, values: dict[str, float | int]) -> None:
        """Write ``values`` (by point name, engineering units) into a DataBank, as the device holds them.

        This is how a simulated device is served from a map: ``Slave(unit, bank)`` over the filled bank.
        """
        for name, value in values.items():
            p = self[name]
            raw = value / p.scale if p.scale != 1 else value
            if not TYPES[p.type].is_float:
                raw = round(raw)
            table = bank.holding_registers if p.table == "holding" else bank.input_registers
            for i, r in enumerate(encode_value(raw, p.type, p.order)):
                table[p.address + i] = r

    def plan(self, max_gap: int = 0) -> list[Poll]:
        """The fewest legal FC 3/FC 4 requests that read every point (see :func:`plan_polls`)."""
        return plan_polls(self.points.values(), max_gap=max_gap)

    def read(self, master, unit: int, max_gap: int = 0) -> dict[str, float | int]:
        """Read every point from ``unit`` through ``master`` with the planned requests; values by name."""
        values: dict[str, float | int] = {}
        for poll in self.plan(max_gap):
            if poll.function == 3:
                regs = master.read_holding_registers(unit=unit, address=poll.address, count=poll.count)
            else:
                regs = master.read_input_registers(unit=unit, address=poll.address, count=poll.count)
            for p in poll.points:
                start = p.address - poll.address
                values[p.name] = p.decode(regs[start : start + p.count])
        return {name: values[name] for name in self.points}


def _check_overlaps(points: Iterable[Point], where: str) -> None:
    for table in _TABLES:
        ordered = sorted((p for p in points if p.table == table), key=lambda p: p.address)
        for a, b in zip(ordered, ordered[1:]):
            if b.address < a.address + a.count:
                raise RegisterMapError(
                    f"{where}: {table} point {shown(b.name)} at address {b.address} overlaps {shown(a.name)} "
                    f"(addresses {a.address}-{a.address + a.count - 1})"
                )


def plan_polls(points: Iterable[Point], max_gap: int = 0) -> list[Poll]:
    """Group points into the fewest requests: one table each, <= 125 registers, gaps <= ``max_gap``.

    Greedy over the points sorted by address, which is optimal for intervals on a line: a request is
    closed only when the next point would make it longer than 125 registers or leave too long a gap.
    """
    if isinstance(max_gap, bool) or not isinstance(max_gap, int) or max_gap < 0:
        raise RegisterMapError(f"max_gap must be an int >= 0, got {shown(max_gap)}")
    polls: list[Poll] = []
    for table, function in _TABLES.items():
        ordered = sorted((p for p in points if p.table == table), key=lambda p: p.address)
        group: list[Point] = []
        for p in ordered:
            if group:
                start = group[0].address
                end = max(q.address + q.count for q in group)
                if p.address - end > max_gap or p.address + p.count - start > MAX_READ_REGISTERS:
                    polls.append(_poll(function, group))
                    group = []
            group.append(p)
        if group:
            polls.append(_poll(function, group))
    return polls


def _poll(function: int, group: list[Point]) -> Poll:
    start = group[0].address
    end = max(p.address + p.count for p in group)
    return Poll(function, start, end - start, tuple(group))


NUMBERINGS = ("0-based", "1-based", "reference")


def _declared_numbering(text: str, where: str) -> str | None:
    """The numbering a file names in a comment line before its header (``# numbering: reference``)."""
    for line_number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if not stripped:
            continue
        if not stripped.startswith("#"):
            return None
        key, sep, value = stripped.lstrip("#").partition(":")
        if sep and key.strip().lower() == "numbering":
            value = value.strip().lower()
            if value not in NUMBERINGS:
                raise RegisterMapError(f"{where} line {line_number}: numbering {shown(value)} must be one of "
                                       f"{', '.join(NUMBERINGS)}")
            return value
    return None


def _looks_like_reference(table: str, number: int) -> bool:
    prefix = 3 if table == "input" else 4
    return (prefix * 10000 + 1 <= number <= prefix * 10000 + 9999
            or prefix * 100000 + 1 <= number <= prefix * 100000 + 65536)


def load_map(source: str | Path, numbering: str | None = None, name: str | None = None) -> RegisterMap:
    """Load a CSV register map from a path (or from CSV text if ``source`` contains a newline).

    ``numbering`` says how the file's ``address`` column counts (see :func:`datasheet_to_address`);
    the file may say it itself, in a line ``# numbering: reference`` before its header. Both given and
    different is an error; neither given means ``"0-based"``, unless the addresses look like
    reference numbers (30001 in the input table, 40001 in the holding table): then the file must say.
    """
    if isinstance(source, str) and "\n" in source:
        text, where = source.removeprefix("\ufeff"), name or "<text>"
    else:
        path = Path(source)
        where = name or path.name
        try:
            with path.open("rb") as file:
                data = file.read(MAX_FILE_BYTES + 1)
        except OSError as exc:
            raise RegisterMapError(f"cannot read register map {str(path)!r}: {exc.strerror}") from None
        if len(data) > MAX_FILE_BYTES:
            raise RegisterMapError(f"{where}: larger than {MAX_FILE_BYTES // 2**20} MiB: not a register map")
        text = _decode_text(data, where)
    declared = _declared_numbering(text, where)
    if numbering is not None and declared is not None and numbering != declared:
        raise RegisterMapError(f"{where} says '# numbering: {declared}', but numbering={numbering!r} was "
                               f"asked for: drop one, or make them agree")
    chosen = numbering or declared or "0-based"
    try:
        rows = list(csv.reader(io.StringIO(text)))
    except csv.Error as exc:
        raise RegisterMapError(f"{where}: not readable as CSV ({exc})") from None
    rows = [(i, r) for i, r in enumerate(rows, 1) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise RegisterMapError(f"{where}: empty file, expected a header row ({','.join(_COLUMNS)})")
    for line, row in rows:
        for column, cell in enumerate(row, 1):
            if len(cell) > MAX_FIELD:
                raise RegisterMapError(
                    f"{where} line {line}: field {column} is {len(cell)} characters long; a register map's "
                    f"fields are at most {MAX_FIELD}"
                )
    header_line, header = rows[0]
    header = [h.strip().lower() for h in header]
    for col in set(header):
        if header.count(col) > 1:
            raise RegisterMapError(f"{where} line {header_line}: the column {shown(col)} appears twice")
    for col in _REQUIRED:
        if col not in header:
            raise RegisterMapError(
                f"{where} line {header_line}: header has no {col!r} column (expected {','.join(_COLUMNS)})"
            )
    for col in header:
        if col not in _COLUMNS:
            raise RegisterMapError(
                f"{where} line {header_line}: unknown column {shown(col)} (expected {','.join(_COLUMNS)})"
            )
    points = []
    for line, row in rows[1:]:
        if len(row) != len(header):
            raise RegisterMapError(f"{where} line {line}: {len(row)} fields, the header has {len(header)}")
        cells = dict(zip(header, (c.strip() for c in row)))
        if numbering is None and declared is None:
            _refuse_a_guess(cells, f"{where} line {line}")
        points.append(_point(cells, f"{where} line {line}", chosen))
    return RegisterMap(points, name=where)


def _refuse_a_guess(cells: dict[str, str], where: str) -> None:
    """A file that does not name its numbering, whose address looks like a reference number: refused."""
    try:
        number = int(cells["address"], 0)
    except ValueError:
        return  # _point says what is wrong with it
    table = cells["table"].lower()
    if table in _TABLES and _looks_like_reference(table, number):
        raise RegisterMapError(
            f"{where}: address {number} looks like a reference number ({table} table), but the file does "
            f"not say how it numbers: add the line '# numbering: reference' before the header (or "
            f"'# numbering: 0-based' if {number} really is the protocol address), or pass numbering="
        )


def _point(row: dict[str, str], where: str, numbering: str) -> Point:
    name = row["name"]
    if not name.isidentifier():
        raise RegisterMapError(f"{where}: name {name!r} must be a Python identifier (letters, digits, _)")
    table = row["table"].lower()
    if table not in _TABLES:
        raise RegisterMapError(f"{where}: table {row['table']!r} must be 'holding' or 'input'")
    try:
        number = int(row["address"], 0)
    except ValueError:
        raise RegisterMapError(f"{where}: address {row['address']!r} is not an integer") from None
    try:
        address = datasheet_to_address(number, numbering)
    except RegisterMapError as exc:
        raise RegisterMapError(f"{where}: {exc}") from None
    type_ = row["type"].lower()
    if type_ not in TYPES:
        raise RegisterMapError(f"{where}: type {row['type']!r} must be one of {', '.join(TYPES)}")
    order = (row.get("order") or "ABCD").upper()
    if order not in ORDERS:
        raise RegisterMapError(f"{where}: order {row.get('order')!r} must be one of {', '.join(ORDERS)}")
    try:
        scale = check_scale(float(row.get("scale") or 1), where)
    except ValueError:
        raise RegisterMapError(f"{where}: scale {row.get('scale')!r} is not a number") from None
    if address + register_count(type_) > 65536:
        raise RegisterMapError(f"{where}: {type_} at address {address} runs past address 65535")
    return Point(name, table, address, type_, order, scale, row.get("unit") or "")
