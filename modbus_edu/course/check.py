"""Checking the course's conventions (``python -m modbus_edu.course check``); the rules are listed in
the package's docstring."""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path

from .._optional import load_nbformat
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
    nbformat = load_nbformat()

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
    nbformat = load_nbformat()

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
    nbformat = load_nbformat()

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
    problems.extend(check_integrity(folder))
    return problems


# --- the course as one: the map, the links, quoted frames and the sources ------------------------------

TITLE_PATTERN = re.compile(r"^#\s+(?:\d+\.\s*)?(.+?)\s*$", re.M)
NOTEBOOK_LINK = re.compile(
    r"\[([^\]\n]+)\]\((?:https://github\.com/[\w.-]+/[\w.-]+/blob/[\w.-]+/)?((?:notebooks/)?\d\d_[a-z0-9_]+\.ipynb)\)")
NEXT_LINK = re.compile(r"\bnext\b[^\n\[]*\[([^\]\n]+)\]\((\d\d_[a-z0-9_]+\.ipynb)\)", re.I)
CALLS_ITSELF_LAST = re.compile(
    r"\b(?:this|the present)\s+(?:last|final)\s+notebook\b"
    r"|\bthe\s+(?:last|final)\s+notebook\s+of\s+the\s+course\b"
    r"|\b(?:reached|at)\s+the\s+end\s+of\s+the\s+course\b|\bthe\s+course\s+ends\s+here\b", re.I)
MARKDOWN_LINK = re.compile(r"\[[^\]\n]+\]\((?:https?://|[^)\s]*\.(?:ipynb|md)\b|#)[^)\s]*\)")
PROSE_FRAME = re.compile(r"(?<![0-9A-Za-z_])[0-9A-F]{2}(?: [0-9A-F]{2})+(?![0-9A-Za-z_])")
PROSE_ASCII_FRAME = re.compile(r"(?<![0-9A-Za-z]):[0-9A-F]{6,}")
WHERE_HEADING = re.compile(r"^(?:#+\s*|\*\*)where this comes from\b", re.I | re.M)
SOURCES_HEADING = re.compile(r"^#+\s*sources\b", re.I | re.M)
HEADING = re.compile(r"^(#+)\s", re.M)
EXERCISE_PROMPT = re.compile(r"^\s*(?:\*\*|#+\s*)(?:Exercise|Puzzle)\s+\d\d\.\d+", re.M)
UNSEEN_TABLE = re.compile(r"\bits\s+(?:table|figure|fig\.)\s*\d+", re.I)

MAX_SOURCE_MENTIONS = 3
SOURCE_NAMES = ("the robot test-tool paper", "the CodeProject RTU master", "the Arduino slave paper",
                "the power-meter paper", "the Inst Tools ASCII article")
"""The sources' short names (``/work/shared/seeds/README.md``'s table; notebook 00 cites each in full)."""
SOURCE_WORDS = re.compile(r"\b(?:papers?|articles?|CodeProject|Inst\s+Tools)\b", re.I)

SPECIFICATION_EXAMPLES = {
    "11 03 00 6B 00 03 76 87": "the specification's Read Holding Registers request (unit 17, 40108-40110)",
    "11 01 00 13 00 25 0E 84": "the specification's Read Coils request (unit 17, coils 20-56)",
    "11 05 00 AC FF 00 4E 8B": "the specification's Write Single Coil request (coil 172 ON)",
    "11 0F 00 13 00 0A 02 CD 01 BF 0B": "the specification's Write Multiple Coils request (coils 20-29)",
    "01 10 00 01 00 02 04 00 0A 01 02 92 30": "the specification's Write Multiple Registers request",
    "01 83 02 C0 F1": "the specification's exception response (function 3, code 02)",
}
"""Frames the prose may quote without a cell showing them: named examples of the Modbus specifications
(a part of one counts too: its PDU, its CRC)."""


def notebook_title(path: Path | str) -> str:
    """The notebook's title, without its number: "The data model: four tables"."""
    nbformat = load_nbformat()

    for cell in nbformat.read(Path(path), as_version=4).cells:
        if cell.cell_type == "markdown":
            match = TITLE_PATTERN.search(_text(cell))
            return match.group(1).strip() if match else ""
    return ""


def names_notebook(text: str, title: str) -> bool:
    """True if a link's text names the notebook titled ``title``: the title itself or its beginning up to
    a word's end ("The data model" for "The data model: four tables"), after an optional number."""
    name = re.sub(r"^\s*\d+\.?\s+", "", text).strip().rstrip(".").casefold()
    title = title.strip().casefold()
    return bool(name) and (name == title or (title.startswith(name) and not title[len(name)].isalnum()))


