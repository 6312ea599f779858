"""Opening a class's zip download (Moodle's "Download all submissions", Canvas's "Download submissions",
a learner's own zip of notebooks) without trusting it.

The zip's central directory is read here, not by :mod:`zipfile`, so that nothing in it is believed
before it is checked:

- **The directory itself.** At most :data:`MAX_ENTRIES` entries.  Every entry's local header is where
  the directory says, carries the same name, and its bytes overlap no other entry's nor the directory:
  a directory that lists one deflated entry many times (a zip bomb that writes gigabytes from a
  megabyte) is refused whole, before a byte is inflated.  Python's own :mod:`zipfile` refuses
  overlapping entries only from 3.12.
- **Each entry, on its own.** An entry is refused, with a reason, when its name leads out of the zip's
  folder (absolute, ``..``, a drive), is not valid UTF-8 where the zip says it is, holds a part longer
  than a file name may be (255 bytes) or a NUL; when it is a symbolic link, encrypted, compressed in a
  way the grader does not read, damaged (its CRC), or larger than a notebook may be.  A refused entry
  stops nothing else: the next one is read.
- **Bytes inflated are counted as they come out**, never taken from the headers: each entry in
  :data:`CHUNK` pieces, against one :class:`Budget` per learner (:data:`LEARNER_BYTES`) and one for the
  class (:data:`CLASS_BYTES`), zips inside a zip (one level down: a learner who zipped their notebooks)
  counted twice, once as the zip and once as what it holds.  Past a budget, that learner's (or the
  class's) next entries are refused, not inflated.

Only notebooks and zips inside the zip are written out, into a folder the grader owns, under the zip's
own name, each with the time the zip gives it (so that "the newest copy" is the newest the zip says, not
the last one unpacked).
"""

from __future__ import annotations

import bz2
import os
import stat
import struct
import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from ..errors import ModbusError

NOTEBOOK_LIMIT = 5_000_000
"""The largest notebook file the grader reads, in bytes (from a zip here, from a folder in :mod:`.runner`)."""
MAX_ENTRIES = 10_000
"""The most entries a zip may list."""
LEARNER_BYTES = 200_000_000
"""The most bytes one learner's entries may inflate to (their zips and what the zips hold, all counted)."""
CLASS_BYTES = 2_000_000_000
"""The most bytes all the zips of one grading run may inflate to."""
MAX_DEPTH = 1
"""How deep zips inside a zip are opened (1: a learner's zip inside a platform's download)."""
NAME_MAX = 255
"""The longest file or folder name, in bytes, that the file systems the grader runs on take."""
CHUNK = 1 << 16
OVER = "over"
SKIPPED_FOLDERS = {"__MACOSX"}
"""Folders a zip carries that are no one's work (macOS's resource forks)."""
STORED, DEFLATED, BZIP2 = 0, 8, 12
METHODS = {STORED: "stored", DEFLATED: "deflated", BZIP2: "bzip2"}
UTF8_NAME, ENCRYPTED = 0x800, 0x1
END = struct.Struct("<4s4H2LH")
END64 = struct.Struct("<4sQ2H2L4Q")
LOCATOR64 = struct.Struct("<4sLQL")
CENTRAL = struct.Struct("<4s4B4HL2L5H2L")
LOCAL = struct.Struct("<4s2B4HL2L2H")


class ArchiveError(ModbusError):
    """A zip that cannot be read: damaged, not a zip at all, or a directory that lies (entries that
    overlap, a header that is not where the directory says)."""


@dataclass
class Budget:
    """Bytes inflated so far, per learner (any key: the learner's name as the zip's names give it) and
    for the class, against :data:`LEARNER_BYTES` and :data:`CLASS_BYTES`."""

    learner: int = field(default_factory=lambda: LEARNER_BYTES)
    whole: int = field(default_factory=lambda: CLASS_BYTES)
    spent: dict[str, int] = field(default_factory=dict)
    total: int = 0

    def left(self, owner: str) -> int:
        return max(0, min(self.learner - self.spent.get(owner, 0), self.whole - self.total))

    def take(self, owner: str, size: int) -> None:
        self.spent[owner] = self.spent.get(owner, 0) + size
        self.total += size

    def spent_reason(self, owner: str) -> str:
        if self.whole - self.total <= self.learner - self.spent.get(owner, 0):
            return (f"the class's zips have inflated to {self.whole / 1e6:g} MB, all the grader unpacks for "
                    "one class (not unpacked)")
        return (f"this learner's zips have inflated to {self.learner / 1e6:g} MB, all the grader unpacks for "
                "one learner (not unpacked)")


@dataclass
class Unpacked:
    """What unpacking a zip gave: its folder, one line saying what was read, and the entries refused
    (the entry's name, why)."""

    folder: Path
    note: str = ""
    refused: list[tuple[str, str]] = field(default_factory=list)
    size: int = 0  # bytes written


