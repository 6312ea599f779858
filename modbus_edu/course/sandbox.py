"""Each learner sealed off: where a graded kernel runs, what it can reach, and how it ends.

:func:`detect` picks the strongest level this machine offers, said in one line:

* **sealed** (root, Linux namespaces and a writable cgroup): each learner's kernels run under a user id
  of their own (no passwd entry needed), in new PID and mount namespaces, with ``/tmp`` replaced by a
  private folder holding a copy of only that learner's notebooks; the class's folders and the output
  folder are covered by empty read-only mounts, ``/proc`` shows only the learner's own processes, and a
  cgroup (v2 when its memory and pids controllers are usable, else v1) limits memory and the number of
  processes of the learner as a whole.  When the learner is done every process of the cgroup is killed;
  the kernel's PID namespace dies with it, so a child that started a session of its own dies too;
* **limited** (no root, or no namespaces): each kernel in a process group of its own, with
  ``RLIMIT_AS`` and ``RLIMIT_NPROC``; a process that leaves the group is still found by the marker in
  its environment and killed, unless it cleared its environment;
* **container** (``--container IMAGE``, docker or podman answering): each kernel in a container of the
  image (which must hold Python, ipykernel and modbus_edu), with the private folder as ``/tmp``, memory
  and pids limits, removed when it stops.

Whatever the level, every kernel's process carries ``MODBUS_EDU_GRADE_RUN=<token>`` in its environment
(and, of the grader's environment, only :data:`KEPT`); its stdout and stderr go to ``/dev/null`` once
ipykernel has caught them, so what it prints, with ``print`` or straight to fd 1, reaches the grader only
as counted messages; ``RLIMIT_AS`` bounds each process as well.

Run as a script (``python sandbox.py enter|init|limit CONFIG -f CONNECTION_FILE``) this module is the
kernel's launcher; it imports nothing but the standard library, so that it starts fast.
"""

from __future__ import annotations

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

MARKER = "MODBUS_EDU_GRADE_RUN"
"""The environment variable every process of a graded kernel carries (its value: the learner's token)."""
MAX_PROCESSES = 256
"""Tasks (processes and threads) one learner's kernels may have at once."""
UID_BASE = 100_000
"""Learners' user ids start here (sealed level): one per learner, from ``UID_BASE + 1000 * (pid % 50000)``."""
CGROUP_V1 = Path("/sys/fs/cgroup")
CGROUP_V2 = (Path("/sys/fs/cgroup"), Path("/sys/fs/cgroup/unified"))
SCRIPT = Path(__file__).resolve()
LIBRARY = SCRIPT.parents[2]
"""The folder that holds the ``modbus_edu`` package (site-packages, or a clone for an editable install)."""


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
            probe = subprocess.run(["unshare", "--pid", "--mount", "--fork", "--kill-child", "--mount-proc",
                                    "true"], capture_output=True, timeout=20)
            why = "" if probe.returncode == 0 else "no PID and mount namespaces"
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
    return Sandbox("sealed", f"isolation: sealed: each learner under a user id of its own, in PID and mount "
                             f"namespaces, a private copy of its notebooks, memory and processes limited "
                             f"per learner by a cgroup ({cgroup.split(':')[0]})", cgroup=cgroup)


