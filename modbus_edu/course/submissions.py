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

Each layout read, each merge of differently written names and each zip unpacked is one line of
:attr:`Found.notes`.  Hidden files and folders (``.ipynb_checkpoints``, ``.git``) are skipped.  A
symbolic link or anything that is not a regular file is refused, never followed, with a reason: a link
would grade its target, another learner's work or a file of the grader's.
"""

from __future__ import annotations

import re
import shutil
import stat
import tempfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from ..errors import ModbusError
from .archives import ArchiveError, unpack

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


def without_marks(text: str) -> str:
    """A file or folder name without the marks of downloads and duplicates."""
    return DOWNLOAD_MARKS.sub("", text).strip(EDGES)


def learner_name(text: str) -> str:
    """One learner's name however it was written: ``" Hal (1)"`` and ``"hal"`` are both ``"hal"``."""
    name = " ".join(without_marks(text).casefold().split()).strip(EDGES)
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


def _visible(folder: Path) -> list[Path]:
    """The entries of ``folder`` that are not hidden, in order."""
    return sorted(p for p in folder.iterdir() if not p.name.startswith("."))


def _is_zip(path: Path) -> bool:
    """A zip file, never a link to one (a link is refused like any other)."""
    return path.suffix.lower() == ".zip" and not path.is_symlink() and path.is_file()


class _Walk:
    """Going through the paths given: each file found with the name of the folder it was found in (or
    None when its own name says whose it is) and whether nbgrader's tree named it."""

    def __init__(self, found: Found, scratch: Path | None):
        self.found = found
        self.scratch = scratch
        self.raw: list[tuple[str | None, Path, bool]] = []
        self.refused: list[tuple[str | None, Path, str]] = []
        self.onlinetext = 0

    def unpacked(self, archive: Path) -> Path:
        if self.scratch is None:
            self.scratch = self.found.scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-unpacked-"))
        into = self.scratch / str(len(list(self.scratch.iterdir())))
        result = unpack(archive, into)
        self.found.notes.append(result.note)
        for entry, reason in result.refused:
            parts = PurePosixPath(entry).parts
            folder = parts[0] if len(parts) > 1 else None
            self.refused.append((folder, Path(parts[-1] if parts else entry), f"in {archive.name}: {reason}"))
        return result.folder

    def consider(self, entry: Path, learner: str | None, nbgrader: bool = False) -> None:
        reason = _refusal(entry)
        if reason:
            self.refused.append((learner, entry, reason))
        elif entry.is_file() and entry.suffix == ".ipynb":
            self.raw.append((learner, entry, nbgrader))

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
                self.consider(entry, name)
        self.count_onlinetext(entries)

    def learner_zip(self, archive: Path, name: str | None) -> None:
        """A learner's own zip: its notebooks are the learner's (``name``, else the zip's own name)."""
        try:
            folder = self.unpacked(archive)
        except ArchiveError as exc:
            self.refused.append((name, archive, str(exc)))
            return
        self.learner_folder(folder, name if name is not None else folder.name, deep=True)

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
            self.path(self.unpacked(path))
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
            for archive in zips:  # a folder the platform's downloads were put in
                self.path(self.unpacked(archive))
            return
        linked = [p for p in entries if p.is_symlink() and p.suffix != ".ipynb"]
        if folders or linked or zips:
            for folder in folders:
                self.learner_folder(folder, folder.name)
            for archive in zips:  # a learner's own zip: a folder of its name
                self.learner_zip(archive, None)
            for entry in linked:
                self.refused.append((entry.name, entry, _refusal(entry) or ""))
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
    titles = class_titles([_own_stem(folder, file) for folder, file, _ in [*raw, *refused]])
    readings = [(folder, file, _reading(folder, file, nbgrader, titles)) for folder, file, nbgrader in raw]
    people = {identity for _, _, (_, identity, _, _) in readings if identity is not None}
    people |= {identity for folder, file, _ in refused
               for identity in [_reading(folder, file, False, titles)[1]] if identity is not None}
    shared = Counter((person.platform, person.name) for person in people)
    shown = {person: person.name if shared[(person.platform, person.name)] == 1 else f"{person.name} "
             f"({person.id})" for person in people}
    for person, name in shown.items():
        found.identities[name] = person

    spellings: dict[str, dict[str, str]] = {}  # learner -> {file or folder/: the name as written}
    tally: dict[str, list[set]] = {}  # platform -> [files, learners, late files, resubmissions]
    late: dict[str, list[str]] = {}
    for folder, file, (plain, identity, named, title) in readings:
        if identity is not None:
            learner = shown[identity]
            found.submissions.append(Submission(learner, title or learner_name(file.stem), file,
                                                named.version if named else (0, 0)))
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
        found.submissions.append(Submission(learner, title or learner_name(file.stem), file))
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
    for folder, file, reason in refused:
        plain, identity, _, _ = _reading(folder, file, False, titles)
        learner = shown[identity] if identity is not None else plain or UNNAMED
        found.refused.setdefault(learner, []).append(f"{file.name}: refused, {reason}")
    found.submissions.sort(key=lambda s: (s.learner, s.notebook, str(s.path)))
    for learner, spelt in sorted(spellings.items()):
        if set(spelt.values()) != {learner}:
            found.notes.append(f"{learner}: one learner from {', '.join(map(repr, sorted(spelt)))}")
    return found


def find_submissions(paths: list[Path]) -> dict[str, list[Path]]:
    """Learner name -> notebooks (see :func:`collect`, which also says what it refused and merged)."""
    learners: dict[str, list[Path]] = {}
    for submission in collect(paths).submissions:
        learners.setdefault(submission.learner, []).append(submission.path)
    return {name: sorted(files) for name, files in sorted(learners.items())}
