"""The machinery behind every exercise: the registry, ``check`` and ``evaluate``, and the small helpers
checkers share to turn a learner's answer into a verdict that teaches.

An exercise cell in a notebook ends with::

    answer = ...          # replace ... with your answer
    check("03.1", answer)

Run unanswered, ``check`` prints "not answered yet" and raises nothing, so the notebook still runs from
top to bottom.  With an answer it says whether it is right and, if not, what is wrong and a hint.  The
expected values are computed with the library itself, never typed in.  Whatever the learner passes in
(a huge int, a deeply nested list, an object whose methods raise), ``check`` answers with a message and
never raises.

How strict a checker is, the same in every exercise: **spelling is free, the value is not.**  A right value
is accepted in every spelling the course uses: hex digits in upper or lower case, with or without ``0x``
and leading zeros; an int, a float that is a whole number (``3.0``) or a number written as text
(``"17"``, ``"0x11"``); bytes, a hex string or a list of ints; more decimals than asked when they round to
the answer.  Where an exercise asks for a form (a 5-digit reference number, an ASCII frame's upper-case hex
characters, an exception class rather than an instance of it, hex as the test tool's grid shows it,
milliseconds, a fraction, a CRC's two bytes in wire order), a right value in another form is refused with
:func:`right_value_in_another_form` (the catalogue's "another-form"): "the right value in another form: the
value is right; write it as ...".  A wrong value is never accepted for its form.
"""

from __future__ import annotations

import dataclasses
import math
import reprlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..codes import _hex
from ..crc import crc16
from ..errors import ModbusError
from ..explain import explain, explain_pdu
from ..framing import parse_hex
from .calls import safe_str
from .diagnosis.frames import frame_verdict
from .diagnosis.frameslip import frame_slip
from .diagnosis.misconceptions import CATALOGUE, detect, diagnose
from .diagnosis.misconceptions import name as catalogue_words
from .diagnosis.procedures import ADDRESS
from .plain import PlainError, plain, revive

PLACEHOLDER = ...
"""What an unanswered exercise cell holds: the Ellipsis, ``...``."""

MAX_MESSAGE = 700
"""The longest verdict ``check`` prints, in characters: a learner's huge answer never floods a cell."""

MAX_ANSWER_BYTES = 4096
"""The most bytes a byte answer may hold; every answer in the course is far shorter."""


class AnswerError(ModbusError):
    """A learner's answer that cannot even be read as what the exercise asks for."""


@dataclass(frozen=True)
class Exercise:
    """One exercise: its key (``"NN.k"``: notebook and number), title, hint, checker and a wrong answer.

    ``kind`` is ``"value"`` when the learner gives a value (a number, some bytes) and ``"build"`` when the
    learner writes a function that the checker runs against the library on many inputs.

    ``accepts`` are answers the checker must take as right (the spellings a learner may use);
    ``refuses`` are ``(answer, misconception)`` pairs: a wrong answer (or a wrong function, for a build
    exercise) and the key of :data:`~.misconceptions.CATALOGUE` its verdict must name, or None for a
    wrong answer that is no catalogued misconception.  The test suite runs both tables.
    """

    key: str
    title: str
    hint: str
    checker: Callable[[Any], str | None]
    wrong: Any
    kind: str = "value"
    accepts: tuple = ()
    refuses: tuple = ()

    @property
    def solution(self) -> str:
        """The worked solution's file, relative to the notebooks folder."""
        return f"solutions/{self.key.replace('.', '_')}.py"


@dataclass(frozen=True)
class Result:
    """What :func:`check` found.  ``ok`` is None while the exercise is unanswered."""

    key: str
    ok: bool | None
    message: str

    def __str__(self) -> str:
        return self.message

    def __bool__(self) -> bool:
        return bool(self.ok)

    def _ipython_display_(self) -> None:
        """As the last line of a notebook cell: nothing more to show, check() has printed the verdict."""


EXERCISES: dict[str, Exercise] = {}