@dataclass
class Seal:
    """One learner's sealed room: a private folder, a user id, a cgroup; :meth:`close` ends them all."""

    sandbox: Sandbox
    index: int
    folder: Path  # the private folder (it is /tmp inside a sealed kernel)
    notebooks: list[Path]
    hide: list[Path]
    memory_mb: int
    token: str
    uid: int = 0
    cgroups: list[Path] = field(default_factory=list)

    @classmethod
    def open(cls, sandbox: Sandbox, index: int, scratch: Path, notebooks: list[Path], hide: list[Path],
             memory_mb: int, token: str) -> Seal:
        folder = scratch / f"learner-{index}"
        seal = cls(sandbox, index, folder, [], hide, memory_mb, token)
        for name in ("work", "home", "run"):
            (folder / name).mkdir(parents=True, exist_ok=True)
        for position, source in enumerate(notebooks):
            copy = folder / "work" / source.name
            if copy.exists():  # two notebooks of one name (from two folders): keep both
                copy = folder / "work" / f"{source.stem}-{position}{source.suffix}"
            shutil.copyfile(source, copy)
            seal.notebooks.append(copy)
        if sandbox.level in ("sealed", "container"):
            seal.uid = UID_BASE + 1000 * (os.getpid() % 50_000) + index
            for path in [folder, *folder.rglob("*")]:
                os.chown(path, seal.uid, seal.uid)
            folder.chmod(0o700)
        if sandbox.level == "sealed":
            seal._make_cgroups()
        return seal

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

    def config(self, timeout: float) -> dict:
        """What the kernel's launcher needs (JSON in its command line)."""
        return {"engine": self.sandbox.engine, "image": self.sandbox.image, "uid": self.uid,
                "folder": str(self.folder), "hide": [str(p) for p in self.hide],
                "memory": self.memory_mb * 1024 * 1024, "cpu": int(timeout) + 10,
                "procs": [str(group / "cgroup.procs") for group in self.cgroups], "token": self.token,
                "python": sys.executable, "path": os.environ.get("PYTHONPATH", ""),
                "needed": sorted({sys.base_prefix, sys.prefix, str(LIBRARY),
                                  *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))})}

    def kernel_argv(self, timeout: float) -> list[str]:
        """The kernel's command line (``{connection_file}`` where jupyter puts the connection file)."""
        config = json.dumps(self.config(timeout))
        stage = {"sealed": "enter", "limited": "limit", "container": "container"}[self.sandbox.level]
        return [sys.executable, "-s", str(SCRIPT), stage, config, "-f", "{connection_file}"]

    # --- a command run as the learner (the clean room); minimal: the limited level at every level -------

    def command_argv(self, argv: list[str], *, read_only: Iterable[str] = (),
                     timeout: float = 30) -> list[str]:
        """A command line that runs ``argv`` as the learner, its stdin and stdout passed through.

        ``read_only``: folders ``argv`` reads (the clean room's copy of the library), to be reachable,
        read-only, at the same path.  This version runs ``argv`` at the limited level whatever the
        sandbox's: the learner's environment and per-process limits (the caller starts it in a process
        group of its own); nothing is hidden, so ``read_only`` is reachable as it is.  ``timeout``: the
        seconds it may run (its CPU time is limited a little above)."""
        config = dict(self.config(timeout), argv=list(argv), read_only=[str(path) for path in read_only])
        return [sys.executable, "-s", str(SCRIPT), "command", json.dumps(config), "-f", ""]

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
        """Kill every process of the learner (cgroup, then the marker), remove the cgroup and the folder."""
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


# --- the kernel's launcher (run as a script, standard library only) ---------------------------------------

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


def _kernel(config: dict, connection: str) -> None:
    os.execve(config["python"], [config["python"], "-s", "-m", "ipykernel_launcher", "-f", connection],
              config["env"])


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


def _enter(config: dict, connection: str) -> None:
    """Sealed, step 1 (root, on the host): join the learner's cgroup, then new PID and mount namespaces."""
    for procs in config["procs"]:
        Path(procs).write_text(str(os.getpid()))
    os.execvp("unshare", ["unshare", "--pid", "--mount", "--fork", "--kill-child", "--mount-proc",
                          sys.executable, "-s", str(SCRIPT), "init", json.dumps(config), "-f", connection])


def _init(config: dict, connection: str) -> None:
    """Sealed, step 2 (root, PID 1 of the new namespace): hide the class, make /tmp the learner's own
    folder, then start the kernel as the learner's user and wait for it (its end ends the namespace)."""
    folder = config["folder"]
    for path in config["hide"]:
        if os.path.isdir(path) and not (folder + "/").startswith(path.rstrip("/") + "/"):
            subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=4k,mode=0555", "tmpfs", path], check=True)
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64m,mode=1777", "tmpfs", "/dev/shm"], check=True)
    _reach(config["needed"])
    kept = _stage_below_tmp(config["needed"])
    subprocess.run(["mount", "--bind", folder, "/tmp"], check=True)
    for stage, path in kept:  # Python or the library installed below /tmp: back in place, read-only
        os.makedirs(path, mode=0o755, exist_ok=True)
        subprocess.run(["mount", "--move", stage, path], check=True)
        os.rmdir(stage)
    inside = _inside(config, connection)
    uid = config["uid"]
    os.chown(inside, uid, uid)
    config["env"] = _environment(config, "/tmp/home")
    config["nproc"] = MAX_PROCESSES
    child = os.fork()
    if child == 0:
        os.setgroups([])
        os.setgid(uid)
        os.setuid(uid)
        os.chdir("/tmp/work")
        _limits(config)
        _quiet()
        _kernel(config, inside)
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
    os._exit(os.waitstatus_to_exitcode(status) & 0xFF)


def _inside(config: dict, connection: str) -> str:
    """The connection file's path seen from inside (where the private folder is /tmp)."""
    folder = config["folder"]
    return "/tmp" + connection[len(folder):] if connection.startswith(folder + "/") else connection


