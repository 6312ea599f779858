"""Run the held-out slips (tests/heldout_slips.py, and the second set tests/heldout_slips_2.py) through
the course's checkers.

The slips were written from the notebooks alone and never tuned against the checkers, so this test
measures how the checkers meet mistakes they were not written for. It asserts only what must hold
whatever the wording of the checkers: no slip is accepted, and the set is large enough to mean
something. With ``-s`` it prints, per notebook, how many slips the checkers

- name: the verdict names a misconception among the slip's candidates;
- name wrongly: the verdict names a misconception, none of the slip's (non-empty) candidates;
- name, no candidate: the verdict names a misconception, and no catalogue id fitted the slip;
- leave generic: the verdict refuses the answer but names no misconception;
- accept: the verdict is ok.

A verdict names a misconception when the text before its hint carries that misconception's label.

The two sets are measured and printed separately. The second set was written without the catalogue;
its candidates were mapped afterwards from the slips' words and the catalogue's (see its docstring), so
it splits "named" from "wrongly named" as the first does. Both sets' named and wrongly named counts are
held by a ratchet (RATCHET).
A third test, which runs no checker, holds every slip of the second set against the right answer the
library computes (tests/heldout_right.py): each must be wrong; a fourth, that every candidate of every
set is an id of the catalogue. A fifth, which runs no checker either, holds every slip of the third set
(tests/heldout_slips_3.py, written like the second and not yet measured; its candidates were mapped
afterwards like the second set's) against the right answer.

    python -m pytest tests/test_heldout.py -s
"""

import ast
import math
import sys
from collections import Counter
from pathlib import Path

import pytest

import modbus_edu as mb
from modbus_edu.exercises import evaluate
from modbus_edu.exercises.diagnosis.catalogue import CATALOGUE

sys.path.insert(0, str(Path(__file__).parent))
from heldout_right import ACCEPTS, REFERENCE, RIGHT, RIGHT_MAP_16_1, TOLERANCE  # noqa: E402
from heldout_slips import HELDOUT  # noqa: E402
from heldout_slips_2 import HELDOUT_2, board  # noqa: E402
from heldout_slips_3 import HELDOUT_3  # noqa: E402

COLUMNS = ("named", "wrongly named", "named, no candidate", "generic", "accepted")


def _function_from_source(source: str):
    """The function a build slip defines, as a learner's cell would define it."""
    names = [node.name for node in ast.parse(source).body if isinstance(node, ast.FunctionDef)]
    namespace: dict = {}
    exec(compile(source, "<slip>", "exec"), namespace)
    return namespace[names[-1]]


def _named(message: str) -> set[str]:
    """The catalogue ids whose label the verdict's text (before its hint) carries."""
    text = message.split("\nHint:")[0].lower()
    return {key for key, entry in CATALOGUE.items() if entry.label and entry.label.lower() in text}


def _verdict(slip: dict):
    answer = slip["answer"]
    if slip["kind"] == "build":
        answer = _function_from_source(answer)
    return evaluate(slip["key"], answer)


def _outcome(slip: dict, result) -> str:
    if result.ok:
        return "accepted"
    named = _named(result.message)
    candidates = set(slip["candidates"] or ())
    if not named:
        return "generic"
    if not candidates:
        return "named, no candidate"
    return "named" if named & candidates else "wrongly named"