AFTER_CHECK: dict[str, Callable[[Any, Result], Result]] = {}
"""What :func:`~.submit.check` does after judging an exercise in the learner's own kernel, by key (never
under the grader, never in :func:`evaluate`): the concept inventory keeps the pre-test's answers and
sets the post-test's beside them."""


class Recorded(str):
    """A checker's words for an answer it keeps without judging it yet (the pre-test's): :func:`check`
    prints them as they are, and the exercise counts as done."""

LINES: dict[str, tuple[str, ...]] = {}
"""The hints after the first, by key.  Hints escalate: the exercise's ``hint`` gives the idea from the
first wrong try; from :data:`TRIES_BEFORE_LINE` wrong tries on, :func:`check` adds the next level, one
more per try: the step, then a worked example of the same idea on other numbers (never the exercise's
own line).  An exercise gives them as ``hint=(idea, step, example)``, or :func:`line_after_tries`."""

TRIES_BEFORE_LINE = 2

LEVELS = ("the next step", "the same idea on other numbers")
"""How :func:`check` introduces each level of :data:`LINES`."""

wrong_tries: dict[str, int] = {}
"""How many wrong answers :func:`check` has seen per exercise since its last right one (this kernel)."""


def line_after_tries(key: str, *levels: str) -> None:
    """Give exercise ``key``'s hints after the idea: the step, then a worked example on other numbers,
    shown from the second wrong try on, one more per try."""
    LINES[key] = levels


def register(item: Exercise) -> Exercise:
    """Add ``item`` to :data:`EXERCISES`; a key is registered once.  A ``hint`` given as a tuple is the
    idea followed by the levels of :data:`LINES`."""
    if not isinstance(item.hint, str):
        idea, *more = item.hint
        item = dataclasses.replace(item, hint=idea)
        LINES[item.key] = tuple(more)
    if item.key in EXERCISES:
        raise ValueError(f"exercise {item.key} is registered twice")
    if item.kind not in ("value", "build"):
        raise ValueError(f"exercise {item.key}: kind is 'value' or 'build', not {item.kind!r}")
    for _answer, key in item.refuses:
        if key is not None and key not in CATALOGUE:
            raise ValueError(f"exercise {item.key}: {key!r} is not in the catalogue of misconceptions")
    EXERCISES[item.key] = item
    return item


_NO_ANSWER = object()


def exercise(key: str, title: str, *, hint: str | tuple[str, ...], wrong: Any = _NO_ANSWER, accepts: Any = (),
             refuses: Any = ()) -> Callable:
    """Register a value exercise's checker under ``key`` (decorator).

    The checker takes the learner's answer and returns None when it is right, or a sentence saying
    what is wrong.  ``accepts`` lists answers that must be taken as right (other spellings of the
    answer); ``refuses`` lists ``(wrong answer, misconception key or None)`` pairs: each must be refused,
    and its verdict must name that misconception of the catalogue.  ``wrong`` is a plausible wrong answer
    (by default the first of ``refuses``).
    """
    refuses = tuple((answer, misconception) for answer, misconception in refuses)
    if wrong is _NO_ANSWER:
        if not refuses:
            raise ValueError(f"exercise {key}: give a wrong answer (wrong= or refuses=)")
        wrong = refuses[0][0]

    def decorate(checker: Callable[[Any], str | None]) -> Callable[[Any], str | None]:
        register(Exercise(key, title, hint, checker, wrong, accepts=tuple(accepts), refuses=refuses))
        return checker

    return decorate


def _find(key: Any) -> Exercise | Result:
    """The exercise ``key`` names, or the verdict for a key that names none."""
    if not isinstance(key, str) or key not in EXERCISES:
        known = ", ".join(sorted(EXERCISES))
        return Result(clip(str(show(key)), 100), False,
                      f"There is no exercise {show(key)}; the exercises are {known}.")
    return EXERCISES[key]