def _container(config: dict, connection: str) -> None:
    """Container: the kernel in a container of the image, the private folder as its /tmp."""
    uid, memory, token = config["uid"], config["memory"], config["token"]
    os.chown(connection, uid, uid)
    os.execvp(config["engine"], [
        config["engine"], "run", "--rm", "-i", "--network", "host", "--memory", str(memory),
        "--memory-swap", str(memory), "--pids-limit", str(MAX_PROCESSES), "--user", f"{uid}:{uid}",
        "-v", f"{config['folder']}:/tmp", "-w", "/tmp/work", "-e", f"{MARKER}={token}",
        "-e", "MODBUS_EDU_SUBMIT=1", "-e", "HOME=/tmp/home", "--label", f"{MARKER}={token}", config["image"],
        "python", "-m", "ipykernel_launcher", "-f", _inside(config, connection)])


def _closed(path: str) -> str | None:
    """The highest folder above ``path`` that others may not enter (mode without o+x), or None."""
    parts = Path(path).resolve().parts
    for depth in range(2, len(parts)):
        folder = str(Path(*parts[:depth]))
        if not os.stat(folder).st_mode & 0o001:
            return folder
    return None


def _reach(needed: list[str]) -> None:
    """Let the learner's user reach Python and the library where they sit below a closed folder (a
    Python under /root): an empty tmpfs covers the closed folder, and only the needed folders are bound
    back into it (staged through the private /dev/shm)."""
    covered: dict[str, list[str]] = {}
    for path in needed:
        closed = _closed(path) if os.path.isdir(path) else None
        if closed:
            covered.setdefault(closed, []).append(str(Path(path).resolve()))
    for closed, paths in covered.items():
        stages = []
        for number, path in enumerate(paths):
            stage = f"/dev/shm/.reach-{number}"
            os.mkdir(stage)
            subprocess.run(["mount", "--bind", path, stage], check=True)
            stages.append((stage, path))
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=4k,mode=0755", "tmpfs", closed], check=True)
        for stage, path in stages:
            os.makedirs(path, mode=0o755, exist_ok=True)
            subprocess.run(["mount", "--move", stage, path], check=True)
            os.rmdir(stage)


def below_tmp(paths: Iterable[str]) -> list[str]:
    """Of ``paths``, the outermost folders below ``/tmp`` (which a sealed kernel sees as its own)."""
    resolved = sorted({str(Path(path).resolve()) for path in paths})
    below = [path for path in resolved if path.startswith("/tmp/")]
    return [path for path in below if not any(path.startswith(other + "/") for other in below)]


def _stage_below_tmp(needed: list[str]) -> list[tuple[str, str]]:
    """The needed folders that lie below ``/tmp`` (a clone and its virtual environment there), each bound
    read-only to a stage in the private ``/dev/shm``, to be moved back once ``/tmp`` is the learner's."""
    stages = []
    for number, path in enumerate(below_tmp(path for path in needed if os.path.isdir(path))):
        stage = f"/dev/shm/.tmp-{number}"
        os.mkdir(stage)
        subprocess.run(["mount", "--bind", path, stage], check=True)
        subprocess.run(["mount", "-o", "remount,bind,ro", stage], check=True)
        stages.append((stage, path))
    return stages


def _limit(config: dict, connection: str) -> None:
    """Limited: the same user, a process group of its own, per-process limits; then the kernel."""
    mine = sum(1 for entry in Path("/proc").iterdir()
               if entry.name.isdigit() and _owner(entry) == os.getuid())
    config["nproc"] = mine + MAX_PROCESSES
    config["env"] = _environment(config, str(Path(config["folder"]) / "home"))
    _limits(config)
    _quiet()
    _kernel(config, connection)


def _command(config: dict, connection: str) -> None:
    """A command as the learner (:meth:`Seal.command_argv`): per-process limits, its stdout kept."""
    mine = sum(1 for entry in Path("/proc").iterdir()
               if entry.name.isdigit() and _owner(entry) == os.getuid())
    config["nproc"] = mine + MAX_PROCESSES
    config["env"] = _environment(config, str(Path(config["folder"]) / "home"))
    _limits(config)
    argv = config["argv"]
    os.execve(argv[0], argv, config["env"])


def _owner(entry: Path) -> int:
    try:
        return entry.stat().st_uid
    except OSError:
        return -1


if __name__ == "__main__":
    stage, settings, _, connection_file = sys.argv[1:5]
    stages = {"enter": _enter, "init": _init, "limit": _limit, "container": _container, "command": _command}
    stages[stage](json.loads(settings), connection_file)
