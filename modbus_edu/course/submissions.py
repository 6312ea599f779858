"""Finding a class's submissions: which notebooks belong to which learner, under one name each.

A class comes as folders of learners (``class/ada/03_rtu_and_crc.ipynb``), a learner's folder, or files
named by learner (``ada_03_rtu_and_crc.ipynb``, ``ada.ipynb``).  Names are read the way learning
platforms and JupyterLab write them: case and surrounding spaces do not count, nor do the ``" (1)"`` of a
second download or the ``-Copy1`` of JupyterLab's Duplicate, and a notebook's title before or after a
name (``Hal_01_data_model.ipynb``, ``cy - 03_rtu_and_crc.ipynb``, ``03_rtu_and_crc - cy.ipynb``) is not
part of it.  Each merge of differently written names is one line of :attr:`Found.notes`.

Hidden files and folders (``.ipynb_checkpoints``, ``.git``) are skipped.  A symbolic link or anything that
is not a regular file is refused, never followed, with a reason: a link would grade its target, another
learner's work or a file of the grader's.
"""

from __future__ import annotations

import re
import stat
from dataclasses import dataclass, field
from pathlib import Path

TITLE = re.compile(r"(?<![A-Za-z0-9])\d\d_[A-Za-z0-9]+(?:_[A-Za-z0-9]+)*")
"""A course notebook's title in a file name: ``03_rtu_and_crc``."""
DOWNLOAD_MARKS = re.compile(r"\s*\(\d+\)|[\s_-]+copy\d*(?![A-Za-z0-9])|^copy of\s+", re.IGNORECASE)
"""What downloads and duplicates add to a name: ``" (1)"``, ``"(2)"``, ``"-Copy1"``, ``" - Copy"``."""
EDGES = " \t_-."
UNNAMED = "unnamed"


@dataclass(frozen=True)
class Submission:
    """One notebook handed in: whose it is, which of the course's notebooks it is, where it lies."""

    learner: str
    notebook: str  # the course notebook's title ("03_rtu_and_crc"), else the file's own cleaned name
    path: Path

    @property
    def mtime(self) -> float:
        return self.path.lstat().st_mtime


@dataclass
class Found:
    """A class's submissions, the files refused (learner -> reasons) and one line per merge or split."""

    submissions: list[Submission] = field(default_factory=list)
    refused: dict[str, list[str]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def learners(self) -> list[str]:
        return sorted({s.learner for s in self.submissions} | set(self.refused))


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


def collect(paths: list[Path]) -> Found:
    """Every learner's notebooks, from folders of learners, a learner's folder or files named by learner."""
    found = Found()
    raw: list[tuple[str | None, Path]] = []  # (the learner's name as the folder gives it, or None; file)
    refused: list[tuple[str | None, Path, str]] = []

    def consider(entry: Path, learner: str | None) -> None:
        reason = _refusal(entry)
        if reason:
            refused.append((learner, entry, reason))
        elif entry.is_file() and entry.suffix == ".ipynb":
            raw.append((learner, entry))

    for path in paths:
        if path.is_file():
            consider(path, None)
        elif path.is_dir():
            entries = _visible(path)
            notebooks = [p for p in entries if p.suffix == ".ipynb"]
            folders = [p for p in entries if p.is_dir() and not p.is_symlink()
                       and any(q.suffix == ".ipynb" for q in _visible(p))]
            linked = [p for p in entries if p.is_symlink() and p.suffix != ".ipynb"]
            if folders or linked:
                for folder in folders:
                    for entry in _visible(folder):
                        consider(entry, folder.name)
                for entry in linked:
                    refused.append((entry.name, entry, _refusal(entry) or ""))
                for entry in notebooks:
                    consider(entry, None)
            elif any(split_name(p.stem)[0] for p in notebooks):
                for entry in notebooks:
                    consider(entry, None)
                found.notes.append(f"{path.name or path}/: files named by learner, split by their names")
            else:
                for entry in notebooks:
                    consider(entry, path.resolve().name)
        else:
            raise FileNotFoundError(f"{path} is neither a notebook nor a folder of notebooks")

    titles = class_titles([file.stem for _, file in raw] + [file.stem for _, file, _ in refused])
    spellings: dict[str, dict[str, str]] = {}  # learner -> {file or folder/: the name as written}
    for folder, file in raw:
        name, title = split_name(file.stem, titles)
        given = folder if folder is not None else name
        learner = learner_name(given if given is not None else file.stem)
        found.submissions.append(Submission(learner, title or learner_name(file.stem), file))
        spelt = folder + "/" if folder is not None else file.name
        if folder is None and title:  # a copy's or a download's marks are a choice of copies, not a name
            stem = without_marks(file.stem)
            at = stem.casefold().find(title)
            as_written = (stem[:at] + " " + stem[at + len(title):]).strip(EDGES)
        else:
            as_written = folder if folder is not None else file.stem
        spellings.setdefault(learner, {})[spelt] = as_written
    for folder, file, reason in refused:
        name = folder if folder is not None else (split_name(file.stem, titles)[0] or file.stem)
        found.refused.setdefault(learner_name(name), []).append(f"{file.name}: refused, {reason}")
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
