"""The boundary read back: what a sealed kernel (and a clean room) can read, write and connect to, walked
from inside, must be the list the sandbox is built from (:data:`modbus_edu.course.boundary.BOUNDARY`),
nothing more and nothing less; TEACHING.md prints the same list.  A host Unix socket that anyone may
write to (in a folder outside the room, and under /run) is not reachable, and PID 1 shows no path of the
grader's."""

from __future__ import annotations

import json
import os
import secrets
import shutil
import socket
import sys
import tempfile
import threading
from pathlib import Path

import pytest
from test_grade import SETUP, right, write

from modbus_edu.course import grade as grading
from modbus_edu.course.boundary import BOUNDARY, base_python, markdown, resolve
from modbus_edu.course.sandbox import LIBRARY, Seal, detect

ROOT = Path(__file__).resolve().parents[1]
SANDBOX = detect()
SEALED = SANDBOX.level == "sealed"
ONLY_SEALED = pytest.mark.skipif(not SEALED, reason=f"no sealed level here: {SANDBOX.note}")

WALK = r'''
import collections, json, os, socket, stat, fcntl, struct

def walk(hosts):
    readable, writable, sockets, files = set(), set(), [], 0
    mounts = []
    for line in open('/proc/self/mountinfo'):
        mounts.append(line.split()[4])
    stack = collections.deque([('/', 0)])  # breadth first: every top level, then deeper
    while stack and files < 60000:
        top, depth = stack.popleft()
        if top in ('/proc', '/sys') or top.startswith('/proc/'):
            readable.add(top)
            continue
        try:
            names = os.listdir(top)
        except OSError:
            continue
        readable.add(top)
        if os.access(top, os.W_OK):
            writable.add(top)
        for name in names:
            files += 1
            path = os.path.join(top, name)
            try:
                mode = os.lstat(path).st_mode
            except OSError:
                continue
            if stat.S_ISSOCK(mode):
                sockets.append(path)
            elif stat.S_ISDIR(mode) and depth < 12:
                stack.append((path, depth + 1))
    reached = []
    for path in sorted(set(sockets) | set(hosts)):
        probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        probe.settimeout(1)
        try:
            probe.connect(path)
            reached.append(path)
        except OSError:
            pass
        finally:
            probe.close()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        flags = struct.unpack('16sH22x', fcntl.ioctl(probe, 0x8913, struct.pack('16sH22x', b'lo', 0)))[1]
    return {'top': sorted(os.listdir('/')), 'mounts': mounts, 'writable': sorted(writable),
            'readable': sorted(readable), 'reached': reached, 'files': files,
            'interfaces': [name for _, name in socket.if_nameindex()], 'lo_up': bool(flags & 1),
            'pid1': open('/proc/1/cmdline').read(), 'uid': os.getuid()}
'''


def test_teaching_prints_the_boundary():
    """TEACHING.md holds the list, line for line (indented in its list item), as ``markdown()`` prints it."""
    teaching = [line.strip() for line in (ROOT / "TEACHING.md").read_text(encoding="utf-8").splitlines()]
    wanted = [line.strip() for line in markdown().splitlines()]
    starts = [index for index, line in enumerate(teaching) if line == wanted[0]]
    assert any(teaching[start:start + len(wanted)] == wanted for start in starts), (
        "TEACHING.md's boundary differs from modbus_edu.course.boundary.markdown()")


def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip("/") + "/")


def _compare(report: dict, places) -> None:
    """Every place the walk found is one of the list's, and every place of the list is there."""
    inside = {place.inside for place in places if place.kind != "loopback"}
    tops = {"/" + place.split("/")[1] for place in inside}
    assert {"/" + name for name in report["top"]} == tops, report["top"]
    bound = {place.inside for place in places if place.kind not in ("link", "loopback")}
    extra = {point for point in report["mounts"] if point != "/" and not any(
        _within(point, place) for place in bound)}
    assert extra == set(), extra  # a mount the list does not hold
    assert bound <= set(report["mounts"]), bound - set(report["mounts"])  # every place is there
    writable = {place.inside for place in places if place.row and place.row.may in ("write", "connect")}
    allowed = writable | {"/dev/pts"}  # devpts: a folder where no file can be made (the /dev row says so)
    assert all(any(_within(path, place) for place in allowed) for path in report["writable"]), (
        report["writable"])
    assert all(place in report["writable"] for place in writable if place != "lo"), report["writable"]
    readable = {place.inside for place in places if place.kind not in ("loopback",)}
    for path in report["readable"]:  # every folder it could list lies in a place of the list, or above one
        assert any(_within(path, place) or _within(place, path) for place in readable), path
    assert report["interfaces"] == ["lo"] and report["lo_up"]


class _Listener:
    """A Unix path socket on the host that anyone may write to; counts who connects."""

    def __init__(self, path: Path) -> None:
        self.path, self.accepted = path, 0
        self.server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.server.bind(str(path))
        os.chmod(path, 0o777)
        self.server.listen()
        self.server.settimeout(0.2)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while not self.stop.is_set():
            try:
                connection, _ = self.server.accept()
                self.accepted += 1
                connection.close()
            except OSError:
                continue

    def close(self) -> None:
        self.stop.set()
        self.thread.join(5)
        self.server.close()
        self.path.unlink(missing_ok=True)


