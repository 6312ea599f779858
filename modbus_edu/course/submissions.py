"""Finding a class's submissions: which notebooks belong to which learner."""

from __future__ import annotations

import re
from pathlib import Path

LEARNER_FILE = re.compile(r"^(?P<learner>.+?)[_\-. ](?P<notebook>\d\d_[A-Za-z0-9_]+)$")


def find_submissions(paths: list[Path]) -> dict[str, list[Path]]:
    """Learner name -> notebooks, from folders of learners, a learner's folder or files named by learner."""
    learners: dict[str, list[Path]] = {}

    def add_file(file: Path, learner: str | None = None) -> None:
        if learner is None:
            match = LEARNER_FILE.match(file.stem)
            learner = match.group("learner") if match else file.stem
        learners.setdefault(learner, []).append(file)

    for path in paths:
        if path.is_file():
            add_file(path)
        elif path.is_dir():
            notebooks = sorted(p for p in path.glob("*.ipynb") if not p.name.startswith("."))
            folders = sorted(p for p in path.iterdir() if p.is_dir() and any(p.glob("*.ipynb")))
            if folders:
                for folder in folders:
                    for file in sorted(folder.glob("*.ipynb")):
                        add_file(file, folder.name)
                for file in notebooks:
                    add_file(file)
            elif any(LEARNER_FILE.match(p.stem) for p in notebooks):
                for file in notebooks:
                    add_file(file)
            else:
                for file in notebooks:
                    add_file(file, path.name)
        else:
            raise FileNotFoundError(f"{path} is neither a notebook nor a folder of notebooks")
    return {name: sorted(files) for name, files in sorted(learners.items())}
