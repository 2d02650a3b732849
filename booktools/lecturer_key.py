"""The lecturer's key to the labs: ``book/_build/lecturer/key.md``, written by ``make student``.

The reference edition of a lab (``notebooks/lab*.ipynb``) holds each task's reference solution
between the gated directives ``solution-start`` and ``solution-end`` (:mod:`booktools.student`):
code cells, and written answers. A written answer is a Markdown cell starting with
``**Answer.**``, gated with the label of the exercise its question belongs to, right after the
question (a Markdown cell with a paragraph starting ``**Question.**``, ``**Questions.**`` or
``**Question: why?**``); a task may have several gated solutions (its code, then the answers
to its questions), and the student edition puts a blank in place of each.

The key (:func:`write_key`) gathers them into one Markdown document for the lecturer: per lab a
heading, per task its text, its reference solution code in fenced ``python`` blocks, and each
of its questions with the model answer. MyST roles are written out as text
(:func:`booktools.student.plain_roles`); a number that the lab computes when it runs (glued into
the book's page with ``{glue:text}``) is shown by its name in square brackets, ``[lab6_tau1]``.

``make student`` (:func:`booktools.student.main`) writes the key after the student edition has
been written and checked, beside the student folder (``book/_build/lecturer/`` beside
``book/_build/student/``), never inside it: it is not part of the hand-out, and the scan of the
hand-out for solution code runs before it exists. A run that fails removes the key as well as
its hand-out (a key left from an earlier run included): after ``make student`` the key is there
exactly when a checked hand-out is. :func:`unanswered_questions` lists the questions that have
no gated answer; the key names them at its top (the tests require none).
"""

from __future__ import annotations

import argparse
import dataclasses
import re
import sys
from pathlib import Path

import nbformat

from booktools.student import (
    BOOK,
    EXERCISE_LABEL,
    LABS,
    SOLUTION_END,
    SOLUTION_START,
    TASK_HEADING,
    plain_exercise,
    plain_roles,
)

KEY = BOOK / "_build" / "lecturer" / "key.md"

QUESTION = re.compile(r"^\*\*Questions?\b", re.M)
ANSWER = re.compile(r"^\*\*Answer\b")
_GLUE = re.compile(r"\{glue(?::\w+)?\}`([^`:]+)(?::[^`]*)?`")
_TITLE = re.compile(r"^# (.+)$", re.M)

__all__ = ["KEY", "QUESTION", "ANSWER", "Task", "lab_tasks", "unanswered_questions",
           "key_text", "lab_key", "write_key", "remove_key", "main"]


@dataclasses.dataclass
class Task:
    """One exercise of a lab: its label, heading (``Task N: title``) and text, its reference
    solution's code cells, and its written answers, each with the question it answers (None
    where the gated answer does not follow a question cell)."""

    label: str
    heading: str
    text: str
    code: list = dataclasses.field(default_factory=list)
    answers: list = dataclasses.field(default_factory=list)


def _is_markdown(cell, pattern) -> bool:
    return cell.cell_type == "markdown" and pattern.search(cell.source) is not None


def lab_tasks(nb) -> list[Task]:
    """The exercises of the lab ``nb`` in order, each with what its gated solutions hold.
    Raises ``ValueError`` for a gated solution that names no exercise before it."""
    tasks, inside, previous = {}, False, None
    for cell in nb.cells:
        if _is_markdown(cell, SOLUTION_START):
            label = SOLUTION_START.search(cell.source).group(1)
            if label not in tasks:
                raise ValueError(f"solution-start {label} names no exercise above it")
            inside, task = True, tasks[label]
            question = previous.source if previous is not None and _is_markdown(
                previous, QUESTION) else None
            continue
        if _is_markdown(cell, SOLUTION_END):
            inside = False
            continue
        if inside:
            if cell.cell_type == "code":
                task.code.append(cell.source)
            elif cell.cell_type == "markdown":
                task.answers.append((question, cell.source))
            continue
        previous = cell
        if cell.cell_type == "markdown" and "{exercise}" in cell.source:
            heading, label = TASK_HEADING.search(cell.source), EXERCISE_LABEL.search(cell.source)
            if heading and label:
                text = TASK_HEADING.sub("", plain_exercise(cell.source), count=1).strip()
                tasks[label.group(1)] = Task(label.group(1), heading.group(0)[3:].strip(), text)
    return list(tasks.values())


