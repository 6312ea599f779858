"""Finding a class's submissions: which notebooks belong to which learner, under one name each, and why.

A class comes as a learning platform downloads it, or as an instructor gathered it:

- **Moodle** ("Download all submissions"): ``Full Name_ID_assignsubmission_file_03_rtu_and_crc.ipynb``
  flat, or a folder per learner ``Full Name_ID_assignsubmission_file_/`` (``assignsubmission_onlinetext``
  too); the learner is the full name, told apart by Moodle's participant id (any number of digits).
- **Canvas** ("Download submissions"): ``name_ID_ATTACHMENT_03_rtu_and_crc.ipynb``, ``name_LATE_ID_...``
  for a late hand-in, and ``03_rtu_and_crc-1.ipynb`` for a file handed in again; the learner is Canvas's
  name (``lovelaceada``), told apart by its user id, and of several resubmissions the newest counts.
- **nbgrader**: ``submitted/STUDENT/ASSIGNMENT/NOTEBOOK.ipynb`` (or ``autograded/``); the learner is the
  student id.
- Folders of learners (``class/ada/03_rtu_and_crc.ipynb``), a learner's folder, or files named by learner
  (``ada_03_rtu_and_crc.ipynb``, ``ada.ipynb``), named as JupyterLab and downloads write them: case and
  surrounding spaces do not count, nor do the ``" (1)"`` of a second download or the ``-Copy1`` of
  JupyterLab's Duplicate, and a notebook's title before or after a name (``Hal_01_data_model.ipynb``,
  ``cy - 03_rtu_and_crc.ipynb``, ``03_rtu_and_crc - cy.ipynb``) is not part of it.
- A zip of any of these (the platform's download itself, or a learner's zip of notebooks), unpacked into a
  folder the grader owns (:mod:`.archives`).

**A zip never names another learner.**  Only what the instructor gave (a folder, a zip given on the
command line) and a platform's whole download name learners, by their folders or file names.  A folder
that holds only zips is a folder of platform downloads when every zip's notebooks are named as a
platform names them, and otherwise a folder of learners: one zip, one learner, named by the zip.  Inside
a learner's zip (or a learner's folder), every path is that learner's, whatever its folders are called.

**One bad entry never stops the class.**  A notebook that cannot be read (larger than
:data:`~.archives.NOTEBOOK_LIMIT`, a name in a bad encoding, not UTF-8, not JSON, not nbformat 4) or a
zip entry refused by :mod:`.archives` is refused on its own, in the row of the learner whose folder or
zip held it.  A refused entry never makes a row of its own: one that names no learner (a path leading
out of the zip, a link beside the learners' folders) is one line of :attr:`Found.notes`.

**One learner, one row, keyed by the platform's id.**  Two learners of one name are told apart by their
ids ("Sam Lee (21)"); a learner whose name is literally that of a disambiguated classmate is told apart
further (participant 555 named "Sam Lee (21)" is "Sam Lee (21) (555)", and participant 21 "Sam Lee (Moodle
21)"), so no two identities ever share a row.

Each layout read, each merge of differently written names and each zip unpacked is one line of
:attr:`Found.notes`.  Hidden files and folders (``.ipynb_checkpoints``, ``.git``) are skipped.  A
symbolic link or anything that is not a regular file is refused, never followed, with a reason: a link
would grade its target, another learner's work or a file of the grader's.
"""

from __future__ import annotations

import json
import re
import shutil
import stat
import tempfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from ..errors import ModbusError
from .archives import NOTEBOOK_LIMIT, ArchiveError, Budget, names, unpack

TITLE = re.compile(r"(?<![A-Za-z0-9])\d\d_[A-Za-z0-9]+(?:_[A-Za-z0-9]+)*")
"""A course notebook's title in a file name: ``03_rtu_and_crc``."""
DOWNLOAD_MARKS = re.compile(r"\s*\(\d+\)|[\s_-]+copy\d*(?![A-Za-z0-9])|^copy of\s+", re.IGNORECASE)
"""What downloads and duplicates add to a name: ``" (1)"``, ``"(2)"``, ``"-Copy1"``, ``" - Copy"``."""
EDGES = " \t_-."
UNNAMED = "unnamed"
MOODLE = re.compile(r"(?P<name>.+?)_(?P<id>\d+)_assignsubmission_(?P<plugin>file|onlinetext)"
                    r"(?:_(?P<rest>.*))?", re.DOTALL)
