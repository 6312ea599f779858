"""Build exercises: the learner writes a function, and the checker runs it against the library.

A build exercise is registered with :func:`build_exercise`.  Its checker calls the learner's function on
the exercise's edge cases and then on ``count`` inputs drawn from a seeded random generator (the same
inputs every run), and compares each result with what the library's ``reference`` gives for the same
arguments.  The first input where they differ is shown with both values.  Where the reference refuses
the input (it raises a :class:`~modbus_edu.ModbusError`, as for a frame with a bad CRC), the learner's
function must raise too.

The learner's function runs in a worker thread with a time limit (2 s for all the inputs together), so a
function that never returns is reported, and stopped, instead of hanging the notebook (in a browser, where
no thread can start, a trace function keeps the same limit: :func:`~.calls.run_within`).  Whatever it does
(raise, return the wrong type, print), the checker answers with a message and never raises.
"""

from __future__ import annotations

import copy
import math
import random
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import modbus_edu

from ..errors import ModbusError, ReferenceUnavailable
from .calls import call_all, follow_plan, is_unwritten
from .core import EXERCISES, Exercise, Raised, bytes_diagnosis, first_difference, kind, register, show
from .diagnosis.misconceptions import CATALOGUE
from .diagnosis.misconceptions import name as misconception
from .diagnosis.procedure import REFUSED, Procedure
from .plain import revive

TIME_LIMIT = 2.0
"""Seconds the learner's function gets for all the inputs of one check together."""


class _Refused:
    """The reference raised a ModbusError for this input: the learner's function must raise too."""

    def __init__(self, error: ModbusError) -> None:
        self.error = error


def same(expected: Any, got: Any) -> bool:
    """The default comparison: equal values of the same kind.

    bytes and bytearray count as the same kind, as do tuples and lists; floats compare to 1e-9; an int
    answer is not accepted where a float is expected only when it differs; bools are not ints."""
    if isinstance(expected, bool) or isinstance(got, bool):
        return type(expected) is type(got) and expected == got
    if isinstance(expected, float) or isinstance(got, float):
        if not isinstance(got, (int, float)) or not isinstance(expected, (int, float)):
            return False
        if math.isnan(expected):
            return math.isnan(got)
        return math.isclose(expected, got, rel_tol=1e-9, abs_tol=1e-9)
    if isinstance(expected, (bytes, bytearray)):
        return isinstance(got, (bytes, bytearray)) and bytes(got) == bytes(expected)
    if isinstance(expected, (tuple, list)):
        return (isinstance(got, (tuple, list)) and len(got) == len(expected)
                and all(same(a, b) for a, b in zip(expected, got)))
    if isinstance(expected, dict):
        return (isinstance(got, dict) and got.keys() == expected.keys()
                and all(same(expected[k], got[k]) for k in expected))
    if isinstance(expected, int):
        return isinstance(got, int) and got == expected
    return type(got) is type(expected) and bool(got == expected)


def _type_note(expected: Any, got: Any) -> str:
    """A sentence when ``got`` is of another kind than ``expected``, else an empty string."""
    want, have = kind(expected), kind(got)
    alike = ({"a tuple", "a list"}, {"a float", "an int"}, {"bytes"})
    if want == have or any({want, have} <= group for group in alike):
        return ""
    return f" Your function returns {have}; {want} is expected."


