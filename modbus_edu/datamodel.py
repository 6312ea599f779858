"""The Modbus data model: four tables of data, and the reference numbers people use to name them.

A Modbus slave (server) exposes its data as **four tables**.  Each table has its own address space of
65 536 elements, addressed 0..65535 *in the frame*; the tables do not overlap, so "address 0" means a
different thing in each of them.  Which table a request reaches is decided by its function code alone.

=====================  ========  ====================  ===============================================
table                  element   a master may...       function codes that reach it
=====================  ========  ====================  ===============================================
coils                  1 bit     read and write        01 read coils, 05 write single coil,
                                                       15 write multiple coils
discrete inputs        1 bit     only read             02 read discrete inputs
input registers        16 bits   only read             04 read input registers
holding registers      16 bits   read and write        03 read holding registers, 06 write single
                                                       register, 16 write multiple registers
=====================  ========  ====================  ===============================================

*Coils* are on/off outputs (a relay, a lamp); *discrete inputs* are on/off inputs (a switch, a limit
sensor); *input registers* hold measurements the device produces (an analog input); *holding registers*
hold numbers a master may change (a set point, a configuration value).  "Read-only" is about the
**master**: the device itself updates its discrete inputs and input registers all the time, which is
why :meth:`Table.write` works on every table from Python.

:class:`DataBank` holds the four tables.  A **dense** bank (the default) has all 65 536 addresses of each
table, zeroed, like a device that answers every address.  A **sparse** bank has only the addresses you
declare, like the Arduino library of the Arduino slave paper (``regBank.add(40001)``); a request that
touches an undeclared address makes the slave answer exception 02, *illegal data address*.

Reference numbers
-----------------
Manuals rarely print addresses; they print **reference numbers** such as ``40001``: a table prefix
(0 coils, 1 discrete inputs, 3 input registers, 4 holding registers) followed by a **number that
starts at 1**.  So the number is the address plus one: holding register 40001 is address 0 in the
holding register table, coil 00308 is coil address 307.  These numbers are a *convention* from
Modicon's PLC documentation, not part of the protocol: the prefix never travels on the wire (the
function code says which table) and neither does the +1.  A frame reading "40001" carries function
code 03 and address ``00 00``.  See :func:`parse_reference` and :func:`format_reference`.
"""

from __future__ import annotations

import operator
from array import array
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any, Union

from .errors import (
    DataModelError,
    IllegalAddressError,
    ReferenceNumberError,
    ValueRangeError,
    guard_numbers,
    shown,
)
from .filerecords import MAX_FILE_REGISTERS, FileMemoryError, FileRecords

__all__ = [
    "ADDRESS_SPACE",
    "TABLE_KINDS",
    "PREFIXES",
    "DataBank",
    "FileMemoryError",
    "FileRecords",
    "MAX_FILE_REGISTERS",
    "Table",
    "Reference",
    "parse_reference",
    "format_reference",
    "AddressText",
    "parse_address_text",
    "table_kind",
]

#: Number of addresses in each table: 0..65535.
ADDRESS_SPACE = 65536
LAST_ADDRESS = ADDRESS_SPACE - 1

#: The four table names, in the order of their reference prefixes (0x, 1x, 3x, 4x).
TABLE_KINDS = ("coils", "discrete_inputs", "input_registers", "holding_registers")

#: Reference prefix digit of each table (there is no 2x table).
PREFIXES = {"coils": 0, "discrete_inputs": 1, "input_registers": 3, "holding_registers": 4}
_KIND_OF_PREFIX = {prefix: kind for kind, prefix in PREFIXES.items()}

#: One element of each table, in words (for messages).
_SINGULAR = {
    "coils": "coil",
    "discrete_inputs": "discrete input",
    "input_registers": "input register",
    "holding_registers": "holding register",
}

#: Function code -> the table it reaches.
_KIND_OF_FUNCTION = {
    1: "coils",
    2: "discrete_inputs",
    3: "holding_registers",
    4: "input_registers",
    5: "coils",
    6: "holding_registers",
    15: "coils",
    16: "holding_registers",
    22: "holding_registers",
    23: "holding_registers",
    24: "holding_registers",
}


