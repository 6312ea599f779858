"""The concept inventory: twelve questions on the catalogue's misconceptions, asked before and after.

Notebook 00 opens the course with them (exercise ``00.0``, in :data:`ORDER_PRE`) and notebook 17 closes it
with the same questions in another, fixed order (exercise ``17.0``, :data:`ORDER_POST`).  Each question
probes one misconception of :mod:`.misconceptions` (its ``probes`` key), and each wrong choice is the
answer a misconception gives (its key in ``wrong``): the post-test's verdict names, for each wrong letter,
the misconception that letter stands for.

A learner answers with the letters of the choices in the notebook's order, as a string (``"BADC..."``,
spaces ignored, ``?`` for "I do not know") or a dict ``{1: "b", 2: "a", ...}``.  The pre-test's verdict
only records the answers, right or wrong: a pre-test must not teach its answers before the course does.
``check`` keeps them in the learner's home (:data:`RECORD`), and the post-test's verdict, which names
the misconception behind each wrong answer, then shows which of the pre-test's answers were right.

:func:`score` marks one answer per question; :func:`gains` gives a class's normalised gain
g = (post - pre) / (max - pre) per question and overall, from class averages over the learners who
answered both.  When the class's pre average is already the maximum, g is undefined (None, shown "—").
"""

from __future__ import annotations

import contextlib
import json
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ModbusError
from .core import AFTER_CHECK, Recorded, Result, exercise
from .diagnosis.misconceptions import CATALOGUE

PRE = "00.0"
POST = "17.0"
LETTERS = "abcd"
DONT_KNOW = "?"
RECORD = Path.home() / ".modbus_edu" / "inventory.json"
"""Where :func:`~.submit.check` keeps a learner's pre-test letters, for notebook 17 (another kernel)."""


class InventoryError(ModbusError):
    """An answer to the concept inventory that cannot be read as one letter per question."""


@dataclass(frozen=True)
class Question:
    """One question: its id, text, four choices (a to d), the right letter, the misconception the
    question probes (a key of the catalogue: the gain table's label) and, for each wrong letter, the
    misconception that choice stands for (the verdict names it)."""

    id: str
    text: str
    choices: tuple[str, str, str, str]
    right: str
    probes: str
    wrong: dict[str, str]

    def misconception(self, letter: str | None) -> str:
        """The catalogue key a learner's ``letter`` stands for: that wrong choice's, or the question's
        own for "I do not know"."""
        return self.wrong.get(letter or "", self.probes)


