"""Cells that draw, in a copy of the course that has no matplotlib (the offline site, in a browser).

The offline JupyterLite site carries no matplotlib: it is a compiled package that only Pyodide's CDN
serves.  So that a notebook still runs to its last cell there, the site's build (``lite/build_site.py``)
takes, from each executed notebook, the pictures every drawing cell drew on CPython, and ships them as a
small package of data, ``modbus_edu_pictures`` (a ``pictures.json`` keyed by :func:`cell_key`).  The
site's first cell calls :func:`draw_offline`, which does nothing where matplotlib imports (the published
site, Binder, a local install); where it does not, every cell that draws is run by :func:`run_drawing`:

* each top-level statement runs in turn; a statement that fails because matplotlib is missing (its
  import, a figure, a name such as ``plt`` or ``fig`` that an earlier skipped statement would have
  bound) is skipped, and the rest of the cell runs, so the names it defines exist for the cells below;
* the pictures the build drew from that same cell are shown, each with its words (the text equivalent
  :func:`modbus_edu.plotstyle.show` gave it: the image's ``alt`` and the line under it, as on CPython),
  then one line saying that changing them needs the published site or Binder.  A cell the learner has
  edited has no stored picture: the line says so.

Any other error is raised as usual.  Nothing here draws: the pictures are the ones matplotlib drew.
"""

from __future__ import annotations

import ast
import base64
import builtins
import hashlib
import importlib
import json
import sys
from collections.abc import Callable
from importlib.resources import files
from typing import Any

from ._optional import load_transformer_manager
from .errors import MissingDependencyError
from .platform import BINDER

PACKAGE = "modbus_edu_pictures"
"""The package of the pictures the site's build drew (data only)."""
PUBLISHED = "https://modbus-edu.github.io/modbus_edu/"
"""The published site, which loads matplotlib from Pyodide's CDN."""
DRAWS = ("matplotlib", "plotstyle")
"""Words in a cell's source that make it a cell that draws."""
FIGURE_IN_WORDS = "The figure in words: "
"""What starts the line under a figure that :func:`modbus_edu.plotstyle.show` writes (and :func:`run_drawing`
where the figure was drawn by the build)."""


def cell_key(source: str) -> str:
    """The key of a cell's pictures: a hash of its source, trailing blanks ignored."""
    text = "\n".join(line.rstrip() for line in source.strip().splitlines())
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:20]


def has_matplotlib() -> bool:
    try:
        importlib.import_module("matplotlib")
    except ImportError:
        return False
    return True


def stored_pictures() -> dict[str, list[dict[str, str]]]:
    """The build's pictures (cell key -> ``{"png": PNG in base64, "alt": its words}`` in the order the
    cell drew them), or an empty dict where the package is absent."""
    try:
        return json.loads(files(PACKAGE).joinpath("pictures.json").read_text(encoding="utf-8"))
    except (ImportError, OSError, ValueError):
        return {}


def _missing_matplotlib(error: BaseException, skipped: set[str]) -> bool:
    """True if ``error`` comes from matplotlib's absence (or from a name whose binding was skipped)."""
    if isinstance(error, ModuleNotFoundError):
        return (error.name or "").split(".")[0] == "matplotlib"
    if isinstance(error, MissingDependencyError):
        return "matplotlib" in str(error)
    if isinstance(error, NameError):
        return getattr(error, "name", None) in skipped
    return False


