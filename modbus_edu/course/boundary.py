"""What a graded learner may reach, as data: the one list the seal is built from and a test reads back.

A learner's kernel (and each clean room that judges one of its build exercises) runs in a root that
bubblewrap builds from nothing (:mod:`.sandbox`).  :data:`BOUNDARY` says everything that root holds: each
row a place as the learner sees it, what the learner may do there (``read``, ``write``, ``connect``) and
for whom it is there (``kernel``: the learner's kernels, ``room``: the clean rooms, ``both``).  Anything
not in the list is absent: no ``/home``, ``/root``, ``/run``, ``/srv``, ``/var``, no host ``/etc``, no
other checkout, no host socket, no network but a loopback of its own.  :func:`resolve` turns the rows
into this machine's places (where Python, the kernel's environment and the library lie) and
:func:`bwrap_arguments` into bubblewrap's command line; :func:`markdown` prints the list for TEACHING.md.

This module imports only the standard library: the sandbox's launcher imports it before it starts a
kernel.
"""

from __future__ import annotations

import glob
import os
import sys
from dataclasses import dataclass

DISK_MB = 256
"""MB a learner may write into its room (``/tmp``), and again into ``/dev/shm``."""


@dataclass(frozen=True)
class Place:
    """One row of the boundary: ``path`` as the learner sees it (``{python}`` and the like stand for
    places of this machine, :data:`SOURCES`), what it ``may`` do there, ``who`` sees it, and ``what`` it
    is (said in TEACHING.md)."""

    path: str
    may: str  # "read", "write" (read, write and execute), "connect", "none" (there, but empty)
    who: str  # "kernel", "room" or "both"
    what: str


BOUNDARY: tuple[Place, ...] = (
    Place("/usr", "read", "both", "the system's programs and shared libraries (Python's, the loader)"),
    Place("/bin", "read", "both", "a link into /usr, where the system has one (so /lib, /lib64, /sbin)"),
    Place("/lib", "read", "both", "a link into /usr (or the folder, read-only)"),
    Place("/lib64", "read", "both", "a link into /usr (or the folder, read-only)"),
    Place("/sbin", "read", "both", "a link into /usr (or the folder, read-only)"),
    Place("{python}", "read", "both", "the Python installation (its standard library)"),
    Place("{site}", "none", "room", "every site-packages and dist-packages folder of the system: empty"),
    Place("/opt/environment", "read", "kernel", "the kernel's environment, {environment} (ipykernel, "
                                                "pymodbus, numpy...)"),
    Place("/opt/modbus_edu/modbus_edu", "read", "kernel", "the modbus_edu package, {library}"),
    Place("/opt/modbus_edu", "read", "room",
          "the stripped copy of modbus_edu for the exercise judged, {copy}"),
    Place("/etc/passwd", "read", "both", "written for the sandbox: the learner and nobody"),
    Place("/etc/group", "read", "both", "written for the sandbox: the learner's group"),
    Place("/etc/hosts", "read", "both", "written for the sandbox: localhost is 127.0.0.1"),
    Place("/proc", "read", "both", "a fresh /proc: the learner's own processes only"),
    Place("/dev", "read", "both", "null, zero, full, random, urandom, tty, ptmx and /dev/pts (where no file "
                                  "can be made)"),
    Place("/dev/shm", "write", "both", f"a fresh tmpfs of {DISK_MB} MB"),
    Place("/tmp", "write", "both", f"the learner's room: a fresh tmpfs of {DISK_MB} MB for each kernel and "
                                   "each clean room (the kernel's own notebook in /tmp/work)"),
    Place("/tmp/run", "write", "kernel",
          "the kernel's own Unix sockets, the only ones the grader reaches (the kernel binds them, so it may "
          "write here; the grader reaches them by descriptor only, never by a path the kernel could change)"),
    Place("/kernel.json", "read", "kernel", "the kernel's connection file, written for the sandbox"),
    Place("lo", "connect", "both", "the network: a loopback of its own, up; no other interface"),
)
"""Everything a learner's sandbox holds (see :class:`Place`); the sandbox is built from this list only."""