def _markdown(path: Path) -> list[str]:
    nbformat = load_nbformat()

    return [_text(cell) for cell in nbformat.read(path, as_version=4).cells if cell.cell_type == "markdown"]


def _listing_problems(where: str, listed: list[tuple[str, str]], notebooks: list[Path]) -> list[Problem]:
    """Compare a listing's (text, file) pairs with the notebooks that exist, in order, with their titles."""
    problems = []
    names = [path.name for path in notebooks]
    files = [Path(target).name for _, target in listed]
    missing = [name for name in names if name not in files]
    extra = [name for name in files if name not in names]
    if missing:
        problems.append(Problem(where, f"it does not list {', '.join(missing)}"))
    if extra:
        problems.append(Problem(where, f"it lists {', '.join(extra)}, which does not exist"))
    if not missing and not extra and files != names:
        problems.append(Problem(where, "it lists the notebooks out of order"))
    titles = {path.name: notebook_title(path) for path in notebooks}
    for text, target in listed:
        name = Path(target).name
        if name in titles and not names_notebook(text, titles[name]):
            problems.append(Problem(where, f"it calls {name} {text!r}, but its title is {titles[name]!r}"))
    return problems


def map_problems(notebooks: list[Path]) -> list[Problem]:
    """Notebook 00's map (the markdown cell headed "map") lists exactly the notebooks, with their titles."""
    if not notebooks:
        return []
    cells = [text for text in _markdown(notebooks[0]) if re.search(r"^#+[^\n]*\bmap\b", text, re.I | re.M)]
    if not cells:
        return [Problem(notebooks[0].name, "it has no map of the course (a section headed 'map')")]
    return _listing_problems(f"{notebooks[0].name} (the map)", NOTEBOOK_LINK.findall(cells[0]), notebooks)


def readme_problems(readme: Path | str, notebooks: list[Path]) -> list[Problem]:
    """The README's course table (rows linking notebooks/NN_name.ipynb, or its address on GitHub, as a
    README on PyPI needs) lists exactly the notebooks."""
    text = Path(readme).read_text(encoding="utf-8")
    rows = [NOTEBOOK_LINK.search(line) for line in text.splitlines() if line.startswith("|")]
    listed = [(row.group(1), row.group(2)) for row in rows if row]
    return _listing_problems(f"{Path(readme).name} (the course table)", listed, notebooks)


def next_link_problems(notebooks: list[Path]) -> list[Problem]:
    """Every notebook but the last links "Next" to the one after it, naming it by its title; the last has no
    Next link; and only the last calls itself the last."""
    problems = []
    for index, path in enumerate(notebooks):
        prose = "\n".join(_markdown(path))
        links = NEXT_LINK.findall(prose)
        last = index == len(notebooks) - 1
        if last:
            if links:
                problems.append(Problem(path.name, f"the last notebook links 'Next' to {links[-1][1]}"))
        else:
            following = notebooks[index + 1]
            if not links:
                problems.append(Problem(path.name, f"no 'Next' link to {following.name}"))
            else:
                text, target = links[-1]
                title = notebook_title(following)
                if target != following.name:
                    problems.append(Problem(path.name,
                                            f"its 'Next' link goes to {target}, not {following.name}"))
                elif not names_notebook(text, title):
                    problems.append(Problem(path.name, f"its 'Next' link says {text!r}; the next notebook is "
                                                       f"{title!r}"))
            claim = CALLS_ITSELF_LAST.search(prose)
            if claim:
                problems.append(Problem(path.name, f"it calls itself the last ({claim.group(0)!r}), but "
                                                   f"{notebooks[-1].name} is"))
    return problems


def links_in_code(path: Path | str) -> list[Problem]:
    """Markdown links written inside code cells (they show as text, not as links)."""
    nbformat = load_nbformat()

    path = Path(path)
    problems = []
    for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
        if cell.cell_type == "code":
            for match in MARKDOWN_LINK.finditer(_text(cell)):
                problems.append(Problem(path.name, f"cell {index} is code but holds the markdown link "
                                                   f"{match.group(0)!r}"))
    return problems


