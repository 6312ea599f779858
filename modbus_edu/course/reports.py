"""The gradebook's reports: ``gradebook.csv``, a page per learner, and the class summary."""

from __future__ import annotations

import csv
import html
from collections import Counter
from pathlib import Path

from .verdicts import ERRORED, NOT_ANSWERED, RIGHT, WRONG, Verdict, misconception


def _write_csv(path: Path, table: dict, exercises: list[str], flags: dict) -> None:
    with path.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(["learner", *exercises, RIGHT, WRONG, NOT_ANSWERED, ERRORED, "score", "flags"])
        for learner, row in table.items():
            statuses = [row.get(key, Verdict(NOT_ANSWERED)).status for key in exercises]
            counts = Counter(statuses)
            writer.writerow([learner, *statuses, counts[RIGHT], counts[WRONG], counts[NOT_ANSWERED],
                             counts[ERRORED], f"{counts[RIGHT]}/{len(exercises)}",
                             " | ".join(flags[learner])])


PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>{title}</title><style>
body {{ font-family: sans-serif; max-width: 60em; margin: 2em auto; }} td, th {{ padding: .3em .6em;
vertical-align: top; border-bottom: 1px solid #ddd; text-align: left; }} .right {{ color: #1a7f37; }}
.wrong {{ color: #b35900; }} .errored {{ color: #c62828; }} pre {{ white-space: pre-wrap; margin: 0; }}
</style></head><body><h1>{title}</h1>{body}</body></html>
"""


def _write_learner(path: Path, learner: str, row: dict, exercises: list[str], flags: list[str]) -> None:
    right = sum(1 for key in exercises if row.get(key, Verdict(NOT_ANSWERED)).status == RIGHT)
    parts = [f"<p>{right} of {len(exercises)} exercises right.</p>"]
    if flags:
        parts.append("<h2>About the notebooks</h2><ul>" + "".join(f"<li>{html.escape(f)}</li>" for f in flags)
                     + "</ul>")
    parts.append("<table><tr><th>exercise</th><th>result</th><th>the checker's feedback</th></tr>")
    for key in exercises:
        verdict = row.get(key, Verdict(NOT_ANSWERED, "no cell of the notebooks checks this exercise"))
        parts.append(f"<tr><td>{key}</td><td class='{verdict.status.split()[0]}'>{verdict.status}</td>"
                     f"<td><pre>{html.escape(verdict.message)}</pre></td></tr>")
    parts.append("</table>")
    path.write_text(PAGE.format(title=f"Feedback for {html.escape(learner)}", body="".join(parts)),
                    encoding="utf-8")


def _write_summary(out: Path, table: dict, exercises: list[str], flags: dict) -> dict:
    rows = []
    for key in exercises:
        statuses = [row.get(key, Verdict(NOT_ANSWERED)) for row in table.values()]
        counts = Counter(v.status for v in statuses)
        slips = Counter(misconception(v.message) for v in statuses if v.status == WRONG)
        rows.append({"exercise": key, "learners": len(statuses), **{s: counts[s] for s in
                     (RIGHT, WRONG, NOT_ANSWERED, ERRORED)},
                     "success rate": counts[RIGHT] / len(statuses) if statuses else 0.0,
                     "misconceptions": slips.most_common(3)})
    with (out / "summary.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(["exercise", "learners", RIGHT, WRONG, NOT_ANSWERED, ERRORED, "success rate",
                         "most frequent misconception", "learners with it"])
        for row in rows:
            slip, count = row["misconceptions"][0] if row["misconceptions"] else ("", 0)
            writer.writerow([row["exercise"], row["learners"], row[RIGHT], row[WRONG], row[NOT_ANSWERED],
                             row[ERRORED], f"{row['success rate']:.0%}", slip, count])
    parts = [f"<p>{len(table)} learners, {len(exercises)} exercises.</p><table><tr><th>exercise</th>"
             "<th>success rate</th><th>right / wrong / not answered / errored</th>"
             "<th>misconceptions the checkers named (learners)</th></tr>"]
    for row in sorted(rows, key=lambda r: r["success rate"]):
        slips = "".join(f"<li>{html.escape(text)} ({count})</li>" for text, count in row["misconceptions"])
        parts.append(f"<tr><td>{row['exercise']}</td><td>{row['success rate']:.0%}</td><td>{row[RIGHT]} / "
                     f"{row[WRONG]} / {row[NOT_ANSWERED]} / {row[ERRORED]}</td>"
                     f"<td><ul>{slips}</ul></td></tr>")
    parts.append("</table>")
    flagged = {learner: found for learner, found in flags.items() if found}
    if flagged:
        parts.append("<h2>Notebooks to look at</h2><ul>" + "".join(
            f"<li>{html.escape(learner)}: {html.escape('; '.join(found))}</li>"
            for learner, found in flagged.items()) + "</ul>")
    page = PAGE.format(title="Class summary", body="".join(parts))
    (out / "summary.html").write_text(page, encoding="utf-8")
    return {"learners": len(table), "exercises": rows, "flags": flagged}
