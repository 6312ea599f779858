"""Answers as plain data: what a checker judges, and what leaves a grading kernel.

A checker never sees the learner's own objects.  :func:`plain` turns an answer into JSON-able data made
of exact built-in types, and :func:`revive` turns that data back into the value the checker reads:

* ``None``, ``bool``, ``int``, ``float``, ``str``, ``bytes``, ``bytearray`` and ``memoryview`` become
  their exact built-in type, read through the built-in type's own methods: an ``int`` subclass whose
  ``__eq__`` is always true arrives as the plain number it holds, and is compared as that;
* lists, tuples, dicts, sets and frozensets keep their kind, their items converted the same way;
* a class (``type(error)``) and an exception travel by name; Python's built-in ones and the library's
  errors, PDUs, frames and banks (:func:`known_classes`: a table of classes already imported, looked up,
  never imported by name) come back as themselves, any other as a new class of the same name that is
  nothing of the library's;
* a :class:`~modbus_edu.DataBank` travels as its layout (which addresses exist in which table, as runs
  of consecutive addresses); a device or slave as its bank; a widget of the course as its ``config()``;
* anything else arrives as an opaque object that only says its type's name (``<an object>``).

Every answer is bounded (:data:`MAX_ITEMS` values, :data:`MAX_DEPTH` levels, :data:`MAX_TEXT` characters
in one string or byte string, :data:`MAX_BANKS` banks of at most :data:`MAX_RUNS` runs each, no table
declaring more than its 65,536 addresses); beyond that :class:`PlainError` says so in a sentence.  So
reviving plain data from a kernel is work in proportion to its size, whatever the kernel sent.

In a learner's notebook ``check`` judges ``revive(plain(answer))`` at once; under ``modbus-edu grade``
the kernel only sends ``plain(answer)`` and the grader revives and judges it in its own process.
"""

from __future__ import annotations

import builtins
import functools
import json
import math
from typing import Any

from .. import datamodel, errors, framing, pdu
from ..datamodel import ADDRESS_SPACE, DataBank
from ..errors import ModbusError

MAX_ITEMS = 20_000
"""The most values (items of containers included) one answer may hold."""
MAX_DEPTH = 24
"""The deepest nesting of containers an answer may have."""
MAX_TEXT = 100_000
"""The most characters (or bytes) one string (or byte string) of an answer may hold."""
MAX_INT_BITS = 65_536
"""The most bits one int of an answer may have."""
MAX_WIRE = 2_000_000
"""The most characters the JSON of one answer may take."""
MAX_RUNS = 1_000
"""The most runs of consecutive addresses a bank's layout may have, over its four tables."""
MAX_BANKS = 8
"""The most banks (devices, slaves) one answer may hold: each is a bank of 4 x 65,536 addresses to build."""

_TABLES = ("coils", "discrete_inputs", "input_registers", "holding_registers")


class PlainError(ModbusError):
    """An answer too large or too deep to be read as plain data."""


def _name_of(cls: type) -> str:
    module = type.__dict__["__module__"].__get__(cls)
    return f"{module}:{type.__dict__['__qualname__'].__get__(cls)}"


def _layout(bank: DataBank) -> dict:
    tables = {}
    for name in _TABLES:
        table = object.__getattribute__(bank, name)
        if not bank.sparse:
            continue
        runs: list[list[int]] = []
        for address in table.addresses():
            if runs and runs[-1][0] + runs[-1][1] == address:
                runs[-1][1] += 1
            else:
                runs.append([address, 1])
        tables[name] = runs
        if sum(map(len, tables.values())) > MAX_RUNS:
            raise PlainError(f"your bank's addresses come in more than {MAX_RUNS:,} separate runs; a bank "
                             "the course asks for has a few.")
    return {"sparse": bool(bank.sparse), "tables": tables}


def _text(value: Any) -> str:
    try:
        return str.__str__(str(value))[:300]
    except Exception:
        return f"<a {type(value).__name__}>"


def _count_bank(banks: list[int]) -> None:
    banks[0] += 1
    if banks[0] > MAX_BANKS:
        raise PlainError(f"your answer holds more than {MAX_BANKS} banks (devices, slaves); the answer holds "
                         "one or two.")