class BuildChecker:
    """The checker of one build exercise (see the module's docstring), in two halves.

    :meth:`trace` runs where the learner's function lives (the notebook's kernel): it calls the function
    on the inputs drawn from ``seed`` (and reads back what it stored), within the time limit, and returns
    what it gave as plain data.  :meth:`judge` runs where the verdict is made: it draws the same inputs
    from ``seed``, computes what the library gives, and compares.  In a learner's notebook the two run one
    after the other (``judge(trace(function, seed), seed)``).  Under ``modbus-edu grade`` the kernel
    traces nothing: the grader draws the arguments from a seed of its own for each learner
    (:meth:`arguments`), keeps what the library gives for them (:meth:`expected`), has the function taken
    from the notebook called on them in a clean room (:mod:`modbus_edu.course.cleanroom`, with the same
    calling code, :func:`~.calls.call_all`), and judges the trace against those cases."""

    def __init__(self, key: str, reference: Callable, inputs: Callable[[random.Random], Sequence],
                 edge_cases: Iterable[Sequence], count: int,
                 diagnose: Callable[[Sequence, Any, Any], str | None] | None,
                 compare: Callable[[Any, Any], bool] | None, time_limit: float,
                 read_back: Callable[[tuple, tuple], tuple | None] | None = None,
                 show_expected: Callable[[Any], str] | None = None, procedure: Procedure | None = None,
                 boundary: Callable[[tuple], str | None] | None = None) -> None:
        self.key = key
        self.procedure = procedure
        self.boundary = boundary or default_boundary
        self.reference = reference
        self.inputs = inputs
        self.edge_cases = [tuple(case) for case in edge_cases]
        self.count = count
        self.diagnose = diagnose
        self.compare = compare or same
        self.time_limit = time_limit
        self.read_back = read_back
        self.show_expected = show_expected or show
        self.seed = f"modbus_edu exercise {key}"
        """The seed of a learner's own check (the same inputs every run)."""
        self._cases: list[tuple[tuple, Any]] | None = None

    def arguments(self, seed: str | None = None) -> list[tuple]:
        """The argument tuples tried, in order: the edge cases, then ``count`` drawn from ``seed``."""
        rng = random.Random(self.seed if seed is None else seed)
        return self.edge_cases + [tuple(self.inputs(rng)) for _ in range(self.count)]

    def cases(self, seed: str | None = None) -> list[tuple[tuple, Any]]:
        """Every (arguments, expected) pair: the edge cases, then ``count`` seeded random inputs."""
        if (seed is None or seed == self.seed) and self._cases is not None:
            return self._cases
        cases = self.expected(self.arguments(seed))
        if seed is None or seed == self.seed:
            self._cases = cases
        return cases

    def expected(self, arguments: Sequence[tuple]) -> list[tuple[tuple, Any]]:
        """Each argument tuple with what the library gives for it (a refusal where it raises)."""
        cases = []
        for args in arguments:
            try:
                expected = self.reference(*copy.deepcopy(args))
            except ModbusError as exc:
                expected = _Refused(exc)
            cases.append((args, expected))
        return cases

    def follow_plans(self, arguments: Sequence[tuple]) -> list | None:
        """For a function that changes its arguments, how each call's state is read back, as plain data
        (:func:`~.calls.follow_plan`): what the clean room needs without this checker; else None."""
        if self.read_back is None:
            return None
        return [follow_plan(self.read_back, tuple(args)) for args in arguments]

    def __call__(self, function: Any) -> str | None:
        return self.judge(self.trace(function), self.seed)

    # --- the kernel's half: call the learner's function, keep what it gives as plain data ----------------

    def trace(self, function: Any, seed: str | None = None) -> dict:
        """What ``function`` gives on the inputs drawn from ``seed``, as plain data (never raises).

        The calling itself is :func:`~.calls.call_all`, the same code the grader's clean room runs."""
        if not callable(function):
            return {"not_callable": show(function)}
        if is_unwritten(function):
            return {"unwritten": True}
        library = library_name(function)
        if library:
            return {"library": library}
        read_back = self.read_back
        follow = None if read_back is None else (lambda index, args, state: read_back(args, state))
        return call_all(function, self.arguments(seed), time_limit=self.time_limit,
                        name=f"exercise {self.key}", follow=follow)

    # --- the grader's half: the library's answers, compared with the trace ---------------------------------

    def judge(self, trace: dict, seed: str | None = None, *,
              cases: list[tuple[tuple, Any]] | None = None) -> str | None:
        """None if the traced function agrees with the library on every input of ``seed`` (or on the
        arguments of ``cases``, from :meth:`expected`, when the grader drew them itself); else why not."""
        if "not_callable" in trace:
            return ("this exercise asks for a function: define it with def, then pass its name without "
                    f"parentheses, as in check(\"{self.key}\", my_function). "
                    f"You gave {trace['not_callable']}.")
        if "library" in trace:
            return f"that is `{trace['library']}`; write your own."
        name, calls = str(trace.get("name", "your_function"))[:60], list(trace.get("calls", []))
        reference = _reference_called(trace, calls)
        if reference:
            return f"{name} {reference}"
        if "unloadable" in trace:
            return (f"{name} could not be run from the notebook alone: {str(trace['unloadable'])[:300]}. "
                    "A graded function may use Python's standard library, modbus_edu, and what the notebook "
                    "defines at its top level above the check (functions, classes, imports, constants).")
        cases = self.cases(seed) if cases is None else cases
        for index, (args, expected) in enumerate(cases):
            if index >= len(calls):
                if not trace.get("stopped"):
                    return "your function's results did not all come back; run the check again."
                return (f"your function did not finish within {self.time_limit:g} s (it was still working on "
                        f"{self._call(name, args)}, input {index + 1} of {len(cases)}). "
                        "Look for a loop that never ends.")
            verdict = self._one(name, args, expected, calls[index],
                                (cases, calls, self.procedure is not None and self.procedure.refusals))
            if verdict is not None:
                return verdict
        return None

    def _call(self, name: str, args: Sequence) -> str:
        return f"{name}({', '.join(show(arg) for arg in args)})"

    def _note(self, args: tuple, expected: Any, got: Any, evidence: tuple | None = None) -> str:
        """The diagnosis of a failing input, or an empty string.

        With the concept's procedure (:mod:`.diagnosis.procedure`) and the whole trace (``evidence``): the
        change of one step that gives what the learner's function gave on every input, or the candidates;
        where none does, the exercise's own detectors (only for misconceptions the procedure does not
        model), then the change that fits this input alone and the boundary the input falls on."""
        if self.procedure is not None and evidence is not None:
            words = self.procedure.explain([(args, got), *_answers(*evidence[:2], skip=args,
                                                                   refusals=evidence[2:] == (True,))])
            if words:
                return _sentence(words)
            legacy = self._diagnosed(args, expected, got)
            if legacy and not _labels(legacy) & self.procedure.misconceptions:
                return _sentence(legacy)
            return ""
        return _sentence(self._diagnosed(args, expected, got))

    def _clue(self, args: tuple, got: Any, evidence: tuple | None) -> str:
        """Where no change is named: the change that fits this input alone, and the boundary it falls on."""
        if evidence is None:
            return ""
        near = self.procedure.nearest(args, got, "every input") if self.procedure is not None else None
        return "".join(_sentence(part) for part in (near, self.boundary(args)) if part)

    def _bytes_note(self, args: tuple, expected: Any, got: Any, evidence: tuple | None) -> str:
        """Where the function returns bytes and no procedure of the exercise names the slip: the frame
        procedure's change that fits this input and every other the function got wrong (else nothing is
        named), then the field the first wrong byte belongs to and what it should hold, and the clue."""
        if not isinstance(expected, (bytes, bytearray)) or not isinstance(got, (bytes, bytearray)):
            return ""
        cut = _slice_note(args, bytes(expected), bytes(got))
        if cut:
            return _sentence(cut)
        words = bytes_diagnosis(bytes(got), bytes(expected))
        if words and evidence is not None and not _fits_every_answer(words, args, evidence):
            words = None
        if words:
            return _sentence(words)
        return (_sentence(first_difference(bytes(got), bytes(expected), "your function's answer"))
                + self._clue(args, got, evidence))

    def _diagnosed(self, args: tuple, expected: Any, got: Any) -> str:
        """What the exercise's own ``diagnose`` names for this one input, or an empty string."""
        if self.diagnose is None:
            return ""
        try:
            return self.diagnose(args, expected, got) or ""
        except Exception:
            return ""

    def _one(self, name: str, args: tuple, expected: Any, entry: dict,
             evidence: tuple | None = None) -> str | None:
        """None if the traced call agrees with the library on ``args``, else a message."""
        call = self._call(name, args)
        if "fatal" in entry:
            return f"your function raised {entry['fatal']}, which stops everything."
        if "unreadable" in entry:
            return f"{call} returned something the checker cannot read: {entry['unreadable']}"
        if "raised" in entry:
            if isinstance(expected, _Refused):
                return None
            raised = Raised(str(entry["raised"]), str(entry.get("message", "")))
            modelled = self.procedure is not None and self.procedure.refusals
            return (f"{call} raised {entry['raised']}: {show(str(entry.get('message', '')))}. "
                    f"The library gives {self.show_expected(expected)}."
                    + ((self._note(args, expected, REFUSED, evidence) if modelled else "")
                       or self._note(args, expected, raised)))
        got = revive(entry.get("out"))
        if isinstance(expected, _Refused):
            note = self._note(args, expected, got, evidence if self.procedure is not None
                              and self.procedure.refusals else None)
            detail = "" if note else f" ({expected.error})"
            words = misconception("invalid-input-accepted")
            return (f"{call} returned {show(got)}, but that input is not valid{detail}: your function should "
                    "raise an exception for it." + (note or f" {words[0].upper()}{words[1:]}"))
        try:
            if not self.compare(expected, got):
                message = (f"{call} should give {self.show_expected(expected)}; "
                           f"your function gives {show(got)}.")
                note = self._note(args, expected, got, evidence)
                return message + (note or (_type_note(expected, got) if self.compare is same else "")
                                  or self._bytes_note(args, expected, got, evidence)
                                  or self._clue(args, got, evidence))
        except Exception:
            return f"{call} returned {show(got)}, which cannot be compared with the library's answer."
        return self._read_back(name, call, args, entry)

    def _read_back(self, name: str, call: str, args: tuple, entry: dict) -> str | None:
        """After a call that changed its arguments, the read back of the learner's state and the library's."""
        if self.read_back is None:
            return None
        library_state = copy.deepcopy(args)
        try:
            self.reference(*library_state)
        except ModbusError:
            return None
        follow = self.read_back(args, library_state)
        if follow is None:
            return None
        expected = self.reference(*copy.deepcopy(follow))
        mine = self.read_back(args, revive(entry.get("state")))
        read = entry.get("read")
        if mine is None or read is None:
            return f"after {call}, what your function stored could not be read back."
        if "raised" in read:
            return (f"after {call}, reading it back with {self._call(name, mine)} raised "
                    f"{read['raised']}: {show(str(read.get('message', '')))}.")
        if "out" not in read:
            return f"after {call}, reading it back with {self._call(name, mine)} gave nothing readable."
        got = revive(read["out"])
        if self.compare(expected, got):
            return None
        message = (f"after {call}, reading it back with {self._call(name, mine)} should give "
                   f"{show(expected)}; your function gives {show(got)}.")
        return message + self._note(mine, expected, got)


