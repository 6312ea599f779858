"""A build exercise judged from its source, in a clean room.

Under ``modbus-edu grade`` a build exercise (write ``crc16`` yourself) is not judged in the learner's
kernel, which holds the library and could be made to say anything.  Once the notebook has run, the
grader takes the learner's function from the notebook file (:func:`extract`), runs it in a fresh
interpreter that has only that source and the inputs (:func:`run_room`), and judges what comes back with
the exercise's own checker, in its own process.

**What is taken** (:func:`extract`).  The code cells, IPython magics turned into Python as the kernel
turns them, are read as one module.  For ``check(KEY, NAME)`` (the last such check of the exercise),
``NAME``'s last top-level binding before that check is taken (its ``def``, or an assignment such as
``answer = crc16``), then, for every name it uses, that name's last top-level binding before the check
(a ``def``, a ``class``, an ``import``, an assignment, or a top-level ``for``/``if``/``with``/``try``
that binds it), with the top-level statements after that binding which change it (``TABLE.append(x)``,
``TABLE[i] = x``, ``TABLE += ...``, or a loop holding such a statement), and so on for what those use.
The statements taken keep the notebook's order.  An answer that is an expression (a lambda,
``functools.partial(f)``) is taken as ``__answer__ = <expression>`` with what it uses; an answer that
names the library's own function (``mb.crc16``, or ``crc16`` imported from ``modbus_edu``) is "the
library's own" (:func:`~modbus_edu.exercises.build.library_name`) and is not run.

**What is not taken**: every other statement.  A ``print``, a test call, a plot, a ``check``, code that
patches the library or the grader, an ``%env`` or a file written by the notebook: none of it runs in the
room.  So the function must work from what the notebook defines at its top level above the check.

**The room** (:func:`run_room`).  The installation's own Python (``-I -S``: no environment variables, no
site-packages), run as the learner (:meth:`~.sandbox.Seal.run`) in a fresh empty room of its own
that holds the standard library and the stripped copy only (no site-packages, so no pymodbus; nothing a
kernel or an earlier room wrote), gets the module's source and the argument
tuples, as plain data (:mod:`~modbus_edu.exercises.plain`), on its stdin; the grader drew them from its
own seed and keeps what the library gives for them.  The room imports a *stripped copy* of the library
(:func:`stripped_copy`, made once per grading run and exercise), in which the library's own answer to
that exercise (:data:`BLOCKED`) raises :class:`~modbus_edu.errors.ReferenceUnavailable`, and in which
``modbus_edu.exercises`` holds only the calling code (:mod:`~modbus_edu.exercises.calls`,
:mod:`~modbus_edu.exercises.plain`) and ``modbus_edu.course`` nothing.  A wrapper of ``mb.crc16``, a
reference captured at the top level (``ref = mb.crc16``), a loop over the held-back table
(``CRC_TABLE``, which raises when used) or a reload of the module finds no reference
code: the verdict says the function calls ``mb.crc16``.  The room calls the function as a learner's
``check`` does (:func:`~modbus_edu.exercises.calls.call_all`: the same code, the same time limit) and
writes the trace to its stdout; what the function prints goes to its stderr, which the grader drops.
"""

from __future__ import annotations

import ast
import builtins
import compileall
import functools
import importlib
import shutil
import subprocess
import symtable
import tempfile
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import modbus_edu

from .._optional import load_nbformat
from ..errors import ModbusError, ReferenceUnavailable
from ..exercises import EXERCISES
from ..exercises.build import library_name
from ..exercises.plain import MAX_WIRE, PlainError, from_json, plain, to_json
from .boundary import base_python
from .runner import CELL_LIMIT, NOTEBOOK_LIMIT, NotebookRun, _is_check, _python_source, built