def plain(answer: Any) -> Any:
    """``answer`` as JSON-able plain data (see the module's docstring); raises :class:`PlainError`."""
    budget, banks = [MAX_ITEMS], [0]

    def convert(value: Any, depth: int) -> Any:
        budget[0] -= 1
        if budget[0] < 0:
            raise PlainError(f"your answer holds more than {MAX_ITEMS:,} values; the answer is much smaller.")
        if depth > MAX_DEPTH:
            raise PlainError("your answer is nested too deeply to read.")
        cls = type(value)
        if value is ...:
            return {"$ellipsis": 0}
        if value is None or cls is bool:
            return value
        if issubclass(cls, int):
            number = int.__int__(value)
            if number.bit_length() > MAX_INT_BITS:
                raise PlainError("your answer is far too large to check.")
            return number if abs(number) < 2 ** 53 else {"$int": hex(number)}
        if issubclass(cls, float):
            number = float.__float__(value)
            return number if math.isfinite(number) else {"$float": repr(number)}
        if issubclass(cls, str):
            text = str.__str__(value)
            if len(text) > MAX_TEXT:
                raise PlainError(f"your answer holds a text of {len(text):,} characters; the answer is much "
                                 "shorter.")
            return text
        if issubclass(cls, (bytes, bytearray, memoryview)):
            data = (bytes.__getitem__(value, slice(None)) if issubclass(cls, bytes)
                    else bytes(bytearray.__getitem__(value, slice(None))) if issubclass(cls, bytearray)
                    else memoryview.tobytes(value))
            if len(data) > MAX_TEXT:
                raise PlainError(f"your answer holds {len(data):,} bytes; the answer is much shorter.")
            return {"$bytearray" if issubclass(cls, bytearray) else "$bytes": data.hex()}
        if issubclass(cls, (list, tuple, set, frozenset)):
            base = next(kind for kind in (list, tuple, set, frozenset) if issubclass(cls, kind))
            items = [convert(item, depth + 1) for item in base.__iter__(value)]
            return items if base is list else {f"${base.__name__}": items}
        if issubclass(cls, dict):
            return {"$dict": [[convert(key, depth + 1), convert(item, depth + 1)]
                              for key, item in dict.items(value)]}
        if issubclass(cls, type):
            return {"$class": _name_of(value)}
        if issubclass(cls, BaseException):
            args = BaseException.__dict__["args"].__get__(value)
            return {"$exception": _name_of(cls), "args": [_text(arg) for arg in args[:4]]}
        if issubclass(cls, DataBank):
            _count_bank(banks)
            return {"$databank": _layout(value)}
        module = _name_of(cls).split(":")[0]
        if module.startswith("modbus_edu.widgets") and callable(getattr(value, "config", None)):
            return convert(value.config(), depth)  # a panel is its settings (a test tool also holds a bank)
        if module.startswith("modbus_edu"):
            bank = getattr(value, "bank", None)
            if isinstance(bank, DataBank):
                _count_bank(banks)
                return {"$databank": _layout(bank)}
        return {"$object": type.__dict__["__name__"].__get__(cls)[:60]}

    try:
        return convert(answer, 0)
    except RecursionError:
        raise PlainError("your answer is nested too deeply to read.") from None


def to_json(data: Any) -> str:
    """The JSON text of plain data, or a :class:`PlainError` when it is longer than :data:`MAX_WIRE`."""
    text = json.dumps(data, separators=(",", ":"))
    if len(text) > MAX_WIRE:
        raise PlainError("your answer is far too large to check.")
    return text


@functools.cache
def known_classes() -> dict[str, type]:
    """The classes an answer's name (``module:qualname``) brings back as themselves: Python's built-in ones
    and the library's errors, PDUs, frames and banks, by name.

    Built once from modules imported at the top of this one; a name in an answer is only looked up here,
    so reviving an answer never imports a module nor runs its code."""
    table: dict[str, type] = {}
    for module in (builtins, errors, pdu, framing, datamodel):
        for value in vars(module).values():
            if isinstance(value, type):
                name = _name_of(value)
                if name.startswith(("builtins:", "modbus_edu.", "modbus_edu:")):
                    table.setdefault(name, value)
    return table


