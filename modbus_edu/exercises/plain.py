"""Answers as plain data: what a checker judges, and what leaves a grading kernel.

A checker never sees the learner's own objects.  :func:`plain` turns an answer into JSON-able data made
of exact built-in types, and :func:`revive` turns that data back into the value the checker reads:

* ``None``, ``bool``, ``int``, ``float``, ``str``, ``bytes``, ``bytearray`` and ``memoryview`` become
  their exact built-in type, read through the built-in type's own methods: an ``int`` subclass whose
  ``__eq__`` is always true arrives as the plain number it holds, and is compared as that;
* lists, tuples, dicts, sets and frozensets keep their kind, their items converted the same way;
* a class (``type(error)``) and an exception travel by name; the library's own ones come back as
  themselves, any other as a new class of the same name that is nothing of the library's;
* a :class:`~modbus_edu.DataBank` travels as its layout (which addresses exist in which table); a device
  or slave as its bank; a widget of the course as its ``config()``;
* anything else arrives as an opaque object that only says its type's name (``<an object>``).

Every answer is bounded (:data:`MAX_ITEMS` values, :data:`MAX_DEPTH` levels, :data:`MAX_TEXT` characters
in one string or byte string); beyond that :class:`PlainError` says so in a sentence.

In a learner's notebook ``check`` judges ``revive(plain(answer))`` at once; under ``modbus-edu grade``
the kernel only sends ``plain(answer)`` and the grader revives and judges it in its own process.
"""

from __future__ import annotations

import importlib
import json
import math
from typing import Any

from ..datamodel import DataBank
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
    return {"sparse": bool(bank.sparse), "tables": tables}


def _text(value: Any) -> str:
    try:
        return str.__str__(str(value))[:300]
    except Exception:
        return f"<a {type(value).__name__}>"


def plain(answer: Any) -> Any:
    """``answer`` as JSON-able plain data (see the module's docstring); raises :class:`PlainError`."""
    budget = [MAX_ITEMS]

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
            return {"$databank": _layout(value)}
        module = _name_of(cls).split(":")[0]
        if module.startswith("modbus_edu.widgets") and callable(getattr(value, "config", None)):
            return convert(value.config(), depth)  # a panel is its settings (a test tool also holds a bank)
        if module.startswith("modbus_edu"):
            bank = getattr(value, "bank", None)
            if isinstance(bank, DataBank):
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


def _resolve(name: Any, base: type = object) -> type:
    """The library's (or Python's) class of that name, or a new class of that name and nothing more."""
    module, _, qualname = str(name).partition(":")
    if module == "builtins" or module == "modbus_edu" or module.startswith("modbus_edu."):
        try:
            found: Any = importlib.import_module(module)
            for part in qualname.split("."):
                found = getattr(found, part)
            if isinstance(found, type) and issubclass(found, base):
                return found
        except (ImportError, AttributeError, ValueError):
            pass
    title = qualname.rsplit(".", 1)[-1][:60]
    return type(title if title.isidentifier() else "unknown", (base,), {"__module__": "learner"})


class Opaque:
    """An answer that plain data cannot carry: only its type's name remains (it equals nothing else)."""

    def __repr__(self) -> str:
        return f"<a {type(self).__name__}>"


def revive(data: Any) -> Any:
    """The checker's view of plain data made by :func:`plain` (or received from a kernel)."""
    budget = [MAX_ITEMS]

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
            bank = DataBank(sparse=bool(content.get("sparse")))
            for name, runs in dict(content.get("tables", {})).items():
                if name in _TABLES:
                    for first, count in runs:
                        getattr(bank, name).declare(int(first), int(count))
            return bank
        if tag == "$object":
            name = str(content)[:60]
            return type(name if name.isidentifier() else "object", (Opaque,), {})()
        raise PlainError("this answer is not plain data.")

    try:
        return back(data, 0)
    except PlainError:
        raise
    except (TypeError, ValueError, KeyError, AttributeError, ModbusError) as exc:
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