"""Moodle's name for a learner's file or folder: full name, participant id, the submission plugin."""
CANVAS = re.compile(r"(?P<name>[^\W_]+)_(?P<late>LATE_)?(?P<id>\d+)_(?P<attachment>\d+)_(?P<rest>.+)",
                    re.DOTALL)
"""Canvas's name for a learner's file: its name, LATE, the user id, the attachment id, the file's name."""
RESUBMISSION = re.compile(r"-(\d+)$")
"""The ``-1`` Canvas adds to a file handed in again under the same name."""
COPY_MARK = re.compile(r"\((\d+)\)")
"""The ``(1)`` Moodle or a second download adds to a file's name: a later copy."""
NBGRADER_TREES = ("submitted", "autograded")
PLATFORMS = {"moodle": "Moodle", "canvas": "Canvas", "nbgrader": "nbgrader"}


class SubmissionError(ModbusError, FileNotFoundError):
    """A path given to the grader that holds no submissions: missing, or neither a notebook, a zip nor a
    folder."""


@dataclass(frozen=True)
class Identity:
    """A learner as a platform knows them: the platform, its id for them (Moodle's participant id,
    Canvas's user id, nbgrader's student id) and their name as it writes it."""

    platform: str
    id: str
    name: str


@dataclass(frozen=True)
class Submission:
    """One notebook handed in: whose it is, which of the course's notebooks it is, where it lies, and
    its place among the platform's resubmissions (Canvas: the ``-N``, then the attachment id)."""

    learner: str
    notebook: str  # the course notebook's title ("03_rtu_and_crc"), else the file's own cleaned name
    path: Path
    version: tuple[int, int] = (0, 0)
    mark: int = 0  # the download's "(N)": a later copy

    @property
    def mtime(self) -> float:
        return self.path.lstat().st_mtime


