"""Nothing of one learner's reaches a classmate's user id, or a classmate's sandbox.

Each learner's seal keeps a folder of the grader's: ``learner-N`` holds the copies of its notebooks
(``work``), its kernels' folder (``run``), the launcher's settings (``seal.json``) and its worker's
results (``runs-*``).  Two learners' seals are set up by the real code (:meth:`.Seal.open`), then every
path of the first learner's folder, walked by the grader, is listed or read by a probe:

* **as root**, each learner's worker (and, through it, its kernels' launcher) runs under a user id of
  the learner's own, so the boundary between classmates on the host is the file system's permissions:
  the learner's folder and its ``work`` are the grader's, mode 0750, of the learner's group (set through
  their descriptors); ``run`` and ``runs-*`` are the learner's own, 0700.  A probe started exactly as
  a learner's worker is (:meth:`.Seal.worker_argv`: the same view, user and groups) lists and reads every
  path of its own learner's, and nothing of its classmate's;
* **as an unprivileged grader** (here: user 65534 when the test runs as root), every learner's worker
  runs as the grader's user, and a user id separates nothing: the boundary is bubblewrap's.  What runs a
  learner's code, its kernels and its clean rooms, runs in a root built from nothing (:mod:`.boundary`),
  where no folder of the grader's is there at all: a command sealed as the second learner's (the same
  launcher, user, namespaces and places as its kernels, but for the kernel's own ``/tmp/run``) finds
  none of the first learner's paths, while the grader itself, outside, reads them all.  The worker runs
  no learner's code: it only drives the kernels.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from test_grade import SETUP, write
from test_grade_seal_attacks import as_nobody

import modbus_edu as mb
from modbus_edu.course.runner import results_folder
from modbus_edu.course.sandbox import Sandbox, Seal, detect

SANDBOX = detect()
NOTEBOOK = "03_rtu_and_crc"

PROBE = """import json, os, sys
found = {}
for path, folder in json.loads(sys.argv[1]):
    try:
        if folder:
            os.listdir(path)
        else:
            with open(path, 'rb') as stream:
                stream.read(1)
        found[path] = 'read'
    except OSError as exc:
        found[path] = type(exc).__name__
print(json.dumps({'uid': os.getuid(), 'gid': os.getgid(), 'groups': os.getgroups(), 'found': found}))"""
"""Lists each folder and reads each file of ``argv[1]`` (a JSON list of [path, is a folder]): what it
could (``read``), or the error's name."""


def _walk(folder: Path) -> list[list]:
    """Every path below ``folder`` and itself, as the grader sees them: [path, is a folder]."""
    found = [[str(folder), True]]
    for top, folders, files in os.walk(folder):
        found += [[os.path.join(top, name), True] for name in folders]
        found += [[os.path.join(top, name), False] for name in files]
    return found


def _seals(scratch: Path, sandbox: Sandbox) -> tuple[Seal, Seal]:
    seals = []
    for index, name in enumerate(("ada", "bob")):
        folder = scratch.parent / "class" / name
        write(folder, NOTEBOOK, [SETUP, f"secret = {name!r}"])
        seals.append(Seal.open(sandbox, index, scratch, [folder / f"{NOTEBOOK}.ipynb"], [], 1024,
                               f"{os.getpid()}-classmates-{index}"))
    return seals[0], seals[1]


def _probe(argv: list[str]) -> dict:
    done = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout)


@pytest.mark.skipif(not (SANDBOX.level == "sealed" and SANDBOX.drop), reason=(
    f"learners' workers run under user ids of their own only when the grader is root (here: uid "
    f"{os.geteuid()}, {SANDBOX.note})"))