def table_kind(kind_or_function: str | int) -> str:
    """Return the table name for a table name or a function code.

    >>> table_kind(3)
    'holding_registers'
    >>> table_kind("coils")
    'coils'

    Function codes 1/5/15 reach the coils, 2 the discrete inputs, 3/6/16/22/23/24 the holding registers
    and 4 the input registers.  Anything else raises :class:`~modbus_edu.errors.DataModelError`.
    """
    if isinstance(kind_or_function, str):
        name = kind_or_function.strip().lower().replace(" ", "_").replace("-", "_")
        if name in PREFIXES:
            return name
        raise DataModelError(
            f"unknown table {shown(kind_or_function)}: expected one of {', '.join(TABLE_KINDS)} "
            f"or a function code (1, 2, 3, 4, 5, 6, 15, 16)"
        )
    if isinstance(kind_or_function, int) and not isinstance(kind_or_function, bool):
        try:
            return _KIND_OF_FUNCTION[int(kind_or_function)]
        except KeyError:
            raise DataModelError(
                f"function code {shown(int(kind_or_function))} does not reach a data table: 1, 5, 15 reach "
                f"the coils, 2 the discrete inputs, 3, 6, 16 the holding registers, 4 the input registers"
            ) from None
    raise DataModelError(
        f"a table is named by a string such as 'holding_registers' or by a function code, "
        f"not by {type(kind_or_function).__name__} {shown(kind_or_function)}"
    )


def _reference_hint(kind: str, address: int) -> str:
    """'holding register address 5 (reference 40006)' -- for messages."""
    if 0 <= address <= LAST_ADDRESS:
        ref = format_reference(kind, address, digits=5 if address <= 9998 else 6)
        return f"{_SINGULAR[kind]} address {address} (reference {ref})"
    return f"{_SINGULAR[kind]} address {address}"


def _check_address(kind: str, address: Any, count: Any = 1, verb: str = "access") -> tuple[int, int]:
    """Validate an address and a count; return them as ints or raise a teaching error."""
    if isinstance(address, bool) or not isinstance(address, int):
        try:
            if isinstance(address, bool):
                raise TypeError
            address = operator.index(address)
        except TypeError:
            hint = ""
            if isinstance(address, str):
                hint = (
                    "; for a reference number such as '40001' use DataBank.get/set/add "
                    "or parse_reference()"
                )
            raise IllegalAddressError(
                f"{_SINGULAR[kind]} address must be a whole number 0..65535, "
                f"got {type(address).__name__} {shown(address)}{hint}"
            ) from None
    if isinstance(count, bool) or not isinstance(count, int):
        try:
            if isinstance(count, bool):
                raise TypeError
            count = operator.index(count)
        except TypeError:
            raise DataModelError(
                f"count must be a whole number, got {type(count).__name__} {shown(count)}"
            ) from None
    if not 0 <= address <= LAST_ADDRESS:
        raise IllegalAddressError(
            f"{_SINGULAR[kind]} address {shown(address)} is outside the table: Modbus addresses run from "
            f"0 to 65535 (the 16-bit address field of the frame)"
        )
    if count < 0:
        raise DataModelError(f"count must be 0 or more, got {shown(count)}")
    if address + count > ADDRESS_SPACE:
        raise IllegalAddressError(
            f"cannot {verb} {shown(count)} {kind.replace('_', ' ')} from address {address}: that would run "
            f"to address {shown(address + count - 1)}, past the last address 65535"
        )
    return address, count


