"""The seal between learners, measured from inside: what a sealed learner's kernel can reach.

One class, its folders and the old gradebook inside the checkout that holds the library, is graded as
``modbus-edu grade`` grades it (each learner in a seal of its own, four at once): an honest learner beside
an intruder (it sniffs the machine's sockets for classmates' kernels, listens to them, replays their code
and speaks to them with their session's identity), a peeker (classmates' notebooks, the gradebook, the
course's solutions, the checkout's ``.git``, PID 1's command line) and a writer (a file in every place it
may write); then a reader looks for the writer's files and maps its own boundary.  Each attacker reports
what it found as an answer, which the test reads."""

from __future__ import annotations

import json
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from test_grade import SETUP, right, write

from modbus_edu.course import grade as grading
from modbus_edu.course.boundary import base_python
from modbus_edu.course.sandbox import (
    DISK_MB,
    FORCE,
    LIBRARY,
    UID_BASE,
    Seal,
    detect,
    processes_marked,
    running,
)

NOTEBOOK = "03_rtu_and_crc"
KEYS = ["03.1", "03.2", "03.5"]
SEALED = detect().level == "sealed"
CHECKOUT = any((LIBRARY / mark).exists() for mark in (".git", "pyproject.toml"))
LEFT = f"modbus-edu-seal-{os.getpid()}"  # the writer's file, in each place it may write
NOT_SEALED = ("the sealed level needs bubblewrap and user namespaces; the limited level shares the network, "
              "the file system and the grader's user (TEACHING.md)")
ONLY_SEALED = pytest.mark.skipif(not SEALED, reason=NOT_SEALED)

FIND = """import json, os, socket, time, zmq
from ipykernel.connect import get_connection_file
own = json.load(open(get_connection_file()))

def mine():
    found = set()
    for fd in os.listdir('/proc/self/fd'):
        try:
            found.add(os.readlink(f'/proc/self/fd/{fd}'))
        except OSError:  # the folder's own
            pass
    return found

def endpoints():
    own_sockets, found = mine(), set()
    for name in ('tcp', 'tcp6'):
        try:
            lines = open(f'/proc/net/{name}').read().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            port = int(fields[1].rsplit(':', 1)[1], 16)
            if fields[3] == '0A' and f'socket:[{fields[9]}]' not in own_sockets:
                found.add(f'tcp://127.0.0.1:{port}')
    for line in open('/proc/net/unix').read().splitlines()[1:]:
        fields = line.split()
        if len(fields) > 7 and f'socket:[{fields[6]}]' not in own_sockets:
            found.add('ipc://' + fields[7])
    return found

def reach(endpoint):
    kind, _, where = endpoint.partition('://')
    family = socket.AF_UNIX if kind == 'ipc' else socket.AF_INET
    address = ('\\0' + where[1:] if where.startswith('@') else where) if kind == 'ipc' else (
        '127.0.0.1', int(where.rsplit(':', 1)[1]))
    probe = socket.socket(family, socket.SOCK_STREAM)
    probe.settimeout(1)
    try:
        probe.connect(address)
        return True
    except OSError:
        return False
    finally:
        probe.close()"""

SNIFF = """context = zmq.Context.instance()
seen, listeners, heard, sessions, replayed, reachable, spoken = set(), [], 0, set(), 0, {}, set()
start = time.time()
while time.time() - start < 30:
    for endpoint in sorted(endpoints() - seen)[:50]:
        seen.add(endpoint)
        listener = context.socket(zmq.SUB)
        listener.setsockopt(zmq.SUBSCRIBE, b'')
        listener.setsockopt(zmq.LINGER, 0)
        listener.connect(endpoint)
        listeners.append(listener)
    for listener in listeners:
        while listener.poll(0):
            parts = listener.recv_multipart()
            heard += 1
            if b'<IDS|MSG>' not in parts:
                continue
            at = parts.index(b'<IDS|MSG>')
            header, parent, content = (json.loads(parts[at + shift]) for shift in (2, 3, 5))
            sessions.add(parent.get('session', ''))
            code = content.get('code', '') if header.get('msg_type') == 'execute_input' else ''
            if 'check(' in code or '__modbus_edu_record__(' in code:  # a graded cell, as the grader runs it
                try:
                    exec(code.replace('time.sleep', 'int'))
                    replayed += 1
                except Exception:
                    pass
    for endpoint in sorted(seen):  # the hijacker: speak to it as its grader's session
        if endpoint not in reachable:
            reachable[endpoint] = reach(endpoint)
        for session in sorted(sessions - {''})[:3]:
            if reachable[endpoint] and (endpoint, session) not in spoken:
                spoken.add((endpoint, session))
                dealer = context.socket(zmq.DEALER)
                dealer.setsockopt(zmq.IDENTITY, session.encode())
                dealer.setsockopt(zmq.LINGER, 0)
                dealer.connect(endpoint)
                try:
                    dealer.send_multipart([b'<IDS|MSG>', b'', b'{}', b'{}', b'{}', b'{}'], zmq.NOBLOCK)
                except zmq.ZMQError:
                    pass
    time.sleep(0.2)
sniffed = {'endpoints': sorted(seen)[:20], 'count': len(seen), 'heard': heard, 'replayed': replayed,
           'window': [start, time.time()]}
check('seal.sniffer', json.dumps(sniffed))
reached = sorted(endpoint for endpoint, flag in reachable.items() if flag)
check('seal.hijacker', json.dumps({'reached': reached, 'spoken': len(spoken)}))"""


