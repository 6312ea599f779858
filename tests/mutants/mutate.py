"""Small wrong versions of a worked solution, made with :mod:`ast`, one slip each.

A build exercise's checker must refuse a function that is almost right: one comparison flipped (``<``
for ``<=``, ``==`` for ``!=``), one operator for another (``+`` for ``-``, ``&`` for ``|``, ``>>`` for
``<<``), a constant one off or replaced (``0xA001`` by ``0x8005``, ``0xFFFF`` by 0), a slice bound moved by
one, a byte order swapped (``"big"`` for ``"little"``, ``">f"`` for ``"<f"``), ``and`` for ``or``, a
``not``, a minus sign or a ``~`` lost, ``min`` for ``max``, or one statement dropped.  :func:`mutants`
makes every such version of a solution file's function; each is named by the line it changes and the
change, so that the few which behave exactly like the solution can be listed by name (``equivalent.py``).

Only the solution's own code is changed: its function and the module-level constants it reads.  The
lines that show and check the answer (``print(...)``, ``answer = ...``, ``check(...)``) are dropped before
a mutant runs.
"""

from __future__ import annotations

import ast
import copy
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

SOLUTIONS = Path(__file__).resolve().parents[2] / "notebooks" / "solutions"

FLIPPED = {ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt, ast.Eq: ast.NotEq,
           ast.NotEq: ast.Eq, ast.In: ast.NotIn, ast.NotIn: ast.In, ast.Is: ast.IsNot, ast.IsNot: ast.Is}
"""Each comparison and the one a slip puts in its place."""

SWAPPED = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.BitAnd: ast.BitOr,
           ast.BitOr: ast.BitAnd, ast.BitXor: ast.BitOr, ast.LShift: ast.RShift, ast.RShift: ast.LShift,
           ast.FloorDiv: ast.Div, ast.Mod: ast.FloorDiv}
"""Each arithmetic or bitwise operator and the one a slip puts in its place."""

REPLACED = {0xA001: (0x8005,), 0xFFFF: (0x0000,), 0x8005: (0xA001,), 0xFF: (0x7F,), 0x80: (0x40,)}
"""Constants with a well-known wrong twin, besides the one-off ones (the CRC's polynomial written
unreflected, a register started at 0, a mask one bit short, the exception bit in the wrong place)."""

Edit = Callable[[ast.Module, tuple], None]
"""A change: it edits the copy of a module it is given, at the node the path leads to."""


@dataclass(frozen=True)
class Mutant:
    """One wrong version of a solution: ``name`` says which line changed and how."""

    name: str
    tree: ast.Module
    function: str

    def compile(self) -> Callable:
        """The mutant's function, defined in a namespace of its own."""
        namespace: dict = {"__name__": f"mutant_of_{self.function}"}
        exec(compile(self.tree, f"<mutant: {self.name}>", "exec"), namespace)  # noqa: S102
        return namespace[self.function]


def _answer_name(tree: ast.Module) -> str:
    for node in tree.body:
        if (isinstance(node, ast.Assign) and isinstance(node.value, ast.Name)
                and any(isinstance(target, ast.Name) and target.id == "answer" for target in node.targets)):
            return node.value.id
    raise ValueError("the solution sets no `answer = function`")


def _kept(node: ast.stmt) -> bool:
    """Module-level statements a mutant keeps: imports, definitions and constants, not the demonstration."""
    if isinstance(node, ast.Expr):
        return False
    if isinstance(node, ast.Assign):
        return not any(isinstance(target, ast.Name) and target.id == "answer" for target in node.targets)
    return True