QUESTIONS: tuple[Question, ...] = (
    Question("word-order", "A power meter sends a 32-bit float in two registers. Which order do those two "
             "registers come in?",
             ("the high half first: the specification fixes it",
              "the low half first: the specification fixes it",
              "each device's own choice: its datasheet tells",
              "either: a float reads the same in both orders"), "c", "word-order",
             {"a": "word-order-in-specification", "b": "word-order-in-specification", "d": "word-order"}),
    Question("mbap-order", "A Modbus/TCP request has transaction identifier 10. Which bytes carry it?",
             ("00 0A", "0A 00", "00 10", "0A"), "a", "mbap-little-endian",
             {"b": "mbap-little-endian", "c": "decimal-written-as-hex", "d": "field-in-one-byte"}),
    Question("reference", "A datasheet lists the first holding register as 40001. Which address does a "
             "function 3 request send for it?",
             ("40001", "40000", "1", "0"), "d", "reference-number",
             {"a": "reference-number", "b": "reference-number", "c": "one-based-address"}),
    Question("one-based", "A datasheet numbers its registers from 1; you want register 10. Which address "
             "goes on the wire?",
             ("10", "11", "40010", "9"), "d", "one-based-address",
             {"a": "one-based-address", "b": "one-based-address", "c": "reference-number"}),
    Question("crc-order", "The CRC of an RTU frame's bytes is 0x4B37. How does the frame end?",
             ("4B 37", "37 4B", "37 4B 0D 0A", "with no CRC: the slave computes it"), "b", "crc-swapped",
             {"a": "crc-swapped", "c": "crlf-for-frame-end", "d": "crc-forgotten"}),
    Question("tcp-crc", "How does a Modbus/TCP frame end?",
             ("with a CRC, low byte first", "with a CRC, high byte first", "with CR LF",
              "with the PDU's last byte"), "d", "crc-on-tcp",
             {"a": "crc-on-tcp", "b": "crc-on-tcp", "c": "crlf-for-frame-end"}),
    Question("damaged", "A slave receives a request whose CRC is wrong. What does the master see?",
             ("exception 03 (illegal data value)", "exception 04 (slave device failure)",
              "nothing: a timeout", "a normal response, as if the CRC were right"), "c",
             "answer-to-damaged-request",
             {"a": "answer-to-damaged-request", "b": "answer-to-damaged-request",
              "d": "answer-to-damaged-request"}),
    Question("missing-address", "A slave implements function 3 but has no register at the requested "
             "address. Per the specification, what does it answer?",
             ("exception 01 (illegal function)", "exception 02 (illegal data address)",
              "nothing: a timeout", "a normal response holding zeros"), "b", "illegal-function-for-address",
             {"a": "illegal-function-for-address", "c": "refusal-unanswered", "d": "refusal-unanswered"}),
    Question("mbap-length", "A Modbus/TCP frame carries unit 0x11 and the 5-byte PDU 03 00 6B 00 03. What "
             "is its MBAP length field?",
             ("5", "7", "6", "12"), "c", "mbap-length",
             {"a": "mbap-length", "b": "mbap-length", "d": "mbap-length"}),
    Question("frame-end", "At 9600 baud, what tells an RTU slave that a frame has ended, per the "
             "specification?",
             ("CR LF", "a silence of one character time", "a silence of 3.5 character times",
              "a silence of 1.5 character times"), "c", "one-character-for-t35",
             {"a": "crlf-for-frame-end", "b": "one-character-for-t35", "d": "t15-for-t35"}),
    Question("pause-inside", "At 9600 baud, halfway through an RTU frame the sender pauses for 2 character "
             "times. Per the specification, what happens?",
             ("nothing: the slave waits for the rest and answers",
              "the slave drops the frame and does not answer",
              "the slave answers exception 03 (illegal data value)",
              "the slave answers the first half as a frame"), "b", "t15-forgotten",
             {"a": "t15-forgotten", "c": "answer-to-damaged-request", "d": "t15-for-t35"}),
    Question("exception-code", "A slave refuses a function 3 request with an exception. What is the "
             "function code of its response?",
             ("83", "03", "80", "03, then 80 after it"), "a", "exception-bit-missing",
             {"b": "exception-bit-missing", "c": "exception-function-forgotten",
              "d": "exception-bit-missing"}),
)

BY_ID = {question.id: question for question in QUESTIONS}
ORDER_PRE: tuple[str, ...] = tuple(question.id for question in QUESTIONS)
"""The order of notebook 00: the questions as listed."""
ORDER_POST: tuple[str, ...] = tuple(random.Random(17).sample(ORDER_PRE, len(ORDER_PRE)))
"""The order of notebook 17: a fixed permutation (seed 17) of the same questions."""
ORDERS = {PRE: ORDER_PRE, POST: ORDER_POST}


def key_letters(quiz: str) -> str:
    """The right letters of ``quiz`` (``"00.0"`` or ``"17.0"``) in its order, upper case."""
    return "".join(BY_ID[qid].right for qid in ORDERS[quiz]).upper()


def markdown(quiz: str) -> str:
    """The questions of ``quiz`` in its order, as the notebook's markdown list."""
    lines = []
    for number, qid in enumerate(ORDERS[quiz], 1):
        question = BY_ID[qid]
        lines.append(f"{number}. {question.text}")
        lines += [f"   - **{letter}**: {choice}" for letter, choice in zip(LETTERS, question.choices)]
    return "\n".join(lines)