SOURCE_LIMIT = 200_000
"""The most characters of source taken for one exercise; a larger closure is not run."""
MAX_STATEMENTS = 400
"""The most top-level statements taken for one exercise."""
ROOM_TIMEOUT = 30.0
"""Seconds one room may run (its start, loading the module and every call), before it is stopped."""
ANSWER = "__answer__"
"""The name an answer given as an expression is bound to in the module taken."""
PACKAGE = Path(modbus_edu.__file__).resolve().parent


# --- what the room holds back: the library's own answer to each build exercise -------------------------

@dataclass(frozen=True)
class Blocked:
    """The library code that answers one build exercise: ``names`` maps ``"module:qualname"`` to how a
    learner would write it; ``why`` says why each is held back."""

    why: str
    names: dict[str, str]


_CRC = {"modbus_edu.crc:crc16": "mb.crc16", "modbus_edu.crc:crc16_bitwise": "mb.crc16_bitwise",
        "modbus_edu.crc:crc_bytes": "mb.crc_bytes", "modbus_edu.crc:crc16_trace": "mb.crc16_trace",
        "modbus_edu.crc:crc16_table_trace": "mb.crc16_table_trace", "modbus_edu.crc:_word_table": "mb.crc16",
        # the precomputed table and what builds it: a three-line loop over them is the library's CRC
        "modbus_edu.crc:CRC_TABLE": "mb.CRC_TABLE", "modbus_edu.crc:build_crc_table": "mb.build_crc_table"}
_READ_REQUEST = {
    "modbus_edu.pdu.base:_AddressQuantity.__post_init__": "mb.ReadHoldingRegistersRequest",
    "modbus_edu.pdu.base:_AddressQuantity.encode": "mb.ReadHoldingRegistersRequest(...).encode",
    "modbus_edu.pdu.base:_check_quantity": "the library's quantity check",
    "modbus_edu.pdu.base:_check_span": "the library's address range check"}
_TCP_ENCODE = {"modbus_edu.framing.tcp:TcpFrame.encode": "mb.TcpFrame(...).encode"}
_FLOAT = {"modbus_edu.values:decode_value": "mb.decode_value", "modbus_edu.values:decode_values":
          "mb.decode_values", "modbus_edu.values:_registers_to_bytes": "the library's word order"}