class Table:
    """One of the four tables of a :class:`DataBank`.

    ``kind`` is its name, ``is_bits`` tells a bit table (coils, discrete inputs: values are ``bool``)
    from a register table (16-bit unsigned ints 0..65535), ``writable`` whether a *master* may write it
    (coils and holding registers).  Python code -- the device itself -- may always write.

    Storage is compact: one byte per bit (a ``bytearray``) and two bytes per register (an
    ``array('H')``), so a dense table of 65 536 registers takes 128 KiB.  A sparse table also keeps a
    one-byte-per-address map of which addresses were declared.

    Reads and writes take a starting address and a count (or a list of values), like the requests
    that reach them::

        t.read(0, 3)          # -> [0, 0, 0]
        t.write(0, [1, 2, 3])
        t[0], t[1] = 10, 20   # one element
        t[0:3]                # the same as t.read(0, 3)
    """

    __slots__ = ("kind", "is_bits", "writable", "sparse", "_data", "_declared")

    def __init__(self, kind: str, sparse: bool = False) -> None:
        kind = table_kind(kind)
        self.kind: str = kind
        self.is_bits: bool = kind in ("coils", "discrete_inputs")
        self.writable: bool = kind in ("coils", "holding_registers")
        self.sparse: bool = bool(sparse)
        self._data: bytearray | array
        if self.is_bits:
            self._data = bytearray(ADDRESS_SPACE)
        else:
            self._data = array("H", bytes(2 * ADDRESS_SPACE))
        # sparse: 1 = declared, 0 = does not exist
        self._declared: bytearray | None = bytearray(ADDRESS_SPACE) if self.sparse else None

    # --- what exists ---------------------------------------------------------------------------
    def _require_declared(self, address: int, count: int) -> None:
        if self._declared is None or count == 0:
            return
        missing = self._declared.find(0, address, address + count)
        if missing != -1:
            raise IllegalAddressError(
                f"{_reference_hint(self.kind, missing)} is not declared in this sparse bank, so it does "
                f"not exist: a slave answers exception 02 (illegal data address). Declare it first, "
                f"e.g. bank.{self.kind}.declare({missing})"
            )

    def declare(self, address: int, count: int = 1, value: Any = 0) -> None:
        """Make ``count`` addresses from ``address`` exist, and set them to ``value``.

        This is ``regBank.add()`` followed by ``regBank.set()`` in the Arduino library of the Arduino slave
        paper.
        ``value`` is one value for all of them, or a sequence of ``count`` values.  On a dense table
        every address already exists, so ``declare`` only sets the values.
        """
        address, count = _check_address(self.kind, address, count, "declare")
        if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
            values = [value] * count
        else:
            values = list(value)
            if len(values) != count:
                raise DataModelError(
                    f"declare() got {len(values)} values for {count} addresses; give one value "
                    f"for all of them or exactly {count}"
                )
        packed = self._pack(values, address)
        if self._declared is not None:
            self._declared[address : address + count] = b"\x01" * count
        self._data[address : address + count] = packed

    def is_declared(self, address: int, count: int = 1) -> bool:
        """True when every address of ``address .. address+count-1`` exists in this table.

        Addresses outside 0..65535 do not exist (``False``, no error).
        """
        try:
            address, count = _check_address(self.kind, address, count)
        except IllegalAddressError:
            return False
        if self._declared is None or count == 0:
            return True
        return self._declared.find(0, address, address + count) == -1

    def addresses(self) -> range | list[int]:
        """The addresses that exist, sorted: ``range(65536)`` when dense, the declared ones when sparse."""
        if self._declared is None:
            return range(ADDRESS_SPACE)
        found: list[int] = []
        find = self._declared.find
        i = find(1)
        while i != -1:
            found.append(i)
            i = find(1, i + 1)
        return found

    def __len__(self) -> int:
        """How many addresses exist (65536 when dense)."""
        if self._declared is None:
            return ADDRESS_SPACE
        return self._declared.count(1)

    def __contains__(self, address: object) -> bool:
        return self.is_declared(address)  # type: ignore[arg-type]

    # --- values ------------------------------------------------------------------------------------
    def _pack(self, values: list[Any], address: int) -> bytearray | array:
        """Validate values and return them packed for this table's storage (no loop on the fast path)."""
        if self.is_bits:
            try:
                packed = bytearray(values)
                if not packed or max(packed) <= 1:
                    return packed
            except (TypeError, ValueError):
                pass
            for i, v in enumerate(values):  # slow path: find the culprit for the message
                if isinstance(v, bool) or (isinstance(v, int) and v in (0, 1)):
                    continue
                raise ValueRangeError(
                    f"{_SINGULAR[self.kind]} at address {address + i} takes a bit: True/False (or 1/0), "
                    f"got {type(v).__name__} {shown(v)}"
                )
            return bytearray(int(v) for v in values)  # pragma: no cover - e.g. numpy bools
        try:
            if bool not in map(type, values):  # True would pass as 1: a register is a number, not a flag
                return array("H", values)
        except (TypeError, OverflowError, ValueError):
            pass
        for i, v in enumerate(values):
            ok = False
            if not isinstance(v, (float, bool)):
                try:
                    ok = 0 <= operator.index(v) <= 65535
                except TypeError:
                    ok = False
            if not ok:
                raise ValueRangeError(
                    f"{_SINGULAR[self.kind]} at address {address + i} holds a 16-bit unsigned number "
                    f"0..65535, got {type(v).__name__} {shown(v)} (for negative or wide numbers convert "
                    f"with modbus_edu.values.encode_value)"
                )
        return array("H", [operator.index(v) for v in values])  # pragma: no cover

    def read(self, address: int, count: int = 1) -> list:
        """Return ``count`` values from ``address``: a list of bools (bit tables) or ints (registers).

        Raises :class:`~modbus_edu.errors.IllegalAddressError` when the range leaves 0..65535 or, in a
        sparse table, touches an address that was never declared (the message names the first one).
        """
        address, count = _check_address(self.kind, address, count, "read")
        self._require_declared(address, count)
        chunk = self._data[address : address + count]
        if self.is_bits:
            return [b != 0 for b in chunk]
        return chunk.tolist()  # type: ignore[union-attr]

    def stored(self, address: int, count: int) -> bytearray | array:
        """A copy of ``count`` values from ``address`` as kept (0/1 bytes, or an ``array('H')``), for a
        caller that has checked the range itself: a slave's fast path (``Pdu.answer_from_bytes``)."""
        return self._data[address : address + count]

    def write(self, address: int, values: Iterable[Any]) -> None:
        """Write the sequence ``values`` from ``address`` on (all of them, or none on an error).

        Bit tables take bools (1/0 are accepted), register tables ints 0..65535
        (:class:`~modbus_edu.errors.ValueRangeError` otherwise).
        """
        if isinstance(values, (int, str)) or not isinstance(values, Iterable):
            raise DataModelError(
                f"write() takes a sequence of values, got {type(values).__name__} {shown(values)}; "
                f"to set one element use table[address] = value"
            )
        values = list(values)
        address, count = _check_address(self.kind, address, len(values), "write")
        self._require_declared(address, count)
        packed = self._pack(values, address)
        self._data[address : address + count] = packed

    def _slice(self, key: slice) -> tuple[int, int]:
        if key.step not in (None, 1):
            raise DataModelError("table slices take no step: use table[start:stop]")
        start = 0 if key.start is None else key.start
        stop = ADDRESS_SPACE if key.stop is None else key.stop
        start, _ = _check_address(self.kind, start, 0)
        if isinstance(stop, bool) or not isinstance(stop, int):
            raise DataModelError(f"slice stop must be a whole number, got {shown(stop)}")
        if stop < start:
            raise DataModelError(f"slice [{start}:{stop}] runs backwards")
        return start, stop - start

    def __getitem__(self, key: int | slice) -> Any:
        if isinstance(key, slice):
            return self.read(*self._slice(key))
        return self.read(key, 1)[0]

    def __setitem__(self, key: int | slice, value: Any) -> None:
        if isinstance(key, slice):
            start, count = self._slice(key)
            values = list(value)
            if len(values) != count:
                raise DataModelError(
                    f"slice [{start}:{start + count}] has {count} addresses "
                    f"but {len(values)} values were given"
                )
            self.write(start, values)
            return
        self.write(key, [value])

    def __iter__(self) -> Iterator[int]:
        """Iterate over the addresses that exist (like a dict's keys); values via ``t[address]``."""
        return iter(self.addresses())

    def snapshot(self, nonzero_only: bool | None = None) -> dict[int, Any]:
        """``{address: value}`` of this table.

        Sparse tables list every declared address.  Dense tables list only the non-zero ones (zero is
        the default of the others); ``nonzero_only=True`` drops the zeros of a sparse table too, and
        ``nonzero_only=False`` lists all 65 536 addresses of a dense one.
        """
        if nonzero_only is None:
            nonzero_only = self._declared is None
        if self._declared is not None:
            addrs: Iterable[int] = self.addresses()
        else:
            addrs = range(ADDRESS_SPACE)
        data = self._data
        if self.is_bits:
            return {a: data[a] != 0 for a in addrs if not nonzero_only or data[a]}
        return {a: data[a] for a in addrs if not nonzero_only or data[a]}

    def copy(self) -> Table:
        """An independent copy (values and declarations)."""
        new = Table(self.kind, self.sparse)
        new._data[:] = self._data
        if self._declared is not None:
            new._declared[:] = self._declared  # type: ignore[index]
        return new

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Table):
            return NotImplemented
        return (
            self.kind == other.kind
            and self._declared == other._declared
            and self._data == other._data
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        mode = "sparse" if self.sparse else "dense"
        return f"<Table {self.kind} ({mode}, {len(self)} addresses)>"


ReferenceLike = Union["Reference", str, int]


class DataBank:
    """The four tables of a Modbus slave: ``coils``, ``discrete_inputs``, ``input_registers``,
    ``holding_registers`` (see the module's docstring for what each one is).

    ``DataBank()`` is **dense**: all 65 536 addresses of each table exist and hold 0 (or False).
    ``DataBank(sparse=True)`` starts empty: only addresses declared with :meth:`Table.declare` or
    :meth:`add` exist, and touching any other one raises
    :class:`~modbus_edu.errors.IllegalAddressError` (the slave answers exception 02).

    Reference numbers work as in the Arduino slave paper's ``regBank``::

        bank = DataBank(sparse=True)
        bank.add(40001)          # holding register address 0
        bank.set(40001, 1234)
        bank.get(40001)          # -> 1234
        bank.add("00308")        # coil address 307
    """

    __slots__ = ("sparse", "coils", "discrete_inputs", "input_registers", "holding_registers", "files")

    def __init__(self, sparse: bool = False) -> None:
        self.sparse: bool = bool(sparse)
        self.coils = Table("coils", sparse)
        self.discrete_inputs = Table("discrete_inputs", sparse)
        self.input_registers = Table("input_registers", sparse)
        self.holding_registers = Table("holding_registers", sparse)
        self.files = FileRecords(sparse)
        """File records (FC 20/21): file number 1..65535 -> its registers, record 0 first (see
        :class:`FileRecords`: a dense bank answers any file and record, a sparse one only those put here)."""

    @classmethod
    def from_references(cls, values: Mapping[ReferenceLike, Any], sparse: bool = False) -> DataBank:
        """Build a bank from ``{reference: value}``, e.g. ``{"40001": 5, "00308": True}``.

        Every reference is declared (on a sparse bank) and set.
        """
        if not isinstance(values, Mapping):
            raise DataModelError(f"from_references() takes a mapping such as {{'40001': 5}}, "
                                 f"got {type(values).__name__} {shown(values)}")
        bank = cls(sparse=sparse)
        for ref, value in values.items():
            bank.add(ref, value)
        return bank

    def table(self, kind: str | int) -> Table:
        """The table named ``kind``, or the one function code ``kind`` reaches (3 -> holding registers)."""
        return getattr(self, table_kind(kind))

    @property
    def tables(self) -> tuple[Table, Table, Table, Table]:
        """The four tables, in reference-prefix order (0x, 1x, 3x, 4x)."""
        return (self.coils, self.discrete_inputs, self.input_registers, self.holding_registers)

    # --- reference numbers -------------------------------------------------------------------------
    def add(self, reference: ReferenceLike, value: Any = 0) -> Reference:
        """Declare the element a reference number names (``add(40001)`` -> holding register 0).

        The element is set to ``value``.  Returns the parsed :class:`Reference`.
        """
        ref = parse_reference(reference)
        self.table(ref.kind).declare(ref.address, 1, value)
        return ref

    def set(self, reference: ReferenceLike, value: Any) -> None:
        """Write one element by reference number: ``set("40001", 1234)``, ``set("00308", True)``."""
        ref = parse_reference(reference)
        self.table(ref.kind)[ref.address] = value

    def get(self, reference: ReferenceLike) -> Any:
        """Read one element by reference number: ``get(30001)`` -> input register address 0."""
        ref = parse_reference(reference)
        return self.table(ref.kind)[ref.address]

    # --- whole bank ---------------------------------------------------------------------------------
    def snapshot(self) -> dict[str, dict[int, Any]]:
        """``{table name: {address: value}}``: declared addresses if sparse, non-zero ones if dense."""
        return {t.kind: t.snapshot() for t in self.tables}

    def copy(self) -> DataBank:
        """An independent copy of the bank."""
        new = DataBank(self.sparse)
        for kind in TABLE_KINDS:
            setattr(new, kind, getattr(self, kind).copy())
        return new

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DataBank):
            return NotImplemented
        return all(a == b for a, b in zip(self.tables, other.tables))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        if not self.sparse:
            return "<DataBank dense: 4 tables x 65536 addresses>"
        sizes = ", ".join(f"{t.kind} {len(t)}" for t in self.tables)
        return f"<DataBank sparse: {sizes}>"