def _sentence(words: str) -> str:
    """``words`` as a sentence that follows another: a space, then a capital."""
    words = words.strip()
    return f" {words[0].upper()}{words[1:]}" if words else ""


def _labels(words: str) -> set[str]:
    """The catalogue keys whose labels ``words`` contains."""
    lowered = words.lower()
    return {key for key, entry in CATALOGUE.items() if entry.label.lower() in lowered}


def _slice_note(args: tuple, expected: bytes, got: bytes) -> str | None:
    """Where the answer and the function's are both slices of an argument (a function that cuts its input):
    where each starts and ends, so the slice's off-by-one shows."""
    for number, arg in enumerate(args, 1):
        if not isinstance(arg, (bytes, bytearray)) or not got or not expected:
            continue
        arg = bytes(arg)
        mine, right = arg.rfind(got), arg.rfind(expected)
        if mine < 0 or right < 0 or (mine, len(got)) == (right, len(expected)):
            continue
        off = abs(mine - right) or abs(len(got) - len(expected))
        return (f"your function's answer is bytes {mine}-{mine + len(got) - 1} of argument {number}; the "
                f"answer is bytes {right}-{right + len(expected) - 1}: the cut is {off} "
                f"byte{'s' * (off > 1)} off, at its {'start' if mine != right else 'end'}.")
    return None