def _resolve(name: Any, base: type = object) -> type:
    """The known class of that name (:func:`known_classes`), or a new class of that name and nothing more."""
    name = str(name)[:200]
    found = known_classes().get(name)
    if found is not None and issubclass(found, base):
        return found
    title = name.rpartition(":")[2].rsplit(".", 1)[-1][:60]
    return type(title if title.isidentifier() else "unknown", (base,), {"__module__": "learner"})


def _bank(layout: dict) -> DataBank:
    """The bank a layout describes (:func:`plain`'s ``$databank``), after checking its size: at most
    :data:`MAX_RUNS` runs, and no table declaring more addresses than it has."""
    tables = {name: list(runs) for name, runs in dict(layout.get("tables", {})).items() if name in _TABLES}
    runs = sum(map(len, tables.values()))
    if runs > MAX_RUNS:
        raise PlainError(f"this bank's layout has {runs:,} runs of addresses, more than the {MAX_RUNS:,} an "
                         "answer may have.")
    bank = DataBank(sparse=bool(layout.get("sparse")))
    for name, table in tables.items():
        declared = 0
        for first, count in table:
            declared += int(count)
            if declared > ADDRESS_SPACE:
                raise PlainError(f"this bank's layout declares more than the {ADDRESS_SPACE:,} addresses of "
                                 f"a table in its {name}.")
            getattr(bank, name).declare(int(first), int(count))
    return bank


class Opaque:
    """An answer that plain data cannot carry: only its type's name remains (it equals nothing else)."""

    def __repr__(self) -> str:
        return f"<a {type(self).__name__}>"


def revive(data: Any) -> Any:
    """The checker's view of plain data made by :func:`plain` (or received from a kernel)."""
    budget, banks = [MAX_ITEMS], [0]

    def back(value: Any, depth: int) -> Any:
        budget[0] -= 1
        if budget[0] < 0 or depth > MAX_DEPTH + 2:
            raise PlainError("your answer is far too large to check.")
        if value is None or type(value) in (bool, int, float, str):
            return value
        if type(value) is list:
            return [back(item, depth + 1) for item in value]
        if type(value) is not dict or len(value) not in (1, 2):
            raise PlainError("this answer is not plain data.")
        tag, content = next(iter(value.items()))
        if tag == "$error":
            raise PlainError(str(content)[:300])
        if tag == "$ellipsis":
            return ...
        if tag == "$int":
            return int(content, 16)
        if tag == "$float":
            return float(content)
        if tag in ("$bytes", "$bytearray"):
            data = bytes.fromhex(content)
            return data if tag == "$bytes" else bytearray(data)
        if tag in ("$tuple", "$set", "$frozenset"):
            items = [back(item, depth + 1) for item in content]
            return {"$tuple": tuple, "$set": set, "$frozenset": frozenset}[tag](items)
        if tag == "$dict":
            return {back(key, depth + 1): back(item, depth + 1) for key, item in content}
        if tag == "$class":
            return _resolve(content)
        if tag == "$exception":
            cls = _resolve(content, BaseException)
            error = BaseException.__new__(cls)
            error.args = tuple(str(arg) for arg in value.get("args", []))
            return error
        if tag == "$databank":
            _count_bank(banks)
            return _bank(content)
        if tag == "$object":
            name = str(content)[:60]
            return type(name if name.isidentifier() else "object", (Opaque,), {})()
        raise PlainError("this answer is not plain data.")

    try:
        return back(data, 0)
    except PlainError:
        raise
    except (TypeError, ValueError, KeyError, AttributeError, ArithmeticError, ModbusError) as exc:
        raise PlainError(f"this answer is not plain data ({type(exc).__name__}).") from None


def from_json(text: str) -> Any:
    """Plain data from its JSON text (as a kernel sends it); raises :class:`PlainError`."""
    if len(text) > MAX_WIRE:
        raise PlainError("your answer is far too large to check.")
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise PlainError(f"this answer is not plain data ({type(exc).__name__}).") from None


def as_plain(answer: Any) -> Any:
    """What a checker reads for ``answer``: ``revive(plain(answer))``."""
    return revive(plain(answer))