# --- reference numbers ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Reference:
    """A table and a 0-based address: what a reference number such as 40001 stands for.

    ``number`` is the 1-based element number (``address + 1``), ``prefix`` the table digit (0, 1, 3, 4).
    ``str(Reference("holding_registers", 0))`` is ``'40001'`` (the 6-digit form when the address is
    above 9998).
    """

    kind: str
    address: int

    def __post_init__(self) -> None:
        if self.kind not in PREFIXES:
            raise ReferenceNumberError(
                f"unknown table {shown(self.kind)}: expected one of {', '.join(TABLE_KINDS)}"
            )
        if isinstance(self.address, bool) or not isinstance(self.address, int):
            raise ReferenceNumberError(f"address must be an int, got {shown(self.address)}")
        if not 0 <= self.address <= LAST_ADDRESS:
            raise ReferenceNumberError(
                f"{_SINGULAR[self.kind]} address {shown(self.address)} is outside 0..65535"
            )

    @property
    def number(self) -> int:
        """The 1-based element number: address + 1."""
        return self.address + 1

    @property
    def prefix(self) -> int:
        """The table digit of the reference: 0 coils, 1 discrete inputs, 3 input registers, 4 holding."""
        return PREFIXES[self.kind]

    def format(self, digits: int | None = None, style: str = "plain") -> str:
        """Same as :func:`format_reference` (``digits=None``: 5 when the address fits, else 6)."""
        if digits is None:
            digits = 5 if self.address <= 9998 else 6
        return format_reference(self.kind, self.address, digits=digits, style=style)

    def __str__(self) -> str:
        return self.format()