def peek(targets: list[str], solutions: list[str], classmate: str) -> list[str]:
    look = f"""import json, os
report = {{}}
for path in {targets!r}:
    try:
        is_folder = os.path.isdir(path)
        report[path] = sorted(os.listdir(path))[:10] if is_folder else open(path, errors='replace').read(300)
    except OSError as exc:
        report[path] = type(exc).__name__
report['cmdline'] = open('/proc/1/cmdline').read().replace('\\0', ' ')
try:
    report['environ'] = open('/proc/1/environ').read()[:300]
except OSError as exc:
    report['environ'] = type(exc).__name__
check('seal.peeker', json.dumps(report))"""
    copy = f"""for path in {solutions!r}:
    try:
        exec(open(path).read())
    except Exception:
        pass
try:
    for cell in json.load(open({classmate!r}))['cells']:
        if cell['cell_type'] == 'code':
            exec(''.join(cell['source']).replace('time.sleep', 'int'))
except Exception:
    pass"""
    return [look, copy]


WRITE = f"""for folder in ('/tmp', '/var/tmp', '/dev/shm', '/run/lock'):
    try:
        open(f'{{folder}}/{LEFT}', 'w').write('left by the writer')
    except OSError:
        pass"""

BOUNDARY = f"""import json, os, socket
from ipykernel.connect import get_connection_file
own = json.load(open(get_connection_file()))
mine = set()
for fd in os.listdir('/proc/self/fd'):
    try:
        mine.add(os.readlink(f'/proc/self/fd/{{fd}}'))
    except OSError:  # the folder's own
        pass
report = {{'left': [path for path in ('/tmp/{LEFT}', '/var/tmp/{LEFT}', '/dev/shm/{LEFT}', '/run/lock/{LEFT}')
                    if os.path.exists(path)]}}
report['interfaces'] = [name for _, name in socket.if_nameindex()]
report['tcp'] = [line.split()[1] for name in ('tcp', 'tcp6')
                 for line in open(f'/proc/net/{{name}}').read().splitlines()[1:]
                 if line.split()[3] == '0A' and f'socket:[{{line.split()[9]}}]' not in mine]
report['unix'] = [line.split()[7] for line in open('/proc/net/unix').read().splitlines()[1:]
                  if len(line.split()) > 7]
report['own'] = own['ip'] if own['transport'] == 'ipc' else ''
writable = []
for top, folders, _ in os.walk('/'):
    if top in ('/proc', '/sys', '/tmp', '/var/tmp', '/dev/shm') or os.access(top, os.W_OK):
        if top not in ('/proc', '/sys'):
            writable.append(top)
        folders.clear()
report['writable'] = writable
server = socket.socket()
server.bind(('127.0.0.1', 0))
server.listen()
client = socket.create_connection(server.getsockname(), timeout=5)
connection, _ = server.accept()
client.sendall(b'ping')
report['loopback'] = connection.recv(4).decode()
check('seal.boundary', json.dumps(report))"""


def honest() -> list[str]:
    """Right answers, slowly (so that the intruder's kernel runs while this one does)."""
    return [f"import time\ntime.sleep(4)\n{right(key)}" for key in KEYS]


def _report(runs, key: str) -> dict:
    answers = [s["answer"] for run in runs for s in run.submissions if s.get("key") == key]
    assert answers, f"{key} reported nothing: {[run.problems for run in runs]}"
    return json.loads(answers[0])


def _statuses(runs) -> dict[str, bool]:
    return {record["key"]: record["ok"] for run in runs for record in run.records if record["key"] in KEYS}