MOST_BYTES_CHECKED = 12
"""How many other wrong answers of a trace a frame slip is held against before it is named."""


def _fits_every_answer(words: str, args: tuple, evidence: tuple) -> bool:
    """Whether the slip ``words`` names (the frame procedure's, on the input ``args``) is named the same on
    the other inputs the function returned wrong bytes for (the first :data:`MOST_BYTES_CHECKED` of them)."""
    labels, checked = _labels(words), 0
    if not labels:
        return True
    for (other, expected), entry in zip(*evidence[:2]):
        if other is args or not isinstance(entry, dict) or "out" not in entry:
            continue
        try:
            got = revive(entry["out"])
        except Exception:  # an answer the checker cannot read is no evidence either way
            continue
        if not isinstance(expected, (bytes, bytearray)) or not isinstance(got, (bytes, bytearray)) \
                or bytes(got) == bytes(expected):
            continue
        found = bytes_diagnosis(bytes(got), bytes(expected))
        if not found or _labels(found) != labels:
            return False
        checked += 1
        if checked >= MOST_BYTES_CHECKED:
            break
    return True


def _answers(cases: list, calls: list, skip: tuple, refusals: bool = False) -> list[tuple[tuple, Any]]:
    """Every (arguments, what the learner's function returned) of a trace, but the call with ``skip``;
    with ``refusals``, a call that raised counts too, as :data:`~.diagnosis.procedure.REFUSED`."""
    found = []
    for (args, _expected), entry in zip(cases, calls):
        if refusals and args is not skip and isinstance(entry, dict) and "raised" in entry:
            found.append((args, REFUSED))
        elif args is not skip and isinstance(entry, dict) and "out" in entry:
            try:
                found.append((args, revive(entry["out"])))
            except Exception:  # an answer the checker cannot read is no evidence either way
                continue
    return found


def default_boundary(args: tuple) -> str | None:
    """The boundary a failing input falls on, said in words: no bytes, one byte, more than 256 bytes."""
    for arg in args:
        if isinstance(arg, (bytes, bytearray)):
            if not arg:
                return "This input is the empty one (no bytes): the task allows it."
            if len(arg) == 1:
                return "This input is a single byte."
            if len(arg) > 256:
                return f"This input is {len(arg)} bytes long, more than 256: the task allows any length."
    return None


