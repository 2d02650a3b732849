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

The student *book* (:func:`build_student_book`) is the whole book built with the Sphinx option
``roughgp_student_book`` of this module's extension (:func:`setup`, loaded by the book's
``_config.yml``): after sphinx-exercise has merged each gated solution into one solution node, the
extension removes those nodes, so the chapters and the labs' tasks are as in the book and every
solution (code and written answers) is left out. (sphinx-exercise's own ``hide_solutions`` drops
only the opening directive of a gated solution: its content stays on the page, and the closing
node stops the HTML writer; sphinx-exercise 1.2.1.) It takes the executed notebooks from the
book's cache, so after ``make book`` (or ``make test``) it only renders; :func:`solutions_left`
checks its pages.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
LABS = ROOT / "notebooks"
OUT = BOOK / "_build" / "student"

_START = re.compile(r"^:::\{solution-start\}\s+(\S+)", re.M)
_END = re.compile(r"^:::\{solution-end\}", re.M)
_TASK = re.compile(r"^## Task (\d+): (.*)$", re.M)
_LABEL = re.compile(r":label:\s*(\S+)")
_SOLUTION_HTML = re.compile(r'class="[^"]*\bsolution\b[^"]*\badmonition\b')

__all__ = ["student_notebook", "write_student_edition", "student_book_config",
           "build_student_book", "solutions_left", "setup", "main"]


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


def student_book_config(out: Path, book: Path = BOOK, cache: Path | None = None) -> Path:
    """Write ``out/_config.yml``: the book's configuration with ``roughgp_student_book`` on
    (:func:`setup`) and the book's own notebook cache (``cache``, default
    ``book/_build/.jupyter_cache``), so the student book re-uses the book's executions."""
    import yaml

    from booktools.notebook_cache import CACHE

    config = yaml.safe_load((Path(book) / "_config.yml").read_text())
    sphinx = config.setdefault("sphinx", {})
    sphinx.setdefault("config", {})["roughgp_student_book"] = True
    # the local extensions' paths are relative to the book's folder: make them absolute
    sphinx["local_extensions"] = {name: str((Path(book) / path).resolve()) for name, path
                                  in (sphinx.get("local_extensions") or {}).items()}
    config.setdefault("execute", {})["cache"] = str(Path(cache or CACHE).resolve())
    config["title"] = f"{config.get('title', 'roughgp')} (student edition)"
    out.mkdir(parents=True, exist_ok=True)
    path = out / "_config.yml"
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    return path


def build_student_book(out: Path = OUT / "book", book: Path = BOOK) -> Path:
    """Build the book without the labs' solutions into ``out``; returns the HTML folder.
    Raises ``RuntimeError`` with the build's last output when the build fails."""
    config = student_book_config(Path(out), book)
    command = [str(Path(sys.executable).with_name("jupyter-book")), "build", "-W", "-n",
               "--keep-going", "--path-output", str(out), "--config", str(config), str(book)]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"the student book did not build ({done.returncode}):\n"
                           f"{(done.stdout + done.stderr)[-4000:]}")
    return Path(out) / "_build" / "html"


def solutions_left(html: Path) -> list[str]:
    """The pages of a built book (``html``) that still show a solution (a sphinx-exercise
    solution admonition, ``class="solution ... admonition"``)."""
    return [str(page.relative_to(html)) for page in sorted(Path(html).rglob("*.html"))
            if _SOLUTION_HTML.search(page.read_text(errors="replace"))]


def setup(app):
    """Sphinx extension (``sphinx.local_extensions`` of ``book/_config.yml``): with
    ``roughgp_student_book = True`` every sphinx-exercise solution is removed from the pages."""
    from sphinx.transforms import SphinxTransform

    class RemoveSolutions(SphinxTransform):
        default_priority = 11  # after sphinx-exercise merges the gated solutions (10)

        def apply(self):
            if not self.config.roughgp_student_book:
                return
            from sphinx_exercise.nodes import solution_node

            for node in list(self.document.findall(solution_node)):
                node.parent.remove(node)

    app.add_config_value("roughgp_student_book", False, "env")
    app.add_transform(RemoveSolutions)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m booktools.student",
                                     description="Write the labs without their solutions.")
    parser.add_argument("--out", type=Path, default=OUT, help=f"folder (default {OUT})")
    parser.add_argument("--no-book", action="store_true",
                        help="write the notebooks and the zip only, not the student book")
    args = parser.parse_args(argv)
    written = write_student_edition(out=args.out)
    for path in written:
        print(f"wrote {path}")
    print(f"wrote {args.out / 'roughgp-labs-student.zip'}")
    if not args.no_book:
        print("building the book without solutions (the notebooks come from the book's cache)")
        html = build_student_book(args.out / "book")
        left = solutions_left(html)
        if left:
            print(f"error: solutions left in the student book: {left}", file=sys.stderr)
            return 1
        print(f"wrote {html} (no solution on any page): open {html / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