@pytest.fixture(scope="module")
def sealed_class():
    if not CHECKOUT or not os.access(LIBRARY, os.W_OK):
        pytest.skip(f"the library at {LIBRARY} is not a writable checkout: no class can lie inside it")
    base = Path(tempfile.mkdtemp(prefix=".seal-class-", dir=LIBRARY))  # the class inside the checkout
    base.chmod(0o755)  # as a checkout's folders are
    scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-grade-"))
    try:
        yield _grade_class(base, scratch)
    finally:
        shutil.rmtree(base, ignore_errors=True)
        shutil.rmtree(scratch, ignore_errors=True)


def _grade_class(base: Path, scratch: Path) -> dict:
    submissions, out = base / "submissions", base / "grades"
    out.mkdir(parents=True)
    (out / "gradebook.csv").write_text("learner,score\nada,SECRET-GRADEBOOK\n")
    classmate = str(submissions / "ada" / f"{NOTEBOOK}.ipynb")
    checkouts = [LIBRARY, *(above for above in Path(sys.prefix).parents if (above / ".git").exists())]
    solutions = [str(folder / "notebooks" / "solutions" / "03_5.py") for folder in checkouts]
    targets = [str(submissions), classmate, str(out), str(out / "gradebook.csv"), str(LIBRARY / ".git"),
               *solutions, str(LIBRARY / "notebooks" / "solutions")]
    cells = {"ada": honest(), "intruder": [FIND, SNIFF], "writer": [WRITE], "reader": [BOUNDARY],
             "peeker": peek(targets, solutions, classmate)}
    for name, learner_cells in cells.items():
        write(submissions / name, NOTEBOOK, [SETUP, *learner_cells])
    sandbox = detect()
    hide = grading._hidden([submissions], out)
    token = f"{os.getpid()}-{secrets.token_hex(4)}"
    windows: dict[str, list[float]] = {}

    def learner(index: int, name: str):
        start = time.time()
        notebooks = [submissions / name / f"{NOTEBOOK}.ipynb"]
        runs = grading._grade_learner(sandbox, index, notebooks, scratch, hide, 90, 1024, token)
        windows[name] = [start, time.time()]
        return runs

    with ThreadPoolExecutor(4) as pool:  # the honest learner beside each attacker, at once
        futures = {name: pool.submit(learner, index, name)
                   for index, name in enumerate(["ada", "intruder", "peeker", "writer"])}
        runs = {name: future.result() for name, future in futures.items()}
    runs["reader"] = learner(4, "reader")  # after the writer is done
    host = [path for path in (Path("/var/tmp") / LEFT, Path("/dev/shm") / LEFT, Path("/run/lock") / LEFT)
            if path.exists()]
    for path in host:  # the old seal left them: clean up, the test reports them
        path.unlink()
    return {"runs": runs, "windows": windows, "scratch": scratch, "base": base, "left_on_host": host,
            # what is left of the learners in the grader's scratch (the clean rooms' copies of the library,
            # "rooms", are the grading run's, removed with the scratch by grade())
            "rooms": sorted(p.name for p in scratch.iterdir() if p.name != "rooms"),
            "processes": _learners_processes(token)}


def _learners_processes(token: str) -> set[int]:
    low = UID_BASE + 1000 * (os.getpid() % 50_000)
    found = processes_marked(f"{token}-")  # root-mapped learners are root outside: found by their marker
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and low <= entry.stat().st_uid < low + 1000 and running(entry):
                found.add(int(entry.name))
        except OSError:
            continue
    return found


def SLOW(test):  # five kernels, four at once (about a minute)
    return pytest.mark.slow(ONLY_SEALED(test))


@SLOW
def test_the_honest_learner_keeps_every_verdict_beside_the_attackers(sealed_class):
    (run,) = sealed_class["runs"]["ada"]
    assert _statuses([run]) == dict.fromkeys(KEYS, True), (run.records, run.problems)
    assert run.problems == [] and run.errored_cells == {}


@SLOW
def test_a_sniffer_finds_no_classmates_kernel(sealed_class):
    runs, windows = sealed_class["runs"], sealed_class["windows"]
    sniffed = _report(runs["intruder"], "seal.sniffer")
    start, end = sniffed["window"]
    assert start < windows["ada"][1] and windows["ada"][0] < end  # it looked while the classmate ran
    assert sniffed["endpoints"] == [] and sniffed["heard"] == 0 and sniffed["replayed"] == 0, sniffed
    assert not any(_statuses(runs["intruder"]).values())


@SLOW
def test_a_hijacker_reaches_no_classmates_kernel(sealed_class):
    assert _report(sealed_class["runs"]["intruder"], "seal.hijacker") == {"reached": [], "spoken": 0}


