"""The attacks that broke the third round's seal, each beside an honest learner who keeps every verdict.

* A link swapped over the next kernel's files, as they appear (inotify), to a root-owned file of the
  host: the owner of that file is unchanged (the grader writes nothing where a learner writes, and every
  process of a kernel ends with it).
* Credit for a build exercise without writing it: the kernel's copy of the library's ``crc.py`` in the
  room, pymodbus from the environment's site-packages (found from ``sys.executable``, or by its path),
  ``from modbus_edu.crc import CRC_TABLE`` and a loop: none is right in the clean room.
* 200 forked busy loops cost an honest classmate no more than a fair share of the CPU.
* A whole class graded by an unprivileged user.
"""

from __future__ import annotations

import csv
import json
import os
import secrets
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from test_grade import SETUP, right, write

import modbus_edu as mb
from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.course.sandbox import Sandbox, as_user, bubblewrap, detect, view

SANDBOX = detect()
SEALED = SANDBOX.level == "sealed"
ONLY_SEALED = pytest.mark.skipif(not SEALED, reason=f"no sealed level here: {SANDBOX.note}")
SITE = sysconfig.get_paths()["purelib"]  # the grader's own site-packages, which holds pymodbus

COPY = """import os, modbus_edu
source = open(os.path.join(os.path.dirname(modbus_edu.__file__), 'crc.py')).read()
source = source.replace('from .errors', 'from modbus_edu.errors')  # a module of its own, outside the package
for folder in ('/tmp', '/tmp/work', '/tmp/home', '/dev/shm'):
    try:
        open(os.path.join(folder, 'crc_copy.py'), 'w').write(source)
    except OSError:
        pass"""
COPIED = """def crc16(data):
    import sys
    sys.path[:0] = ['/tmp', '/tmp/work', '/tmp/home', '/dev/shm']
    import crc_copy
    return crc_copy.crc16(data)
check('03.5', crc16)"""
SITES = f"""def sites():
    import glob, os, sys
    here = os.path.dirname(os.path.dirname(sys.executable))
    real = os.path.dirname(os.path.dirname(os.path.realpath(sys.executable)))
    found = []
    for top in (here, real, '/opt/environment', '/usr', '/usr/local'):
        found += glob.glob(os.path.join(top, 'lib', 'python3*', '*-packages'))
    return found + [{SITE!r}, '/usr/lib/python3/dist-packages']"""
PYMODBUS_CRC = SITES + """
def crc16(data):
    import sys
    sys.path.extend(sites())
    from pymodbus.framer import FramerRTU
    value = FramerRTU.compute_CRC(bytes(data))
    return ((value & 0xFF) << 8) | (value >> 8)
check('03.5', crc16)"""
PYMODBUS_LRC = SITES + """
def lrc(data):
    import sys
    sys.path.extend(sites())
    from pymodbus.framer import FramerAscii
    return FramerAscii.compute_LRC(bytes(data))
check('04.5', lrc)"""
TABLE = """from modbus_edu.crc import CRC_TABLE
def crc16(data):
    register = 0xFFFF
    for byte in data:
        register = (register >> 8) ^ CRC_TABLE[(register ^ byte) & 0xFF]
    return register
check('03.5', crc16)"""


def swapper(victim: str) -> str:
    """A build exercise whose function, when the clean room calls it, leaves a process behind: inotify on
    the room's folders, and a link to ``victim`` swapped over every file that appears there (the next
    kernel's connection file, if the room were shared), for a minute.  The CRC itself is honest."""
    return f"""def crc16(data):
    import ctypes, os, struct, time
    if not os.environ.get('SWAPPER') and os.fork() == 0:
        os.environ['SWAPPER'] = '1'
        os.setsid()
        null = os.open('/dev/null', os.O_RDWR)
        for fd in (0, 1, 2):
            os.dup2(null, fd)
        libc = ctypes.CDLL(None, use_errno=True)
        watch = libc.inotify_init()
        for folder in ('/tmp/run', '/tmp', '/tmp/work'):
            libc.inotify_add_watch(watch, folder.encode(), 0x100 | 0x80)  # IN_CREATE | IN_MOVED_TO
        end = time.time() + 60
        while time.time() < end:
            events = os.read(watch, 65536)
            at = 0
            while at < len(events):
                length = struct.unpack_from('iIII', events, at)[3]
                name = events[at + 16:at + 16 + length].rstrip(b'\\0').decode()
                at += 16 + length
                for folder in ('/tmp/run', '/tmp', '/tmp/work'):
                    path = os.path.join(folder, name)
                    if name.endswith('.json') and os.path.exists(path) and not os.path.islink(path):
                        try:
                            os.symlink({victim!r}, path + '.swap')
                            os.rename(path + '.swap', path)
                        except OSError:
                            pass
        os._exit(0)
    os.environ['SWAPPER'] = '1'
    register = 0xFFFF
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register
check('03.5', crc16)"""