def _result(item: Exercise, decide: Callable[[], str | None], raising: bool = False) -> Result:
    """The verdict ``decide()`` gives (None: right, else what is wrong), as a Result; never raises, unless
    ``raising``: then an exception that is no verdict on the answer (the checker itself failed) is raised."""
    try:
        problem = decide()
    except PlainError as exc:
        problem = str(exc)
    except ModbusError as exc:
        problem = f"the library could not use your answer: {clip(safe_str(exc), 300)}"
    except RecursionError:
        problem = "your answer is nested too deeply to read."
    except MemoryError:
        problem = "your answer is far too large to check."
    except Exception:  # the learner's object may fail in any way: answer, never raise
        if raising:
            raise
        problem = ("the checker cannot read your answer as what this exercise asks for; give it in the form "
                   "the exercise's cell and its hint show.")
    if problem is None:
        return Result(item.key, True, f"Right! Exercise {item.key} ({item.title}) is solved.")
    if isinstance(problem, Recorded):
        return Result(item.key, True, str(problem))
    return Result(item.key, False, clip(f"Not yet: {problem}", MAX_MESSAGE - len(item.hint) - 8)
                  + f"\nHint: {item.hint}")


def count_try(result: Result) -> Result:
    """``result`` as :func:`check` prints it: counts the wrong tries per exercise and, from the second
    on, adds the next level of its hints (:data:`LINES`) under the idea; a right answer starts again."""
    key = result.key
    if key in EXERCISES:
        if result.ok is False:
            tries = wrong_tries[key] = wrong_tries.get(key, 0) + 1
            levels = LINES.get(key, ())[:tries - TRIES_BEFORE_LINE + 1]
            if levels:
                more = "\n".join(f"After {TRIES_BEFORE_LINE + n} tries, {LEVELS[min(n, len(LEVELS) - 1)]}: "
                                  f"{level}" for n, level in enumerate(levels))
                return Result(key, False, f"{result.message}\n{more}")
        elif result.ok:
            wrong_tries.pop(key, None)
    return result


def _unanswered(item: Exercise, build: bool = False) -> Result:
    more = ": write the body of the function, then run the cell again." if build else "."
    return Result(item.key, None, f"Exercise {item.key} ({item.title}) is not answered yet{more}")


def evaluate(key: Any, answer: Any) -> Result:
    """Check ``answer`` against exercise ``key`` without printing anything; never raises.

    The checker judges the answer's plain form (:mod:`.plain`): an object that only pretends to equal
    the answer is read as the plain value it holds.  A build exercise's function is traced here and
    judged from its trace, as the grader judges it (:meth:`~.build.BuildChecker.trace`)."""
    item = _find(key)
    if isinstance(item, Result):
        return item
    if answer is PLACEHOLDER:
        return _unanswered(item)
    if item.kind == "build":
        return judge(key, item.checker.trace(answer))
    try:
        data = plain(answer)
    except PlainError as exc:
        data = {"$error": str(exc)}
    return verdict(key, data)


def verdict(key: Any, data: Any, *, raising: bool = False) -> Result:
    """The verdict on a value exercise's answer given as plain data (:func:`.plain.plain`); never raises.

    With ``raising`` (the grader's way), a checker that fails on the answer (an exception other than the
    library's errors, which are verdicts) raises it: the grader reports that exercise as errored rather
    than telling a learner their answer has the wrong shape."""
    item = _find(key)
    if isinstance(item, Result):
        return item
    if item.kind == "build":
        return Result(item.key, False, f"Exercise {item.key} asks for a function, which the grader traces.")
    try:
        answer = revive(data)
    except PlainError as exc:
        problem = str(exc)
        return _result(item, lambda: problem)
    if answer is PLACEHOLDER:
        return _unanswered(item)
    return _result(item, lambda: item.checker(answer), raising)


def judge(key: Any, trace: Any, seed: str | None = None, *, cases: list | None = None,
          raising: bool = False) -> Result:
    """The verdict on a build exercise from the trace of the learner's function (inputs drawn from
    ``seed``, by default the exercise's own; or the (arguments, expected) ``cases`` the grader drew with
    :meth:`~.build.BuildChecker.expected`); never raises, unless ``raising`` (as :func:`verdict`)."""
    item = _find(key)
    if isinstance(item, Result):
        return item
    if item.kind != "build" or not isinstance(trace, dict):
        return Result(item.key, False, f"Exercise {item.key}: this is no trace of a function.")
    if trace.get("unwritten"):
        return _unanswered(item, build=True)
    return _result(item, lambda: item.checker.judge(trace, seed, cases=cases), raising)