def unanswered_questions(nb) -> list[str]:
    """The question cells of the lab ``nb`` (outside the solutions) that are not followed at
    once by a gated solution of their task (the exercise above them) holding a Markdown cell
    that starts with ``**Answer``; one line each: ``cell N (label): the question's start``."""
    missing, label, inside = [], None, False
    cells = nb.cells
    for index, cell in enumerate(cells):
        if _is_markdown(cell, SOLUTION_START):
            inside = True
        elif _is_markdown(cell, SOLUTION_END):
            inside = False
        elif inside:
            continue
        elif cell.cell_type == "markdown" and "{exercise}" in cell.source:
            found = EXERCISE_LABEL.search(cell.source)
            label = found.group(1) if found else label
        elif _is_markdown(cell, QUESTION) and not _answered(cells, index + 1, label):
            start = cell.source[QUESTION.search(cell.source).start():].splitlines()[0]
            missing.append(f"cell {index} ({label}): {start[:80]}")
    return missing


def _answered(cells, index, label) -> bool:
    """Whether ``cells[index]`` opens a gated solution of ``label`` that holds an answer."""
    if index >= len(cells) or not _is_markdown(cells[index], SOLUTION_START):
        return False
    if SOLUTION_START.search(cells[index].source).group(1) != label:
        return False
    for cell in cells[index + 1:]:
        if _is_markdown(cell, SOLUTION_END):
            return False
        if cell.cell_type == "markdown" and ANSWER.match(cell.source.lstrip()):
            return True
    return False


def key_text(markdown: str) -> str:
    """``markdown`` of a lab as the key shows it: the book's roles as plain text, a glued
    number by its name in square brackets."""
    return plain_roles(_GLUE.sub(lambda match: f"[{match.group(1)}]", markdown)).strip()


def _fenced(code: str) -> str:
    longest = max((len(run) for run in re.findall(r"`+", code)), default=0)
    fence = "`" * max(3, longest + 1)
    return f"{fence}python\n{code.rstrip()}\n{fence}"


def lab_key(nb, name: str = "") -> str:
    """The key's Markdown for one lab: its title, then per task its text, its reference
    solution code and its questions with their answers."""
    first = next((c.source for c in nb.cells if c.cell_type == "markdown"), "")
    title = _TITLE.search(first)
    parts = [f"## {title.group(1).strip() if title else name}"]
    if name:
        parts.append(f"`notebooks/{name}`")
    for task in lab_tasks(nb):
        parts += [f"### {key_text(task.heading)}", key_text(task.text)]
        if task.code:
            parts.append("**Reference solution.**")
            parts += [_fenced(code) for code in task.code]
        for question, answer in task.answers:
            if question is not None:
                parts.append(key_text(question))
            parts.append(key_text(answer))
    return "\n\n".join(parts) + "\n"


_HEADER = """# The lecturer's key to the labs

For the lecturer, not for students: each lab's tasks with their reference solutions (the code)
and the model answers to the questions. Written by `make student` from the reference edition
(`notebooks/`, shown in the book with each solution collapsed); the student edition beside this
folder leaves all of it out. A number in square brackets, such as [lab6_tau1], is computed by
the lab when it runs: the lab's page in the book shows it.
"""


def write_key(path: Path = KEY, labs: Path = LABS) -> Path:
    """Write the key of every ``labs/lab*.ipynb`` to ``path`` (its folder is created);
    returns ``path``."""
    sections, missing = [], []
    for lab in sorted(Path(labs).glob("lab*.ipynb")):
        nb = nbformat.read(lab, as_version=4)
        sections.append(lab_key(nb, lab.name))
        missing += [f"- {lab.name}, {line}" for line in unanswered_questions(nb)]
    header = _HEADER
    if missing:
        header += "\n**Questions without a model answer:**\n\n" + "\n".join(missing) + "\n"
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join([header, *sections]), encoding="utf-8")
    return path


def remove_key(path: Path = KEY) -> None:
    """Remove the key at ``path``, and its folder if that leaves it empty."""
    path = Path(path)
    path.unlink(missing_ok=True)
    if path.parent.is_dir() and not any(path.parent.iterdir()):
        path.parent.rmdir()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m booktools.lecturer_key",
                                     description="Write the lecturer's key to the labs alone "
                                                 "(make student writes it too).")
    parser.add_argument("--out", type=Path, default=KEY, help=f"the key's path (default {KEY})")
    args = parser.parse_args(argv)
    print(f"wrote {write_key(args.out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
