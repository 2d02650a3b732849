"""The student edition of the labs: ``make student`` (``python -m booktools.student``).

The labs in ``book/labs/`` are the reference edition: each task is a sphinx-exercise
``exercise``, and its reference solution (code cells, or a written answer) sits between the
gated directives ``solution-start`` and ``solution-end``, so that the tests run every lab and the
book shows the solutions collapsed. The student edition keeps everything else (the text, the
given code, the self-checks) and puts in place of each solution

* for code, a cell that stops the notebook with the lab's own message until the student has
  written their solution there (``NotImplementedError: Task 2 (circulant embedding) is not solved
  yet ...``), so a student running the notebook from the top stops at the first blank, not at a
  ``NameError`` in the next self-check;
* for a written answer, an empty "Your answer" cell.

The MyST directives become plain Markdown (the notebooks are opened in Jupyter, not in Sphinx),
outputs are cleared, and the notebooks are also packed into one zip for handing out.
"""

from __future__ import annotations

import argparse
import re
import sys
import zipfile
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
LABS = ROOT / "book" / "labs"
OUT = ROOT / "book" / "_build" / "student"

_START = re.compile(r"^:::\{solution-start\}\s+(\S+)", re.M)
_END = re.compile(r"^:::\{solution-end\}", re.M)
_TASK = re.compile(r"^## Task (\d+): (.*)$", re.M)
_LABEL = re.compile(r":label:\s*(\S+)")

__all__ = ["student_notebook", "write_student_edition", "main"]


def _plain_exercise(source: str) -> str:
    """An ``exercise`` directive's Markdown without the directive's fences and options."""
    lines = [line for line in source.splitlines()
             if not re.match(r"^:::(\{exercise\}.*)?\s*$", line)
             and not line.startswith((":label:", ":nonumber:"))]
    return re.sub(r"\n{3,}", "\n\n", "\n".join(lines)).strip()


def _tasks(nb) -> dict[str, str]:
    """Each exercise's label -> ``Task N (title)``."""
    tasks = {}
    for cell in nb.cells:
        if cell.cell_type == "markdown" and "{exercise}" in cell.source:
            task, label = _TASK.search(cell.source), _LABEL.search(cell.source)
            if task and label:
                tasks[label.group(1)] = f"Task {task.group(1)} ({task.group(2).strip()})"
    return tasks


def student_notebook(nb):
    """The student edition of the lab notebook ``nb`` (an nbformat node; a new one is
    returned). Raises ``ValueError`` for a ``solution-start`` without its ``solution-end``."""
    tasks = _tasks(nb)
    cells, inside, label = [], False, None
    for cell in nb.cells:
        if cell.cell_type == "markdown" and _START.search(cell.source):
            if inside:
                raise ValueError(f"solution-start {label} is not closed before the next one")
            inside, label, blanked = True, _START.search(cell.source).group(1), set()
            continue
        if cell.cell_type == "markdown" and _END.search(cell.source):
            if not inside:
                raise ValueError("solution-end without solution-start")
            inside = False
            continue
        if inside:
            task = tasks.get(label, label)
            if cell.cell_type == "code" and "code" not in blanked:
                blanked.add("code")
                cells.append(nbformat.v4.new_code_cell(
                    f"# {task}: your solution goes here; then delete the next line and run "
                    f"the self-check below\n"
                    f"raise NotImplementedError({task + ' is not solved yet: write your solution in this cell'!r})"))
            elif cell.cell_type == "markdown" and "answer" not in blanked:
                blanked.add("answer")
                cells.append(nbformat.v4.new_markdown_cell(f"**Your answer ({task}).** ..."))
            continue
        new = nbformat.from_dict(dict(cell))
        if new.cell_type == "markdown" and "{exercise}" in new.source:
            new.source = _plain_exercise(new.source)
        if new.cell_type == "code":
            new.outputs, new.execution_count = [], None
        new.metadata = {}
        cells.append(new)
    if inside:
        raise ValueError(f"solution-start {label} is never closed")
    out = nbformat.v4.new_notebook(metadata=dict(nb.metadata))
    out.cells = cells
    return out


def write_student_edition(labs: Path = LABS, out: Path = OUT) -> list[Path]:
    """Write the student edition of every ``labs/lab*.ipynb`` into ``out`` (same names) and
    ``out/roughgp-labs-student.zip``; returns the notebooks' paths."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for path in sorted(Path(labs).glob("lab*.ipynb")):
        nb = student_notebook(nbformat.read(path, as_version=4))
        target = out / path.name
        nbformat.write(nb, target)
        written.append(target)
    with zipfile.ZipFile(out / "roughgp-labs-student.zip", "w", zipfile.ZIP_DEFLATED) as z:
        for path in written:
            z.write(path, f"roughgp-labs/{path.name}")
    return written


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m booktools.student",
                                     description="Write the labs without their solutions.")
    parser.add_argument("--out", type=Path, default=OUT, help=f"folder (default {OUT})")
    args = parser.parse_args(argv)
    written = write_student_edition(out=args.out)
    for path in written:
        print(f"wrote {path}")
    print(f"wrote {args.out / 'roughgp-labs-student.zip'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