def _reference_error(ref: object, why: str) -> ReferenceNumberError:
    return ReferenceNumberError(f"reference number {shown(ref)}: {why}")


_PREFIX_HELP = (
    "0 = coils (0x), 1 = discrete inputs (1x), 3 = input registers (3x), 4 = holding registers (4x)"
)


def _kind_for_prefix(ref: object, prefix: int, int_hint: str = "") -> str:
    try:
        return _KIND_OF_PREFIX[prefix]
    except KeyError:
        extra = ""
        if prefix == 2:
            extra = " There is no 2x table."
        elif prefix == 6:
            extra = " (6x is sometimes used for file records, function codes 20/21, not served here.)"
        raise _reference_error(
            ref, f"the first digit {prefix} is not a table prefix: {_PREFIX_HELP}.{extra}{int_hint}"
        ) from None


def _checked_number(ref: object, kind: str, number: int, limit: int, form: str) -> int:
    if number == 0:
        raise _reference_error(
            ref,
            f"element numbers start at 1 (number = address + 1): the first {_SINGULAR[kind]} is "
            f"{PREFIXES[kind]}0001, address 0",
        )
    if number > limit:
        raise _reference_error(
            ref, f"the {form} form numbers elements 1..{limit}, got {number}"
        )
    return number - 1


