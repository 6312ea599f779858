"""``python -m modbus_edu.course``: re-execute or check the course's notebooks."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import __doc__ as PACKAGE_DOC
from .check import check_course
from .execute import course_notebooks, execute


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m modbus_edu.course",
                                     description=PACKAGE_DOC.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("execute", help="re-execute notebooks in place (default: the whole course)")
    run.add_argument("paths", nargs="*", default=["notebooks"])
    run.add_argument("--timeout", type=int, default=120, help="seconds per cell")
    check = sub.add_parser("check", help="check the course's conventions")
    check.add_argument("folder", nargs="?", default="notebooks")
    args = parser.parse_args(argv)
    if args.command == "execute":
        paths: list[Path] = []
        for item in map(Path, args.paths):
            paths.extend(course_notebooks(item) if item.is_dir() else [item])
        for path in paths:
            print(f"{path} ... ", end="", flush=True)
            print(f"{execute(path, args.timeout):.1f} s")
        return 0
    problems = check_course(args.folder)
    for item in problems:
        print(item)
    print("course conventions: OK" if not problems else f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