# --- showing a learner's values safely ---------------------------------------------------------------

_repr = reprlib.Repr()
_repr.maxstring = 60
_repr.maxother = 60
_repr.maxlong = 40
_repr.maxlist = _repr.maxtuple = _repr.maxdict = _repr.maxset = 8
_repr.maxlevel = 3


def clip(text: str, limit: int) -> str:
    """``text`` cut to ``limit`` characters, with an ellipsis when cut."""
    limit = max(limit, 20)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def kind(value: Any) -> str:
    """The kind of ``value`` in words, with its article: "an int", "a str", "bytes", "None"."""
    name = type(value).__name__
    if value is None or name in ("bytes", "bytearray"):
        return "None" if value is None else "bytes"
    return f"{'an' if name[0] in 'aeiou' else 'a'} {name}"


@dataclass(frozen=True)
class Raised:
    """What a build exercise's diagnosis gets as ``got`` when the learner's function raised where the
    library answers: the exception's class name and message."""

    name: str
    message: str


class Written(int):
    """A number drawn for a build exercise that messages write the way the exercise writes it:
    ``Written(0x43C9, "0x{:04X}")`` as 0x43C9 (a register, in an exercise given in hex),
    ``Written(38400)`` as 38400 (a baud rate, never 0x9600).  Otherwise a plain int."""

    form: str

    def __new__(cls, value: int, form: str = "{}") -> Written:
        number = super().__new__(cls, value)
        number.form = form
        return number

    def __repr__(self) -> str:
        return self.form.format(int(self))

    def __str__(self) -> str:
        return int.__repr__(self)


def show(value: Any) -> str:
    """A short, readable form of ``value`` for a message: bytes in hex, ints also in hex (a
    :class:`Written` number as its exercise writes it), long things cut."""
    try:
        if isinstance(value, Written):
            return repr(value)
        if isinstance(value, (bytes, bytearray)):
            text = _hex(bytes(value[:24]))
            more = f" … ({len(value)} bytes)" if len(value) > 24 else ""
            return f'bytes.fromhex("{text}"){more}'
        if isinstance(value, int) and not isinstance(value, bool):
            if value.bit_length() > 64:
                return f"an int of {value.bit_length()} bits"
            return f"{value} (0x{value:X})" if value > 9 else str(value)
        if isinstance(value, tuple):
            return "(" + ", ".join(show(item) for item in value[:8]) + (", …" if len(value) > 8 else "") \
                + ("," if len(value) == 1 else "") + ")"
        return clip(_repr.repr(value), 120)
    except Exception:
        return f"<a {type(value).__name__}>"


# --- reading answers -----------------------------------------------------------------------------------

def as_bytes(answer: Any) -> bytes:
    """Accept bytes, a bytearray, a list of ints 0..255 or a hex string ("01 03 00 ...") as a byte answer.

    Raises :class:`AnswerError` (never allocates from an int, never reads more than
    :data:`MAX_ANSWER_BYTES`)."""
    if isinstance(answer, (bytes, bytearray, memoryview)):
        data = bytes(answer)
    elif isinstance(answer, str):
        if len(answer) > 3 * MAX_ANSWER_BYTES:
            raise AnswerError(f"your hex text is {len(answer)} characters long; the answer is much shorter.")
        data = parse_hex(answer)
    elif isinstance(answer, (list, tuple)):
        if len(answer) > MAX_ANSWER_BYTES:
            raise AnswerError(f"your list has {len(answer)} items; the answer is much shorter.")
        for index, item in enumerate(answer):
            if isinstance(item, bool) or not isinstance(item, int) or not 0 <= item <= 255:
                raise AnswerError(f"item {index} of your list is {show(item)}; each byte is an int 0..255.")
        data = bytes(answer)
    else:
        raise AnswerError(f"give bytes (b'\\x01\\x03', bytes.fromhex(\"01 03\"), a hex string \"01 03\" or a "
                          f"list of ints), not {kind(answer)}.")
    if len(data) > MAX_ANSWER_BYTES:
        raise AnswerError(f"your answer has {len(data)} bytes; the answer is much shorter.")
    return data