@pytest.fixture
def quiet_home(tmp_path, monkeypatch):
    """Whatever a check may keep for a learner stays in a scratch folder."""
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _measure(slips: list[dict], title: str) -> list[tuple[str, str]]:
    """Print the per-notebook table of a set's verdicts; return the accepted slips (key, mistake).  The
    totals are kept in :data:`TOTALS` under ``title``."""
    table: dict[str, Counter] = {}
    accepted = []
    for slip in slips:
        outcome = _outcome(slip, _verdict(slip))
        table.setdefault(slip["key"].split(".")[0], Counter())[outcome] += 1
        if outcome == "accepted":
            accepted.append((slip["key"], slip["mistake"]))

    width = max(len(c) for c in COLUMNS)

    def row(name: str, counts: Counter) -> str:
        return f"{name:>8} {sum(counts.values()):>5} " + " ".join(f"{counts[c]:>{width}}" for c in COLUMNS)

    lines = [f"{'notebook':>8} {'slips':>5} " + " ".join(f"{c:>{width}}" for c in COLUMNS)]
    total: Counter = Counter()
    for notebook in sorted(table):
        total.update(table[notebook])
        lines.append(row(notebook, table[notebook]))
    lines.append(row("all", total))
    named = total["named"] + total["wrongly named"] + total["named, no candidate"]
    lines.append(f"a misconception named for {named} of {len(slips)} ({100 * named / len(slips):.1f}%)")
    print(f"\n{title}\n" + "\n".join(lines))
    TOTALS[title] = total
    return accepted


TOTALS: dict[str, Counter] = {}

# The ratchet: what the checkers reached on each set (2026-12-08: set 1 258 named, 2 wrongly named; set 2
# 296 named, 2 wrongly named; none accepted). A change that names fewer, or names more wrongly, fails.
RATCHET = {"held-out slips through the checkers": (258, 2),
           "second held-out set through the checkers": (296, 2)}


def _ratchet(title: str) -> None:
    named, wrongly = RATCHET[title]
    total = TOTALS[title]
    assert total["named"] >= named, f"{title}: {total['named']} named, fewer than {named}"
    assert total["wrongly named"] <= wrongly, f"{title}: {total['wrongly named']} wrongly named (> {wrongly})"


def test_no_heldout_slip_is_accepted(quiet_home):
    assert len(HELDOUT) >= 300
    accepted = _measure(HELDOUT, "held-out slips through the checkers")
    assert not accepted, f"{len(accepted)} held-out slips accepted: {accepted}"
    _ratchet("held-out slips through the checkers")


# The first measurement of the second set (before any checker changed) found 3 slips accepted: 01.2's
# int 30010 where the string "30010" is asked (now "the right value in another form"); 16.4's strip_echo
# that removes every copy of the request (16.4 now tries a write, whose answer repeats its request); 17.3's
# decide that refuses an engineer the functions above 24 (17.3 now tries FC 8 and 65 for an engineer).
def test_no_second_heldout_slip_is_accepted(quiet_home):
    assert len(HELDOUT_2) >= 400
    accepted = _measure(HELDOUT_2, "second held-out set through the checkers")
    assert not accepted, f"{len(accepted)} slips of the second held-out set accepted: {accepted}"
    _ratchet("second held-out set through the checkers")


# The third set, written from the notebooks alone and mapped to candidates afterwards, measured here
# for the first time after every checker change of its round had landed: its figures are reported,
# and none of its accepted slips is marked expected.
# Its first measurement (the checkers of this set's own round, before the round's procedure changes)
# accepted 3: 01.2 (a reference number as text), 12.2 (the serial line's master) and 13.7 (an absolute
# tolerance of 1); after the round's procedure changes (the right value in another form, part of an
# answer, another question's answer), 2: 12.2 and 13.7.
@pytest.mark.xfail(strict=True, reason="2 slips of the third held-out set are accepted (see above)")
def test_no_third_heldout_slip_is_accepted(quiet_home):
    assert len(HELDOUT_3) >= 450
    accepted = _measure(HELDOUT_3, "third held-out set through the checkers")
    assert not accepted, f"{len(accepted)} slips of the third held-out set accepted: {accepted}"


# --- every slip of the second set is wrong (no checker involved) ---------------------------------
def _bytes_of(key: str, answer):
    """Hex text as the bytes it names (an ASCII frame's characters as they are); other answers as given."""
    if isinstance(answer, (list, tuple)):
        return type(answer)(_bytes_of(key, a) for a in answer)
    if isinstance(answer, str) and isinstance(RIGHT.get(key), (bytes, list)):
        if key == "04.2":
            return answer.encode("ascii")
        try:
            return bytes.fromhex(answer)
        except ValueError:
            return answer
    if isinstance(answer, bytearray):
        return bytes(answer)
    return answer


