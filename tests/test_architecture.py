"""The house (DESIGN.md): rooms of at most 800 lines, imports at the top of a module, and no circle.

Read from the syntax tree of every module of ``modbus_edu``:

* no module is longer than :data:`MAX_LINES` lines;
* an import inside a function only defers a heavy optional dependency (:data:`DEFERRABLE`), says why in
  a comment, and there are at most :data:`MAX_LOCAL_IMPORTS` of them in all;
* the modules of ``modbus_edu`` import one another without a circle, counting every import (a circle
  closed by an import inside a function is still a circle: it only waits for the first call).
"""

from __future__ import annotations

import ast
import functools
import io
import tokenize
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "modbus_edu"
MAX_LINES = 800
MAX_LOCAL_IMPORTS = 20
#: What an import inside a function may load: scapy, cryptography, matplotlib and the notebook tools
#: (nbformat, nbclient, IPython, ipywidgets; tqdm.auto loads ipywidgets), or the library's own rooms that
#: import them at their top (the widgets: ipywidgets; plotstyle: matplotlib).
DEFERRABLE = {"scapy", "cryptography", "matplotlib", "nbformat", "nbclient", "IPython", "ipywidgets", "tqdm",
              "modbus_edu.widgets", "modbus_edu.plotstyle"}


FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)
IMPORTS = (ast.Import, ast.ImportFrom)


def _modules() -> dict[str, Path]:
    """Every module of the package by its dotted name."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES[name].name == "__init__.py"


def _resolve(module: str, node: ast.ImportFrom) -> str:
    """The absolute name of a ``from ... import`` in ``module``."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not _is_package(module):
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


@functools.cache
def _imports(module: str) -> list[tuple[ast.stmt, list[str], bool]]:
    """Each import statement of ``module``: the node, the modules it loads, and whether it sits in a function
    (``if TYPE_CHECKING:`` blocks load nothing and are left out)."""
    tree = ast.parse(MODULES[module].read_text())
    found = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                continue
            if isinstance(child, ast.Import):
                found.append((child, [alias.name for alias in child.names], in_function))
            elif isinstance(child, ast.ImportFrom):
                source = _resolve(module, child)
                named = [f"{source}.{alias.name}" for alias in child.names]
                submodules = [name for name in named if name in MODULES]
                # ``from . import pdu`` loads the module pdu; ``from .codes import _hex`` loads codes
                loaded = submodules if len(submodules) == len(child.names) else [source, *submodules]
                found.append((child, loaded, in_function))
            visit(child, in_function or isinstance(child, FUNCTIONS))

    visit(tree, False)
    return found


def _local_imports() -> list[tuple[str, ast.stmt, list[str]]]:
    return [(module, node, loaded) for module in MODULES for node, loaded, local in _imports(module) if local]


def test_no_module_is_over_800_lines() -> None:
    long = {name: len(path.read_text().splitlines()) for name, path in MODULES.items()}
    assert {name: n for name, n in long.items() if n > MAX_LINES} == {}


def test_imports_inside_functions_are_few_and_only_defer_a_heavy_optional_dependency() -> None:
    local = _local_imports()
    where = [f"{module}:{node.lineno} {' '.join(loaded)}" for module, node, loaded in local]
    assert len(local) <= MAX_LOCAL_IMPORTS, "\n".join(where)
    for (_, _, loaded), place in zip(local, where):
        roots = {name for name in loaded if any(name == d or name.startswith(d + ".") for d in DEFERRABLE)}
        assert roots == set(loaded), f"{place}: import it at the top of the module"


def test_every_deferred_import_says_why() -> None:
    """The function holding a deferred import says why: a comment between its ``def`` and its first import,
    or a docstring that names the package it defers."""
    for module in {module for module, _, _ in _local_imports()}:
        source = MODULES[module].read_text()
        comments = {token.start[0] for token in tokenize.generate_tokens(io.StringIO(source).readline)
                    if token.type == tokenize.COMMENT}
        tree = ast.parse(source)
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            lines = [node.lineno for node in ast.walk(function) if isinstance(node, IMPORTS)]
            first = min(lines, default=None)
            if first is None:
                continue
            deferred = {alias.name.split(".")[0] for node in ast.walk(function) if isinstance(node, IMPORTS)
                        for alias in ([ast.alias(node.module or "")] if isinstance(node, ast.ImportFrom)
                                      else node.names)}
            named = any(d in (ast.get_docstring(function) or "") for d in deferred)
            assert named or comments & set(range(function.lineno, first + 1)), (
                f"{module}:{first}: say in a comment why this import waits for the call")


def _cycles() -> list[list[str]]:
    """The strongly connected components (Tarjan) of more than one module in the import graph."""
    graph = {module: sorted({name for _, loaded, _ in _imports(module) for name in loaded
                             if name in MODULES and name != module}) for module in MODULES}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def connect(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in graph[node]:
            if nxt not in index:
                connect(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                component.append(top)
                if top == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for module in graph:
        if module not in index:
            connect(module)
    return found


def test_no_import_circle_among_the_modules() -> None:
    assert _cycles() == []


def test_the_checks_see_what_they_look_for() -> None:
    """The readers above find what they count: a known import at the top, a known one in a function."""
    top = {name for node, loaded, local in _imports("modbus_edu.explain") if not local for name in loaded}
    assert {"modbus_edu.pdu", "modbus_edu.framing"} <= top
    local = {name for module, _, loaded in _local_imports() if module == "modbus_edu.capture"
             for name in loaded}
    assert "scapy.layers.inet" in local


@pytest.mark.parametrize("module, source, expected", [
    ("modbus_edu.explain", "from . import pdu", "modbus_edu"),
    ("modbus_edu.cli.common", "from ..framing import base", "modbus_edu.framing"),
    ("modbus_edu.cli", "from .common import PROG", "modbus_edu.cli.common"),
    ("modbus_edu.framing.rtu", "from .base import MODES", "modbus_edu.framing.base"),
])
def test_relative_imports_resolve(module: str, source: str, expected: str) -> None:
    assert _resolve(module, ast.parse(source).body[0]) == expected


def test_a_pdu_shows_as_its_dissection_in_a_notebook() -> None:
    """explain attaches the HTML view to every PDU; the PDU classes do not import explain."""
    from modbus_edu.explain import explain_pdu
    from modbus_edu.pdu import ReadHoldingRegistersRequest

    pdu = ReadHoldingRegistersRequest(address=0, count=2)
    assert pdu._repr_html_() == explain_pdu(pdu)._repr_html_()
    assert "<table" in pdu._repr_html_()