def test_as_root_a_learners_worker_reads_nothing_of_a_classmates():
    """As root: a process started as a learner's worker is, under its user id, lists and reads every path
    of its own learner's folder, and none of a classmate's (each a PermissionError)."""
    work = Path(tempfile.mkdtemp(prefix="modbus-edu-classmates-"))  # in TMPDIR, as grade() makes its own
    scratch = work / "scratch"
    ada, bob = _seals(scratch, SANDBOX)
    try:
        results_folder(ada.folder, ada.user)  # what ada's worker writes its runs into
        paths = _walk(ada.folder)
        assert {Path(path).name for path, _ in paths} >= {"learner-0", "work", f"{NOTEBOOK}.ipynb", "run",
                                                          "seal.json"}
        probe = [sys.executable, "-I", "-c", PROBE, json.dumps(paths)]
        own, classmate = _probe(ada.worker_argv(probe)), _probe(bob.worker_argv(probe))
    finally:
        ada.close()
        bob.close()
        shutil.rmtree(work, ignore_errors=True)
    assert (own["uid"], own["gid"], own["groups"]) == (ada.uid, ada.uid, [])
    assert (classmate["uid"], classmate["gid"], classmate["groups"]) == (bob.uid, bob.uid, [])
    assert classmate["found"] == {path: "PermissionError" for path, _ in paths}, classmate["found"]
    assert own["found"] == {path: "read" for path, _ in paths}, own["found"]


UNPRIVILEGED = """import json, os, sys
from pathlib import Path
sys.path.insert(0, sys.argv[2])
from test_grade_seal_classmates import PROBE, _seals, _walk
from modbus_edu.course.boundary import base_python
from modbus_edu.course.sandbox import detect
sandbox = detect()
ada, bob = _seals(Path(sys.argv[1]), sandbox)
try:
    paths = _walk(ada.folder)
    done = bob.run([base_python(), '-I', '-S', '-c', PROBE, json.dumps(paths)], capture_output=True,
                   text=True, timeout=60)
    print(json.dumps({'note': sandbox.note, 'level': sandbox.level, 'uid': os.getuid(),
                      'sealed': json.loads(done.stdout or 'null'), 'err': done.stderr[-1000:],
                      'grader': json.loads(__import__('subprocess').run(
                          [sys.executable, '-I', '-c', PROBE, json.dumps(paths)], capture_output=True,
                          text=True, timeout=60).stdout)}))
finally:
    ada.close()
    bob.close()
"""
"""Run as the unprivileged grader: two seals, and the probe over the first's folder from a command sealed
as the second's, and from the grader itself."""


def test_as_an_unprivileged_grader_a_learners_sandbox_holds_nothing_of_a_classmates():
    """An unprivileged grader (as root: user 65534, no capability, shown the Python installation by the
    view a learner's worker gets): all runs under its one user id, and a command sealed as a learner's
    finds none of a classmate's paths (FileNotFoundError: they are not in its root), which the grader
    itself reads."""
    work = Path(tempfile.mkdtemp(prefix="modbus-edu-nobody-", dir="/tmp"))  # not below pytest's 0700 folder
    argv = [sys.executable, "-c", UNPRIVILEGED, str(work / "scratch"), str(Path(__file__).parent)]
    argv = as_nobody(argv)
    try:
        work.chmod(0o777)
        env = dict(os.environ, HOME=str(work), TMPDIR=str(work),
                   PYTHONPATH=str(Path(mb.__file__).resolve().parents[1]))
        done = subprocess.run(argv, capture_output=True, text=True, timeout=120, env=env)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout)
    if report["level"] != "sealed":
        pytest.skip(f"no sealed level for an unprivileged grader here: {report['note']}")
    assert "rootless" in report["note"] and report["uid"] != 0
    grader, sealed = report["grader"], report["sealed"]
    assert sealed is not None, report["err"]
    assert set(grader["found"].values()) == {"read"}, grader  # one user id: the grader reads all
    assert sealed["uid"] == report["uid"]  # the same user id inside, as outside
    assert sealed["found"] == {path: "FileNotFoundError" for path in grader["found"]}, sealed