SOURCES = {"{python}": "the Python installation (sys.base_prefix)",
           "{environment}": "the virtual environment (sys.prefix), when there is one",
           "{library}": "the modbus_edu package folder", "{copy}": "the clean room's stripped copy",
           "{site}": "site-packages and dist-packages below /usr and the Python installation"}
"""What each placeholder of :data:`BOUNDARY` stands for."""

LINKS = ("/bin", "/lib", "/lib64", "/sbin")
HOST = {"{python}": "{python}", "/opt/environment": "{environment}",
        "/opt/modbus_edu/modbus_edu": "{library}", "/opt/modbus_edu": "{copy}"}
"""The rows bound from a place of this machine, and which (:data:`SOURCES`); Python keeps its own path
(a virtual environment names it), the others are seen at a path that says nothing of the grader's."""


def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip("/") + "/")


def python_home() -> str:
    """The Python installation (its prefix), real path."""
    return os.path.realpath(sys.base_prefix)


def base_python() -> str:
    """The installation's own interpreter (not the virtual environment's), for a clean room: it finds
    its standard library from where it lies, and no environment's site-packages."""
    version = f"python{sys.version_info[0]}.{sys.version_info[1]}"
    for candidate in (os.path.join(sys.base_prefix, "bin", version), os.path.join(sys.base_prefix, "bin",
                                                                                   "python3")):
        if os.path.exists(candidate):
            return os.path.realpath(candidate)
    return os.path.realpath(sys.executable)


def site_folders() -> list[str]:
    """Every site-packages and dist-packages folder below /usr and the Python installation."""
    found = set()
    for top in ("/usr", "/usr/local", python_home()):
        for pattern in ("lib/python3*/site-packages", "lib/python3*/dist-packages",
                        "lib/python3/dist-packages", "lib64/python3*/site-packages"):
            found.update(os.path.realpath(path) for path in glob.glob(os.path.join(top, pattern))
                         if os.path.isdir(path))
    return sorted(found)


@dataclass(frozen=True)
class Resolved:
    """A row of the boundary on this machine: ``inside`` the sandbox, from ``source`` on the host (a
    folder or file bound read-only; ``""`` when the sandbox makes it), as ``kind`` says."""

    inside: str
    kind: str  # "bind", "link", "empty", "data", "proc", "dev", "tmpfs", "sockets", "loopback"
    source: str = ""
    row: Place | None = None


def resolve(mode: str, library: str, copy: str = "", sockets: str = "") -> list[Resolved]:
    """The boundary's rows for ``mode`` (``kernel`` or ``room``) on this machine, outer places first:
    ``library`` is the modbus_edu package folder (kernels), ``copy`` the stripped copy's folder (clean
    rooms), ``sockets`` the host folder that becomes ``/tmp/run`` (kernels)."""
    places: list[Resolved] = []
    bound: list[str] = []
    who = {"kernel": ("kernel", "both"), "room": ("room", "both")}[mode]
    for row in BOUNDARY:
        if row.who not in who:
            continue
        if row.path in LINKS:
            if os.path.islink(row.path):
                places.append(Resolved(row.path, "link", os.readlink(row.path), row))
            elif os.path.isdir(row.path):
                places.append(Resolved(row.path, "bind", row.path, row))
            continue
        if row.path in HOST:
            source = {"{python}": python_home(), "{environment}": os.path.realpath(sys.prefix),
                      "{library}": os.path.realpath(library), "{copy}": os.path.realpath(copy) if copy else ""
                      }[HOST[row.path]]
            if source and not any(_within(source, done) for done in ["/usr", *bound]):
                bound.append(source)
                places.append(Resolved(source if row.path == "{python}" else row.path, "bind", source, row))
            continue
        if row.path == "{site}":
            places.extend(Resolved(folder, "empty", "", row) for folder in site_folders())
            continue
        kind = {"/usr": "bind", "/proc": "proc", "/dev": "dev", "/dev/shm": "tmpfs", "/tmp": "tmpfs",
                "/tmp/run": "sockets", "lo": "loopback"}.get(row.path, "data")
        source = {"/usr": "/usr", "/tmp/run": sockets}.get(row.path, "")
        places.append(Resolved(row.path, kind, source, row))
    return sorted(places, key=lambda place: (place.kind == "loopback", place.inside.count("/"), place.inside))


