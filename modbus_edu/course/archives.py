"""Opening a class's zip download (Moodle's "Download all submissions", Canvas's "Download submissions",
a learner's own zip of notebooks) without trusting it.

A zip is read with :mod:`zipfile` and only its notebooks (and the zips inside it, one level down: a
learner who zipped their notebooks) are written out, into a folder the grader owns, under the zip's own
name, so that the rest of :mod:`.submissions` reads it as the folder it stands for.  An entry is refused,
with a reason, when its name leaves that folder (an absolute path, ``..``, a drive), when it is a
symbolic link, when it is encrypted, or when it is larger than a notebook may be; a zip with more than
:data:`MAX_ENTRIES` entries or more than :data:`MAX_BYTES` bytes of notebooks stops being read there.
Sizes are counted as the bytes come out, never taken from the zip's own headers.
"""

from __future__ import annotations

import stat
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from ..errors import ModbusError

NOTEBOOK_LIMIT = 5_000_000
"""The largest notebook file the grader reads, in bytes (from a zip here, from a folder in :mod:`.runner`)."""
MAX_ENTRIES = 10_000
"""The most entries a zip may list."""
MAX_BYTES = 1_000_000_000
"""The most bytes the notebooks of one zip (the zips inside it included) may unpack to."""
MAX_DEPTH = 1
"""How deep zips inside a zip are opened (1: a learner's zip inside a platform's download)."""
CHUNK = 1 << 16
SKIPPED_FOLDERS = {"__MACOSX"}
"""Folders a zip carries that are no one's work (macOS's resource forks)."""


class ArchiveError(ModbusError):
    """A zip that cannot be read: damaged, or not a zip at all."""


@dataclass
class Unpacked:
    """What unpacking a zip gave: its folder, one line saying what was read, and the entries refused
    (the entry's name, why)."""

    folder: Path
    note: str = ""
    refused: list[tuple[str, str]] = field(default_factory=list)
    size: int = 0  # bytes written


def _refusal(info: zipfile.ZipInfo, parts: tuple[str, ...]) -> str | None:
    """Why a zip entry is not written out, or None."""
    if not parts or info.filename.startswith(("/", "\\")) or ".." in parts or ":" in parts[0]:
        return "its name leads outside the zip's folder (not unpacked)"
    if stat.S_ISLNK(info.external_attr >> 16):
        return "a symbolic link inside the zip (not followed)"
    if info.flag_bits & 0x1:
        return "encrypted (cannot be read)"
    return None


def _copy(source, target: Path, limit: int) -> bool:
    """Copy at most ``limit`` bytes; False (and nothing left behind) when there are more."""
    written = 0
    with target.open("xb") as out:
        while chunk := source.read(CHUNK):
            written += len(chunk)
            if written > limit:
                break
            out.write(chunk)
    if written > limit:
        target.unlink()
        return False
    return True


def unpack(archive: Path, into: Path, depth: int = 0, budget: int = MAX_BYTES) -> Unpacked:
    """Write the notebooks of ``archive`` into a new folder ``into/NAME`` (NAME: the zip's name without
    ``.zip``); zips inside it become folders of their own name, up to :data:`MAX_DEPTH` down, all of them
    together within ``budget`` bytes."""
    stem = archive.name[:-len(".zip")] if archive.name.lower().endswith(".zip") else archive.name
    folder = into / stem
    folder.mkdir(parents=True, exist_ok=False)
    found = Unpacked(folder)
    notebooks = others = 0
    try:
        with zipfile.ZipFile(archive) as zipped:
            entries = zipped.infolist()
            if len(entries) > MAX_ENTRIES:
                raise ArchiveError(f"{archive.name} lists {len(entries)} entries; a class's download has at "
                                   f"most {MAX_ENTRIES} (not unpacked: unzip it yourself if it is one)")
            for info in entries:
                name = info.filename.replace("\\", "/")
                parts = tuple(p for p in PurePosixPath(name).parts if p not in ("", "."))
                is_zip = name.lower().endswith(".zip")
                wanted = name.lower().endswith(".ipynb") or (is_zip and depth < MAX_DEPTH)
                reason = _refusal(info, parts) if wanted and not info.is_dir() else None
                if reason is None and (info.is_dir() or any(p.startswith(".") or p in SKIPPED_FOLDERS
                                                            for p in parts)):
                    continue
                if not wanted:
                    others += 1
                    continue
                limit = budget if is_zip else min(budget, NOTEBOOK_LIMIT)
                if reason is None and info.file_size > limit:
                    reason = f"{info.file_size / 1e6:.1f} MB, more than the grader unpacks (not unpacked)"
                target = folder.joinpath(*parts)
                if reason is None and target.exists():
                    reason = "a second entry of the same name (not unpacked)"
                if reason is None:
                    target.parent.mkdir(parents=True, exist_ok=True)
                    with zipped.open(info) as source:
                        if not _copy(source, target, limit):
                            reason = "larger than its header says, and than the grader unpacks (not unpacked)"
                if reason:
                    found.refused.append((name, reason))
                    continue
                if not is_zip:
                    budget -= target.stat().st_size
                    found.size += target.stat().st_size
                else:
                    try:
                        inner = unpack(target, target.parent, depth + 1, budget)
                    except (ArchiveError, FileExistsError) as exc:
                        found.refused.append((name, f"a zip inside the zip that cannot be unpacked ({exc})"))
                        continue
                    finally:
                        target.unlink()
                    found.refused += [(f"{name}/{entry}", why) for entry, why in inner.refused]
                    notebooks += sum(1 for _ in inner.folder.rglob("*.ipynb"))
                    budget -= inner.size
                    found.size += inner.size
                    continue
                notebooks += 1
    except (zipfile.BadZipFile, zipfile.LargeZipFile, NotImplementedError, EOFError, OSError,
            zlib.error) as exc:
        raise ArchiveError(f"{archive.name} cannot be read as a zip ({type(exc).__name__}: {exc}); download "
                           f"it again from the platform") from exc
    skipped = f", {others} other file(s) left in it" if others else ""
    refused = f", {len(found.refused)} entry(ies) refused" if found.refused else ""
    found.note = f"{archive.name}: unpacked, {notebooks} notebook(s){skipped}{refused}"
    return found