def read(answer: Any, quiz: str) -> dict[str, str | None]:
    """``answer`` (letters, or a dict from question number to letter) as each question's letter, by
    question id; None for "I do not know" (``?``).  Raises :class:`InventoryError` when it cannot."""
    order = ORDERS[quiz]
    count = len(order)
    if isinstance(answer, str):
        letters = [c for c in answer.lower() if not c.isspace()]
        if len(letters) != count:
            raise InventoryError(f"give {count} letters, one per question (a to d, or ? when you do not "
                                 f"know), such as \"{'?' * count}\"; you gave {len(letters)}.")
        by_number = dict(enumerate(letters, 1))
    elif isinstance(answer, dict):
        by_number = {}
        for number, letter in answer.items():
            text = number.strip() if isinstance(number, str) else ""
            if text.isascii() and text.isdigit() and len(text) <= 4:  # not "²", "٣" nor 5,000 digits
                number = int(text)
            if not isinstance(number, int) or isinstance(number, bool) or not 1 <= number <= count:
                raise InventoryError(f"the questions are numbered 1 to {count}, not {number!r}.")
            if not isinstance(letter, str):
                raise InventoryError(f"question {number}: give a letter (a to d), not "
                                     f"{type(letter).__name__}.")
            by_number[number] = letter.strip().lower()
        missing = [n for n in range(1, count + 1) if n not in by_number]
        if missing:
            raise InventoryError(f"question(s) {', '.join(map(str, missing))} have no answer: give a letter "
                                 f"or ? when you do not know.")
    else:
        raise InventoryError(f"give the letters as a string (such as \"{'?' * count}\") or a dict such as "
                             f"{{1: \"a\", 2: \"?\", ...}}.")
    bad = [n for n, letter in by_number.items() if letter not in LETTERS + DONT_KNOW]
    if bad:
        raise InventoryError(f"question {bad[0]}: the choices are a, b, c and d (or ? when you do not know), "
                             f"not {by_number[bad[0]]!r}.")
    return {qid: (None if by_number[n] == DONT_KNOW else by_number[n]) for n, qid in enumerate(order, 1)}


def score(answers: dict[str, str | None]) -> dict[str, bool]:
    """Whether each answer (by question id, as :func:`read` gives them) is right."""
    return {qid: answers.get(qid) == question.right for qid, question in BY_ID.items()}


@dataclass(frozen=True)
class Gain:
    """One row of the gain table: the class's share right before and after (0..1) and g (None when
    the share before is already 1)."""

    question: str
    label: str
    pre: float
    post: float
    g: float | None

    @property
    def shown(self) -> str:
        """g as the reports write it: two decimals, or "—" when it is undefined."""
        return "—" if self.g is None else f"{self.g:.2f}"


def normalised_gain(pre: float, post: float) -> float | None:
    """g = (post - pre) / (1 - pre) for shares 0..1; None when ``pre`` is already 1."""
    return None if pre >= 1 else (post - pre) / (1 - pre)


def gains(class_pre_post: dict[str, tuple[dict[str, bool] | None, dict[str, bool] | None]]
          ) -> tuple[list[Gain], Gain | None]:
    """The class's gain per question (in :data:`QUESTIONS`' order) and overall, from each learner's
    (pre marks, post marks) as :func:`score` gives them; only learners with both count.  No such
    learner: no rows and None."""
    both = [(pre, post) for pre, post in class_pre_post.values() if pre is not None and post is not None]
    if not both:
        return [], None
    rows = []
    for question in QUESTIONS:
        pre = sum(marks[question.id] for marks, _ in both) / len(both)
        post = sum(marks[question.id] for _, marks in both) / len(both)
        rows.append(Gain(question.id, CATALOGUE[question.probes].label, pre, post,
                         normalised_gain(pre, post)))
    pre = sum(row.pre for row in rows) / len(rows)
    post = sum(row.post for row in rows) / len(rows)
    return rows, Gain("overall", "all questions", pre, post, normalised_gain(pre, post))


def _judge(answer: Any, quiz: str) -> str | None:
    try:
        answers = read(answer, quiz)
    except InventoryError as exc:
        return str(exc)
    marks = score(answers)
    if quiz == PRE:
        unknown = sum(letter is None for letter in answers.values())
        return Recorded(f"Recorded: your {len(marks)} answers ({unknown} marked ?). Which are right stays "
                        f"unseen for now: the course answers every question, and notebook 17 asks them "
                        f"again, then shows these beside the new ones.")
    right = sum(marks.values())
    if right == len(marks):
        return None
    wrong = [f"{n} ({CATALOGUE[BY_ID[qid].misconception(answers[qid])].label})"
             for n, qid in enumerate(ORDERS[quiz], 1) if not marks[qid]]
    return f"{right} of {len(marks)} right; look again at question {', '.join(wrong)}."