BLOCKED: dict[str, Blocked] = {
    "01.5": Blocked("the reference parses with mb.parse_reference (datasheet_to_address reads the same "
                    "numbers)", {"modbus_edu.datamodel:parse_reference": "mb.parse_reference",
                                 "modbus_edu.registermap:datasheet_to_address": "mb.datasheet_to_address"}),
    "02.5": Blocked("the reference is ReadHoldingRegistersRequest: its checks of address and count, and "
                    "its encode", _READ_REQUEST),
    "03.5": Blocked("the reference is mb.crc16; every other CRC of crc.py gives the same value, and so do "
                    "the table (CRC_TABLE, build_crc_table) and the RTU framing built on them", _CRC),
    "04.5": Blocked("the reference is mb.lrc; lrc_trace gives its running sum (the ASCII framing's encoder "
                    "calls lrc)",
                    {"modbus_edu.crc:lrc": "mb.lrc", "modbus_edu.crc:lrc_trace": "mb.lrc_trace"}),
    "05.5": Blocked("the reference is the first 7 bytes of TcpFrame.encode", _TCP_ENCODE),
    "06.5": Blocked("the reference is the library's Slave answering the request", {
        f"modbus_edu.slave:Slave.{method}": "mb.Slave(...).handle" for method in (
            "handle", "handle_direct", "hear", "_handle", "_answer_quickly", "handle_pdu", "process",
            "_execute", "_read_table", "_write_single")} | {
        "modbus_edu.slave:dispatch": "modbus_edu.slave.dispatch",
        "modbus_edu.pdu.base:_ReadRequest.answer_from_bytes": "the library's read fast path"}),
    "07.4": Blocked("the reference is ExceptionResponse: its checks of function and code, and its encode", {
        "modbus_edu.pdu.exceptions:ExceptionResponse.__post_init__": "mb.ExceptionResponse",
        "modbus_edu.pdu.exceptions:ExceptionResponse.encode": "mb.ExceptionResponse(...).encode"}),
    "08.4": Blocked("the reference is SerialTiming.transaction_time, built from its character time and "
                    "silences", {f"modbus_edu.links.wire:SerialTiming.{name}": f"mb.SerialTiming(...).{name}"
                                 for name in ("bits_per_char", "char_time", "t15", "t35", "frame_gap",
                                              "frame_time", "transaction_time")}
                    | {"modbus_edu.links.wire:SerialTiming.__post_init__": "mb.SerialTiming",
                       "modbus_edu.links.wire:character_time": "mb.character_time"}),
    "09.4": Blocked("the reference is expected_answered_fraction", {
        "modbus_edu.devices.arduino:expected_answered_fraction":
            "modbus_edu.devices.arduino.expected_answered_fraction"}),
    "10.4": Blocked("the reference is mb.decode_value(registers, 'float32', order)", _FLOAT),
    "11.4": Blocked("the reference is TcpFrame.decode; the TCP splitter cuts frames by the same header", {
        "modbus_edu.framing.tcp:TcpFrame.decode": "mb.TcpFrame.decode",
        "modbus_edu.framing.tcp:TcpSplitter._cut": "mb.TcpSplitter",
        "modbus_edu.framing.tcp:TcpSplitter._cut_strict": "mb.TcpSplitter"}),
    "12.4": Blocked("the reference is TcpFrame around a ReadHoldingRegistersRequest",
                    _TCP_ENCODE | _READ_REQUEST),
    "13.7": Blocked("nothing: the exercise is to try each word order with mb.decode_value, which the "
                    "learner may call; no function of the library finds the order (the reference lives "
                    "beside the exercise, out of the room)", {}),
    "14.2": Blocked("the reference is mask_write; the Slave applies the same formula", {
        "modbus_edu.pdu.registers:mask_write": "modbus_edu.pdu.registers.mask_write",
        "modbus_edu.slave:Slave._mask_write_register": "mb.Slave(...).handle"}),
    "15.2": Blocked("the reference is RtuFrame.decode then TcpFrame.encode (mb.crc16 stays: the learner "
                    "checks the CRC with it)",
                    {"modbus_edu.framing.rtu:RtuFrame.decode": "mb.RtuFrame.decode"} | _TCP_ENCODE),
    "16.4": Blocked("the reference is strip_echo", {
        "modbus_edu.links.echo:strip_echo": "modbus_edu.links.echo.strip_echo"}),
    "17.3": Blocked("the reference is the course's RoleTable deciding", {
        "modbus_edu.security:RoleTable.decide": "mb.security.course_roles().decide",
        "modbus_edu.security:RoleTable.check": "mb.security.course_roles().check"}),
}
"""Per build exercise, the library code held back in its room (one table; see :class:`Blocked`)."""


class CleanRoomError(ModbusError):
    """The clean room could not be prepared (a blocked name that the library does not have)."""


# --- taking the function from the notebook ------------------------------------------------------------

@dataclass
class Taken:
    """What :func:`extract` took for one exercise: the module's source and the name of the learner's
    function in it; or the library's own name (``library``), or why nothing could be taken (``problem``)."""

    key: str
    name: str = ""
    source: str = ""
    library: str = ""
    problem: str = ""


@dataclass
class _Statement:
    node: ast.stmt
    binds: set[str] = field(default_factory=set)
    changes: set[str] = field(default_factory=set)

    @functools.cached_property
    def source(self) -> str:
        return ast.unparse(self.node)


def _scope_nodes(node: ast.AST):
    """``node`` and what it holds at the same scope (a def, class or lambda is yielded, not entered)."""
    yield node
    for child in ast.iter_child_nodes(node):
        if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda,
                              ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)):
            yield child
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                yield from child.decorator_list
        else:
            yield from _scope_nodes(child)