@pytest.fixture(scope="module")
def host_sockets():
    folder = Path(tempfile.mkdtemp(prefix="modbus-edu-host-", dir="/var/tmp" if os.path.isdir("/var/tmp")
                                   else None))
    folder.chmod(0o777)
    listeners = [_Listener(folder / "service.sock")]
    if os.geteuid() == 0 and os.path.isdir("/run"):
        listeners.append(_Listener(Path("/run") / f"modbus-edu-test-{os.getpid()}.sock"))
    try:
        yield listeners
    finally:
        for listener in listeners:
            listener.close()
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def kernel_walk(host_sockets, tmp_path_factory):
    """The walk from inside one sealed kernel, the class and the grader's scratch folder it ran from."""
    if not SEALED:
        pytest.skip(f"no sealed level here: {SANDBOX.note}")
    base = tmp_path_factory.mktemp("boundary")
    hosts = [str(listener.path) for listener in host_sockets]
    cell = f"{WALK}\ncheck('seal.walk', json.dumps(walk({hosts!r})))"
    write(base / "class" / "ada", "03_rtu_and_crc", [SETUP, right("03.1"), cell, right("03.5")])
    # the grader's scratch as grade() makes it, short: the kernels' Unix socket paths must fit 100 bytes
    scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-grade-"))
    try:
        runs = grading._grade_learner(SANDBOX, 0, [base / "class" / "ada" / "03_rtu_and_crc.ipynb"], scratch,
                                      [], 120, 1024, f"{os.getpid()}-{secrets.token_hex(4)}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    answers = [s["answer"] for run in runs for s in run.submissions if s["key"] == "seal.walk"]
    assert answers, [run.problems for run in runs]
    report = answers[0] if isinstance(answers[0], dict) else json.loads(answers[0])
    return {"report": report, "runs": runs, "base": base, "scratch": scratch}


@ONLY_SEALED
def test_the_boundary_read_back_from_inside_a_sealed_kernel(kernel_walk):
    report = kernel_walk["report"]
    places = resolve("kernel", str(LIBRARY / "modbus_edu"), sockets="/host/run")
    _compare(report, places)
    assert all(path.startswith("/tmp/run/k-") for path in report["reached"]), report["reached"]
    assert len(report["reached"]) == 5  # its own five kernel sockets, and nothing else
    print("\nthe boundary, read from inside a kernel:", json.dumps(
        {key: report[key] for key in ("top", "mounts", "writable", "reached", "interfaces")}))
    statuses = {record["key"]: record["ok"] for run in kernel_walk["runs"] for record in run.records}
    assert statuses["03.1"] and statuses["03.5"]  # the walk changed no verdict


@ONLY_SEALED
def test_no_host_unix_socket_answers_a_graded_kernel(kernel_walk, host_sockets):
    report = kernel_walk["report"]
    for listener in host_sockets:
        assert str(listener.path) not in report["reached"]
        assert listener.accepted == 0, listener.path


@ONLY_SEALED
def test_pid_1_shows_no_path_of_the_graders(kernel_walk):
    pid1 = kernel_walk["report"]["pid1"]
    assert pid1.startswith("bwrap\0--args\0"), pid1
    for secret in (str(kernel_walk["scratch"]), str(kernel_walk["base"]), str(LIBRARY), sys.prefix):
        assert secret not in pid1, (secret, pid1)


@ONLY_SEALED
def test_the_clean_rooms_boundary_holds_the_standard_library_and_the_copy_only(tmp_path, host_sockets):
    copy = tmp_path / "rooms" / "library-03.5"
    (copy / "modbus_edu").mkdir(parents=True)
    (copy / "modbus_edu" / "__init__.py").write_text("")
    notebook = tmp_path / "class" / "03_rtu_and_crc.ipynb"
    write(notebook.parent, "03_rtu_and_crc", [SETUP])
    seal = Seal.open(SANDBOX, 0, tmp_path / "scratch", [notebook], memory_mb=1024,
                     token=f"{os.getpid()}-room")
    hosts = [str(listener.path) for listener in host_sockets]
    code = (f"{WALK}\nimport importlib.util\nreport = walk({hosts!r})\n"
            "report['pymodbus'] = importlib.util.find_spec('pymodbus') is not None\n"
            "report['modbus_edu'] = importlib.util.find_spec('modbus_edu') is not None\n"
            "print(json.dumps(report))")
    try:
        done = seal.run([base_python(), "-I", "-S", "-c", code], copy=copy, capture_output=True, text=True,
                        timeout=120)  # as the grader runs a clean room: bubblewrap started straight
    finally:
        seal.close()
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    _compare(report, resolve("room", str(LIBRARY / "modbus_edu"), copy=str(copy)))
    assert report["reached"] == [] and not report["pymodbus"] and not report["modbus_edu"]
    assert "/opt/environment" not in report["readable"]
    assert not any("pymodbus" in path for path in report["readable"])
    assert any(_within(path, "/opt/modbus_edu") for path in report["readable"])  # its copy only


def test_the_list_names_no_place_of_the_hosts_that_a_learner_must_not_see():
    for row in BOUNDARY:
        for banned in ("/home", "/run", "/srv", "/var", "/root", "/mnt", "/media"):
            assert not _within(row.path, banned), row
    kernel = {place.inside for place in resolve("kernel", str(LIBRARY / "modbus_edu"), sockets="/x")}
    room = {place.inside for place in resolve("room", str(LIBRARY / "modbus_edu"), copy="/y")}
    assert "/opt/environment" in kernel or sys.prefix == sys.base_prefix
    assert "/opt/environment" not in room and "/tmp/run" not in room and "/kernel.json" not in room