def _rows(out: Path) -> dict:
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        return {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}
                for row in csv.DictReader(stream)}


def test_the_attacks_work_where_nothing_holds_them_back():
    """Each attack gives the right answer in the grader's own environment: so only the seal stops it."""
    for source, name, reference in ((PYMODBUS_CRC, "crc16", mb.crc16), (PYMODBUS_LRC, "lrc", mb.lrc),
                                    (TABLE, "crc16", mb.crc16)):
        scope = {"check": lambda key, answer: None}
        exec(source, scope)
        assert scope[name](b"123456789") == reference(b"123456789")


@pytest.fixture(scope="module")
def attacked(tmp_path_factory):
    if not SEALED:
        pytest.skip(f"no sealed level here: {SANDBOX.note}")
    base = tmp_path_factory.mktemp("attacks")
    victims = Path(tempfile.mkdtemp(prefix="modbus-edu-victim-", dir="/var/tmp"))
    victims.chmod(0o755)
    victim = victims / "authorized_keys"
    victim.write_text("ssh-ed25519 AAAA the instructor\n")
    victim.chmod(0o644)
    before = victim.stat()
    root = base / "class"
    write(root / "ada", "03_rtu_and_crc", [SETUP, right("03.1"), right("03.5")])
    write(root / "ada", "04_ascii_and_lrc", [SETUP, right("04.5")])
    write(root / "copycat", "03_rtu_and_crc", [SETUP, COPY, COPIED])
    write(root / "pymodbus", "03_rtu_and_crc", [SETUP, PYMODBUS_CRC])
    write(root / "pymodbus", "04_ascii_and_lrc", [SETUP, PYMODBUS_LRC])
    write(root / "table", "03_rtu_and_crc", [SETUP, TABLE])
    write(root / "swapper", "03_rtu_and_crc", [SETUP, swapper(str(victim))])
    write(root / "swapper", "04_ascii_and_lrc", [SETUP, "import time\ntime.sleep(3)", right("04.5")])
    write(root / "swapper", "05_tcp_and_mbap", [SETUP, "import time\ntime.sleep(3)", right("05.1")])
    out = base / "grades"
    try:
        status = main(["grade", str(root), "--out", str(out), "--timeout", "60", "--jobs", "2", "-q"])
        assert status == 0
        after = victim.stat()
        yield {"rows": _rows(out), "before": before, "after": after, "text": victim.read_text()}
    finally:
        shutil.rmtree(victims, ignore_errors=True)


@ONLY_SEALED
def test_a_link_swapped_over_the_next_kernels_files_changes_no_host_files_owner(attacked):
    before, after = attacked["before"], attacked["after"]
    assert (after.st_uid, after.st_gid, after.st_mode) == (before.st_uid, before.st_gid, before.st_mode)
    assert attacked["text"] == "ssh-ed25519 AAAA the instructor\n"
    assert [attacked["rows"]["swapper"][key] for key in ("03.5", "04.5", "05.1")] == ["right"] * 3  # its own


@ONLY_SEALED
def test_no_route_to_the_answer_from_a_clean_room(attacked):
    rows = attacked["rows"]
    assert rows["copycat"]["03.5"] != "right", rows["copycat"]  # the kernel's copy of crc.py is not there
    assert rows["pymodbus"]["03.5"] != "right" and rows["pymodbus"]["04.5"] != "right", rows["pymodbus"]
    assert rows["table"]["03.5"] != "right", rows["table"]  # CRC_TABLE is held back


@ONLY_SEALED
def test_the_honest_learner_keeps_every_verdict_beside_the_attackers(attacked):
    row = attacked["rows"]["ada"]
    assert [row[key] for key in ("03.1", "03.5", "04.5")] == ["right"] * 3, row


BUSY = """import os, time
for _ in range(200):
    if os.fork() == 0:
        while True:
            pass
time.sleep(45)"""
WORK = """import json, time
time.sleep(%d)
start, cpu = time.monotonic(), time.process_time()
total = 0
for number in range(12_000_000):
    total += number
check('seal.work', json.dumps({'wall': time.monotonic() - start, 'cpu': time.process_time() - cpu}))"""