def _byte_runs(text: str) -> list[bytes]:
    """Every run of bytes ``text`` shows: spaced hex, unbroken hex, 0x numbers, Python bytes literals."""
    runs = []
    for match in re.finditer(r"(?<![0-9A-Za-z])[0-9A-Fa-f]{2}(?:[ :,-]{1,2}[0-9A-Fa-f]{2})*(?![0-9A-Za-z])",
                             text):
        runs.append(bytes.fromhex(re.sub(r"[ :,-]", "", match.group(0))))
    for match in re.finditer(r"(?:0x|\b)((?:[0-9A-Fa-f]{2}){2,})\b", text):
        runs.append(bytes.fromhex(match.group(1)))
    for match in re.finditer(r"0x([0-9A-Fa-f]{1,2})\b(?:\s*,\s*)?", text):
        runs.append(bytes([int(match.group(1), 16)]))
    hexes = re.findall(r"0x([0-9A-Fa-f]{1,2})\b", text)
    if hexes:
        runs.append(bytes(int(item, 16) for item in hexes))
    for match in re.finditer(r"""b(['"])((?:\\.|(?!\1).)*)\1""", text):
        try:
            runs.append(ast.literal_eval(match.group(0)))
        except (ValueError, SyntaxError):
            pass
    return runs


def _shown(path: Path) -> str:
    """Everything a notebook's cells show: code and every text output."""
    nbformat = load_nbformat()

    parts = []
    for cell in nbformat.read(path, as_version=4).cells:
        if cell.cell_type != "code":
            continue
        parts.append(_text(cell))
        for output in cell.get("outputs", []):
            text = output.get("text", "")
            parts.append(text if isinstance(text, str) else "".join(text))
            for kind in ("text/plain", "text/html", "text/markdown"):
                value = output.get("data", {}).get(kind, "")
                parts.append(re.sub(r"<[^>]+>", " ", value if isinstance(value, str) else "".join(value)))
    return "\n".join(parts)


def unshown_frames(path: Path | str, allowed: dict[str, str] | None = None) -> list[Problem]:
    """Hex frames of two or more bytes (and ASCII frames) the prose quotes that no code cell or output of
    the notebook shows, and that are no named specification example."""
    path = Path(path)
    allowed = SPECIFICATION_EXAMPLES if allowed is None else allowed
    shown = _shown(path)
    runs = _byte_runs(shown) + [bytes.fromhex(frame) for frame in allowed]
    problems = []
    for text in dict.fromkeys(_prose_frames(path)):
        if text.startswith(":"):
            if text.casefold() not in shown.casefold() and text not in allowed:
                problems.append(Problem(path.name, f"the prose quotes the frame {text} but no cell shows it"))
            continue
        frame = bytes.fromhex(text)
        if not any(frame in run for run in runs):
            problems.append(Problem(path.name,
                                    f"the prose quotes the bytes {text} but no cell shows them (or "
                                               "name it a specification example)"))
    return problems


def _prose_frames(path: Path) -> list[str]:
    """The frames a notebook's prose quotes as facts.  An exercise's prompt ("**Exercise 05.4.** ... sends
    `01 18 ...`", "### Puzzle 13.5: ...") is left out: its frame is the learner's puzzle, which the checker
    holds."""
    found = []
    for text in _markdown(path):
        if EXERCISE_PROMPT.search(text):
            continue
        for match in PROSE_FRAME.finditer(text):
            tokens = match.group(0).split()
            if tokens[0] == "FC":  # "FC 16" names a function code
                tokens = tokens[1:]
            if len(tokens) >= 2 and not re.fullmatch(r"[A-D ]+", " ".join(tokens)):  # "CD AB": a word order
                found.append(" ".join(tokens))
        found.extend(PROSE_ASCII_FRAME.findall(text))
    return found


def _running_prose(path: Path) -> str:
    """A notebook's markdown without its "Where this comes from" box and notebook 00's "Sources" section:
    the prose a learner reads as the course's own words."""
    kept = []
    for text in _markdown(path):
        lines, skipping = [], 0
        for line in text.splitlines():
            heading = HEADING.match(line)
            if skipping and heading and len(heading.group(1)) <= skipping:
                skipping = 0
            if WHERE_HEADING.match(line) or SOURCES_HEADING.match(line):
                skipping = len(heading.group(1)) if heading else 6
            elif not skipping:
                lines.append(line)
        kept.append("\n".join(lines))
    return "\n".join(kept)


def source_mentions(path: Path | str) -> list[str]:
    """Each mention of a source in a notebook's running prose: a short name, or paper / article /
    CodeProject / Inst Tools (the closing "Where this comes from" box does not count)."""
    prose = _running_prose(Path(path))
    found = []
    for name in SOURCE_NAMES:
        pattern = re.compile(re.escape(name).replace(r"\ ", r"\s+"), re.I)
        found.extend(match.group(0) for match in pattern.finditer(prose))
        prose = pattern.sub(" ", prose)
    found.extend(match.group(0) for match in SOURCE_WORDS.finditer(prose))
    return found


