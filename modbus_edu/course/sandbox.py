"""Each learner sealed off: where a graded kernel runs, what it can reach, and how it ends.

:func:`detect` picks the strongest level this machine offers, said in one line:

* **sealed** (root, Linux namespaces and a writable cgroup): the seal is what each side can reach.  Each
  learner's processes run under a user id of their own (no passwd entry needed), in new PID, mount,
  network, IPC and UTS namespaces.  *Network*: only a loopback of their own (a notebook that serves on
  127.0.0.1 still works); the grader reaches a kernel over Unix sockets (ZeroMQ ``ipc://``) in the
  learner's room, which no other learner can see, so no classmate's kernel can be found or spoken to.
  *Files*: ``/tmp`` is the learner's room, a tmpfs of :data:`DISK_MB` MB mounted for this learner alone,
  holding a copy of only its notebooks; ``/var/tmp`` and ``/dev/shm`` are fresh tmpfs of the same budget;
  every other mount is read-only.  The class's folders, the output, the grader's scratch folder and any
  checkout around Python or the library (a clone with ``.git`` or ``pyproject.toml``) are covered by
  empty read-only mounts, and only what a kernel needs (Python's prefixes, the ``modbus_edu`` package
  folder) is bound back, read-only.  *Processes*: ``/proc`` shows only the learner's own, no setuid
  program raises its rights, and PID 1 (the launcher) carries no path of the grader's in its command
  line (its settings come from a file only root reads, then from its environment, which only root
  reads).  A cgroup (v2 when its memory and pids
  controllers are usable, else v1) limits memory and the number of processes of the learner as a whole.
  When the learner is done every process of the cgroup is killed and its room unmounted: nothing it wrote
  outlives its grade;
* **limited** (no root, or no namespaces): each kernel in a process group of its own, with
  ``RLIMIT_AS`` and ``RLIMIT_NPROC``; a process that leaves the group is still found by the marker in
  its environment and killed, unless it cleared its environment;
* **container** (``--container IMAGE``, docker or podman answering): each kernel in a container of the
  image (which must hold Python, ipykernel and modbus_edu), with no network but its loopback, the room as
  ``/tmp``, memory and pids limits, removed when it stops.

Whatever the level, every process carries ``MODBUS_EDU_GRADE_RUN=<token>`` in its environment (and, of
the grader's environment, only :data:`KEPT`); a kernel's stdout and stderr go to ``/dev/null`` once
ipykernel has caught them, so what it prints, with ``print`` or straight to fd 1, reaches the grader only
as counted messages; ``RLIMIT_AS`` bounds each process as well.  :meth:`Seal.command_argv` runs any
command the same way, its standard streams passed through.

Run as a script (``python sandbox.py SETTINGS kernel CPU CONNECTION_FILE`` or ``python sandbox.py
SETTINGS command CPU -- ARGV...``) this module is the launcher; it imports nothing but the standard
library, so that it starts fast.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import fcntl
import json
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

try:
    import resource
except ImportError:  # Windows: no limits (the sealed level needs Linux anyway)
    resource = None

MARKER = "MODBUS_EDU_GRADE_RUN"
"""The environment variable every process of a graded kernel carries (its value: the learner's token)."""
MAX_PROCESSES = 256
"""Tasks (processes and threads) one learner's kernels may have at once."""
DISK_MB = 256
"""MB a learner may write into its room (``/tmp``), and again into each of ``/var/tmp`` and ``/dev/shm``
(sealed level; tmpfs pages count in the learner's memory too)."""
FILES = 20_000
"""Files and folders a learner may create in each of those places."""
UID_BASE = 100_000
"""Learners' user ids start here (sealed level): one per learner, from ``UID_BASE + 1000 * (pid % 50000)``."""
CGROUP_V1 = Path("/sys/fs/cgroup")
CGROUP_V2 = (Path("/sys/fs/cgroup"), Path("/sys/fs/cgroup/unified"))
SCRIPT = Path(__file__).resolve()
LIBRARY = SCRIPT.parents[2]
"""The folder that holds the ``modbus_edu`` package (site-packages, or a clone for an editable install)."""
CHECKOUT_MARKS = (".git", ".hg", "pyproject.toml", "setup.py")
"""A folder holding one of these is a checkout: a sealed kernel never sees it, only what it needs inside."""
ROOM = "modbus-edu-room"
"""The source name of every learner's room (a tmpfs), by which a sealed namespace finds the others' rooms."""
SETTINGS = "MODBUS_EDU_SEAL"
"""The environment variable that hands the launcher's settings to PID 1 of the sealed namespaces."""


@dataclass
class Sandbox:
    """The level of isolation of one grading run (:func:`detect`)."""

    level: str  # "sealed", "limited" or "container"
    note: str  # the one line that says it
    cgroup: str = ""  # "v2:/sys/fs/cgroup/..." or "v1" (sealed level)
    engine: str = ""  # docker or podman (container level)
    image: str = ""


def _v2_root() -> Path | None:
    for root in CGROUP_V2:
        controllers = root / "cgroup.controllers"
        try:
            if {"memory", "pids"} <= set(controllers.read_text().split()) and os.access(root, os.W_OK):
                return root
        except OSError:
            continue
    return None


def _v1_usable() -> bool:
    return all(os.access(CGROUP_V1 / name, os.W_OK) and (CGROUP_V1 / name / "cgroup.procs").exists()
               for name in ("memory", "pids"))


NAMESPACES = ("--pid", "--mount", "--net", "--ipc", "--uts")
"""The namespaces a sealed learner gets of its own."""
FORCE = "MODBUS_EDU_GRADE_ISOLATION"
"""Set to ``limited`` to grade at the limited level even where the sealed one is possible."""


def detect(container: str | None = None) -> Sandbox:
    """The strongest isolation this machine offers (or the container engine, for ``--container IMAGE``;
    the limited level when :data:`FORCE` says so)."""
    if container:
        for engine in ("docker", "podman"):
            if shutil.which(engine) is None:
                continue
            try:
                answered = subprocess.run([engine, "info"], capture_output=True, timeout=20).returncode == 0
            except (OSError, subprocess.TimeoutExpired):
                answered = False
            if answered:
                return Sandbox("container", f"isolation: each kernel in a {engine} container of {container}",
                               engine=engine, image=container)
        raise OSError("--container: neither docker nor podman answers on this machine")
    why = "not root" if os.geteuid() != 0 else ""
    if os.environ.get(FORCE) == "limited":
        why = f"{FORCE}=limited"
    if not why:
        try:
            probe = subprocess.run(["unshare", *NAMESPACES, "--fork", "--kill-child", "--mount-proc", "true"],
                                   capture_output=True, timeout=20)
            why = "" if probe.returncode == 0 else "no PID, mount, network, IPC and UTS namespaces"
        except (OSError, subprocess.TimeoutExpired):
            why = "no unshare command"
    v2 = _v2_root()
    cgroup = f"v2:{v2}" if v2 else "v1" if _v1_usable() else ""
    if not why and not cgroup:
        why = "no writable cgroup"
    if why:
        return Sandbox("limited", f"isolation: limited ({why}): each kernel in a process group with "
                                  "per-process memory and process limits; a learner's processes are found "
                                  "by an environment marker")
    return Sandbox("sealed", f"isolation: sealed: each learner under a user id of its own, in PID, mount, "
                             f"network, IPC and UTS namespaces (no network but its loopback), a private "
                             f"room of {DISK_MB} MB with a copy of its notebooks, everything else "
                             f"read-only, memory and processes limited per learner by a cgroup "
                             f"({cgroup.split(':')[0]})", cgroup=cgroup)


@dataclass
class Seal:
    """One learner's sealed room: a private folder, a user id, a cgroup; :meth:`close` ends them all.

    :meth:`kernel_argv` starts a kernel in it, :meth:`command_argv` any command (both through the same
    launcher, so with the same user, namespaces, cgroup, limits and room)."""

    sandbox: Sandbox
    index: int
    folder: Path  # the private folder, the learner's room (it is /tmp inside a sealed kernel)
    notebooks: list[Path]
    hide: list[Path]
    memory_mb: int
    token: str
    uid: int = 0
    cgroups: list[Path] = field(default_factory=list)
    mounted: bool = False  # the room is a tmpfs of its own (sealed and container levels)
    reads: list[str] = field(default_factory=list)  # the grader's folders its commands read

    @classmethod
    def open(cls, sandbox: Sandbox, index: int, scratch: Path, notebooks: list[Path], hide: list[Path],
             memory_mb: int, token: str, reads: Iterable[Path] = ()) -> Seal:
        """The learner's seal: its room holding a copy of ``notebooks``; ``hide`` covered; ``reads``,
        folders of the grader's its commands read (the clean rooms' copies of the library), bound back
        read-only at their own paths."""
        folder = scratch / f"learner-{index}"
        seal = cls(sandbox, index, folder, [], hide, memory_mb, token)
        seal.reads = [os.path.realpath(path) for path in reads]
        try:
            seal._furnish(notebooks)
        except BaseException:
            seal.close()
            raise
        return seal

    def _furnish(self, notebooks: list[Path]) -> None:
        """The room (a tmpfs of its own where root), a copy of the notebooks, the cgroup, the settings."""
        folder = self.folder
        folder.mkdir(parents=True, exist_ok=True)
        if self.sandbox.level in ("sealed", "container"):
            self.uid = UID_BASE + 1000 * (os.getpid() % 50_000) + self.index
            _mount(ROOM, str(folder), "tmpfs", MS["nosuid"] | MS["nodev"],
                   f"size={DISK_MB}m,nr_inodes={FILES},mode=0700,uid={self.uid},gid={self.uid}")
            self.mounted = True
        for name in ("work", "home", "run"):
            (folder / name).mkdir(exist_ok=True)
        for position, source in enumerate(notebooks):
            copy = folder / "work" / source.name
            if copy.exists():  # two notebooks of one name (from two folders): keep both
                copy = folder / "work" / f"{source.stem}-{position}{source.suffix}"
            shutil.copyfile(source, copy)
            self.notebooks.append(copy)
        if self.uid:
            for path in [folder, *folder.rglob("*")]:
                os.chown(path, self.uid, self.uid)
        if self.sandbox.level == "sealed":
            self._make_cgroups()
        handle = os.open(self.settings, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)  # only root reads it
        with os.fdopen(handle, "w") as stream:
            json.dump(self.config(), stream)

    @property
    def settings(self) -> Path:
        """The launcher's settings: beside the room, never in it (no learner sees the grader's paths)."""
        return self.folder.parent / f"{self.folder.name}.json"

    def _make_cgroups(self) -> None:
        name = f"modbus-edu-grade-{os.getpid()}-{self.index}"
        limit = str(self.memory_mb * 1024 * 1024)
        if self.sandbox.cgroup.startswith("v2:"):
            root = Path(self.sandbox.cgroup[3:])
            (root / "cgroup.subtree_control").write_text("+memory +pids")
            group = root / name
            group.mkdir(exist_ok=True)
            (group / "memory.max").write_text(limit)
            if (group / "memory.swap.max").exists():
                (group / "memory.swap.max").write_text("0")
            (group / "pids.max").write_text(str(MAX_PROCESSES))
            self.cgroups = [group]
            return
        memory, pids = CGROUP_V1 / "memory" / name, CGROUP_V1 / "pids" / name
        memory.mkdir(exist_ok=True)
        pids.mkdir(exist_ok=True)
        (memory / "memory.limit_in_bytes").write_text(limit)
        if (memory / "memory.memsw.limit_in_bytes").exists():
            (memory / "memory.memsw.limit_in_bytes").write_text(limit)
        (pids / "pids.max").write_text(str(MAX_PROCESSES))
        self.cgroups = [memory, pids]

    def config(self) -> dict:
        """What the launcher needs (written to :attr:`settings`, a file only root reads): the user, the
        room, what to cover and what to bind back, the limits, the cgroups, the marker."""
        needed = sorted({*needed_paths(), *self.reads})
        return {"level": self.sandbox.level, "engine": self.sandbox.engine, "image": self.sandbox.image,
                "uid": self.uid, "folder": str(self.folder), "needed": needed,
                "package": os.path.realpath(LIBRARY / "modbus_edu"),
                "covers": covered_paths(self.hide, needed, self.folder.parent),
                "memory": self.memory_mb * 1024 * 1024, "token": self.token,
                "procs": [str(group / "cgroup.procs") for group in self.cgroups],
                "python": sys.executable, "path": os.environ.get("PYTHONPATH", "")}

    def _launcher(self, mode: str, timeout: float, rest: list[str]) -> list[str]:
        return [sys.executable, "-s", str(SCRIPT), str(self.settings), mode, str(int(timeout) + 10), *rest]

    def kernel_argv(self, timeout: float) -> list[str]:
        """The kernel's command line (``{connection_file}`` where jupyter puts the connection file, which
        must lie in the room: the launcher hands the kernel a copy that names the room as ``/tmp``)."""
        return self._launcher("kernel", timeout, ["{connection_file}"])

    def command_argv(self, argv: list[str], timeout: float = 300) -> list[str]:
        """A command line that runs ``argv`` inside this learner's seal: the same user, namespaces (no
        network but a loopback of its own), cgroup, limits and room (``/tmp``, working folder
        ``/tmp/work``) as its kernels, with a CPU-time limit of ``timeout`` + 10 s.

        ``argv[0]`` is a program (such as ``sys.executable``; looked up on ``PATH`` unless absolute) and the
        rest its arguments, passed unchanged: a file placed in the room is named by :meth:`inside`.  stdin,
        stdout and stderr are passed through, not silenced as a kernel's are, and the exit status is the
        command's (128 + N when killed by signal N).  Its processes end with the seal (:meth:`close`)."""
        return self._launcher("command", timeout, ["--", *map(str, argv)])

    def inside(self, path: Path | str) -> str:
        """Where a file of the room is seen from inside the seal (``/tmp/...``; the same when limited)."""
        path = Path(path)
        if self.sandbox.level == "limited" or not (path == self.folder or self.folder in path.parents):
            return str(path)
        return str(Path("/tmp") / path.relative_to(self.folder))

    def out_of_memory(self) -> bool:
        """True if the kernel's out-of-memory killer struck in the learner's cgroup."""
        for group in self.cgroups:
            for name in ("memory.oom_control", "memory.events"):  # cgroup v1, v2
                try:
                    lines = (group / name).read_text().splitlines()
                except OSError:
                    continue
                if any(line.split()[:1] == ["oom_kill"] and line.split()[1] != "0" for line in lines):
                    return True
        return False

    def close(self) -> None:
        """Kill every process of the learner (cgroup, then the marker), remove the cgroup, unmount and
        remove the room: nothing the learner wrote outlives it."""
        if self.sandbox.level == "container":
            subprocess.run([self.sandbox.engine, "rm", "-f", *self._containers()], capture_output=True,
                           timeout=60)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            left = self._processes()
            if not left:
                break
            for pid in left:
                try:
                    os.kill(pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
            time.sleep(0.05)
        for group in self.cgroups:
            for _ in range(100):
                try:
                    group.rmdir()
                    break
                except FileNotFoundError:
                    break
                except OSError:
                    time.sleep(0.05)
        if self.mounted:
            _unmount(str(self.folder))
            self.mounted = False
        shutil.rmtree(self.folder, ignore_errors=True)
        self.settings.unlink(missing_ok=True)

    def _containers(self) -> list[str]:
        found = subprocess.run([self.sandbox.engine, "ps", "-aq", "--filter", f"label={MARKER}={self.token}"],
                               capture_output=True, text=True, timeout=60)
        return found.stdout.split()

    def _processes(self) -> set[int]:
        pids = set()
        for group in self.cgroups:
            try:
                pids.update(int(line) for line in (group / "cgroup.procs").read_text().split())
            except OSError:
                pass
        return pids | processes_marked(self.token)


def processes_marked(token: str) -> set[int]:
    """The processes whose environment carries ``MODBUS_EDU_GRADE_RUN=token`` (or, with a token ending in
    ``-``, any token that starts so)."""
    wanted = f"{MARKER}={token}".encode()
    found = set()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            environ = (entry / "environ").read_bytes()
        except OSError:
            continue
        if any(item.startswith(wanted) if token.endswith("-") else item == wanted
               for item in environ.split(b"\0")):
            found.add(int(entry.name))
    return found


# --- what a sealed learner sees: the grader decides, the launcher mounts ----------------------------------

def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip("/") + "/")


def below(folder: str, paths: Iterable[str]) -> list[str]:
    """Of ``paths``, the outermost ones strictly below ``folder``."""
    inner = sorted({path for path in paths if path != folder and _within(path, folder)})
    return [path for path in inner if not any(path != other and _within(path, other) for other in inner)]


def below_tmp(paths: Iterable[str]) -> list[str]:
    """Of ``paths``, the outermost folders below ``/tmp`` (which a sealed kernel sees as its own room)."""
    return below("/tmp", (os.path.realpath(path) for path in paths))


def library_checkout() -> str | None:
    """The checkout that holds the library (an editable install: :data:`LIBRARY` outside Python's
    prefixes), or None when the library is installed in site-packages."""
    library = os.path.realpath(LIBRARY)
    prefixes = {os.path.realpath(sys.prefix), os.path.realpath(sys.base_prefix)}
    return None if any(_within(library, prefix) for prefix in prefixes) else library


def needed_paths() -> list[str]:
    """The folders a sealed kernel needs: Python's prefixes, the ``modbus_edu`` package folder and the
    folders of ``PYTHONPATH``, except the checkout that holds the library (only its package is needed)."""
    entries = [path for path in os.environ.get("PYTHONPATH", "").split(os.pathsep) if os.path.isdir(path)]
    found = {os.path.realpath(path)
             for path in (sys.base_prefix, sys.prefix, LIBRARY / "modbus_edu", *entries)}
    return sorted(found - {library_checkout()})


def _closed(path: str) -> str | None:
    """The highest folder above ``path`` that others may not enter (mode without o+x), or None."""
    parts = Path(path).resolve().parts
    for depth in range(2, len(parts)):
        folder = str(Path(*parts[:depth]))
        if not os.stat(folder).st_mode & 0o001:
            return folder
    return None


def covered_paths(hide: Iterable[Path], needed: list[str], scratch: Path) -> list[str]:
    """The folders a sealed learner finds empty (read-only tmpfs over them, only ``needed`` bound back):
    ``hide`` (the class's folders and the output), the library's checkout and any checkout around a
    needed folder, a folder others may not enter that holds one (Python under ``/root``), and the grader's
    scratch folder when it does not lie below ``/tmp`` (which becomes the learner's room anyway)."""
    covers = {os.path.realpath(path) for path in hide}
    checkout = library_checkout()
    if checkout:
        covers.add(checkout)
    for path in needed:
        for above in Path(path).parents:
            if any((above / mark).exists() for mark in CHECKOUT_MARKS):
                covers.add(str(above))
        closed = _closed(path) if os.path.isdir(path) else None
        if closed:
            covers.add(closed)
    scratch_path = os.path.realpath(scratch)
    if not _within(scratch_path, "/tmp"):
        covers.add(scratch_path)
    covers.discard("/")  # a class at the root: its notebooks are copied; the system stays
    return sorted(covers)


# --- the launcher (run as a script, standard library only) -------------------------------------------------

MS = {"ro": 1, "nosuid": 2, "nodev": 4, "noexec": 8, "remount": 32, "noatime": 1024, "nodiratime": 2048,
      "bind": 4096, "rec": 16384, "relatime": 1 << 21, "strictatime": 1 << 24}
"""mount(2) flags, by the names ``/proc/self/mountinfo`` gives them."""
WRITABLE = ("/tmp", "/var/tmp", "/dev/shm")
"""The only places a sealed learner may write: its room, and two fresh tmpfs of :data:`DISK_MB` MB."""
KERNEL_FILESYSTEMS = ("/proc", "/sys", "/dev")
"""Left as they are (fresh ``/proc`` and ``/sys`` of the learner's namespaces; ``/dev`` holds no folder the
learner may write once ``/dev/shm`` is its own); every other mount is made read-only."""


def _libc():
    return ctypes.CDLL(None, use_errno=True)


def _mount(source: str | None, target: str, fstype: str | None = None, flags: int = 0,
           data: str | None = None) -> None:
    encoded = [None if text is None else text.encode() for text in (source, target, fstype, data)]
    if _libc().mount(encoded[0], encoded[1], encoded[2], ctypes.c_ulong(flags), encoded[3]) != 0:
        number = ctypes.get_errno()
        raise OSError(number, f"mount on {target}: {os.strerror(number)}")


def _unmount(target: str) -> None:
    _libc().umount2(target.encode(), 2)  # MNT_DETACH: gone for good once no process holds it


def _mount_points() -> list[tuple[str, set[str], str]]:
    """Each mount of this namespace: its mount point (octal escapes decoded), its options, its source."""
    points = []
    with open("/proc/self/mountinfo", encoding="utf-8", errors="surrogateescape") as stream:
        for line in stream:
            fields, _, described = line.partition(" - ")
            fields = fields.split()
            point = re.sub(r"\\([0-7]{3})", lambda match: chr(int(match.group(1), 8)), fields[4])
            points.append((point, set(fields[5].split(",")), (described.split() + ["", ""])[1]))
    return points


def _read_only() -> None:
    """Every mount read-only, keeping its other flags, but :data:`WRITABLE` and :data:`KERNEL_FILESYSTEMS`
    (``/dev/mqueue`` included in the read-only ones: it would be shared between learners)."""
    for point, options, _ in _mount_points():
        kernel = any(_within(point, top) for top in KERNEL_FILESYSTEMS) and point != "/dev/mqueue"
        if point in WRITABLE or kernel or "ro" in options:
            continue
        flags = MS["remount"] | MS["bind"] | MS["ro"] | sum(MS[name] for name in options & {
            "nosuid", "nodev", "noexec", "noatime", "nodiratime", "relatime", "strictatime"})
        try:
            _mount(None, point, None, flags)
        except OSError as exc:  # a mount point now covered (the host's /tmp below the room): out of reach
            if exc.errno not in (errno.ENOENT, errno.EINVAL):
                raise


def _seal_files(config: dict) -> None:
    """Sealed (root, in the learner's new mount namespace): cover, outer folders first, each folder of
    ``covers`` with an empty tmpfs, ``/tmp`` with the room, ``/var/tmp`` and ``/dev/shm`` with fresh tmpfs,
    binding back the needed folders below each; a fresh read-only ``/sys``; then every other mount
    read-only.  Needed folders are held open first and bound back from their handles; the other learners'
    rooms (mounted on the host before this namespace was made) are unmounted here first.  For a command
    (a clean room) the library's own package stays covered: the room imports its stripped copy only."""
    folder = config["folder"]
    for point, _, source in _mount_points():  # the other learners' rooms (of any grading run), copied into
        if source == ROOM and point != folder:  # this namespace: let go of them, so each dies with its own
            _unmount(point)
    wanted, covers = config["needed"], config["covers"]
    if config.get("mode") == "command":  # a clean room: the library's own package stays out of reach
        wanted = [path for path in wanted if path != config["package"]]
        covers = [*covers, config["package"]]
    held = {path: os.open(path, os.O_PATH | os.O_DIRECTORY) for path in [folder, *wanted]
            if os.path.isdir(path)}
    needed = [path for path in wanted if path in held]
    places = [(path, "") for path in covers] + [(path, path) for path in WRITABLE]
    for path, what in sorted(places, key=lambda place: (place[0].count("/"), place[0])):
        if os.path.islink(path) or not os.path.isdir(path):
            continue  # below a folder covered already (or a link to a place sealed on its own)
        if what == "/tmp":
            _mount(f"/proc/self/fd/{held[folder]}", path, None, MS["bind"])
        elif what:
            _mount("tmpfs", path, "tmpfs", MS["nosuid"] | MS["nodev"],
                   f"size={DISK_MB}m,nr_inodes={FILES},mode=1777")
        else:
            _mount("tmpfs", path, "tmpfs", MS["nosuid"] | MS["nodev"] | MS["noexec"], "size=64k,mode=0755")
        for inner in below(path, needed):
            os.makedirs(inner, mode=0o755, exist_ok=True)
            _mount(f"/proc/self/fd/{held[inner]}", inner, None, MS["bind"] | MS["rec"])
    for handle in held.values():
        os.close(handle)
    _mount("sysfs", "/sys", "sysfs", MS["ro"] | MS["nosuid"] | MS["nodev"] | MS["noexec"])
    _read_only()


def _loopback() -> None:
    """Bring up ``lo`` in the learner's new network namespace (``ip link set lo up``, by ioctl)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        request = struct.pack("16sH22x", b"lo", 0)
        flags = struct.unpack("16sH22x", fcntl.ioctl(probe, 0x8913, request))[1]  # SIOCGIFFLAGS
        fcntl.ioctl(probe, 0x8914, struct.pack("16sH22x", b"lo", flags | 0x1))  # SIOCSIFFLAGS, IFF_UP


def _limits(config: dict) -> None:
    memory, cpu = config["memory"], config["cpu"]
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
    resource.setrlimit(resource.RLIMIT_NPROC, (config["nproc"], config["nproc"]))


def _quiet() -> None:
    """stdout and stderr to /dev/null: what the kernel prints reaches the grader only as messages."""
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    os.close(null)


KEPT = ("PATH", "LANG", "LANGUAGE", "LC_ALL", "LC_CTYPE", "TZ", "PYTHONHASHSEED")
"""The grader's environment variables a kernel inherits; no others (no tokens of the instructor's, and no
``PYTEST_CURRENT_TEST``, which would stop ipykernel from catching what is written straight to fd 1 and 2)."""


def _environment(config: dict, home: str) -> dict:
    env = {key: os.environ[key] for key in KEPT if key in os.environ}
    env.update({MARKER: config["token"], "MODBUS_EDU_SUBMIT": "1", "HOME": home, "TMPDIR": "/tmp",
                "IPYTHONDIR": f"{home}/.ipython", "MPLCONFIGDIR": f"{home}/.matplotlib",
                "MPLBACKEND": "Agg", "MALLOC_ARENA_MAX": "2", "OPENBLAS_NUM_THREADS": "1"})
    if config["path"]:
        env["PYTHONPATH"] = config["path"]
    return env


def _inside(config: dict, path: str) -> str:
    """A path of the room as seen from inside (where the room is /tmp)."""
    folder = config["folder"]
    return "/tmp" + path[len(folder):] if path.startswith(folder + "/") else path


def _sealed_connection(config: dict) -> str:
    """The kernel's own copy of the grader's connection file (which lies outside the room), in the room's
    ``run`` folder: the room's paths (the ``ipc`` sockets' ``ip``) as seen from inside; owned by the
    learner.  Written as a new file, never through a link a learner's process left.  Its path from
    inside."""
    connection = config["rest"][0]
    with open(connection, encoding="utf-8") as stream:
        info = json.load(stream)
    if info.get("transport") == "ipc":
        info["ip"] = _inside(config, info["ip"])
    copy = os.path.join(config["folder"], "run", os.path.basename(connection).removesuffix(".json")
                        + "-sealed.json")
    with contextlib.suppress(FileNotFoundError):  # whatever a learner's process left there, a link too
        os.unlink(copy)
    handle = os.open(copy, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)  # a new file only
    with os.fdopen(handle, "w", encoding="utf-8") as stream:
        json.dump(info, stream)
    os.chown(copy, config["uid"], config["uid"])
    return _inside(config, copy)


def _kernel_command(python: str, connection: str) -> list[str]:
    return [python, "-s", "-m", "ipykernel_launcher", "-f", connection]


def _enter(config: dict) -> None:
    """Sealed, step 1 (root, on the host): join the learner's cgroup, then new namespaces; PID 1 of them
    gets its settings through its environment (only root reads it) and a short command line."""
    for procs in config["procs"]:
        Path(procs).write_text(str(os.getpid()))
    env = dict(os.environ, **{SETTINGS: json.dumps(config)})
    os.execvpe("unshare", ["unshare", *NAMESPACES, "--fork", "--kill-child", "--mount-proc",
                           sys.executable, "-s", str(SCRIPT), "init"], env)


def _init(config: dict) -> None:
    """Sealed, step 2 (root, PID 1 of the new namespaces): seal the files, bring up the loopback, then run
    the kernel or the command as the learner's user and wait for it (its end ends the namespaces)."""
    kernel = config["mode"] == "kernel"
    connection = _sealed_connection(config) if kernel else ""
    _seal_files(config)
    _loopback()
    socket.sethostname("learner")
    config["env"] = _environment(config, "/tmp/home")
    config["nproc"] = MAX_PROCESSES
    argv = _kernel_command(config["python"], connection) if kernel else config["rest"]
    uid = config["uid"]
    child = os.fork()
    if child == 0:
        try:
            os.setgroups([])
            os.setgid(uid)
            os.setuid(uid)
            _libc().prctl(38, 1, 0, 0, 0)  # PR_SET_NO_NEW_PRIVS: no setuid program raises its rights
            os.chdir("/tmp/work")
            _limits(config)
            if kernel:
                _quiet()
            os.execvpe(argv[0], argv, config["env"])
        except OSError as exc:
            print(f"the seal cannot start {argv[0]}: {exc}", file=sys.stderr)
        os._exit(127)
    for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, lambda number, frame: os.kill(child, number))
    while True:
        try:
            _, status = os.waitpid(child, 0)
            break
        except ChildProcessError:
            status = 0
            break
        except InterruptedError:
            continue
    code = os.waitstatus_to_exitcode(status)
    os._exit(code if code >= 0 else 128 - code)