def _root(node: ast.AST) -> str | None:
    while isinstance(node, (ast.Attribute, ast.Subscript)):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _binds(statement: ast.stmt) -> set[str]:
    """The names a top-level statement binds at the top level (``"*"`` for a star import)."""
    names: set[str] = set()
    for node in _scope_nodes(statement):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.Import):
            names.update(alias.asname or alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            names.update(alias.asname or alias.name for alias in node.names)
    return names


def _changes(statement: ast.stmt) -> set[str]:
    """The names whose value a top-level statement changes without rebinding them (``T[i] = x``,
    ``T.append(x)``, ``T += x``)."""
    names: set[str | None] = set()
    for node in _scope_nodes(statement):
        targets = (node.targets if isinstance(node, (ast.Assign, ast.Delete))
                   else [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else [])
        names.update(_root(t) for t in targets if isinstance(t, (ast.Attribute, ast.Subscript)))
        if isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            names.add(_root(node.func))
    return {name for name in names if name}


def _uses(source: str, statement: ast.stmt) -> set[str]:
    """The names a statement reads from the top level (builtins included; its own bindings not)."""
    try:
        table = symtable.symtable(source, "<cell>", "exec")
    except (SyntaxError, ValueError, RecursionError):
        return set()
    names = {symbol.get_name() for symbol in table.get_symbols()
             if symbol.is_referenced() and not symbol.is_assigned() and not symbol.is_imported()}
    stack = list(table.get_children())
    while stack:
        child = stack.pop()
        stack.extend(child.get_children())
        names.update(symbol.get_name() for symbol in child.get_symbols()
                     if symbol.is_global() and (symbol.is_referenced() or symbol.is_assigned()))
    if isinstance(statement, ast.AugAssign) and isinstance(statement.target, ast.Name):
        names.add(statement.target.id)
    return names


def _statements(cells: Sequence[str]) -> list[_Statement]:
    """Every top-level statement of the notebook's code cells, in order (a cell that does not parse, or
    is longer than the grader runs, binds nothing; the body of a ``%%time`` or ``%%capture`` cell is read
    as the cell, as the kernel runs it)."""
    found = []
    for cell in cells:
        if len(cell) > CELL_LIMIT:
            continue
        first, _, body = cell.lstrip().partition("\n")
        if first.split()[:1] in (["%%time"], ["%%capture"]):  # the body runs as the notebook's own code
            cell = body
        python = _python_source(cell)
        if python is None:
            continue
        for node in ast.parse(python).body:
            found.append(_Statement(node, _binds(node), _changes(node)))
    return found


def _checks(statements: list[_Statement]) -> dict[str, tuple[int, ast.expr]]:
    """Each exercise key's last ``check(KEY, ANSWER)``: the index of its top-level statement, the answer."""
    found: dict[str, tuple[int, ast.expr]] = {}
    for index, statement in enumerate(statements):
        for node in ast.walk(statement.node):
            if _is_check(node) and isinstance(node.args[0], ast.Constant) \
                    and isinstance(node.args[0].value, str):
                found[node.args[0].value] = (index, node.args[1])
    return found


def _dotted(node: ast.expr, statements: list[_Statement], before: int) -> str | None:
    """``modbus_edu.crc16`` for ``mb.crc16`` when ``mb`` is last bound, before ``before``, by an import of
    the library (or ``crc16`` by ``from modbus_edu import crc16``); else None."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    for statement in reversed(statements[:before]):
        if node.id not in statement.binds:
            continue
        if isinstance(statement.node, ast.Import):
            for alias in statement.node.names:
                if (alias.asname or alias.name.split(".")[0]) == node.id:
                    base = alias.name if alias.asname else alias.name.split(".")[0]
                    return ".".join([base, *reversed(parts)])
        if isinstance(statement.node, ast.ImportFrom) and not statement.node.level:
            for alias in statement.node.names:
                if (alias.asname or alias.name) == node.id:
                    return ".".join([statement.node.module or "", alias.name, *reversed(parts)])
        return None
    return None


def _librarys_own(dotted: str | None) -> str:
    """The library's name for ``dotted`` (``mb.crc16``) when it is the library's own function, else ''."""
    if not dotted or not (dotted == "modbus_edu" or dotted.startswith("modbus_edu.")):
        return ""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            found = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for part in parts[cut:]:
                found = getattr(found, part)
        except AttributeError:
            return ""
        return library_name(found) or ""
    return ""


def extract(cells: Sequence[str], key: str) -> Taken | None:
    """The learner's function for build exercise ``key`` from a notebook's code cells (see the module's
    docstring), or None when the notebook does not check ``key``."""
    statements = _statements(cells)
    found = _checks(statements).get(key)
    if found is None:
        return None
    position, answer = found
    named = answer
    while isinstance(named, ast.Call) and named.args and \
            _dotted(named.func, statements, position) == "functools.partial":  # a partial is its function
        named = named.args[0]
    library = _librarys_own(_dotted(named, statements, position))
    if library:
        return Taken(key, library=library)
    chosen: set[int] = set()
    if isinstance(answer, ast.Name):
        name, wanted = answer.id, [answer.id]
        extra: list[_Statement] = []
    else:
        name = ANSWER
        line = f"{ANSWER} = {ast.unparse(answer)}"
        extra = [_Statement(ast.parse(line).body[0])]
        wanted = sorted(_uses(line, extra[0].node))
    binders: dict[str, list[int]] = {}
    changers: dict[str, list[int]] = {}
    for index, statement in enumerate(statements[:position]):
        for bound in statement.binds:
            binders.setdefault(bound, []).append(index)
        for changed in statement.changes:
            changers.setdefault(changed, []).append(index)
    seen: set[str] = set()
    while wanted:
        needed = wanted.pop()
        if needed in seen:
            continue
        seen.add(needed)
        binding = (binders.get(needed) or binders.get("*") or [None])[-1]
        if binding is None:  # a builtin, or a name the room will say is not defined
            if needed == name and not hasattr(builtins, needed):
                return Taken(key, name=name, problem=(
                    f"{name} is not defined at the top level of the notebook before check({key!r}, "
                    f"{name}) (define it with def in a cell of its own, above the check)"))
            continue
        for index in [binding, *(i for i in changers.get(needed, []) if i > binding)]:
            if index not in chosen:
                chosen.add(index)
                wanted.extend(_uses(statements[index].source, statements[index].node) - seen)
        if len(chosen) > MAX_STATEMENTS:
            return Taken(key, name=name,
                         problem=f"uses more than {MAX_STATEMENTS} statements of the notebook")
    source = "\n".join(statements[index].source for index in sorted(chosen))
    source = "\n".join(part for part in (source, *(s.source for s in extra)) if part) + "\n"
    if len(source) > SOURCE_LIMIT:
        return Taken(key, name=name, problem=f"takes {len(source):,} characters of source with what it uses; "
                                             f"the grader takes up to {SOURCE_LIMIT:,}")
    return Taken(key, name=name, source=source)


def notebook_cells(path: Path) -> list[str]:
    """The code cells' sources of a notebook file (empty when it cannot be read, or is larger than the
    grader reads)."""
    try:
        if path.stat().st_size > NOTEBOOK_LIMIT:
            return []
        notebook = load_nbformat().read(path, as_version=4)
    except Exception:
        return []
    return [cell.source for cell in notebook.cells if cell.cell_type == "code"]


# --- the stripped copy of the library -----------------------------------------------------------------

_copying = threading.Lock()


HELD = (
    "class _Held:\n"
    "    \"\"\"A value of the library held back in the clean room: any use of it raises.\"\"\"\n"
    "    def __init__(self, shown):\n"
    "        object.__setattr__(self, '_shown', shown)\n"
    "    def _refuse(self, *args, **kwargs):\n"
    "        from modbus_edu.errors import ReferenceUnavailable as _Unavailable\n"
    "        raise _Unavailable(object.__getattribute__(self, '_shown'))\n"
    "    __getitem__ = __iter__ = __len__ = __contains__ = __call__ = __index__ = __int__ = _refuse\n"
    "    __add__ = __radd__ = __mul__ = __rmul__ = __eq__ = __ne__ = __bool__ = __reversed__ = _refuse\n"
    "    __getattr__ = _refuse\n"
    "    __hash__ = object.__hash__\n")
"""Prepended to a module of the stripped copy where a value (a table, a constant) is held back."""


def _strip(source: str, qualnames: dict[str, str], module: str) -> str:
    """``source`` with each function or method of ``qualnames`` reduced to raising ReferenceUnavailable,
    and each module-level value of ``qualnames`` (``CRC_TABLE``) replaced by one that raises when used."""
    tree = ast.parse(source)
    left = dict(qualnames)
    held = False

    def visit(body: list[ast.stmt], prefix: str) -> None:
        nonlocal held
        for node in body:
            if isinstance(node, ast.ClassDef):
                visit(node.body, f"{prefix}{node.name}.")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and f"{prefix}{node.name}" in left:
                shown = left.pop(f"{prefix}{node.name}")
                node.body = ast.parse(f"from modbus_edu.errors import ReferenceUnavailable as _Unavailable\n"
                                      f"raise _Unavailable({shown!r})").body
            elif not prefix and isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names = [target.id for target in targets
                         if isinstance(target, ast.Name) and target.id in left]
                if names:
                    node.value = ast.parse(f"_Held({left.pop(names[0])!r})", mode="eval").body
                    held = True
    visit(tree.body, "")
    if left:
        raise CleanRoomError(f"{module} has no {', '.join(sorted(left))} to hold back")
    if held:
        start = next((index + 1 for index, node in enumerate(tree.body) if isinstance(node, ast.ImportFrom)
                      and node.module == "__future__"), 0)
        tree.body[start:start] = ast.parse(HELD).body
    return ast.unparse(ast.fix_missing_locations(tree)) + "\n"


def stripped_copy(key: str, folder: Path) -> Path:
    """The folder holding a copy of ``modbus_edu`` for exercise ``key``'s room, made in ``folder`` once.

    Every blocked function or method of :data:`BLOCKED` ``[key]`` raises ReferenceUnavailable there;
    ``modbus_edu/course`` is left out and ``modbus_edu/exercises`` holds only ``calls`` and ``plain``.
    The rest is the library as it is, so the copy imports as the library does."""
    target = folder / f"library-{key}"
    with _copying:
        if (target / "modbus_edu").is_dir():
            return target
        work = Path(tempfile.mkdtemp(prefix=f"library-{key}-", dir=folder))
        package = work / "modbus_edu"
        shutil.copytree(PACKAGE, package, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "course"))
        kept = {"__init__.py", "calls.py", "plain.py"}
        for entry in (package / "exercises").iterdir():
            if entry.name not in kept:
                shutil.rmtree(entry) if entry.is_dir() else entry.unlink()
        (package / "exercises" / "__init__.py").write_text(
            '"""In the clean room: only the code that calls a learner\'s function (no checker, no '
            'reference)."""\n', encoding="utf-8")
        by_module: dict[str, dict[str, str]] = {}
        for target_name, shown in BLOCKED.get(key, Blocked("", {})).names.items():
            module, _, qualname = target_name.partition(":")
            by_module.setdefault(module, {})[qualname] = shown
        for module, qualnames in by_module.items():
            path = package.joinpath(*module.split(".")[1:])
            path = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
            path.write_text(_strip(path.read_text(encoding="utf-8"), qualnames, module), encoding="utf-8")
        # compiled here, once: a room sees its copy read-only, and would compile every module it imports
        compileall.compile_dir(work, quiet=2)
        for path in [work, *work.rglob("*")]:
            path.chmod(0o755 if path.is_dir() else 0o644)
        work.rename(target)
    return target