def source_problems(path: Path | str) -> list[Problem]:
    """More than three mentions of a source in the prose, or a table or figure the learner cannot see."""
    path = Path(path)
    problems = []
    mentions = source_mentions(path)
    if len(mentions) > MAX_SOURCE_MENTIONS:
        problems.append(Problem(path.name, f"its prose names a source {len(mentions)} times (at most "
                                           f"{MAX_SOURCE_MENTIONS}; cite them in 'Where this comes from')"))
    for match in UNSEEN_TABLE.finditer("\n".join(_markdown(path))):
        problems.append(Problem(path.name, f"{match.group(0)!r} points to a table or figure the learner "
                                           "cannot see: show it"))
    return problems


PANEL_PICTURE = "mbe-picture"
"""The class of a panel's stored picture (:mod:`modbus_edu.widgets.picture`): what the learner sees of it."""
SOURCE_TABLE = re.compile(r"\b(?:table|figure|fig\.)\s*\d+", re.I)


def panel_problems(path: Path | str) -> list[Problem]:
    """A panel whose picture names a source, or a source's table or figure, which the learner never sees
    (the panel says what it shows in its own words)."""
    import nbformat

    path = Path(path)
    problems = []
    for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
        for output in cell.get("outputs", []) if cell.cell_type == "code" else []:
            html = output.get("data", {}).get("text/html", "")
            html = html if isinstance(html, str) else "".join(html)
            if PANEL_PICTURE not in html:
                continue
            text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
            named = [m.group(0) for m in SOURCE_TABLE.finditer(text)]
            named += [name for name in SOURCE_NAMES if name.lower() in text.lower()]
            if named:
                names = ", ".join(map(repr, named))
                problems.append(Problem(path.name, f"cell {index}: a panel names {names}, which the learner "
                                                   "never sees: say what it shows"))
    return problems


def solution_problems(folder: Path | str) -> list[Problem]:
    """Worked solutions (``solutions/NN_k.py``) that do not end with their own ``check("NN.k", ...)``:
    ``%load`` replaces the exercise's cell, check call included, so the solution must bring it back."""
    problems = []
    for path in sorted(Path(folder).glob("[0-9][0-9]_*.py")):
        key = path.stem.replace("_", ".", 1)
        try:
            body = ast.parse(path.read_text(encoding="utf-8")).body
        except SyntaxError as exc:
            problems.append(Problem(f"solutions/{path.name}",
                                    f"it does not parse: {exc.msg} (line {exc.lineno})"))
            continue
        last = body[-1] if body else None
        call = last.value if isinstance(last, ast.Expr) else None
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id == "check"
                and call.args and isinstance(call.args[0], ast.Constant) and call.args[0].value == key):
            problems.append(Problem(f"solutions/{path.name}", f'it does not end with check("{key}", ...): '
                                                              "%load replaces the cell, its check included"))
    return problems


def where_box_problems(path: Path | str) -> list[Problem]:
    """A "Where this comes from" section, placed before the notebook's Next link (notebook 00's "Sources"
    section, which cites every source in full, counts as its box)."""
    path = Path(path)
    prose = "\n".join(_markdown(path))
    box = WHERE_HEADING.search(prose) or (SOURCES_HEADING.search(prose) if path.name[:2] == "00" else None)
    if not box:
        return [Problem(path.name, "it has no 'Where this comes from' section")]
    following = [match.start() for match in NEXT_LINK.finditer(prose)]
    if following and following[-1] < box.start():
        return [Problem(path.name, "its 'Where this comes from' section comes after its Next link")]
    return []


def check_integrity(folder: Path | str, readme: Path | str | None = None) -> list[Problem]:
    """The course as one: the map in 00 and the README's table, the Next links, who calls itself the last,
    links in code, quoted frames, sources in the prose and the "Where this comes from" boxes, panels
    that name a source's table, and worked solutions that do not end with their check."""
    notebooks = course_notebooks(folder)
    readme = Path(folder).resolve().parent / "README.md" if readme is None else Path(readme)
    problems = map_problems(notebooks)
    if readme.exists():
        problems.extend(readme_problems(readme, notebooks))
    problems.extend(next_link_problems(notebooks))
    for path in notebooks:
        problems.extend(links_in_code(path))
        problems.extend(unshown_frames(path))
        problems.extend(source_problems(path))
        problems.extend(where_box_problems(path))
        problems.extend(panel_problems(path))
    problems.extend(solution_problems(Path(folder) / "solutions"))
    return problems
