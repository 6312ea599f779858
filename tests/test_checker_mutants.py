"""No almost-right function passes a build exercise: each checker refuses the mutants of its worked solution.

``tests/mutants/mutate.py`` makes every one-slip version of ``notebooks/solutions/NN_M.py`` (a comparison
flipped, an operator swapped, a constant one off or replaced, a slice bound moved, a byte order swapped, a
statement dropped); each must fail the exercise's own check, unless ``tests/mutants/equivalent.py`` lists it
with the reason it is not wrong at all.  A mutant that never returns is stopped by the checker's time limit
and fails like any other.
"""

from __future__ import annotations

import ast

import pytest
from mutants.equivalent import EQUIVALENT
from mutants.mutate import SOLUTIONS, mutants, unchanged

from modbus_edu.exercises import EXERCISES, evaluate

BUILD = sorted(key for key, item in EXERCISES.items() if item.kind == "build")


def _solution(key: str):
    return SOLUTIONS / f"{key.replace('.', '_')}.py"


def _accepted(key: str) -> set[str]:
    """The names of the mutants of ``key``'s solution that its checker accepts."""
    accepted = set()
    for mutant in mutants(_solution(key)):
        try:
            function = mutant.compile()
        except Exception:  # a mutant that cannot even be defined is no answer to check
            continue
        if evaluate(key, function).ok:
            accepted.add(mutant.name)
    return accepted


@pytest.mark.parametrize("key", BUILD)
def test_every_wrong_mutant_of_the_worked_solution_is_refused(key):
    assert evaluate(key, unchanged(_solution(key)).compile()).ok, f"{key}: the worked solution itself fails"
    accepted = _accepted(key)
    listed = set(EQUIVALENT.get(key, {}))
    assert sorted(accepted - listed) == [], f"{key}'s checker accepts these wrong functions"
    assert sorted(listed - accepted) == [], f"{key}: listed as equivalent but refused: take them off the list"


def test_the_equivalent_mutants_are_named_each_with_its_reason():
    assert set(EQUIVALENT) <= set(BUILD)
    for key, listed in EQUIVALENT.items():
        names = {mutant.name for mutant in mutants(_solution(key))}
        assert set(listed) <= names, f"{key}: no such mutant: {sorted(set(listed) - names)}"
        assert all(isinstance(why, str) and len(why) > 20 for why in listed.values())


def test_each_build_exercise_has_a_solution_with_enough_mutants():
    for key in BUILD:
        made = mutants(_solution(key))
        assert len(made) >= 5, key
        assert len({mutant.name for mutant in made}) == len(made), f"{key}: two mutants share a name"


def test_the_mutator_makes_each_kind_of_slip(tmp_path):
    path = tmp_path / "99_9.py"
    path.write_text('def f(data: bytes) -> int:\n'
                    '    register = 0xFFFF\n'
                    '    if len(data) < 2 and not data:\n'
                    '        return register\n'
                    '    return int.from_bytes(data[:len(data) - 1], "big") ^ 0xA001\n'
                    'print(f(b"12"))\n'
                    'answer = f\n', encoding="utf-8")
    names = {mutant.name for mutant in mutants(path)}
    assert {"register = 0xFFFF | `0xFFFF` -> `0x0000`",
            "if len(data) < 2 and not data: | `<` -> `<=`",
            "if len(data) < 2 and not data: | `and` -> `or`",
            "if len(data) < 2 and not data: | `not` dropped",
            "if len(data) < 2 and not data: | `2` -> `3`",
            "register = 0xFFFF | line dropped",
            'return int.from_bytes(data[:len(data) - 1], "big") ^ 0xA001 | `0xA001` -> `0x8005`',
            'return int.from_bytes(data[:len(data) - 1], "big") ^ 0xA001 | `\'big\'` -> `\'little\'`',
            'return int.from_bytes(data[:len(data) - 1], "big") ^ 0xA001 | `^` -> `|`',
            'return int.from_bytes(data[:len(data) - 1], "big") ^ 0xA001 | slice bound `len(data) - 1` +1',
            } <= names
    mutant = next(m for m in mutants(path) if m.name.endswith("`0xFFFF` -> `0x0000`"))
    assert mutant.compile()(b"") == 0  # the demonstration line is gone; the function runs changed
    assert "print" not in ast.unparse(mutant.tree)