def _ratio(runs) -> float:
    answers = [s["answer"] for run in runs for s in run.submissions if s["key"] == "seal.work"]
    assert answers, [run.problems for run in runs]
    measured = answers[0] if isinstance(answers[0], dict) else json.loads(answers[0])
    return measured["wall"] / max(measured["cpu"], 1e-3)


@pytest.mark.skipif(not (SEALED and SANDBOX.cgroup), reason=(
    "a CPU share per learner needs a cgroup (root with cgroup v1's cpu controller, or a cgroup v2 with cpu, "
    f"memory and pids): {SANDBOX.note}"))
def test_200_busy_loops_cost_an_honest_classmate_no_more_than_a_fair_share(tmp_path):
    """The honest learner's wall time per CPU second, alone and beside 200 busy loops of a classmate's:
    the classmate gets at most one core and an equal share, so the honest one keeps its share (a bound,
    not a timing: the machine is shared)."""
    write(tmp_path / "class" / "ada", "01_data_model", [SETUP, WORK % 0])
    write(tmp_path / "class" / "hal", "01_data_model", [SETUP, WORK % 10])
    write(tmp_path / "class" / "eve", "01_data_model", [SETUP, BUSY])
    # the grader's scratch as grade() makes it, short: the kernels' Unix socket paths must fit 100 bytes
    scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-grade-"))
    token = f"{os.getpid()}-{secrets.token_hex(4)}"

    def learner(index: int, name: str):
        return grading._grade_learner(SANDBOX, index, [tmp_path / "class" / name / "01_data_model.ipynb"],
                                      scratch, [], 90, 1024, token)

    try:
        alone = _ratio(learner(0, "ada"))
        with ThreadPoolExecutor(2) as pool:
            start = time.monotonic()
            busy = pool.submit(learner, 1, "eve")
            honest = pool.submit(learner, 2, "hal")
            beside = _ratio(honest.result())
            busy.result()
            seconds = time.monotonic() - start
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    print(f"\nwall time per CPU second: alone {alone:.2f}, beside 200 busy loops {beside:.2f}; "
          f"the busy learner's run took {seconds:.0f} s")
    assert beside <= 2.5 * alone + 1.0, (alone, beside)


def as_nobody(argv: list[str]) -> list[str]:
    """``argv`` run as user 65534 with no capability where the tests run as root, shown the Python
    installation by the view a learner's worker gets; as it is where they do not."""
    if os.geteuid() != 0:
        return argv
    tool = bubblewrap()
    if tool is None:
        pytest.skip("no bubblewrap to show user 65534 the Python installation")
    return as_user(Sandbox("sealed", "", view=view(tool)), 65534, argv)


def test_a_whole_class_graded_by_an_unprivileged_user():
    """The grader itself unprivileged (as root: user 65534, no capability, shown the Python installation
    by the same view a learner's worker gets where it lies in a folder no other user may enter), and the
    sandbox rootless: the class is graded all the same."""
    work = Path(tempfile.mkdtemp(prefix="modbus-edu-nobody-", dir="/tmp"))  # not below pytest's 0700 folder
    argv = [sys.executable, "-m", "modbus_edu", "grade", str(work / "class"), "--out", str(work / "grades"),
            "--timeout", "60", "--jobs", "2", "-q"]
    argv = as_nobody(argv)
    try:
        for name, answer in (("ada", right), ("bob", lambda key: f"answer = 0\ncheck({key!r}, answer)")):
            write(work / "class" / name, "03_rtu_and_crc", [SETUP, answer("03.1"), answer("03.5")])
        for path in [work, *work.rglob("*")]:
            path.chmod(0o777 if path.is_dir() else 0o666)
        env = dict(os.environ, HOME=str(work), TMPDIR=str(work),
                   PYTHONPATH=str(Path(mb.__file__).resolve().parents[1]))
        done = subprocess.run(argv, capture_output=True, text=True, timeout=300, env=env)
        assert done.returncode == 0, done.stderr[-2000:]
        assert "isolation: sealed" in done.stderr and "rootless" in done.stderr, done.stderr
        rows = _rows(work / "grades")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    assert [rows["ada"][key] for key in ("03.1", "03.5")] == ["right", "right"]
    assert rows["bob"]["03.1"] == "wrong"