# --- the room: running the module on the grader's arguments -------------------------------------------

ROOM_CODE = ("import sys; sys.path.insert(0, sys.argv[1]); "
             "from modbus_edu.exercises.calls import room_main; room_main()")
"""What the room's Python runs (``-c``), the stripped copy's folder as its argument."""


def room_argv(library: Path) -> list[str]:
    """The room's command line before sealing: the installation's own Python (not the environment's),
    reading no environment variable and no site-packages."""
    return [base_python(), "-I", "-S", "-c", ROOM_CODE, str(library)]


def run_room(taken: Taken, arguments: Sequence[tuple], *, library: Path, time_limit: float,
             follow_plans: list | None = None,
             seal: Callable[..., subprocess.CompletedProcess] | None = None) -> dict:
    """The trace of the function ``taken`` on ``arguments``, run in a room on the stripped copy
    ``library``; ``seal`` runs the room's command line as the learner, as ``subprocess.run`` runs it
    (:meth:`~.sandbox.Seal.run`).  Never raises: a room that fails gives a trace that says so."""
    if taken.library:
        return {"library": taken.library}
    if taken.problem:
        return {"name": taken.name, "unloadable": taken.problem}
    try:
        job = to_json({"source": taken.source, "name": taken.name, "time_limit": time_limit,
                       "arguments": plain([tuple(args) for args in arguments]), "plans": follow_plans})
    except PlainError as exc:
        return {"name": taken.name, "unloadable": f"the grader could not send the inputs ({exc})"}
    options = {"input": job.encode("utf-8"), "stdout": subprocess.PIPE, "stderr": subprocess.DEVNULL,
               "timeout": ROOM_TIMEOUT, "start_new_session": True, "cwd": library}
    try:
        done = seal(room_argv(library), copy=library, **options) if seal else subprocess.run(
            room_argv(library), **options)
    except subprocess.TimeoutExpired:
        return {"name": taken.name, "calls": [], "stopped": True}
    except OSError as exc:
        return {"name": taken.name, "unloadable": f"the grader could not start its room ({exc})"}
    text = done.stdout[-MAX_WIRE:].decode("utf-8", "replace").strip()
    try:
        trace = from_json(text)
    except PlainError:
        trace = None
    if not isinstance(trace, dict):
        return {"name": taken.name, "unloadable": f"the room ended without a trace (exit status "
                                                  f"{done.returncode})"}
    return trace


