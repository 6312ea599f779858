"""Checking the course's conventions (``python -m modbus_edu.course check``); the rules are listed in
the package's docstring."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from .execute import course_notebooks

SHORTHAND_PATTERN = re.compile(r"\bsources?\s+00[0-4]\b|(?<![\w.:-])00[0-4](?:['’]s)?(?![\w.])", re.I)
LIBRARY_NAME_PATTERN = re.compile(r"\bmb\.([A-Za-z_]\w*)")
IMPORT_PATTERN = re.compile(
    r"^[ \t]*from[ \t]+modbus_edu(?:\.[\w.]+)?[ \t]+import[ \t]+(?:\(([^)]*)\)|([^\n#]*))", re.M)
LINK_PATTERN = re.compile(r"\]\((?![a-z]+://)((?:\.?/)?(?:solutions/)?[^)\s#?]+\.ipynb)(?:#[^)]*)?\)")


@dataclass(frozen=True)
class Problem:
    notebook: str
    message: str

    def __str__(self) -> str:
        return f"{self.notebook}: {self.message}"


def _text(cell) -> str:
    return cell.source if isinstance(cell.source, str) else "".join(cell.source)


def _comments(code: str) -> str:
    return "\n".join(line.split("#", 1)[1] for line in code.splitlines() if "#" in line)


def source_shorthands(path: Path | str) -> list[str]:
    """The source-number shorthands ("source 003", "003's") in a notebook's prose and code comments."""
    import nbformat

    found = []
    for cell in nbformat.read(Path(path), as_version=4).cells:
        text = _text(cell) if cell.cell_type == "markdown" else _comments(_text(cell))
        found.extend(match.group(0) for match in SHORTHAND_PATTERN.finditer(text))
    return found


def used_before_introduced(paths: list[Path]) -> list[Problem]:
    """Library names a code cell uses before any prose or comment of the course has named them.

    ``paths`` are the notebooks in course order.  A name is introduced by a markdown cell or a code
    comment at or before the cell that uses it, in that notebook or an earlier one; its first use is
    reported once."""
    import nbformat

    introduced: set[str] = set()
    reported: set[str] = set()
    problems = []
    for path in paths:
        for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
            text = _text(cell)
            if cell.cell_type == "markdown":
                introduced.update(re.findall(r"\w+", text))
                continue
            if cell.cell_type != "code":
                continue
            introduced.update(re.findall(r"\w+", _comments(text)))
            names = set(LIBRARY_NAME_PATTERN.findall(text))
            for groups in IMPORT_PATTERN.findall(text):
                names.update(name for name in re.findall(r"\w+", " ".join(groups)) if name != "as")
            for name in sorted(names - introduced - reported):
                reported.add(name)
                problems.append(Problem(path.name, f"cell {index} uses {name} before the course introduces "
                                                   "it (name it in the prose or a comment first)"))
    return problems


def check_notebook(path: Path | str, last: bool = False) -> list[Problem]:
    """Everything in one notebook that breaks the course's conventions (empty list: none)."""
    import nbformat

    path = Path(path)
    name = path.name
    notebook = nbformat.read(path, as_version=4)
    problems: list[Problem] = []

    def problem(message: str) -> None:
        problems.append(Problem(name, message))

    if "widgets" in notebook.metadata:
        problem("it stores widget state: re-execute it with the course script, which strips it (an unrun "
                "notebook then shows each panel's text, never dead controls)")

    kernel = notebook.metadata.get("kernelspec", {}).get("name")
    if kernel != "python3":
        problem(f"kernelspec is {kernel!r}, expected 'python3'")

    counts = [cell.get("execution_count") for cell in notebook.cells if cell.cell_type == "code"]
    if counts != list(range(1, len(counts) + 1)):
        problem(f"execution counts are {counts}, expected 1..{len(counts)} in order: re-execute it")

    markdown = [_text(cell) for cell in notebook.cells if cell.cell_type == "markdown"]
    if not markdown or not markdown[0].lstrip().startswith("# "):
        problem("the first cell must be a markdown title ('# ...')")
    opening = markdown[0] if markdown else ""
    learn = re.search(r"what you will learn(.*?)(?:\n#|\Z)", opening, re.I | re.S)
    if not learn:
        problem("the opening cell has no 'What you will learn' section")
    else:
        points = [line for line in learn.group(1).splitlines() if re.match(r"\s*([-*]|\d+\.)\s", line)]
        if not 3 <= len(points) <= 5:
            problem(f"'What you will learn' has {len(points)} points, expected 3 to 5")
    if not re.search(r"what you need", opening, re.I):
        problem("the opening cell has no 'What you need' section")

    everything = "\n".join(markdown)
    if not re.search(r"^#+\s*summary", everything, re.I | re.M):
        problem("there is no 'Summary' heading")
    if not re.search(r"^#+\s*exercises", everything, re.I | re.M):
        problem("there is no 'Exercises' heading")
    checks = sum(1 for cell in notebook.cells if cell.cell_type == "code" and "check(" in _text(cell))
    if checks < 2:
        problem(f"{checks} exercise cell(s) call check(), expected at least 2")

    if not name.startswith("00"):
        shorthands = source_shorthands(path)
        if shorthands:
            problem(f"{len(shorthands)} source shorthand(s) such as {shorthands[0]!r}: name the source by "
                    "its short name, linked to notebook 00's Sources section")

    links = LINK_PATTERN.findall(everything)
    for link in links:
        if not (path.parent / link).exists():
            problem(f"link to {link} points to a notebook that does not exist")
    if not last and not re.search(r"next[^\n]*\]\(\d\d_[a-z0-9_]+\.ipynb\)", markdown[-1] if markdown else "",
                                  re.I):
        problem("the last cell must link to the next notebook ('Next: [title](NN_name.ipynb)')")
    return problems


def check_course(folder: Path | str) -> list[Problem]:
    """Check every notebook of the course; also that they are numbered 00, 01, 02, ... without gaps."""
    notebooks = course_notebooks(folder)
    problems: list[Problem] = []
    numbers = [int(p.name[:2]) for p in notebooks]
    if numbers != list(range(len(numbers))):
        expected = f"0..{len(numbers) - 1}"
        problems.append(Problem(str(folder), f"notebooks are numbered {numbers}, expected {expected}"))
    for index, path in enumerate(notebooks):
        problems.extend(check_notebook(path, last=index == len(notebooks) - 1))
    problems.extend(used_before_introduced(notebooks))
    return problems