@SLOW
def test_a_peeker_sees_neither_the_class_nor_the_checkout_around_the_library(sealed_class):
    runs, base = sealed_class["runs"], str(sealed_class["base"])
    report = _report(runs["peeker"], "seal.peeker")
    for path, seen in report.items():
        if path not in ("cmdline", "environ"):
            assert seen == "FileNotFoundError", (path, seen)
    assert "SECRET-GRADEBOOK" not in json.dumps(report)
    assert not any(_statuses(runs["peeker"]).values())  # neither a classmate's answers nor the solutions
    assert base.startswith(str(LIBRARY))


@SLOW
def test_pid_1_shows_no_path_of_the_graders(sealed_class):
    report = _report(sealed_class["runs"]["peeker"], "seal.peeker")
    for secret in (str(sealed_class["scratch"]), str(sealed_class["base"]), str(LIBRARY), "{"):
        assert secret not in report["cmdline"], report["cmdline"]
        assert secret not in report["environ"], report["environ"]  # it holds no settings of the grader's


@SLOW
def test_nothing_a_learner_writes_outlives_its_grade(sealed_class):
    assert _report(sealed_class["runs"]["reader"], "seal.boundary")["left"] == []
    assert sealed_class["left_on_host"] == []
    assert sealed_class["rooms"] == [] and sealed_class["processes"] == set()


@SLOW
def test_the_boundary_from_inside_a_sealed_kernel(sealed_class):
    report = _report(sealed_class["runs"]["reader"], "seal.boundary")
    assert report["interfaces"] == ["lo"]
    assert report["tcp"] == []  # no listening socket but its kernel's own
    assert report["own"].startswith("/tmp/run/")  # which the grader reaches over Unix sockets in its room
    assert all(path.startswith(report["own"] + "-") for path in report["unix"]), report["unix"]
    # /dev/pts: devpts, where no file can be made (test_grade_boundary reads every place back)
    assert sorted(report["writable"]) == ["/dev/pts", "/dev/shm", "/tmp"], report["writable"]
    assert report["loopback"] == "ping"  # a notebook that serves on 127.0.0.1 still works


def _seal(tmp_path: Path, index: int = 0) -> Seal:
    notebook = tmp_path / "class" / f"{NOTEBOOK}.ipynb"
    write(notebook.parent, NOTEBOOK, [SETUP])
    return Seal.open(detect(), index, tmp_path / "scratch", [notebook], [notebook.parent], 1024,
                     f"{os.getpid()}-cmd-{index}")


PROBE = """import json, os, socket, sys
print(json.dumps({'stdin': sys.stdin.read(), 'uid': os.getuid(), 'cwd': os.getcwd(),
                  'work': os.listdir('work'),
                  'interfaces': [name for _, name in socket.if_nameindex()],
                  'pid1': open('/proc/1/cmdline').read().replace('\\0', ' '),
                  'rooms': [line.split()[4] for line in open('/proc/self/mountinfo') if 'learner-' in line],
                  'status': [line.split() for line in open('/proc/self/status') if 'NoNewPrivs' in line]}))
open('/dev/shm/' + sys.argv[1], 'w').write('x')
written = 0
try:
    with open('/dev/shm/full', 'wb') as stream:
        for _ in range(int(sys.argv[2]) + 1):
            stream.write(bytes(2 ** 20))
            stream.flush()
            written += 1
except OSError as exc:
    print(json.dumps({'full': written, 'error': exc.strerror}))
print('to stderr', file=sys.stderr)
sys.exit(3)"""


@ONLY_SEALED
@pytest.mark.parametrize("started", ["straight", "by the launcher"])
def test_command_argv_runs_a_command_in_the_learners_seal(tmp_path, started):
    """A command sealed as the learner's: bubblewrap started straight by :meth:`Seal.run` (as a clean
    room is), or by the launcher script of :meth:`Seal.command_argv`; the same seal either way."""
    classmate, seal = _seal(tmp_path, 1), _seal(tmp_path)
    argv = [base_python(), "-c", PROBE, LEFT, str(DISK_MB)]
    try:
        done = seal.run(argv, input=b"hello", capture_output=True, timeout=60) if started == "straight" else \
            subprocess.run(seal.command_argv(argv), input=b"hello", capture_output=True, timeout=60)
        assert done.returncode == 3, done.stderr
        assert done.stderr.decode().strip().endswith("to stderr")
        seen, full = map(json.loads, done.stdout.splitlines())
        assert DISK_MB - 8 < full["full"] < DISK_MB and full["error"] == "No space left on device"  # a budget
        assert seen["stdin"] == "hello" and seen["uid"] == seal.uid and seen["cwd"] == "/tmp"
        assert seen["work"] == [] and seen["interfaces"] == ["lo"]  # a fresh empty room: no notebook
        assert seen["status"] == [["NoNewPrivs:", "1"]]  # no setuid program raises its rights
        assert str(tmp_path) not in seen["pid1"]
        assert seen["rooms"] == []  # neither its own nor a classmate's folder is there
        assert seal.inside(seal.notebooks[0]) == f"/tmp/work/{NOTEBOOK}.ipynb"
        assert not (Path("/dev/shm") / LEFT).exists()
    finally:
        seal.close()
        classmate.close()
    assert not seal.folder.exists() and not seal.settings.exists()