def room_trace(key: str, taken: Taken, seed: str, *, folder: Path,
               seal: Callable[..., subprocess.CompletedProcess] | None = None) -> tuple[dict, list]:
    """Exercise ``key``'s function, taken from the notebook, traced in its room on the inputs of
    ``seed``; the trace and the cases (arguments, expected) the grader judges it against."""
    checker = EXERCISES[key].checker
    arguments = checker.arguments(seed)
    cases = checker.expected(arguments)
    library = stripped_copy(key, folder)
    trace = run_room(taken, arguments, library=library, time_limit=checker.time_limit,
                     follow_plans=checker.follow_plans(arguments), seal=seal)
    return trace, cases


def trace_built(run: NotebookRun, *, source: Path, seed: str, rooms: Path,
                seal: Callable[..., subprocess.CompletedProcess] | None = None
                ) -> dict[str, tuple[dict, list]]:
    """Each of the run's build exercises traced in its clean room: the function taken from ``source``
    (the handed-in notebook file), the inputs drawn from ``seed``, the room's copy of the library made in
    ``rooms``; key -> (trace, cases)."""
    keys = built(run)
    if not keys:
        return {}
    cells = notebook_cells(source)
    traces = {}
    for key in keys:
        taken = extract(cells, key)
        if taken is not None:
            traces[key] = room_trace(key, taken, f"{key} {seed}", folder=rooms, seal=seal)
    return traces


__all__ = ["ANSWER", "BLOCKED", "Blocked", "CleanRoomError", "ReferenceUnavailable", "Taken", "extract",
           "notebook_cells", "room_argv", "room_trace", "run_room", "stripped_copy", "trace_built"]

