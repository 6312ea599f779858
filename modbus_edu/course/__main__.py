"""``python -m modbus_edu.course``: re-execute or check the course's notebooks, or write a class copy."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import __doc__ as PACKAGE_DOC
from .check import check_course
from .execute import course_notebooks, execute
from .release import release


def _execute(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    paths: list[Path] = []
    for item in map(Path, args.paths):
        if item.is_dir():
            paths.extend(course_notebooks(item))
        elif item.is_file():
            paths.append(item)
        else:
            parser.exit(1, f"{parser.prog}: error: {item} is neither a notebook nor a folder of notebooks\n")
    for path in paths:
        print(f"{path} ... ", end="", flush=True)
        print(f"{execute(path, args.timeout):.1f} s")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m modbus_edu.course",
                                     description=PACKAGE_DOC.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("execute", help="re-execute notebooks in place (default: the whole course)")
    run.add_argument("paths", nargs="*", default=["notebooks"])
    run.add_argument("--timeout", type=int, default=120, help="seconds per cell")
    check = sub.add_parser("check", help="check the course's conventions")
    check.add_argument("folder", nargs="?", default="notebooks")
    copy = sub.add_parser("release", help="write a copy of the course for a class, without the solutions")
    copy.add_argument("destination", type=Path)
    copy.add_argument("--root", type=Path, default=Path("."), help="the course's root folder (default: here)")
    args = parser.parse_args(argv)
    if args.command == "execute":
        return _execute(args, parser)
    if args.command == "release":
        try:
            written = release(args.root, args.destination)
        except FileExistsError as exc:
            parser.exit(1, f"{parser.prog}: error: {exc}\n")
        print(f"{args.destination}: {len(written)} notebooks, no worked solutions")
        return 0
    problems = check_course(args.folder)
    for item in problems:
        print(item)
    print("course conventions: OK" if not problems else f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