def number_text(answer: Any) -> Any:
    """``answer`` read as a number when it is short text that writes one ("17", "0x11", " 2.5 "), else
    ``answer`` unchanged: a number's spelling as text is one more spelling of it."""
    if not isinstance(answer, str) or len(answer) > 40:
        return answer
    text = answer.strip().replace("_", "")
    for read in (lambda t: int(t, 0), lambda t: int(t, 10), float):
        try:
            return read(text)
        except ValueError:
            continue
    return answer


def int_answer(answer: Any, what: str) -> int | str:
    """The answer as an int (a float that is a whole number, such as 3.0, and text such as "17" or "0x11"
    are the same value), or a sentence saying why it is not one."""
    answer = number_text(answer)
    if isinstance(answer, float) and math.isfinite(answer) and answer.is_integer() and abs(answer) < 2 ** 63:
        answer = int(answer)
    if isinstance(answer, bool) or not isinstance(answer, int):
        return (f"{what} is a whole number (an int such as 5 or 0x05), "
                f"you gave {kind(answer)}: {show(answer)}.")
    if answer.bit_length() > 64:
        return f"{what} is far smaller than the number you gave ({show(answer)})."
    return answer


def real_answer(answer: Any, what: str) -> float | str:
    """The answer as a finite float (text such as "12.5" is the same value), or a sentence saying why it is
    not a usable number."""
    answer = number_text(answer)
    if isinstance(answer, bool) or not isinstance(answer, (int, float)):
        return f"{what} is a number (such as 12.5), you gave {kind(answer)}: {show(answer)}."
    if isinstance(answer, int) and answer.bit_length() > 1000:
        return f"{what} is far smaller than the number you gave."
    value = float(answer)
    if not math.isfinite(value):
        return f"{what} is a finite number, you gave {answer!r}."
    return value


def close(got: float, expected: float, rel: float = 1e-3) -> bool:
    """True if ``got`` is within the relative tolerance ``rel`` of ``expected``."""
    return abs(got - expected) <= rel * abs(expected)


def number_answer(answer: Any, expected: float, *, decimals: int, unit: str = "",
                  what: str = "the answer") -> str | None:
    """None if ``answer`` equals ``expected`` to ``decimals`` decimals; otherwise what is wrong.

    Names the usual slips from the catalogue: seconds (or microseconds) given where milliseconds were
    asked (or milliseconds for seconds), a fraction where a percentage was asked (or the reverse),
    decimals cut off instead of rounded; and a near miss ("close: give 2 decimals")."""
    got = real_answer(answer, what)
    if isinstance(got, str):
        return got
    tolerance = 0.5 * 10 ** -decimals + 1e-12
    if abs(got - expected) <= tolerance:
        return None
    slips = {"ms": ("seconds-for-milliseconds", "microseconds-for-milliseconds"),
             "%": ("fraction-for-percentage",),
             "s": ("milliseconds-for-seconds",), "": ("percentage-for-fraction",)}
    named = (diagnose(slips.get(unit, ()), got, expected) if expected else None) or diagnose(
        "truncated-not-rounded", got, expected, decimals)
    if named:
        return named
    if abs(got - expected) <= max(10 * tolerance, 0.01 * abs(expected)):
        places = "a whole number" if decimals == 0 else f"{decimals} decimal{'s' * (decimals > 1)}"
        return f"close: give {places}."
    return f"{got:g}{' ' + unit if unit else ''} is not {what}."


# --- comparing and diagnosing ------------------------------------------------------------------------