def _same(a, b, tolerance: float = 1e-9) -> bool:
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        return abs(a - b) <= tolerance
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y, tolerance) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k], tolerance) for k in a)
    if isinstance(a, str) and isinstance(b, str):
        return a.strip().lower().replace(" ", "_") == b.strip().lower().replace(" ", "_")
    if isinstance(a, type) or isinstance(b, type):
        return a is b
    return type(a) is type(b) and a == b


def _value_is_wrong(slip: dict) -> bool:
    key, answer = slip["key"], slip["answer"]
    if key in ACCEPTS:
        try:
            return not ACCEPTS[key](answer)
        except Exception:  # noqa: BLE001 (an answer of the wrong type is wrong)
            return True
    return not _same(_bytes_of(key, answer), _bytes_of(key, RIGHT[key]), TOLERANCE.get(key, 1e-9))


def _run(function, args):
    try:
        return function(*args)
    except Exception:  # noqa: BLE001 (the learner's function may raise anything: only that it raised counts)
        return "raises"


def _build_is_wrong(slip: dict, references: dict = REFERENCE) -> bool:
    reference, probes, how = references[slip["key"]]
    learner = _function_from_source(slip["answer"])
    if how is not None and how != "order":
        learner = how(learner)
    for args in probes:
        mine, right = _run(learner, args), _run(reference, args)
        if how == "order":  # right is the list of orders that fit: any of them, or None if none does
            if not (mine in right if right else mine is None):
                return True
        elif not _same(_bytes_of("", mine), _bytes_of("", right)):
            return True
    return False


def test_every_second_heldout_slip_is_wrong(quiet_home):
    keys = {s["key"] for s in HELDOUT_2}
    assert len(keys) == 79, "every exercise of every notebook has slips"
    assert all(len([s for s in HELDOUT_2 if s["key"] == k]) >= 4 for k in keys)
    right = [(s["key"], s["slip"]) for s in HELDOUT_2
             if not (_build_is_wrong(s) if s["kind"] == "build" else _value_is_wrong(s))]
    assert not right, f"{len(right)} slips of the second set are right answers: {right}"


# --- every slip of the third set is wrong (no checker involved) ----------------------------------
def _slave_answer(registers, pdu):
    """What the library's slave answers to ``pdu``, sent in an RTU frame, and its registers after: a
    request the PDU decoder refuses (a read of 0 or 126 registers) gets the exception a slave sends."""
    bank = mb.DataBank(sparse=True)
    bank.holding_registers.declare(0, len(registers))
    bank.holding_registers.write(0, list(registers))
    body = bytes([1]) + bytes(pdu)
    answer = mb.Slave(unit=1, bank=bank).handle(body + mb.crc_bytes(body))
    return answer[1:-2], bank.holding_registers.read(0, len(registers))


def _stated_17_3(args) -> bool:
    """A probe on which the exercise's stated rules and the library's role table agree: the library lets
    a viewer and an operator use more reading functions (43, 23 ...) than the rules' "1-4" and "5, 6,
    15, 16" say, so a learner who follows the text exactly differs from it there."""
    pdu, role = args
    return role not in ("viewer", "operator") or pdu[0] in (1, 2, 3, 4, 5, 6, 15, 16)


def _reference_3(key: str, reference=None, keep=lambda args: True) -> tuple:
    function, probes, how = REFERENCE[key]
    return (reference or function, [args for args in probes if keep(args)], how)


# The third set is held against three of the second set's references changed where a right learner's
# function would differ from them: 06.5's decodes the PDU first, so it raises for a read of 0 or 126
# registers, where a slave answers exception 03 (the slave's own answer is used instead); 11.4's
# decodes an exception response as a request and refuses it, where the task asks to refuse only a
# protocol id other than 0, a wrong length and a frame too short (that probe is left out); 17.3's
# probes keep those where the stated rules and the library agree (see _stated_17_3).
REFERENCE_3 = {**REFERENCE,
               "06.5": _reference_3("06.5", _slave_answer),
               "11.4": _reference_3("11.4", keep=lambda args: args[0][7:8] < b"\x80"),
               "17.3": _reference_3("17.3", keep=_stated_17_3)}