def inside_path(path: str, places: list[Resolved]) -> str:
    """Where the host's ``path`` is seen inside the sandbox of ``places`` (unchanged when not bound): by
    the path as given first (a virtual environment's interpreter is a link into the installation, and
    must be called by the environment's path), then by its real path."""
    binds = sorted((place for place in places if place.kind == "bind" and place.source),
                   key=lambda place: -len(place.source))
    for candidate in (path, os.path.realpath(path)):
        for place in binds:
            if _within(candidate, place.source):
                return place.inside + candidate[len(place.source):]
    return path


def etc_files(uid: int, gid: int) -> dict[str, str]:
    """The few /etc files the sandbox holds, written for it."""
    return {"/etc/passwd": f"learner:x:{uid}:{gid}:learner:/tmp/home:/bin/false\n"
                           "nobody:x:65534:65534:nobody:/nonexistent:/bin/false\n",
            "/etc/group": f"learner:x:{gid}:\nnogroup:x:65534:\n",
            "/etc/hosts": "127.0.0.1 localhost\n::1 localhost ip6-localhost\n"}


def bwrap_arguments(places: list[Resolved], data: dict[str, int], *, disk_mb: int = DISK_MB,
                    uid: int | None = None, chdir: str = "/tmp") -> list[str]:
    """bubblewrap's arguments for ``places`` (:func:`resolve`): ``data`` maps each place the sandbox
    writes (``/etc/passwd``, the kernel's connection file, the notebook's copy) to the descriptor it is
    read from.  New user, PID, network (its loopback brought up by bubblewrap), IPC, UTS and cgroup
    namespaces; no user namespace within; every capability dropped; the sandbox dies with its parent and
    has a session of its own (no terminal to push keys into)."""
    size = str(disk_mb * 1024 * 1024)
    args = ["--unshare-all", "--unshare-user", "--disable-userns", "--die-with-parent", "--new-session",
            "--cap-drop", "ALL", "--hostname", "learner"]
    if uid is not None:
        args += ["--uid", str(uid), "--gid", str(uid)]
    for place in places:
        if place.kind == "bind":
            args += ["--ro-bind", place.source, place.inside]
        elif place.kind == "link":
            args += ["--symlink", place.source, place.inside]
        elif place.kind == "empty":
            args += ["--perms", "0555", "--size", "4096", "--tmpfs", place.inside,
                     "--remount-ro", place.inside]
        elif place.kind == "proc":
            args += ["--proc", "/proc"]
        elif place.kind == "dev":
            args += ["--dev", "/dev", "--remount-ro", "/dev"]
        elif place.kind == "tmpfs":
            args += ["--perms", "1777", "--size", size, "--tmpfs", place.inside]
            if place.inside == "/tmp":
                args += ["--dir", "/tmp/work", "--dir", "/tmp/home"]
        elif place.kind == "sockets" and place.source:
            args += ["--bind", place.source, place.inside]
        elif place.kind == "data" and place.inside in data:
            args += ["--ro-bind-data", str(data[place.inside]), place.inside]
    for inside, handle in data.items():  # the room's own files (the notebook's copy): the learner's to change
        if not any(place.inside == inside for place in places):
            args += ["--file", str(handle), inside]
    return [*args, "--remount-ro", "/", "--chdir", chdir]


def markdown() -> str:
    """The boundary as TEACHING.md prints it (a table, then what each placeholder stands for)."""
    lines = ["| place (as the learner sees it) | may | for | what |", "|---|---|---|---|"]
    lines += [f"| `{row.path}` | {row.may} | {row.who} | {row.what} |" for row in BOUNDARY]
    lines += ["", *(f"- `{name}`: {meaning}" for name, meaning in SOURCES.items())]
    return "\n".join(lines) + "\n"