def compare_bytes(answer: Any, expected: bytes, what: str, mode: str | None = None) -> str | None:
    """None if ``answer`` is exactly ``expected``; otherwise the slip the frame procedure names
    (:func:`bytes_diagnosis`), or which byte differs first, the field it belongs to and what that field
    should hold, from :func:`~modbus_edu.explain.explain`'s dissection of the expected frame (``mode``:
    "rtu", "tcp" or "pdu"; None: whatever mode dissects it without error)."""
    got = as_bytes(answer)
    if got == expected:
        return None
    return bytes_diagnosis(got, expected, mode) or first_difference(got, expected, what, mode)


def bytes_diagnosis(got: bytes, expected: bytes, mode: str | None = None) -> str | None:
    """The slip that makes ``got`` of the asked bytes ``expected``: one change of the frame procedure
    (:func:`~.diagnosis.frames.frame_verdict`, in ``mode`` or whichever mode reads ``expected``), or a part
    of the asked bytes (:func:`part_diagnosis`); None when neither fits."""
    named = next(filter(None, (frame_verdict(got, expected, kind) for kind in ((mode,) if mode else
                                                                              ("rtu", "tcp", "pdu")))), None)
    return named or part_diagnosis(got, expected, mode)


def first_difference(got: bytes, expected: bytes, what: str, mode: str | None = None) -> str:
    """Where ``got`` first differs from ``expected``, the field that byte belongs to and what it should
    hold (or which field is missing, or that bytes follow the last field)."""
    for index, (mine, theirs) in enumerate(zip(got, expected)):
        if mine != theirs:
            return (f"{what} differs at byte {index}{_field_at(expected, index, mode)}: you have "
                    f"0x{mine:02X}, it should be 0x{theirs:02X} ({len(got)} bytes given, {len(expected)} "
                    "expected).")
    if len(got) < len(expected):
        missing = _field_at(expected, len(got), mode, lead="")
        return (f"{what} has {len(got)} bytes, it should have {len(expected)}"
                f"{missing and '; what is missing starts with the' + missing}.")
    return f"{what} has {len(got)} bytes, it should have {len(expected)}: nothing follows the last field."


def _dissection(expected: bytes, mode: str | None) -> Any:
    """The fields of the frame ``expected`` (:func:`~modbus_edu.explain.explain`), or None."""
    for kind in (mode,) if mode else ("rtu", "tcp", "pdu"):
        try:
            found = explain_pdu(expected) if kind == "pdu" else explain(expected, mode=kind)
        except ModbusError:
            continue
        if found.error is None and found.rows:
            return found
    return None


def part_diagnosis(got: Any, expected: bytes, mode: str | None = None) -> str | None:
    """Name an answer that is one part of the asked bytes (some of its fields, in their place): which
    fields it holds, and that the whole is asked."""
    if not detect("part-of-answer", got, expected):
        return None
    got = bytes(got)
    start = bytes(expected).find(got)
    end = start + len(got) - 1
    dissection = _dissection(expected, mode)
    rows = [] if dissection is None else [row for row in dissection.rows
                                           if row.offset <= end and start < row.offset + len(row.raw)]
    if rows:
        names = [("part of " if row.offset < start or row.offset + len(row.raw) - 1 > end else "") + row.field
                 for row in rows]
        held = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
        span = f"byte {start}" if start == end else f"bytes {start}-{end}"
        words = f"the {held} ({span})"
    else:
        words = f"bytes {start}-{end} of it"
    missing = _field_at(expected, len(got), mode, lead="") if start == 0 else ""
    outside = [] if dissection is None else [row.field.lower() for row in dissection.rows
                                              if row.offset + len(row.raw) - 1 < start or row.offset > end]
    left_out = [next((key for part, key in LEFT_OUT.items() if part in field), None) for field in outside]
    left_out = [] if None in left_out else left_out  # named only where every field left out has its name
    return catalogue_words("part-of-answer", part=words,
                           whole=f"all {len(expected)} bytes, {_dissection_span(dissection)}") + (
        f" What is missing starts with the{missing}." if missing else "") + "".join(
        f" {CATALOGUE[key].label[:1].upper()}{CATALOGUE[key].label[1:]}." for key in dict.fromkeys(left_out))