def solution_tree(path: Path) -> tuple[ast.Module, str]:
    """A solution file's module without its demonstration lines, and its function's name."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    function = _answer_name(tree)
    tree.body = [node for node in tree.body if _kept(node)]
    return tree, function


def _is_text(node: ast.AST) -> bool:
    return isinstance(node, ast.Constant) and isinstance(node.value, str)


def _left_alone(parents: dict, node: ast.AST) -> bool:
    """True inside a ``raise``, an f-string or a type annotation: an error's words and a hint for the
    reader change nothing the checker reads (the ``raise`` itself is still dropped in turn)."""
    while node in parents:
        parent = parents[node]
        if isinstance(parent, (ast.Raise, ast.JoinedStr)):
            return True
        if any(node is getattr(parent, field, None) for field in ("annotation", "returns")):
            return True
        node = parent
    return False


def _byte_order(text: str) -> str | None:
    swapped = {"big": "little", "little": "big"}
    if text in swapped:
        return swapped[text]
    if text[:1] in "<>" and len(text) > 1:
        return {"<": ">", ">": "<"}[text[0]] + text[1:]
    return None


def _one_off(node: ast.expr, delta: int) -> ast.expr:
    if isinstance(node, ast.Constant) and isinstance(node.value, int) and not isinstance(node.value, bool):
        return ast.Constant(node.value + delta)
    operator = ast.Add() if delta > 0 else ast.Sub()
    return ast.BinOp(left=copy.deepcopy(node), op=operator, right=ast.Constant(abs(delta)))


class _Site:
    """One change: ``edit(tree)`` makes it in a copy of the module (found there by ``path``)."""

    def __init__(self, line: str, what: str, path: tuple, edit: Edit) -> None:
        self.line, self.what, self.path, self._edit = line, what, path, edit

    def edit(self, tree: ast.Module) -> None:
        self._edit(tree, self.path)


def _path_to(tree: ast.AST, target: ast.AST) -> tuple:
    """The (field, index) steps from ``tree`` to ``target``, to find the same node in a copy."""
    stack: list[tuple[ast.AST, tuple]] = [(tree, ())]
    while stack:
        node, path = stack.pop()
        if node is target:
            return path
        for field, value in ast.iter_fields(node):
            if isinstance(value, list):
                stack.extend((item, path + ((field, index),)) for index, item in enumerate(value)
                             if isinstance(item, ast.AST))
            elif isinstance(value, ast.AST):
                stack.append((value, path + ((field, None),)))
    raise LookupError("node not in tree")


def _follow(tree: ast.AST, path: tuple) -> ast.AST:
    node = tree
    for field, index in path:
        node = getattr(node, field) if index is None else getattr(node, field)[index]
    return node


def _put(tree: ast.AST, path: tuple, new: ast.AST | None) -> None:
    """Put ``new`` where ``path`` leads (None: remove that statement; a body left empty gets ``pass``)."""
    parent = _follow(tree, path[:-1])
    field, index = path[-1]
    if index is None:
        setattr(parent, field, new)
        return
    items = getattr(parent, field)
    if new is not None:
        items[index] = new
        return
    del items[index]
    if not items and field == "body":
        items.append(ast.Pass())


def _op(op: ast.AST) -> str:
    return {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!=",
            ast.In: "in", ast.NotIn: "not in", ast.Is: "is", ast.IsNot: "is not", ast.And: "and",
            ast.Or: "or", ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//",
            ast.Mod: "%", ast.BitAnd: "&", ast.BitOr: "|", ast.BitXor: "^", ast.LShift: "<<",
            ast.RShift: ">>", ast.Not: "not ", ast.USub: "-", ast.Invert: "~"}[type(op)]


def _written_as(shown: str, value: int | float) -> str:
    """``value`` written the way the solution wrote the constant it replaces (0xA001 -> 0x8005)."""
    if shown.lower().startswith("0x") and isinstance(value, int) and value >= 0:
        return f"0x{value:0{len(shown) - 2}X}"
    return repr(value)


def _changes(node: ast.AST, parents: dict, text: str) -> Iterator[tuple[str, Edit]]:
    """The changes one node allows, as (what, edit) pairs."""
    if isinstance(node, ast.Compare):
        for index, op in enumerate(node.ops):
            if type(op) in FLIPPED:
                new = FLIPPED[type(op)]

                def flip(tree, path, index=index, new=new):
                    _follow(tree, path).ops[index] = new()
                yield f"`{_op(op)}` -> `{_op(new())}`", flip
    elif isinstance(node, ast.BoolOp):
        other = ast.Or if isinstance(node.op, ast.And) else ast.And

        def swap(tree, path, other=other):
            _follow(tree, path).op = other()
        yield f"`{_op(node.op)}` -> `{_op(other())}`", swap
    elif isinstance(node, (ast.BinOp, ast.AugAssign)) and type(node.op) in SWAPPED:
        new_op = SWAPPED[type(node.op)]

        def swap_operator(tree, path, new=new_op):
            _follow(tree, path).op = new()
        yield f"`{_op(node.op)}` -> `{_op(new_op())}`", swap_operator
    elif isinstance(node, ast.Name) and node.id in ("min", "max") and isinstance(parents.get(node), ast.Call):
        other_name = "max" if node.id == "min" else "min"

        def rename(tree, path, new=other_name):
            _follow(tree, path).id = new
        yield f"`{node.id}` -> `{other_name}`", rename
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub, ast.Invert)):
        def lose(tree, path):
            _put(tree, path, _follow(tree, path).operand)
        yield f"`{_op(node.op).strip()}` dropped", lose
    elif isinstance(node, ast.Constant) and not isinstance(parents.get(node), ast.Expr):
        value = node.value
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            shown = ast.get_source_segment(text, node) or repr(value)
            for new in (value + 1, value - 1, *REPLACED.get(value, ())):
                def set_number(tree, path, new=new):
                    _follow(tree, path).value = new
                yield f"`{shown}` -> `{_written_as(shown, new)}`", set_number
        elif isinstance(value, str) and _byte_order(value):
            new_text = _byte_order(value)

            def set_text(tree, path, new=new_text):
                _follow(tree, path).value = new
            yield f"`{value!r}` -> `{new_text!r}`", set_text
    elif isinstance(node, ast.Slice):
        for bound in ("lower", "upper"):
            value = getattr(node, bound)
            if value is None or isinstance(value, ast.Constant):
                continue  # a missing bound stays missing; a constant bound is moved as a constant
            for delta in (1, -1):
                def move(tree, path, bound=bound, delta=delta):
                    target = _follow(tree, path)
                    setattr(target, bound, _one_off(getattr(target, bound), delta))
                yield f"slice bound `{ast.unparse(value)}` {delta:+d}", move


def _sites(tree: ast.Module, text: str) -> Iterator[_Site]:
    source = text.splitlines()
    parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)) or not hasattr(node, "lineno") \
                or _left_alone(parents, node):
            continue
        for what, edit in _changes(node, parents, text):
            yield _Site(source[node.lineno - 1].strip(), what, _path_to(tree, node), edit)
    for node in ast.walk(tree):
        if isinstance(node, ast.Module):
            continue  # the function itself and its constants stay; their insides are dropped in turn
        for field in ("body", "orelse"):
            body = getattr(node, field, None)
            for statement in body if isinstance(body, list) else ():
                yield _Site(source[statement.lineno - 1].strip(), "line dropped", _path_to(tree, statement),
                            lambda tree, path: _put(tree, path, None))


def unchanged(path: Path) -> Mutant:
    """The solution itself, run the way its mutants run (the baseline every mutant is measured from)."""
    tree, function = solution_tree(path)
    return Mutant("unchanged", tree, function)


def mutants(path: Path) -> list[Mutant]:
    """Every mutant of the solution at ``path``, named ``"<line> | <change>"`` (``#2`` etc. if a line has
    the same change twice)."""
    tree, function = solution_tree(path)
    made: list[Mutant] = []
    seen: dict[str, int] = {}
    for where in _sites(tree, path.read_text(encoding="utf-8")):
        name = f"{where.line} | {where.what}"
        seen[name] = seen.get(name, 0) + 1
        if seen[name] > 1:
            name += f" #{seen[name]}"
        changed = copy.deepcopy(tree)
        where.edit(changed)
        ast.fix_missing_locations(changed)
        made.append(Mutant(name, changed, function))
    return made