def test_a_command_reads_its_copy_of_the_library_and_never_the_library_s_own_package(tmp_path):
    """What a clean room can reach: the copy of the library it is handed (at /opt/modbus_edu), not the
    library's own package (which the learner's kernels, to import it, do see)."""
    notebook = tmp_path / "class" / f"{NOTEBOOK}.ipynb"
    write(notebook.parent, NOTEBOOK, [SETUP])
    copy = tmp_path / "scratch" / "rooms" / "library-03.5"
    (copy / "modbus_edu").mkdir(parents=True)
    (copy / "modbus_edu" / "crc.py").write_text("# the room's copy\n")
    for path in [tmp_path / "scratch", *(tmp_path / "scratch").rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    seal = Seal.open(detect(), 0, tmp_path / "scratch", [notebook], [notebook.parent], 1024,
                     f"{os.getpid()}-reads")
    package = LIBRARY / "modbus_edu"
    probe = ("import os, sys; print(os.path.exists(sys.argv[1]), os.path.exists(sys.argv[2]), "
             "os.path.exists(sys.argv[3]))")
    try:
        done = seal.run([base_python(), "-I", "-S", "-c", probe, str(copy / "modbus_edu" / "crc.py"),
                         str(package / "crc.py"), str(package / "__init__.py")], copy=copy,
                        capture_output=True, text=True, timeout=60)
    finally:
        seal.close()
    assert done.returncode == 0, done.stderr
    own_copy, own_crc, own_package = done.stdout.split()
    assert own_copy == "True"
    if seal.sandbox.level == "sealed":
        assert (own_crc, own_package) == ("False", "False")


def test_command_argv_at_the_limited_level(tmp_path, monkeypatch):
    monkeypatch.setenv(FORCE, "limited")
    seal = _seal(tmp_path, 1)
    try:
        done = seal.run([sys.executable, "-c", "import os; print(os.getcwd())"], capture_output=True,
                        text=True, timeout=60)
        assert done.returncode == 0 and done.stdout.strip() == str(seal.folder / "work")
        assert seal.inside(seal.notebooks[0]) == str(seal.notebooks[0])
    finally:
        seal.close()


def test_the_grader_writes_no_file_where_a_kernel_writes(tmp_path):
    """A kernel writes only in its sockets' folder, made fresh for it (a link planted at its name is never
    followed: the folder cannot be made); its connection file lies beside, where no kernel reaches, and
    the launcher hands the kernel its copy through a descriptor, writing nothing."""
    from modbus_edu.course import runner, sandbox

    run = tmp_path / "learner-0" / "run"
    run.mkdir(parents=True)
    victim = tmp_path / "a file of the machine"
    victim.write_text("untouched")

    class Manager:
        connection_file = ""

    manager = runner.connect_in(Manager(), run, 2)
    sockets = Path(manager.ip).parent
    assert Path(manager.connection_file).parent == run and sockets.parent == run
    assert list(sockets.iterdir()) == [] and sockets.stat().st_mode & 0o777 == 0o700
    Path(manager.connection_file).write_text(json.dumps({"transport": "ipc", "ip": manager.ip}))
    config = {"folder": str(run.parent), "rest": [manager.connection_file]}
    before = sorted(run.rglob("*"))
    info, folder = sandbox._kernel_connection(config)
    assert info["ip"] == "/tmp/run/k" and folder == str(sockets)
    assert sorted(run.rglob("*")) == before  # nothing written
    (run / f"k{os.getpid()}-3").symlink_to(victim.parent)  # a link where the next kernel's folder goes
    with pytest.raises(FileExistsError):
        runner.connect_in(Manager(), run, 3)
    elsewhere = tmp_path / "elsewhere"
    Path(manager.connection_file).write_text(json.dumps({"transport": "ipc", "ip": str(elsewhere / "k")}))
    with pytest.raises(OSError, match="outside the learner's run folder"):
        sandbox._kernel_connection(config)
    assert victim.read_text() == "untouched"