def _container(config: dict) -> None:
    """Container: the kernel or the command in a container of the image, no network but its loopback,
    the room as its /tmp."""
    uid, memory, token = config["uid"], config["memory"], config["token"]
    argv = _kernel_command("python", _sealed_connection(config)) if config["mode"] == "kernel" \
        else config["rest"]
    os.execvp(config["engine"], [
        config["engine"], "run", "--rm", "-i", "--network", "none", "--memory", str(memory),
        "--memory-swap", str(memory), "--pids-limit", str(MAX_PROCESSES), "--user", f"{uid}:{uid}",
        "-v", f"{config['folder']}:/tmp", "-w", "/tmp/work", "-e", f"{MARKER}={token}",
        "-e", "MODBUS_EDU_SUBMIT=1", "-e", "HOME=/tmp/home", "--label", f"{MARKER}={token}", config["image"],
        *argv])


def _limit(config: dict) -> None:
    """Limited: the same user, a process group of its own, per-process limits; then the kernel (quiet) or
    the command (in the room's ``work`` folder)."""
    mine = sum(1 for entry in Path("/proc").iterdir()
               if entry.name.isdigit() and _owner(entry) == os.getuid())
    config["nproc"] = mine + MAX_PROCESSES
    env = _environment(config, str(Path(config["folder"]) / "home"))
    _limits(config)
    if config["mode"] == "kernel":
        _quiet()
        argv = _kernel_command(config["python"], config["rest"][0])
    else:
        os.chdir(Path(config["folder"]) / "work")
        argv = config["rest"]
    os.execvpe(argv[0], argv, env)


def _owner(entry: Path) -> int:
    try:
        return entry.stat().st_uid
    except OSError:
        return -1


if __name__ == "__main__":
    if sys.argv[1:] == ["init"]:
        _init(json.loads(os.environ.pop(SETTINGS)))
    else:
        settings, mode, cpu, *rest = sys.argv[1:]
        with open(settings, encoding="utf-8") as stream:
            launch = json.load(stream)
        launch.update(mode=mode, cpu=int(cpu), rest=rest[1:] if mode == "command" else rest)
        {"sealed": _enter, "limited": _limit, "container": _container}[launch["level"]](launch)