def _reference_called(trace: dict, calls: list) -> str:
    """The message of :class:`~modbus_edu.errors.ReferenceUnavailable` when the traced function (or the
    code it was loaded with) reached for the library's own answer in the clean room, else ''."""
    loading = str(trace.get("unloadable", ""))
    if loading.startswith(f"{ReferenceUnavailable.__name__}: "):
        return loading.split(": ", 1)[1][:300]
    for entry in calls:
        for outcome in (entry, entry.get("read") or {}) if isinstance(entry, dict) else ():
            if isinstance(outcome, dict) and outcome.get("raised") == ReferenceUnavailable.__name__:
                return str(outcome.get("message", ""))[:300] or ReferenceUnavailable.__name__
    return ""


def library_name(function: Any) -> str | None:
    """``"mb.crc16"`` when ``function`` is the library's own code (or a method or partial of it), else None.

    The course's deliberately wrong functions (the exercises' ``refuses`` tables) are not counted."""
    target = function
    for _ in range(8):  # unwrap bound methods, partials and decorated functions
        inner = getattr(target, "__func__", None) or getattr(target, "func", None) \
            or getattr(target, "__wrapped__", None)
        if inner is None or inner is target:
            break
        target = inner
    module = getattr(target, "__module__", None) or getattr(type(target), "__module__", "")
    if not isinstance(module, str) or not (module == "modbus_edu" or module.startswith("modbus_edu.")):
        return None
    references = {id(item.checker.reference) for item in EXERCISES.values() if item.kind == "build"}
    if module.startswith("modbus_edu.exercises") and id(target) not in references:
        return None
    short = str(getattr(target, "__name__", "") or type(target).__name__)
    if getattr(modbus_edu, short, None) is target:
        return f"mb.{short}"
    return f"{module}.{getattr(target, '__qualname__', short)}"


def build_exercise(key: str, title: str, *, reference: Callable, inputs: Callable[[random.Random], Sequence],
                   hint: str | tuple[str, ...], wrong: Callable | None = None,
                   edge_cases: Iterable[Sequence] = (),
                   count: int = 100, diagnose: Callable[[Sequence, Any, Any], str | None] | None = None,
                   compare: Callable[[Any, Any], bool] | None = None, time_limit: float = TIME_LIMIT,
                   refuses: Iterable[tuple[Callable, str | None]] = (),
                   read_back: Callable[[tuple, tuple], tuple | None] | None = None,
                   show_expected: Callable[[Any], str] | None = None, procedure: Procedure | None = None,
                   boundary: Callable[[tuple], str | None] | None = None) -> Exercise:
    """Register a build exercise: the learner's function is checked against ``reference``.

    ``inputs(rng)`` draws one tuple of arguments from the seeded ``random.Random`` it is given;
    ``edge_cases`` are argument tuples always tried first.  ``diagnose(args, expected, got)`` names the
    catalogued misconception behind a failing input (see :mod:`.misconceptions`);
    ``compare(expected, got)`` replaces the default comparison :func:`same`; ``show_expected`` words the
    library's answer in a message (default: :func:`~.core.show`).  ``read_back(args, state)``, for a
    function that changes its arguments (a slave storing a write), gives the arguments of a second call
    that reads the state back (``state``: the arguments after the first call), or None.
    ``procedure`` is the concept's procedure with its perturbations (:mod:`.diagnosis.procedures`): a
    failing function is named by the one change that reproduces all it returned (``diagnose`` then names
    only what the procedure does not model); ``boundary(args)`` says in words which boundary of the task a
    failing input falls on (default: no bytes, one byte, more than 256 bytes).

    ``refuses`` lists ``(wrong function, misconception key)`` pairs: each must fail, naming that
    misconception.  ``wrong`` is a plausible wrong function (by default the first of ``refuses``)."""
    if count < 100:
        raise ValueError(f"exercise {key}: a build exercise tries at least 100 generated inputs")
    refuses = tuple((function, misconception) for function, misconception in refuses)
    if wrong is None:
        if not refuses:
            raise ValueError(f"exercise {key}: give a wrong function (wrong= or refuses=)")
        wrong = refuses[0][0]
    checker = BuildChecker(key, reference, inputs, edge_cases, count, diagnose, compare, time_limit,
                           read_back, show_expected, procedure, boundary)
    return register(Exercise(key, title, hint, checker, wrong, kind="build", refuses=refuses))
