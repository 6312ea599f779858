"""How a sealed kernel or clean room is started, and what the grader waits for when a learner's seal closes.

* A kernel's bubblewrap is started straight by the learner's worker (:func:`.sandbox.kernel_spawn`), and
  only for the sealed launcher's own kernel command line; never by root, which would read the learner's
  ``run`` folder (the worker runs under the learner's user id).
* A clean room's copy of the library is compiled once, when it is made: the room sees it read-only and
  would otherwise compile every module it imports, each time.
* Closing a seal kills every process of the learner's that still runs, and does not wait for a zombie
  (a sandbox's PID 1 that bubblewrap leaves to the system's init, dead, until init reaps it).
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import time
from pathlib import Path

import pytest
from test_grade import SETUP, write

from modbus_edu.course.cleanroom import stripped_copy
from modbus_edu.course.sandbox import FORCE, Seal, detect, kernel_spawn, running

SANDBOX = detect()
AS_ROOT = pytest.mark.skipif(not (SANDBOX.level == "sealed" and SANDBOX.drop), reason=(
    f"learners' user ids of their own only when the grader is root (here: uid {os.geteuid()}, "
    f"{SANDBOX.note})"))


def _seal(tmp_path: Path, sandbox=None) -> Seal:
    write(tmp_path / "class", "03_rtu_and_crc", [SETUP])
    notebook = tmp_path / "class" / "03_rtu_and_crc.ipynb"
    return Seal.open(sandbox or detect(), 0, tmp_path / "scratch", [notebook], [], 1024,
                     f"{os.getpid()}-spawn")


def _filled(seal: Seal) -> list[str]:
    return [str(seal.folder / "run" / "k.json") if item == "{connection_file}" else item
            for item in seal.kernel_argv(60)]


def test_a_kernel_is_spawned_straight_only_from_the_sealed_launchers_command_line(tmp_path, monkeypatch):
    assert kernel_spawn(["python", "-m", "ipykernel_launcher", "-f", "k.json"]) is None
    monkeypatch.setenv(FORCE, "limited")
    seal = _seal(tmp_path)
    try:
        assert kernel_spawn(_filled(seal)) is None  # the limited level: its launcher runs the kernel
    finally:
        seal.close()


@AS_ROOT
def test_root_never_spawns_a_learners_kernel(tmp_path):
    seal = _seal(tmp_path, SANDBOX)
    try:
        with pytest.raises(OSError, match="never by root"):
            kernel_spawn(_filled(seal))
    finally:
        seal.close()


def test_a_clean_rooms_copy_of_the_library_is_compiled_when_it_is_made(tmp_path):
    copy = stripped_copy("03.5", tmp_path)
    sources = sorted((copy / "modbus_edu").rglob("*.py"))
    assert sources
    missing = [str(path) for path in sources
               if not Path(importlib.util.cache_from_source(str(path))).exists()]
    assert missing == []
    assert all(path.stat().st_mode & 0o777 == 0o644 for path in (copy / "modbus_edu").rglob("*.pyc"))


def _state(pid: int) -> bytes:
    return Path(f"/proc/{pid}/stat").read_bytes().rpartition(b")")[2].split()[0]


@AS_ROOT
def test_closing_a_seal_kills_what_runs_and_waits_for_no_zombie(tmp_path):
    seal = _seal(tmp_path, SANDBOX)
    as_learner = {"user": seal.uid, "group": seal.uid, "extra_groups": []}
    live = subprocess.Popen(["sleep", "60"], **as_learner)
    dead = subprocess.Popen(["true"], **as_learner)  # never reaped here until the end: a zombie
    try:
        deadline = time.monotonic() + 10
        while _state(dead.pid) != b"Z" and time.monotonic() < deadline:
            time.sleep(0.01)
        assert _state(dead.pid) == b"Z"
        assert not running(Path(f"/proc/{dead.pid}")) and running(Path(f"/proc/{live.pid}"))
        found = seal._processes()
        assert live.pid in found and dead.pid not in found
        seal.close()
        assert live.wait(10) == -9  # killed by the seal
    finally:
        live.kill()
        live.wait()
        dead.wait()
        seal.close()