@dataclass
class Found:
    """A class's submissions, the files refused (learner -> reasons), what the platform marked (learner ->
    flags: a late hand-in), each learner's identity on the platform, and one line per layout, zip, merge
    or split.  :meth:`cleanup` removes the folder zips were unpacked into."""

    submissions: list[Submission] = field(default_factory=list)
    refused: dict[str, list[str]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    flags: dict[str, list[str]] = field(default_factory=dict)
    identities: dict[str, Identity] = field(default_factory=dict)
    scratch: Path | None = None

    @property
    def learners(self) -> list[str]:
        return sorted({s.learner for s in self.submissions} | set(self.refused))

    def cleanup(self) -> None:
        if self.scratch is not None:
            shutil.rmtree(self.scratch, ignore_errors=True)
            self.scratch = None


def readable(text: str) -> str:
    """``text`` as it can be written in a report: a name read from the file system in a bad encoding (its
    undecodable bytes) with U+FFFD in their place."""
    return text.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def copy_mark(stem: str) -> int:
    """The number of the last ``(N)`` a download put in a name (0 when none)."""
    found = COPY_MARK.findall(stem)
    return int(found[-1]) if found else 0


def without_marks(text: str) -> str:
    """A file or folder name without the marks of downloads and duplicates."""
    return DOWNLOAD_MARKS.sub("", text).strip(EDGES)


def learner_name(text: str) -> str:
    """One learner's name however it was written: ``" Hal (1)"`` and ``"hal"`` are both ``"hal"``."""
    name = " ".join(without_marks(readable(text)).casefold().split()).strip(EDGES)
    return name or UNNAMED


def split_name(stem: str, titles: set[str] = frozenset()) -> tuple[str | None, str | None]:
    """(learner, notebook title) of a file's stem; either is None when the name does not hold it.

    ``titles`` are the notebook titles the class's files show: a title that runs into a name
    (``03_rtu_and_crc_hal``) is cut at the longest of them it starts with."""
    stem = without_marks(stem)
    match = TITLE.search(stem)
    if not match:
        return None, None
    title = match.group().casefold()
    before, after = stem[:match.start()], stem[match.end():]
    shorter = [t for t in titles if title.startswith(t + "_")]
    if shorter:
        cut = max(shorter, key=len)
        after = match.group()[len(cut):] + after
        title = cut
    name = " ".join(part.strip(EDGES) for part in (before, after) if part.strip(EDGES))
    return (learner_name(name) if name else None), title


def class_titles(stems: list[str]) -> set[str]:
    """The notebook titles a class's file names show, each cut to what the names of one number share
    (``03_rtu_and_crc`` from ``03_rtu_and_crc_ada`` and ``03_rtu_and_crc_hal``)."""
    by_number: dict[str, set[str]] = {}
    for stem in stems:
        match = TITLE.search(without_marks(stem))
        if match:
            by_number.setdefault(match.group()[:2], set()).add(match.group().casefold())
    titles = set()
    for found in by_number.values():
        titles |= found
        words = [title.split("_") for title in found]
        common = []
        for parts in zip(*words):
            if len(set(parts)) > 1:
                break
            common.append(parts[0])
        if len(found) > 1 and len(common) >= 2:
            titles.add("_".join(common))
    return titles


@dataclass(frozen=True)
class PlatformName:
    """What a platform's name for a file or folder says: whose it is, the file's own name after it (""
    for a folder), whether it came late, and its place among resubmissions."""

    identity: Identity
    rest: str
    late: bool = False
    version: tuple[int, int] = (0, 0)


def platform_name(text: str) -> PlatformName | None:
    """``text`` (a file's stem or a folder's name) read as Moodle or Canvas name it, or None."""
    text = readable(text)
    moodle = MOODLE.fullmatch(text)
    if moodle:
        name, number = moodle["name"].strip(), moodle["id"]
        if name.casefold() == "participant":  # anonymous marking: "Participant_12345_..."
            name = f"Participant {number}"
        return PlatformName(Identity("moodle", number, name), (moodle["rest"] or "").strip(EDGES))
    canvas = CANVAS.fullmatch(text)
    if canvas:
        rest = canvas["rest"]
        again = RESUBMISSION.search(rest)
        times = int(again.group(1)) if again else 0
        rest = rest[:again.start()] if again else rest
        return PlatformName(Identity("canvas", canvas["id"], canvas["name"]), rest, bool(canvas["late"]),
                            (times, int(canvas["attachment"])))
    return None


def _refusal(path: Path) -> str | None:
    """Why ``path`` cannot be a submission (a link, not a regular file), or None."""
    mode = path.lstat().st_mode
    if stat.S_ISLNK(mode):
        return "a symbolic link (a submission is the notebook itself, never a link to one: not followed)"
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        return "not a regular file (a pipe, a socket or a device: not read)"
    return None


def unreadable(path: Path) -> str | None:
    """Why the notebook file ``path`` cannot be graded (too large, a name in a bad encoding, not UTF-8,
    not JSON, not nbformat 4), or None; it reads at most :data:`~.archives.NOTEBOOK_LIMIT` bytes."""
    if readable(path.name) != path.name:
        return "its name is not valid UTF-8 (not read: rename it, then grade it again)"
    size = path.lstat().st_size
    if size > NOTEBOOK_LIMIT:
        return f"{size / 1e6:.1f} MB, more than the grader reads in a notebook ({NOTEBOOK_LIMIT / 1e6:g} MB)"
    with path.open("rb") as stream:
        data = stream.read(NOTEBOOK_LIMIT + 1)
    try:
        notebook = json.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        return "not UTF-8 text, so not a notebook (not read)"
    except (ValueError, RecursionError):
        return "not JSON, so not a notebook (a damaged or renamed file?; not read)"
    version = notebook.get("nbformat") if isinstance(notebook, dict) else None
    if isinstance(version, int) and not isinstance(version, bool) and version < 4:
        return (f"a notebook of nbformat {version} (IPython 2 or older): open it in Jupyter and save it as "
                "nbformat 4 (not read)")
    if version != 4 or not isinstance(notebook.get("cells"), list):
        return "JSON, but not a Jupyter notebook of nbformat 4 with its cells (not read)"
    return None


def _visible(folder: Path) -> list[Path]:
    """The entries of ``folder`` that are not hidden, in order."""
    return sorted(p for p in folder.iterdir() if not p.name.startswith("."))


def _is_zip(path: Path) -> bool:
    """A zip file, never a link to one (a link is refused like any other)."""
    return path.suffix.lower() == ".zip" and not path.is_symlink() and path.is_file()


def _download_owner(entry: str) -> str:
    """Whose an entry of a platform's download is, as its name says (for the budget of bytes a learner's
    entries may inflate to): the learner's folder, else the file's platform or learner name."""
    parts = entry.split("/")
    for tree in NBGRADER_TREES:
        if tree in parts[:2] and len(parts) > parts.index(tree) + 2:
            return parts[parts.index(tree) + 1]
    if len(parts) > 1:
        return parts[0].removesuffix(".zip")
    stem = PurePosixPath(parts[0]).stem
    named = platform_name(stem)
    return f"{named.identity.platform} {named.identity.id}" if named else split_name(stem)[0] or ""


def is_download(archive: Path) -> bool:
    """Whether a zip is a platform's whole download: every notebook and zip in it named as Moodle, Canvas
    or nbgrader name a learner's files (a zip that cannot be read is not)."""
    try:
        held = names(archive)
    except ArchiveError:
        return False
    for name in held:
        parts = name.split("/")
        if any(tree in parts[:2] for tree in NBGRADER_TREES):
            continue
        named = parts[0].removesuffix(".zip") if len(parts) > 1 else PurePosixPath(parts[0]).stem
        if platform_name(named) is None:
            return False
    return bool(held)


LEADS_OUT = "leads outside"
SHOWN_REFUSALS = 10
"""The refusals one learner's row (or the notes) names; the rest are counted."""


def _bounded(lines: list[str], what: str) -> list[str]:
    """At most :data:`SHOWN_REFUSALS` lines, then one that counts the rest (a zip of 10,000 bad entries is
    ten lines and a count, not 10,000)."""
    if len(lines) <= SHOWN_REFUSALS:
        return lines
    return lines[:SHOWN_REFUSALS] + [f"and {len(lines) - SHOWN_REFUSALS} {what}"]


class _Walk:
    """Going through the paths given: each file found with the name of the folder it was found in (or
    None when its own name says whose it is) and whether nbgrader's tree named it; each refusal with the
    same, and whether a learner's own folder or zip held it (then it is theirs, whatever its name)."""

    def __init__(self, found: Found, scratch: Path | None):
        self.found = found
        self.scratch = scratch
        self.raw: list[tuple[str | None, Path, bool]] = []
        self.refused: list[tuple[str | None, Path, str, bool]] = []
        self.onlinetext = 0
        self.budget = Budget()
        self.ownerless: list[str] = []  # refusals that name no learner: lines of the notes

    def unpacked(self, archive: Path, learner: str | None = None) -> Path:
        """``archive`` unpacked: a learner's own zip when ``learner`` is given (every entry theirs), else a
        platform's download or the instructor's zip (its names name learners)."""
        if self.scratch is None:
            self.scratch = self.found.scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-unpacked-"))
        into = self.scratch / str(len(list(self.scratch.iterdir())))
        result = unpack(archive, into, budget=self.budget, owner=learner if learner is not None else
                        _download_owner)
        self.found.notes.append(readable(result.note))
        for entry, reason in result.refused:
            parts = PurePosixPath(entry).parts
            line = f"in {archive.name}: {reason}"
            file = Path(parts[-1] if parts else entry)
            if learner is not None:
                self.refused.append((learner, file, line, True))
            elif any(part.lower().endswith(".zip") for part in parts[:-1]):  # inside a learner's own zip
                self.refused.append((parts[0].removesuffix(".zip"), file, line, True))
            elif LEADS_OUT in reason or not parts:
                self.ownerless.append(readable(f"{archive.name}: {entry!r} refused, {reason}; it names "
                                               "no learner, so it is in no row"))
            else:
                self.refused.append((parts[0] if len(parts) > 1 else None, file, line, False))
        return result.folder

    def consider(self, entry: Path, learner: str | None, nbgrader: bool = False, owned: bool = False) -> None:
        reason = _refusal(entry)
        if reason is None and entry.is_file() and entry.suffix == ".ipynb":
            reason = unreadable(entry)
            if reason is None:
                self.raw.append((learner, entry, nbgrader))
                return
        if reason:
            self.refused.append((learner, entry, reason, owned or learner is not None))

    def count_onlinetext(self, entries: list[Path]) -> None:
        self.onlinetext += sum(1 for p in entries if "assignsubmission_onlinetext" in p.name
                               and p.suffix != ".ipynb" and not p.is_symlink())

    def learner_folder(self, folder: Path, name: str, deep: bool = False) -> None:
        """One learner's files: those in ``folder`` (all below it when ``deep``: an unpacked zip), and the
        notebooks of their own zips."""
        entries = sorted(p for p in folder.rglob("*") if not any(
            part.startswith(".") for part in p.relative_to(folder).parts)) if deep else _visible(folder)
        for entry in entries:
            if _is_zip(entry) and not deep:
                self.learner_zip(entry, name)
            elif not (deep and entry.is_dir()):
                self.consider(entry, name, owned=True)
        self.count_onlinetext(entries)

    def learner_zip(self, archive: Path, name: str | None) -> None:
        """A learner's own zip: every notebook in it is the learner's (``name``, else the zip's own name),
        whatever its folders and files are called."""
        learner = name if name is not None else archive.name[:-len(".zip")]
        try:
            folder = self.unpacked(archive, learner)
        except ArchiveError as exc:
            self.refused.append((learner, archive, str(exc), True))
            return
        self.learner_folder(folder, learner, deep=True)

    def nbgrader(self, root: Path) -> None:
        trees = [root] if root.name in NBGRADER_TREES else [root / "submitted"]
        if root.name not in NBGRADER_TREES and (root / "autograded").is_dir():
            self.found.notes.append(f"{root.name}/autograded/: not read (nbgrader's copies of submitted/)")
        students: set[str] = set()
        for tree in trees:
            for student in _visible(tree):
                if student.is_symlink():
                    self.consider(student, student.name, True)
                if student.is_symlink() or not student.is_dir():
                    continue
                students.add(student.name)
                for assignment in _visible(student):
                    if assignment.is_dir() and not assignment.is_symlink():
                        for entry in _visible(assignment):
                            self.consider(entry, student.name, True)
                    elif assignment.is_symlink():
                        self.consider(assignment, student.name, True)
        where = "/".join(dict.fromkeys(tree.name for tree in trees))
        self.found.notes.append(f"{where}/: nbgrader's tree (STUDENT/ASSIGNMENT/NOTEBOOK.ipynb), "
                                f"{len(students)} student(s), each named by their student id")

    def path(self, path: Path) -> None:
        """A path the instructor gave (a link to a class's folder or zip is followed: theirs to choose)."""
        if path.suffix.lower() == ".zip" and path.is_file():
            self.path(self.unpacked(path))  # the instructor's: its names name learners
        elif path.is_file():
            self.consider(path, None)
        elif path.is_dir():
            self.folder(path)
        else:
            raise SubmissionError(f"{path} is neither a notebook, a zip nor a folder of notebooks")

    def folder(self, path: Path) -> None:
        if path.name in NBGRADER_TREES or (path / "submitted").is_dir():
            self.nbgrader(path)
            return
        entries = _visible(path)
        zips = [p for p in entries if _is_zip(p)]
        notebooks = [p for p in entries if p.suffix == ".ipynb"]
        folders = [p for p in entries if p.is_dir() and not p.is_symlink()
                   and any(q.suffix == ".ipynb" or _is_zip(q) for q in _visible(p))]
        if zips and not notebooks and not folders and not any(platform_name(p.stem) for p in zips):
            if all(is_download(archive) for archive in zips):
                for archive in zips:  # a folder the platform's downloads were put in
                    self.path(self.unpacked(archive))
                return
            self.found.notes.append(readable(
                f"{path.name or path}/: {len(zips)} zip(s) that no platform named: a folder of learners, one "
                "zip one learner, named by the zip (nothing inside a zip names another learner)"))
        linked = [p for p in entries if p.is_symlink() and p.suffix != ".ipynb"]
        if folders or linked or zips:
            for folder in folders:
                self.learner_folder(folder, folder.name)
            for archive in zips:  # a learner's own zip: a folder of its name
                self.learner_zip(archive, None)
            for entry in linked:
                self.ownerless.append(readable(f"{path.name or path}/{entry.name}: refused, "
                                               f"{_refusal(entry) or ''}; it names no learner, so it is "
                                               "in no row"))
            for entry in notebooks:
                self.consider(entry, None)
            self.count_onlinetext(entries)
        elif any(split_name(p.stem)[0] or platform_name(p.stem) for p in notebooks):
            for entry in notebooks:
                self.consider(entry, None)
            self.count_onlinetext(entries)
            if not all(platform_name(p.stem) for p in notebooks):
                self.found.notes.append(f"{path.name or path}/: files named by learner, split by their names")
        else:
            for entry in notebooks:
                self.consider(entry, path.resolve().name)


def _own_stem(folder: str | None, file: Path) -> str:
    """A file's own stem, without the name a platform put before it."""
    named = platform_name(file.stem) if folder is None else None
    return named.rest if named else file.stem


def _reading(folder: str | None, file: Path, nbgrader: bool, titles: set[str]
             ) -> tuple[str | None, Identity | None, PlatformName | None, str | None]:
    """(learner's name as plain names give it, the platform's identity, the platform's name, the notebook
    title) of one file found in ``folder`` (None: named by itself)."""
    if nbgrader and folder is not None:
        return None, Identity("nbgrader", folder, folder), None, split_name(file.stem, titles)[1]
    named = platform_name(folder) if folder is not None else platform_name(file.stem)
    if named:
        text = file.stem if folder is not None else named.rest
        title = split_name(text, titles)[1]
        return None, named.identity, named, title or learner_name(text or file.stem)
    name, title = split_name(file.stem, titles)
    given = folder if folder is not None else name
    return learner_name(given if given is not None else file.stem), None, None, title


def _platform_note(platform: str, files: int, learners: int, late: int, again: int) -> str:
    if platform == "moodle":
        return (f"Moodle's download (FULL NAME_PARTICIPANT ID_assignsubmission_file_...): {files} file(s) of "
                f"{learners} learner(s), one learner per participant id, named as Moodle names them")
    if platform == "canvas":
        return (f"Canvas's download (name_USER ID_ATTACHMENT ID_file, LATE for a late one, -N for a file "
                f"handed in again): {files} file(s) of {learners} learner(s), one learner per Canvas user "
                f"id; {late} file(s) marked LATE, {again} resubmission(s), of which the newest counts")
    return ""


def _labels(people: set[Identity], plain: set[str]) -> dict[Identity, str]:
    """Each identity's row name, never another's nor a learner's gathered by hand: the platform's name,
    with the id when two share it ("Sam Lee (21)"), with the platform too when that is still someone
    else's name (participant 21 is "Sam Lee (Moodle 21)" beside participant 555 named "Sam Lee (21)")."""
    shared = Counter((person.platform, person.name) for person in people)
    level = {person: 0 if shared[(person.platform, person.name)] == 1 else 1 for person in people}

    def label(person: Identity) -> str:
        platform = PLATFORMS.get(person.platform, person.platform)
        return [person.name, f"{person.name} ({person.id})", f"{person.name} ({platform} {person.id})",
                f"{person.name} [{platform} id {person.id}]"][level[person]]

    for _ in range(3):
        taken = Counter(label(person) for person in people) + Counter(plain)
        clash = [person for person in people if taken[label(person)] > 1 and level[person] < 3]
        if not clash:
            break
        for person in clash:
            level[person] += 1
    shown: dict[Identity, str] = {}
    for person in sorted(people, key=lambda p: (p.platform, p.id)):
        name = label(person)
        while name in plain or name in shown.values():
            name += "*"
        shown[person] = name
    return shown


def collect(paths: list[Path], scratch: Path | None = None) -> Found:
    """Every learner's notebooks, from any layout above; zips are unpacked into ``scratch`` (a new
    temporary folder when None: :meth:`Found.cleanup` removes it)."""
    found = Found()
    walk = _Walk(found, scratch)
    try:
        for path in paths:
            walk.path(path)
    except BaseException:
        found.cleanup()
        raise

    raw, refused = walk.raw, walk.refused
    if walk.onlinetext:
        found.notes.append(f"{walk.onlinetext} Moodle online text(s) (assignsubmission_onlinetext): not a "
                           "notebook, not graded")
    titles = class_titles([_own_stem(folder, file) for folder, file, *_ in [*raw, *refused]])
    readings = [(folder, file, _reading(folder, file, nbgrader, titles)) for folder, file, nbgrader in raw]
    kept = []  # the refusals that belong in a learner's row: (reading, reason)
    for folder, file, reason, owned in refused:
        reading = _reading(folder, file, False, titles)
        if owned or folder is not None or reading[1] is not None or split_name(file.stem, titles)[0]:
            kept.append((file, reading, reason))
        else:
            walk.ownerless.append(readable(f"{file.name}: refused, {reason}; it names no learner, so it is "
                                           "in no row"))
    found.notes += _bounded(walk.ownerless, "entries that name no learner refused")
    people = {identity for _, _, (_, identity, _, _) in readings if identity is not None}
    people |= {reading[1] for _, reading, _ in kept if reading[1] is not None}
    plain_names = {reading[0] or UNNAMED for _, _, reading in readings if reading[1] is None}
    plain_names |= {reading[0] or UNNAMED for _, reading, _ in kept if reading[1] is None}
    shown = _labels(people, plain_names)
    for person, name in shown.items():
        found.identities[name] = person

    spellings: dict[str, dict[str, str]] = {}  # learner -> {file or folder/: the name as written}
    tally: dict[str, list[set]] = {}  # platform -> [files, learners, late files, resubmissions]
    late: dict[str, list[str]] = {}
    for folder, file, (plain, identity, named, title) in readings:
        if identity is not None:
            learner = shown[identity]
            found.submissions.append(Submission(learner, title or learner_name(file.stem), file,
                                                named.version if named else (0, 0), copy_mark(file.stem)))
            counts = tally.setdefault(identity.platform, [set(), set(), set(), set()])
            counts[0].add(file)
            counts[1].add(learner)
            if named and named.late:
                counts[2].add(file)
                late.setdefault(learner, []).append(file.name)
            if named and named.version[0]:
                counts[3].add(file)
            continue
        learner = plain or UNNAMED
        found.submissions.append(Submission(learner, title or learner_name(file.stem), file,
                                            mark=copy_mark(file.stem)))
        spelt = folder + "/" if folder is not None else file.name
        if folder is None and title:  # a copy's or a download's marks are a choice of copies, not a name
            stem = without_marks(file.stem)
            at = stem.casefold().find(title)
            as_written = (stem[:at] + " " + stem[at + len(title):]).strip(EDGES)
        else:
            as_written = folder if folder is not None else file.stem
        spellings.setdefault(learner, {})[spelt] = as_written
    for platform, (files, learners, marked, again) in sorted(tally.items()):
        note = _platform_note(platform, len(files), len(learners), len(marked), len(again))
        if note:
            found.notes.append(note)
    for learner, files in late.items():
        found.flags[learner] = [f"handed in late (Canvas marks it LATE): {', '.join(map(repr, files))}"]
    for file, (plain, identity, _, _), reason in kept:
        learner = shown[identity] if identity is not None else plain or UNNAMED
        found.refused.setdefault(learner, []).append(readable(f"{file.name}: refused, {reason}"))
    found.refused = {learner: _bounded(lines, "more entries refused")
                     for learner, lines in found.refused.items()}
    found.submissions.sort(key=lambda s: (s.learner, s.notebook, str(s.path)))
    for learner, spelt in sorted(spellings.items()):
        if set(spelt.values()) != {learner}:
            found.notes.append(readable(f"{learner}: one learner from {', '.join(map(repr, sorted(spelt)))}"))
    return found


def find_submissions(paths: list[Path]) -> dict[str, list[Path]]:
    """Learner name -> notebooks (see :func:`collect`, which also says what it refused and merged)."""
    learners: dict[str, list[Path]] = {}
    for submission in collect(paths).submissions:
        learners.setdefault(submission.learner, []).append(submission.path)
    return {name: sorted(files) for name, files in sorted(learners.items())}