def _letters(answer: Any, quiz: str) -> str | None:
    """``answer`` as letters in ``quiz``'s order (``?`` for "I do not know"), or None when unreadable."""
    try:
        answers = read(answer, quiz)
    except InventoryError:
        return None
    return "".join(answers[qid] or DONT_KNOW for qid in ORDERS[quiz])


def _keep_pre(answer: Any, result: Result) -> Result:
    """After a pre-test check: keep its letters in :data:`RECORD` (quietly skipped where the home folder
    cannot be written)."""
    letters = _letters(answer, PRE)
    if letters is not None:
        with contextlib.suppress(OSError):
            RECORD.parent.mkdir(parents=True, exist_ok=True)
            RECORD.write_text(json.dumps({PRE: letters}) + "\n", encoding="utf-8")
    return result


def before(quiz: str = POST) -> str:
    """The kept pre-test set beside ``quiz``'s numbering: how many were right before, and which; or
    how to keep them when there are none."""
    try:
        letters = json.loads(RECORD.read_text(encoding="utf-8"))[PRE]
        answers = read(letters, PRE)
    except (OSError, ValueError, KeyError, TypeError, InventoryError):
        return ("Your pre-test answers (exercise 00.0) are not kept on this computer: run its check cell "
                "in notebook 00 to set them beside these.")
    marks = score(answers)
    right = [str(n) for n, qid in enumerate(ORDERS[quiz], 1) if marks[qid]]
    which = f": question{'s' * (len(right) > 1)} {', '.join(right)} (numbered as here)" if right else ""
    return f"Before the course (exercise 00.0) you had {len(right)} of {len(marks)} right{which}."


def _set_beside_pre(answer: Any, result: Result) -> Result:
    """After a post-test check: the verdict, then the pre-test's answers that were right."""
    if _letters(answer, POST) is None:
        return result
    return Result(result.key, result.ok, f"{result.message}\n{before(POST)}")


def _wrong_at(quiz: str, qid: str, letter: str | None = None) -> str:
    """The right letters of ``quiz`` with question ``qid`` answered by ``letter`` (by default its first
    wrong choice)."""
    letters = list(key_letters(quiz))
    index = ORDERS[quiz].index(qid)
    letters[index] = (letter or next(c for c in LETTERS if c != BY_ID[qid].right)).upper()
    return "".join(letters)


@exercise(PRE, "before you start: 12 questions",
          hint="answer what you think now, or ? when you have no idea; the course teaches all twelve.",
          accepts=[key_letters(PRE), key_letters(PRE).lower(),
                   {n: letter for n, letter in enumerate(key_letters(PRE), 1)},
                   "?" * len(QUESTIONS), _wrong_at(PRE, "crc-order")],  # recorded, right or wrong
          refuses=[("ABC", None), ("E" * len(QUESTIONS), None)])
def _check_pre(answer: Any) -> str | None:
    return _judge(answer, PRE)


@exercise(POST, "the twelve questions again",
          hint="each question is one idea of the course: the verdict names the one to look at again.",
          accepts=[key_letters(POST), " ".join(key_letters(POST)),
                   {str(n): letter for n, letter in enumerate(key_letters(POST), 1)}],
          refuses=[(_wrong_at(POST, "crc-order"), "crc-swapped"),
                   (_wrong_at(POST, "mbap-length"), "mbap-length"),
                   (_wrong_at(POST, "reference"), "reference-number"),
                   (_wrong_at(POST, "frame-end", "d"), "t15-for-t35"),
                   (_wrong_at(POST, "tcp-crc", "c"), "crlf-for-frame-end"),
                   (_wrong_at(POST, "missing-address", "c"), "refusal-unanswered"),
                   (_wrong_at(POST, "word-order", "a"), "word-order-in-specification"),
                   (_wrong_at(POST, "exception-code", "c"), "exception-function-forgotten"), ("ABCDE", None)])
def _check_post(answer: Any) -> str | None:
    return _judge(answer, POST)


AFTER_CHECK[PRE] = _keep_pre
AFTER_CHECK[POST] = _set_beside_pre