@dataclass(frozen=True)
class Entry:
    """One entry of a zip's central directory, as the directory states it (nothing here is trusted
    until checked): its name (decoded; ``bad_name`` when the bytes are not what the zip says they are),
    where its data lies, and what it claims about them."""

    name: str
    bad_name: bool
    flags: int
    method: int
    crc: int
    compressed: int
    size: int
    start: int  # the local header
    data: int  # the first byte of the data
    end: int  # after the data
    external: int
    date_time: tuple[int, int]

    @property
    def is_dir(self) -> bool:
        return self.name.endswith("/")


def _zip64(extra: bytes, size: int, compressed: int, offset: int) -> tuple[int, int, int]:
    """The sizes and offset a zip64 extra field gives for those the directory marks 0xFFFFFFFF."""
    at = 0
    while at + 4 <= len(extra):
        kind, length = struct.unpack_from("<2H", extra, at)
        body = extra[at + 4:at + 4 + length]
        if kind == 1:
            values = [v[0] for v in struct.iter_unpack("<Q", body[:len(body) // 8 * 8])]
            fields = [size, compressed, offset]
            for index, value in enumerate(fields):
                if value == 0xFFFFFFFF and values:
                    fields[index] = values.pop(0)
            return fields[0], fields[1], fields[2]
        at += 4 + length
    return size, compressed, offset


def directory(stream, length: int) -> list[Entry]:
    """The entries of the zip open as ``stream`` (``length`` bytes), each checked against its local
    header; raises :class:`ArchiveError` for a zip that is damaged or whose entries overlap."""
    tail_at = max(0, length - END.size - 0xFFFF)
    stream.seek(tail_at)
    tail = stream.read(length - tail_at)
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or at + END.size > len(tail):
        raise ArchiveError("no end of central directory (not a zip, or cut short)")
    _, _, _, _, count, cd_size, cd_offset, _ = END.unpack_from(tail, at)
    end_at = tail_at + at
    cd_end = end_at
    if at >= LOCATOR64.size and tail[at - LOCATOR64.size:at - LOCATOR64.size + 4] == b"PK\x06\x07":
        stream.seek(end_at - LOCATOR64.size - END64.size)
        record = stream.read(END64.size)
        if len(record) != END64.size or record[:4] != b"PK\x06\x06":
            raise ArchiveError("a zip64 locator without its record")
        count, cd_size, cd_offset = END64.unpack(record)[7:10]
        cd_end = end_at - LOCATOR64.size - END64.size
    if count > MAX_ENTRIES:
        raise ArchiveError(f"it lists {count} entries; a class's download has at most {MAX_ENTRIES} (not "
                           "unpacked: unzip it yourself if it is one)")
    shift = cd_end - cd_size - cd_offset  # bytes before the zip (a self-extracting one)
    if shift < 0:
        raise ArchiveError("its central directory lies outside the file")
    stream.seek(cd_end - cd_size)
    table = stream.read(cd_size)
    entries: list[Entry] = []
    starts: dict[int, str] = {}  # a local header's offset -> the entry there (a repeat is refused at once)
    pos = 0
    for _ in range(count):
        if pos + CENTRAL.size > len(table) or table[pos:pos + 4] != b"PK\x01\x02":
            raise ArchiveError(f"its central directory is damaged at byte {cd_end - cd_size + pos}")
        fields = CENTRAL.unpack_from(table, pos)
        flags, method, dos_time, dos_date, crc, compressed, size = fields[5:12]
        name_len, extra_len, comment_len = fields[12:15]
        external, offset = fields[17:19]
        raw = table[pos + CENTRAL.size:pos + CENTRAL.size + name_len]
        extra = table[pos + CENTRAL.size + name_len:pos + CENTRAL.size + name_len + extra_len]
        pos += CENTRAL.size + name_len + extra_len + comment_len
        size, compressed, offset = _zip64(extra, size, compressed, offset)
        bad = False
        if flags & UTF8_NAME:
            try:
                name = raw.decode("utf-8")
            except UnicodeDecodeError:
                name, bad = raw.decode("utf-8", "replace"), True
        else:
            name = raw.decode("cp437")
        start = offset + shift
        if start in starts:
            raise ArchiveError(f"entries {starts[start]!r} and {name!r} are the same bytes as one another (a "
                               "zip bomb's trick, never a platform's download: not unpacked)")
        starts[start] = name
        stream.seek(start)
        local = stream.read(LOCAL.size)
        if len(local) != LOCAL.size or local[:4] != b"PK\x03\x04":
            raise ArchiveError(f"entry {name!r}: no local header at byte {start} where the directory says")
        local_name_len, local_extra_len = LOCAL.unpack(local)[10:12]
        if stream.read(local_name_len) != raw:
            raise ArchiveError(f"entry {name!r}: its local header names another file")
        data = start + LOCAL.size + local_name_len + local_extra_len
        entries.append(Entry(name, bad, flags, method, crc, compressed, size, start, data, data + compressed,
                             external >> 16, (dos_date, dos_time)))
    spans = sorted((entry.start, entry.end, entry.name) for entry in entries)
    for (start, end, name), (after, _, other) in zip(spans, spans[1:]):
        if after < end:
            same = "the same bytes as" if after == start else "bytes that overlap"
            raise ArchiveError(f"entries {name!r} and {other!r} are {same} one another (a zip bomb's "
                               "trick, never a platform's download: not unpacked)")
    if spans and max(end for _, end, _ in spans) > cd_end - cd_size:
        raise ArchiveError("an entry's data runs into the central directory (not unpacked)")
    return entries


def _name_refusal(entry: Entry, parts: tuple[str, ...]) -> str | None:
    """Why an entry's name cannot be written out, or None."""
    if entry.bad_name:
        return "its name is not valid UTF-8, though the zip says it is (not unpacked: rename it)"
    if not parts or entry.name.startswith(("/", "\\")) or ".." in parts or ":" in parts[0]:
        return "its name leads outside the zip's folder (not unpacked)"
    if "\x00" in entry.name:
        return "its name holds a NUL character (not unpacked)"
    longest = max(len(part.encode("utf-8")) for part in parts)
    if longest > NAME_MAX:
        return (f"a name of {longest} bytes, longer than a file name may be ({NAME_MAX}; not unpacked: "
                "rename it)")
    return None


def _refusal(entry: Entry, limit: int) -> str | None:
    """Why an entry's data are not read, or None."""
    if stat.S_ISLNK(entry.external):
        return "a symbolic link inside the zip (not followed)"
    if entry.flags & ENCRYPTED:
        return "encrypted (cannot be read)"
    if entry.method not in METHODS:
        return (f"compressed with method {entry.method}, which the grader does not read (not unpacked: zip "
                "it again with the usual compression)")
    if entry.size > limit:
        return f"{entry.size / 1e6:.1f} MB, more than the grader unpacks (not unpacked)"
    return None


def _inflate(stream, entry: Entry, out, limit: int) -> tuple[int, str | None]:
    """Write ``entry``'s data to ``out``, at most ``limit`` bytes, counted as they come out in pieces of
    at most :data:`CHUNK`: (bytes inflated, :data:`OVER` past the limit, a reason when damaged, or None)."""
    engine = zlib.decompressobj(-15) if entry.method == DEFLATED else \
        bz2.BZ2Decompressor() if entry.method == BZIP2 else None
    stream.seek(entry.data)
    left, written, crc, pending = entry.compressed, 0, 0, b""
    try:
        while True:
            if not pending and left:
                pending = stream.read(min(CHUNK, left))
                left = left - len(pending) if pending else 0
            if engine is None:
                piece, pending = pending, b""
            elif engine.eof:
                break
            elif isinstance(engine, bz2.BZ2Decompressor):
                piece = engine.decompress(pending, CHUNK)
                pending = b""
                if not piece and engine.needs_input and not left:
                    break
            else:
                piece = engine.decompress(pending, CHUNK)
                pending = engine.unconsumed_tail
            if not piece and not pending and not left:
                break
            written += len(piece)
            if written > limit:
                return written, OVER
            crc = zlib.crc32(piece, crc)
            out.write(piece)
    except (zlib.error, OSError, EOFError, ValueError) as exc:
        return written, f"damaged ({type(exc).__name__}: not unpacked)"
    if written != entry.size or crc != entry.crc:
        return written, "damaged: its bytes are not what its header says (not unpacked)"
    return written, None


def _timestamp(entry: Entry) -> float | None:
    """The entry's time as the zip gives it (local time, to two seconds), or None when it holds none."""
    date, clock = entry.date_time
    try:
        return time.mktime(((date >> 9) + 1980, (date >> 5) & 0xF, date & 0x1F, clock >> 11,
                            (clock >> 5) & 0x3F, (clock & 0x1F) * 2, 0, 0, -1))
    except (OverflowError, ValueError):
        return None


def _dated(target: Path, entry: Entry) -> None:
    when = _timestamp(entry)
    if when is not None and entry.date_time[0] >> 5 & 0xF in range(1, 13):
        os.utime(target, (when, when))


def _stem(archive: Path) -> str:
    return archive.name[:-len(".zip")] if archive.name.lower().endswith(".zip") else archive.name


def names(archive: Path) -> list[str]:
    """The names of the notebooks and zips ``archive`` holds (hidden ones and macOS's aside), read from
    its checked directory; raises :class:`ArchiveError` for a zip that cannot be read."""
    try:
        with archive.open("rb") as stream:
            entries = directory(stream, archive.stat().st_size)
    except (OSError, struct.error) as exc:
        raise ArchiveError(f"{archive.name} cannot be read as a zip ({type(exc).__name__}: {exc})") from exc
    except ArchiveError as exc:
        raise ArchiveError(f"{archive.name} cannot be read as a zip: {exc}") from exc
    found = []
    for entry in entries:
        parts = tuple(p for p in PurePosixPath(entry.name.replace("\\", "/")).parts if p not in ("", "."))
        if parts and not entry.is_dir and not any(p.startswith(".") or p in SKIPPED_FOLDERS for p in parts) \
                and parts[-1].lower().endswith((".ipynb", ".zip")):
            found.append("/".join(parts))
    return found


def unpack(archive: Path, into: Path, depth: int = 0, budget: Budget | None = None,
           owner: Callable[[str], str] | str = "") -> Unpacked:
    """Write the notebooks of ``archive`` into a new folder ``into/NAME`` (NAME: the zip's name without
    ``.zip``); zips inside it become folders of their own name, up to :data:`MAX_DEPTH` down.  Every
    byte inflated is counted against ``budget``, for the learner ``owner`` names (a name, or what gives
    the learner of an entry's name: a platform's download holds many)."""
    budget = budget if budget is not None else Budget()
    folder = into / _stem(archive)
    folder.mkdir(parents=True, exist_ok=False)
    found = Unpacked(folder)
    notebooks = others = 0
    try:
        with archive.open("rb") as stream:
            for entry in directory(stream, archive.stat().st_size):
                name = entry.name.replace("\\", "/")
                parts = tuple(p for p in PurePosixPath(name).parts if p not in ("", "."))
                is_zip = name.lower().endswith(".zip")
                wanted = name.lower().endswith(".ipynb") or (is_zip and depth < MAX_DEPTH)
                reason = _name_refusal(entry, parts) if wanted and not entry.is_dir else None
                if reason is None and (entry.is_dir or any(p.startswith(".") or p in SKIPPED_FOLDERS
                                                           for p in parts)):
                    continue
                if not wanted:
                    others += 1
                    continue
                whose = owner if isinstance(owner, str) else owner(name) if reason is None else ""
                cap = LEARNER_BYTES if is_zip else NOTEBOOK_LIMIT
                reason = reason or _refusal(entry, cap)
                if reason is None and entry.size > budget.left(whose):
                    reason = budget.spent_reason(whose)
                target = folder.joinpath(*parts)
                if reason is None:
                    reason = _write(stream, entry, target, cap, budget, whose)
                if reason:
                    found.refused.append((name, reason))
                    continue
                if not is_zip:
                    found.size += target.stat().st_size
                    notebooks += 1
                    continue
                try:
                    inner = unpack(target, target.parent, depth + 1, budget, whose)
                except (ArchiveError, OSError) as exc:
                    found.refused.append((name, f"a zip inside the zip that cannot be unpacked ({exc})"))
                    continue
                finally:
                    target.unlink()
                found.refused += [(f"{name}/{entry}", why) for entry, why in inner.refused]
                notebooks += sum(1 for _ in inner.folder.rglob("*.ipynb"))
                found.size += inner.size
    except (OSError, struct.error) as exc:
        raise ArchiveError(f"{archive.name} cannot be read as a zip ({type(exc).__name__}: {exc}); download "
                           f"it again from the platform") from exc
    except ArchiveError as exc:
        raise ArchiveError(f"{archive.name} cannot be read as a zip: {exc}") from exc
    skipped = f", {others} other file(s) left in it" if others else ""
    refused = f", {len(found.refused)} entry(ies) refused" if found.refused else ""
    found.note = f"{archive.name}: unpacked, {notebooks} notebook(s){skipped}{refused}"
    return found


def _write(stream, entry: Entry, target: Path, cap: int, budget: Budget, owner: str) -> str | None:
    """Write one entry to ``target`` (a new file), at most ``cap`` bytes and what ``budget`` has left for
    ``owner``, counting every byte inflated; why not (nothing left behind), or None."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        out = target.open("xb")
    except FileExistsError:
        return "a second entry of the same name (not unpacked)"
    except OSError as exc:
        return f"cannot be written out ({exc.strerror or type(exc).__name__}; not unpacked)"
    left = budget.left(owner)
    with out:
        written, reason = _inflate(stream, entry, out, min(cap, left))
    budget.take(owner, written)
    if reason == OVER:
        reason = budget.spent_reason(owner) if left < cap else \
            "larger than its header says, and than the grader unpacks (not unpacked)"
    if reason:
        target.unlink()
        return reason
    _dated(target, entry)
    return None