# A right learner's function for each reference changed above: the judge must take it.
_RIGHT_BUILDS_3 = {
    "06.5": """def handle(registers, pdu):
    address, number = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
    if pdu[0] == 3:
        if not 1 <= number <= 125:
            return bytes([0x83, 3])
        if address + number > len(registers):
            return bytes([0x83, 2])
        data = b"".join(r.to_bytes(2, "big") for r in registers[address:address + number])
        return bytes([3, 2 * number]) + data
    if address >= len(registers):
        return bytes([0x86, 2])
    registers[address] = number
    return pdu
""",
    "11.4": """def split_mbap(frame):
    if len(frame) < 8 or frame[2:4] != bytes(2) or int.from_bytes(frame[4:6], "big") != len(frame) - 6:
        raise ValueError("not a Modbus/TCP frame")
    return (int.from_bytes(frame[0:2], "big"), 0, len(frame) - 6, frame[6], frame[7:])
""",
    "17.3": """def decide(pdu, role):
    function = pdu[0]
    count = int.from_bytes(pdu[3:5], "big") if function in (15, 16) else 1
    last = int.from_bytes(pdu[1:3], "big") + count - 1
    if (role == "engineer" or (role in ("viewer", "operator") and 1 <= function <= 4)
            or (role == "operator" and function in (5, 6, 15, 16) and last <= 99)):
        return None
    return bytes([function | 0x80, 0x01])
""",
}


def test_every_third_heldout_slip_is_wrong(quiet_home):
    """Each slip of the third set differs from the right answer (a build slip: on some allowed input)."""
    keys = {s["key"] for s in HELDOUT_3}
    assert len(HELDOUT_3) >= 450
    assert len(keys) == 79, "every exercise of every notebook has slips"
    assert all(len([s for s in HELDOUT_3 if s["key"] == k]) >= 5 for k in keys)
    assert all(isinstance(s["candidates"], tuple) and s["kind"] in ("value", "build") for s in HELDOUT_3)
    for key, source in _RIGHT_BUILDS_3.items():  # the changed references take a right function
        assert not _build_is_wrong({"key": key, "answer": source}, REFERENCE_3), key
    right = [(s["key"], s["slip"]) for s in HELDOUT_3
             if not (_build_is_wrong(s, REFERENCE_3) if s["kind"] == "build" else _value_is_wrong(s))]
    assert not right, f"{len(right)} slips of the third set are right answers: {right}"


def test_the_judge_of_wrongness_takes_the_right_answers(quiet_home):
    """The comparison above would call a right answer right: it can fail only for a slip."""
    for key, answer in RIGHT.items():
        assert not _value_is_wrong({"key": key, "answer": answer}), key
    assert not _value_is_wrong({"key": "13.6", "answer": 2.2})
    assert not _value_is_wrong({"key": "16.3", "answer": "swap A and B"})
    assert not _value_is_wrong({"key": "00.0", "answer": "ab?dabcdabcd"})
    assert not _value_is_wrong({"key": "09.3", "answer": 2.0})
    assert not _value_is_wrong({"key": "16.1", "answer": RIGHT_MAP_16_1})
    assert not _value_is_wrong({"key": "09.2", "answer": board((40150, 26), (40200, 26))})


def test_every_candidate_is_a_catalogue_id():
    """A misspelt candidate would silently turn a right verdict into a wrong one: every id must exist."""
    assert all(slip["candidates"] is not None for slip in HELDOUT + HELDOUT_2 + HELDOUT_3)
    assert any(slip["candidates"] for slip in HELDOUT_3), "the third set's candidates are mapped"
    unknown = {(slip["key"], key) for slip in HELDOUT + HELDOUT_2 + HELDOUT_3 for key in slip["candidates"]
               if key not in CATALOGUE}
    assert not unknown, f"candidates that are no catalogue id: {sorted(unknown)}"