LEFT_OUT = {"unit": "unit-missing", "crc": "crc-forgotten", "function code": "function-code-missing",
            "byte count": "byte-count-missing", "length": "mbap-length-missing"}
"""The fields whose leaving out the catalogue names (a part of a field's name: the misconception)."""


def _dissection_span(dissection: Any) -> str:
    if dissection is None or not dissection.rows:
        return "every field in its place"
    return f"from the {dissection.rows[0].field} to the {dissection.rows[-1].field}"


def _field_at(expected: bytes, index: int, mode: str | None, lead: str = ", in the") -> str:
    """Where byte ``index`` of the frame ``expected`` lies, in words: ", in the quantity (bytes 4-5), which
    should hold 00 02 (2: number of registers to read)", or an empty string when no dissection fits."""
    dissection = _dissection(expected, mode)
    if dissection is None:
        return ""
    for row in dissection.rows:
        if row.offset <= index < row.offset + len(row.raw):
            last = row.offset + len(row.raw) - 1
            span = f"byte {row.offset}" if last == row.offset else f"bytes {row.offset}-{last}"
            return (f"{lead} {row.field} ({span}), which should hold {row.raw.hex(' ').upper()} "
                    f"({row.value}: {row.meaning})")
    return ""


def compare_rtu_frame(answer: Any, expected: bytes, what: str, swapped: str | None = None) -> str | None:
    """Like :func:`compare_bytes` for an RTU frame, naming the slips of the catalogue: the two CRC bytes the
    wrong way round (``swapped``, when given, is added to that verdict), no CRC, a CRC over the PDU alone,
    and a field written wrong (:func:`~.frameslip.frame_slip`)."""
    got = as_bytes(answer)
    named = frame_verdict(got, expected, "rtu") or diagnose("crc-swapped", got, expected)
    if named:
        return f"{named} {swapped}" if swapped and detect("crc-swapped", got, expected) else named
    return rtu_frame_diagnosis(got, expected) or compare_bytes(got, expected, what)


def rtu_frame_diagnosis(got: bytes, expected: bytes) -> str | None:
    """Name the slips in an RTU frame that are not the CRC's byte order: no CRC, a CRC without the address,
    a field in decimal digits, low byte first or with its hex digits read as decimal."""
    if got == expected[:-2]:
        return diagnose("crc-forgotten", len(got), len(expected))
    return (diagnose(("checksum-without-address", "unit-missing"), got, expected)
            or request_field_diagnosis(got, expected, 1, 2) or frame_slip(got, expected, tail=2))


def request_field_diagnosis(got: Any, expected: bytes, start: int, tail: int = 0) -> str | None:
    """Name the slip in a request's function code or address when every other byte is right (the last
    ``tail`` bytes, a checksum, left out): holding and input registers confused, an address counted from 1
    or given as a reference number.  ``start`` is the function code's index (0 in a PDU)."""
    if not isinstance(got, (bytes, bytearray)) or len(got) != len(expected):
        return None
    if len(expected) < start + 5 + tail:
        return None
    differ = {i for i in range(len(expected) - tail) if got[i] != expected[i]}
    if differ == {start}:
        return diagnose("holding-for-input", got[start], expected[start])
    if differ and differ <= {start + 1, start + 2}:
        return address_diagnosis(int.from_bytes(got[start + 1:start + 3], "big"),
                                 int.from_bytes(expected[start + 1:start + 3], "big"))
    return None


def pdu_envelope_diagnosis(got: Any, expected: bytes, unit: int | None = None) -> str | None:
    """Name a PDU given with its envelope (the unit, by default whatever byte leads, in front of it, or a
    whole frame around it) or without its function code."""
    got = bytes(got) if isinstance(got, (bytes, bytearray)) else b""
    if len(got) == len(expected) + 1 and got[1:] == expected:
        return diagnose("unit-in-pdu", got, expected, got[0] if unit is None else unit)
    return diagnose(("frame-for-pdu", "function-code-missing"), got, expected)