def _bound(node: ast.stmt) -> set[str]:
    """The names a top-level statement binds."""
    names = set()
    for inner in ast.walk(node):
        if isinstance(inner, ast.Name) and isinstance(inner.ctx, ast.Store):
            names.add(inner.id)
        elif isinstance(inner, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(inner.name)
        elif isinstance(inner, (ast.Import, ast.ImportFrom)):
            names.update((alias.asname or alias.name).split(".")[0] for alias in inner.names)
    return names


UNBOUND: set[str] = set()
"""The names that statements skipped in this kernel would have bound (``plt``, ``plotstyle``, ``fig``):
a later cell's statement that uses one needs matplotlib too."""


def run_statements(source: str, namespace: dict, show: Callable[[Any], None] | None = None,
                   unbound: set[str] | None = None) -> list[int]:
    """Run ``source`` statement by statement in ``namespace``, skipping each statement that needs
    matplotlib; the first line of each statement skipped (empty if none was).  ``unbound`` (updated)
    holds the names that skipped statements would have bound, in this cell and the ones before.

    A last statement that is an expression has its value passed to ``show`` (as a cell's last line is)."""
    tree = ast.parse(source)
    skipped = set() if unbound is None else unbound
    lines: list[int] = []
    for number, node in enumerate(tree.body):
        last = number == len(tree.body) - 1 and isinstance(node, ast.Expr)
        try:
            if last:
                value = eval(compile(ast.Expression(node.value), "<cell>", "eval"), namespace)
                if show is not None and value is not None:
                    show(value)
            else:
                exec(compile(ast.Module([node], type_ignores=[]), "<cell>", "exec"), namespace)
        except Exception as error:
            if not _missing_matplotlib(error, skipped):
                raise
            skipped |= _bound(node)
            lines.append(node.lineno)
    return lines


def _shell() -> Any:
    """The IPython shell this runs in (a kernel puts ``get_ipython`` among the builtins), or None."""
    get = getattr(builtins, "get_ipython", None)
    return get() if get is not None else None


def _display() -> Any:
    """IPython's display module, which the kernel this runs in has loaded: this module is imported by the
    library without the course extra too, so it never imports IPython itself."""
    module = sys.modules.get("IPython.display")
    if module is None:
        raise MissingDependencyError("modbus_edu.pictures shows pictures in a notebook's kernel (IPython)")
    return module


def run_drawing(source: str) -> None:
    """Run a cell that draws where matplotlib is missing: its other statements, then its pictures."""
    shell, display = _shell(), _display()
    code = load_transformer_manager()().transform_cell(source)  # IPython's transforms, not run_drawing again
    namespace, show = (shell.user_ns, shell.displayhook) if shell is not None else ({}, display.display)
    skipped = run_statements(code, namespace, show=show, unbound=UNBOUND)
    stored = stored_pictures()
    pictures = stored.get(cell_key(source))
    if not skipped or pictures == []:  # it drew nothing here, or the build drew nothing from it either
        return
    for picture in pictures or []:
        png, alt = (picture, "") if isinstance(picture, str) else (picture["png"], picture.get("alt", ""))
        image = display.Image(data=base64.b64decode(png), format="png")
        if alt:
            display.display(image, metadata={"image/png": {"alt": alt}})
            print(FIGURE_IN_WORDS + alt)
        else:
            display.display(image)
    if pictures:
        print(f"(This picture was drawn from this cell when the course was built: this copy of the course "
              f"runs without matplotlib. To change it, use the published site ({PUBLISHED}) or Binder "
              f"({BINDER}).)")
    else:
        print(f"(This cell draws with matplotlib, which this copy of the course does not carry, and it has "
              f"changed since the course was built, so there is no picture of it: use the published site "
              f"({PUBLISHED}) or Binder ({BINDER}) to draw it.)")


def draws(source: str) -> bool:
    """True if a cell's source draws (it names matplotlib or the course's plot style)."""
    return any(word in source for word in DRAWS)


def _transform(lines: list[str]) -> list[str]:
    source = "".join(lines)
    if not draws(source) or source.lstrip().startswith("%%"):
        return lines
    return [f"__import__('modbus_edu.pictures').pictures.run_drawing({source!r})\n"]


def draw_offline() -> bool:
    """Where matplotlib is missing, have every cell that draws run by :func:`run_drawing` (an input
    transformer of this IPython); True if it did, False where matplotlib imports (nothing to do)."""
    if has_matplotlib():
        return False
    shell = _shell()
    if shell is None:
        return False
    if _transform not in shell.input_transformers_cleanup:
        shell.input_transformers_cleanup.append(_transform)
    return True