@guard_numbers
def parse_reference(ref: ReferenceLike) -> Reference:
    """Turn a reference number into a :class:`Reference` (table and 0-based **address**).

    Accepted forms (the address is always the number minus one):

    * 5 digits: ``"40001"`` -> holding register 0, ``"30001"`` -> input register 0,
      ``"10005"`` -> discrete input 4, ``"00308"`` -> coil 307.  Numbers 1..9999 (addresses 0..9998).
    * 6 digits: ``"400001"`` .. ``"465536"`` -> addresses 0..65535.
    * with an ``x``: ``"4x0001"``, ``"4x1"``, ``"0x308"`` (here ``0x`` is the coil prefix, not hex).
    * an ``int``: ``40001``, ``400001``; the leading zero of a coil is lost, so ``308`` is coil 00308.
      Coils above 09999 need the string form (``"020001"``): as an int, 20001 reads as prefix 2.

    Prefix 2 (or 5..9) is not a table and raises :class:`~modbus_edu.errors.ReferenceNumberError`,
    as does number 0 (``40000``): numbering starts at 1.
    """
    if isinstance(ref, Reference):
        return ref
    if isinstance(ref, bool):
        raise _reference_error(ref, "a reference number is an int or a string such as '40001'")
    if isinstance(ref, int):
        if ref < 0:
            raise _reference_error(ref, "reference numbers are not negative")
        digits = len(str(ref))
        if digits <= 5:
            hint = ""
            if ref // 10000 == 2:
                hint = (
                    f" If you meant coil number {ref}, write it as the string '0{ref}' "
                    f"(an int loses its leading 0)."
                )
            kind = _kind_for_prefix(ref, ref // 10000, hint)
            return Reference(kind, _checked_number(ref, kind, ref % 10000, 9999, "5-digit"))
        if digits == 6:
            kind = _kind_for_prefix(ref, ref // 100000)
            return Reference(kind, _checked_number(ref, kind, ref % 100000, 65536, "6-digit"))
        raise _reference_error(ref, "too many digits: use 5 (40001) or 6 (400001)")
    if not isinstance(ref, str):
        raise _reference_error(
            ref, f"a reference number is an int or a string such as '40001', not {type(ref).__name__}"
        )
    text = ref.strip()
    if len(text) >= 3 and text[1] in "xX" and text[0].isdigit():
        body = text[2:]
        if not (body.isascii() and body.isdigit()):
            raise _reference_error(ref, "after '4x' (or 0x, 1x, 3x) come only decimal digits, e.g. '4x0001'")
        kind = _kind_for_prefix(ref, int(text[0]))
        return Reference(kind, _checked_number(ref, kind, int(body), 65536, "'x'"))
    if not (text.isascii() and text.isdigit()):
        raise _reference_error(
            ref, "expected digits such as '40001', '400001' or the x form '4x0001'"
        )
    if len(text) == 5:
        hint = ""
        if text[0] == "2":
            hint = f" If you meant coil number {text}, the 6-digit form is '0{text}'."
        kind = _kind_for_prefix(ref, int(text[0]), hint)
        return Reference(kind, _checked_number(ref, kind, int(text[1:]), 9999, "5-digit"))
    if len(text) == 6:
        kind = _kind_for_prefix(ref, int(text[0]))
        return Reference(kind, _checked_number(ref, kind, int(text[1:]), 65536, "6-digit"))
    raise _reference_error(
        ref,
        f"a reference number has 5 digits (40001, coil 00308) or 6 digits (400001), got {len(text)}; "
        f"write leading zeros, or use the x form ('0x308')",
    )


@guard_numbers
def format_reference(kind: str | int, address: int, digits: int = 5, style: str = "plain") -> str:
    """The reference number of ``address`` in table ``kind`` -- the inverse of :func:`parse_reference`.

    >>> format_reference("holding_registers", 0)
    '40001'
    >>> format_reference("coils", 307)
    '00308'
    >>> format_reference("holding_registers", 0, digits=6, style="x")
    '4x00001'

    ``digits=5`` covers addresses 0..9998 (numbers 1..9999); a larger address raises
    :class:`~modbus_edu.errors.ReferenceNumberError` asking for ``digits=6``.  ``style="x"`` puts an
    ``x`` after the prefix ("4x0001").
    """
    try:
        kind = table_kind(kind)
    except DataModelError as exc:
        raise ReferenceNumberError(str(exc)) from None
    if isinstance(address, bool) or not isinstance(address, int) or not 0 <= address <= LAST_ADDRESS:
        raise ReferenceNumberError(
            f"{_SINGULAR[kind]} address must be an int 0..65535, got {shown(address)}"
        )
    if digits not in (5, 6):
        raise ReferenceNumberError(f"digits must be 5 or 6, got {shown(digits)}")
    if style not in ("plain", "x"):
        raise ReferenceNumberError(f"style must be 'plain' or 'x', got {shown(style)}")
    number = address + 1
    if digits == 5 and number > 9999:
        raise ReferenceNumberError(
            f"{_SINGULAR[kind]} address {address} is number {number}, which does not fit the 5-digit "
            f"form (numbers 1..9999): use digits=6 -> {PREFIXES[kind]}{number:05d}"
        )
    sep = "x" if style == "x" else ""
    width = digits - 1
    return f"{PREFIXES[kind]}{sep}{number:0{width}d}"


# --- an address as a person types it -----------------------------------------------------------------
@dataclass(frozen=True)
class AddressText:
    """What :func:`parse_address_text` read: the 0-based ``address``, the ``reference`` when the text was a
    reference number (its table then says which functions may use it), else ``None``, and a ``warning``
    for a plain address that looks like a mistyped reference ('' when none)."""

    address: int
    reference: Reference | None = None
    warning: str = ""


_TABLE_DIGITS = "0134"


def parse_address_text(text: str, what: str = "address") -> AddressText:
    """An address typed on a command line or in a form: a **reference number** or a plain **address**.

    * 5 or 6 decimal digits whose first digit is a table prefix (0, 1, 3, 4) are a reference number,
      read by :func:`parse_reference`: ``40001`` and ``400001`` -> holding register 0, ``30001`` ->
      input register 0, ``10001`` -> discrete input 0, ``00001`` -> coil 0;
    * ``1x``, ``3x`` or ``4x`` then digits is the x form: ``4x0001`` -> holding register 0
      (``0x`` stays hexadecimal here: ``0x0010`` is address 16; write a coil as ``00017``);
    * anything else of fewer digits, or ``0x`` hex, is a plain 0-based protocol address, 0..65535
      (for a plain address of 10000 and up, write it in hex: ``0x2710``).

    A plain address that looks like a reference with a digit missing (``4001``) or with the table digit
    that does not exist (``20001``) is still read as an address, with a ``warning`` that says so.
    """
    if not isinstance(text, str):
        raise ReferenceNumberError(f"{what} must be text such as '40001' or '0', got {shown(text)}")
    raw = text.strip()
    low = raw.lower()
    if len(low) >= 3 and low[0] in "134" and low[1] == "x":
        return AddressText(parse_reference(raw).address, parse_reference(raw))
    if raw.isascii() and raw.isdigit() and len(raw) in (5, 6) and raw[0] in _TABLE_DIGITS:
        ref = parse_reference(raw)
        return AddressText(ref.address, ref)
    try:
        address = int(raw, 16) if low.startswith("0x") else int(raw, 10)
    except ValueError:
        raise ReferenceNumberError(
            f"{what} {shown(text)} is neither an address (0..65535, or hex 0x0000..0xFFFF) nor a reference "
            f"number (40001, 400001, 4x0001)"
        ) from None
    if not 0 <= address <= LAST_ADDRESS:
        raise ReferenceNumberError(f"{what} {shown(text)} is outside 0..65535")
    warning = ""
    if raw.isdigit() and len(raw) == 5 and raw[0] == "2":
        warning = (f"{what} {raw} is read as the 0-based address {address}: there is no 2x table, so it is "
                   f"not a reference number (coils 0x, discrete inputs 1x, input registers 3x, holding 4x)")
    elif raw.isdigit() and len(raw) == 4 and raw[0] in "134" and raw[1:3] == "00" and raw[3] != "0":
        ref = f"{raw[0]}000{raw[3]}"
        warning = (f"{what} {raw} is read as the 0-based address {address}; if you meant the reference "
                   f"number {ref} (address {int(raw[3]) - 1}), write {ref} or {raw[0]}x{raw[1:].zfill(4)}")
    return AddressText(address, None, warning)