def tcp_frame_diagnosis(got: Any, expected: bytes) -> str | None:
    """Name the catalogued slips in a Modbus/TCP frame or MBAP header: a field low byte first, a CRC after
    it, the length field left out or counting the wrong bytes, a PDU field written wrong."""
    if not isinstance(got, (bytes, bytearray)) or got == expected:
        return None
    got = bytes(got)
    named = frame_verdict(got, expected, "tcp") or diagnose(
        ("mbap-little-endian", "crc-on-tcp", "mbap-length-missing", "unit-missing"), got, expected)
    if named:
        return named
    if len(got) == len(expected) >= 7 and got[:4] == expected[:4] and got[6:] == expected[6:]:
        return diagnose("mbap-length", int.from_bytes(got[4:6], "big"), int.from_bytes(expected[4:6], "big"))
    if len(got) == len(expected) + 2 and got[:len(expected)] == expected[:4] + got[4:6] + expected[6:]:
        return diagnose("crc-on-tcp", expected + got[-2:], expected)
    return (request_field_diagnosis(got, expected, 7) or frame_slip(got, expected)
            or (pdu_envelope_diagnosis(got[7:], expected[7:]) if got[:7] == expected[:7] and expected[7:]
                else None))


def field_diagnosis(got: Any, expected: int) -> str | None:
    """Name a one-field slip of number base: a value's hex digits read as decimal (0x36 as 36), or a
    decimal number written as hex digits (54 as 0x54)."""
    named = diagnose("hex-read-as-decimal", got, expected)
    if named:
        return f"{named} Here 0x{expected:X} is {expected}, not {got}."
    return diagnose("decimal-written-as-hex", got, expected)


def named_then(named: str | None, said: str) -> str:
    """A verdict's sentence ``said``, after the slip ``named`` (if any) as a sentence of its own."""
    return f"{named} {said[:1].upper()}{said[1:]}" if named else said


def right_value_in_another_form(form: str) -> str:
    """The verdict for a right value written in another form than the one the exercise asks for (see the
    module's docstring): said the same way in every exercise, as the catalogue's "another-form"."""
    return catalogue_words("another-form", form=form)


def pdu_address_diagnosis(got: Any, expected: bytes) -> str | None:
    """Name an address slip (from 1, a reference number) in a request PDU that is otherwise right."""
    got = bytes(got) if isinstance(got, (bytes, bytearray)) else b""
    if len(got) == len(expected) >= 5 and got[:1] == expected[:1] and got[3:] == expected[3:]:
        return address_diagnosis(int.from_bytes(got[1:3], "big"), int.from_bytes(expected[1:3], "big"))
    return None


def compare_pdu(answer: Any, expected: bytes, what: str = "the PDU", unit: int | None = None) -> str | None:
    """Like :func:`compare_bytes` for a PDU, naming the slips of giving the unit in front of it or a whole
    frame instead, and a field written wrong (:func:`~.frameslip.frame_slip`)."""
    got = as_bytes(answer)
    return (frame_verdict(got, expected, "pdu") or pdu_envelope_diagnosis(got, expected, unit)
            or request_field_diagnosis(got, expected, 0)
            or frame_slip(got, expected) or compare_bytes(got, expected, what))


def address_diagnosis(got: int, expected: int) -> str | None:
    """Name the address slips: the address procedure (:data:`~.diagnosis.procedures.ADDRESS`) of the
    register numbered ``expected + 1``, with one step changed (counted from 1, 1 subtracted twice, the
    reference number given)."""
    if not isinstance(got, int) or isinstance(got, bool) or not isinstance(expected, int):
        return None
    return ADDRESS.explain([((expected + 1,), got)])


def crc_diagnosis(data: bytes, got: Any) -> str | None:
    """Name the CRC slips from the catalogue: a result in bytes, the bytes swapped, the register started
    at 0 (CRC-16/ARC), the unreflected (MSB-first) variant, or one byte of the two."""
    return (diagnose("crc-as-bytes", got) or diagnose("crc-swapped", got, crc16(data))
            or diagnose(("crc-initial-zero", "crc-msb-first"), data, got)
            or diagnose("crc-one-byte", got, crc16(data)))
