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
outputs are cleared, a note meant for the reference edition only (a Markdown cell holding an
admonition with ``:class: reference-edition``) is dropped, and the notebooks are also packed into
one zip for handing out.

The student *book* (:func:`build_student_book`) is the whole book built with the Sphinx option
``roughgp_student_book`` of this module's extension (:func:`setup`, loaded by the book's
``_config.yml``): after sphinx-exercise has merged each gated solution into one solution node, the
extension removes those nodes, so the chapters and the labs' tasks are as in the book and every
solution (code and written answers) is left out; on a page that had a solution it also removes
the outputs of every code cell after the first one (the self-checks' outputs are the reference
run's numbers, and a figure drawn after a solution shows its result), and it removes the notes
with the class ``reference-edition``. After the build the page sources that the download button
serves (``_sources/**/*.ipynb``) are replaced by the student notebooks, and the executed
notebooks (``jupyter_execute``) and pickled doctrees are deleted; :func:`solution_code_left`
then looks in every file of the student build (pages, sources, search index, notebooks, zip) for
a line of solution code. (sphinx-exercise's own ``hide_solutions`` drops
only the opening directive of a gated solution: its content stays on the page, and the closing
node stops the HTML writer; sphinx-exercise 1.2.1.) It takes the executed notebooks from the
book's cache, so after ``make book`` (or ``make test``) it only renders; :func:`solutions_left`
checks its pages. A regressed claim of the ledger does not stop it (the claims chapter shows it
and runs to its end). When anything fails (the build, a solution left on a page, solution code
in a file) :func:`main` removes what it wrote, and a failed build leaves neither the reference
runs nor a half-built book: nothing is left to hand out by mistake.

The lecturer's key is the other side of the hand-out. When the student edition has been written
and checked, :func:`main` writes ``book/_build/lecturer/key.md`` (:mod:`booktools.lecturer_key`:
per lab and task the task's text, its reference solution code and the model answers to its
questions) beside the student folder, never inside it (``--key`` inside ``--out`` is refused);
a run that fails removes the key too, so the key is there exactly when a checked hand-out is.
The model answers are gated written answers (a Markdown cell starting with ``**Answer.**`` after
each question, with the label of the question's exercise): the student edition puts an empty
"Your answer" cell in place of each, and the student book leaves them out with the solutions.
"""

from __future__ import annotations

import argparse
import html as html_module
import io
import json
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
LABS = ROOT / "notebooks"
OUT = BOOK / "_build" / "student"

# The gated solution's directives, a task's heading and an exercise's label (also read by
# booktools.lecturer_key, which collects what these cells hold into the lecturer's key)
SOLUTION_START = re.compile(r"^:::\{solution-start\}\s+(\S+)", re.M)
SOLUTION_END = re.compile(r"^:::\{solution-end\}", re.M)
TASK_HEADING = re.compile(r"^## Task (\d+): (.*)$", re.M)
EXERCISE_LABEL = re.compile(r":label:\s*(\S+)")
_SOLUTION_HTML = re.compile(r'class="[^"]*\bsolution\b[^"]*\badmonition\b')
_TAG = re.compile(r"<[^>]+>")
# A note of the reference edition only ("the solutions are collapsed under each task ..."): an
# admonition with this class; the student notebooks and the student book leave it out.
REFERENCE_ONLY = "reference-edition"
# A solution line shorter than this (``z = f(x)``) is too generic to count as a leak.
MIN_LINE = 13

__all__ = ["REFERENCE_ONLY", "SOLUTION_START", "SOLUTION_END", "TASK_HEADING", "EXERCISE_LABEL",
           "student_notebook", "plain_exercise", "write_student_edition", "student_book_config",
           "build_student_book", "solutions_left", "solution_lines", "solution_code_left",
           "self_check_leaks", "plain_roles", "setup", "main"]


def plain_exercise(source: str) -> str:
    """An ``exercise`` directive's Markdown without the directive's fences and options."""
    lines = [line for line in source.splitlines()
             if not re.match(r"^:::(\{exercise\}.*)?\s*$", line)
             and not line.startswith((":label:", ":nonumber:"))]
    return re.sub(r"\n{3,}", "\n\n", "\n".join(lines)).strip()


def _is_reference_note(source: str) -> bool:
    return re.search(rf"^:class:.*\b{REFERENCE_ONLY}\b", source, re.M) is not None


def _tasks(nb) -> dict[str, str]:
    """Each exercise's label -> ``Task N (title)``."""
    tasks = {}
    for cell in nb.cells:
        if cell.cell_type == "markdown" and "{exercise}" in cell.source:
            task, label = TASK_HEADING.search(cell.source), EXERCISE_LABEL.search(cell.source)
            if task and label:
                tasks[label.group(1)] = f"Task {task.group(1)} ({task.group(2).strip()})"
    return tasks


_ROLE = re.compile(r"\{(doc|ref|numref|eq|download|cite:p|cite:t|cite)\}`([^`]*)`")


def plain_roles(markdown: str) -> str:
    """``markdown`` with the book's MyST roles as plain text, for a notebook opened outside the
    book: ``{doc}`title <page>``` becomes "title", ``{doc}`../running``` becomes "the book's
    page running"; other roles keep their text."""
    def plain(match):
        role, text = match.group(1), match.group(2).strip()
        title, _, target = text.partition("<")
        if target:
            return title.strip()
        if role == "doc":
            return f"the book's page {Path(text).name}"
        return text
    return _ROLE.sub(plain, markdown)


def student_notebook(nb):
    """The student edition of the lab notebook ``nb`` (an nbformat node; a new one is
    returned). Raises ``ValueError`` for a ``solution-start`` without its ``solution-end``."""
    tasks = _tasks(nb)
    cells, inside, label = [], False, None
    for cell in nb.cells:
        if cell.cell_type == "markdown" and SOLUTION_START.search(cell.source):
            if inside:
                raise ValueError(f"solution-start {label} is not closed before the next one")
            inside, label, blanked = True, SOLUTION_START.search(cell.source).group(1), set()
            continue
        if cell.cell_type == "markdown" and SOLUTION_END.search(cell.source):
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
        if cell.cell_type == "markdown" and _is_reference_note(cell.source):
            continue
        new = nbformat.from_dict(dict(cell))
        if new.cell_type == "markdown" and "{exercise}" in new.source:
            new.source = plain_exercise(new.source)
        if new.cell_type == "markdown":
            new.source = plain_roles(new.source)
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
    Raises ``RuntimeError`` with the build's last output when the build fails.

    After the build, each page source that holds solutions (``_sources/<page>.ipynb``, what the
    page's download button serves) is replaced by its student notebook, and the build's
    executed notebooks (``jupyter_execute``, the reference runs) and pickled doctrees are
    deleted: the student build keeps only what is handed out. They are deleted whatever
    happens (in a ``finally``), and a build that fails leaves nothing of itself in ``out``
    (its ``_build`` and ``_config.yml`` are removed: a half-built book is no hand-out)."""
    out = Path(out)
    config = student_book_config(out, book)
    build = out / "_build"
    command = [str(Path(sys.executable).with_name("jupyter-book")), "build", "-W", "-n",
               "--keep-going", "--path-output", str(out), "--config", str(config), str(book)]
    built = False
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"the student book did not build ({done.returncode}):\n"
                               f"{(done.stdout + done.stderr)[-4000:]}")
        html = build / "html"
        # the served copies, mapped back to their sources (book/labs is a link: rglob of the
        # book would not enter it)
        for served in sorted((html / "_sources").rglob("*.ipynb")):
            source = Path(book) / served.relative_to(html / "_sources")
            if source.is_file() and "solution-start" in source.read_text():
                nbformat.write(student_notebook(nbformat.read(source, as_version=4)), served)
        built = True
        return html
    finally:
        for folder in ("jupyter_execute", ".doctrees"):
            shutil.rmtree(build / folder, ignore_errors=True)
        if not built:
            shutil.rmtree(build, ignore_errors=True)
            config.unlink(missing_ok=True)


def solution_lines(nb) -> tuple[list[str], list[str]]:
    """The code lines inside the reference solutions of the lab ``nb`` that no other cell
    holds (stripped, whitespace collapsed, at least :data:`MIN_LINE` characters): what must not
    appear in the student edition. Also returns the text outside the solutions, line by line
    (the given code, the self-checks, the tasks' text), which may appear."""
    inside_lines, outside_lines, inside = [], [], False
    for cell in nb.cells:
        if cell.cell_type == "markdown" and SOLUTION_START.search(cell.source):
            inside = True
            continue
        if cell.cell_type == "markdown" and SOLUTION_END.search(cell.source):
            inside = False
            continue
        lines = [" ".join(line.split()) for line in cell.source.splitlines()]
        if inside and cell.cell_type == "code":
            inside_lines.extend(line for line in lines if len(line) >= MIN_LINE)
        elif not inside:
            outside_lines.extend(lines)
    outside = " ".join(outside_lines)   # a task's text may break a call across its lines
    return [line for line in inside_lines if line not in outside], outside_lines


_LIBRARY_NAMES = {"np", "math", "plt", "print", "len", "float", "int", "abs", "range", "zip",
                  "min", "max", "sum", "list", "dict", "tuple", "round", "sorted", "isinstance",
                  "enumerate", "str", "set", "any", "all", "next", "bool"}


def _solution_expressions(source: str) -> set[str]:
    """The right-hand sides of a solution cell's assignments, and its calls of anything but
    Python's and numpy's own functions (unparsed), from 14 characters on; plain reads of a field
    or an item (``result.samples["x"]``) are not a solution."""
    import ast

    def root(node):
        while isinstance(node, (ast.Attribute, ast.Call, ast.Subscript)):
            node = node.func if isinstance(node, ast.Call) else node.value
        return node.id if isinstance(node, ast.Name) else None

    def plain_access(node):
        while isinstance(node, (ast.Attribute, ast.Subscript)):
            node = node.value
        return isinstance(node, ast.Name)

    found = set()
    for node in ast.walk(ast.parse(source)):
        value = getattr(node, "value", None) if isinstance(
            node, (ast.Assign, ast.AugAssign, ast.AnnAssign)) else None
        if value is not None and not plain_access(value):
            found.add(ast.unparse(value))
        if isinstance(node, ast.Call) and root(node.func) not in _LIBRARY_NAMES:
            found.add(ast.unparse(node))
    return {text for text in found if len(text) >= 14}


def self_check_leaks(nb) -> list[str]:
    """Where a self-check (a code cell outside the solutions that starts with ``# self-check``)
    holds an expression of a reference solution (:func:`_solution_expressions`): a self-check
    tests the result and must not show the code. One line per leak: ``cell N: expression``."""
    import ast

    solutions, checks, inside = set(), [], False
    for index, cell in enumerate(nb.cells):
        if cell.cell_type == "markdown" and SOLUTION_START.search(cell.source):
            inside = True
        elif cell.cell_type == "markdown" and SOLUTION_END.search(cell.source):
            inside = False
        elif cell.cell_type == "code" and inside:
            solutions |= _solution_expressions(cell.source)
        elif cell.cell_type == "code" and cell.source.lstrip().startswith("# self-check"):
            checks.append((index, {ast.unparse(n) for n in ast.walk(ast.parse(cell.source))
                                   if isinstance(n, ast.expr)}))
    return [f"cell {index}: {text}" for index, shown in checks for text in sorted(shown & solutions)]


def _texts(path: Path, name: str):
    """(name, text) of a file of a build: HTML without its tags (highlighted code is split into
    spans), a notebook's cells and outputs, each member of a zip; whitespace collapsed."""
    data = path.read_bytes() if isinstance(path, Path) else path
    if name.endswith(".zip"):
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            for member in archive.namelist():
                yield from _texts(archive.read(member), f"{name}/{member}")
        return
    text = data.decode("utf-8", errors="replace")
    if name.endswith((".html", ".htm")):
        text = html_module.unescape(_TAG.sub("", text))
    elif name.endswith(".ipynb"):
        try:
            nb = nbformat.reads(text, as_version=4)
            text = "\n".join([c.source for c in nb.cells] + [
                json.dumps(c.get("outputs", []), ensure_ascii=False) for c in nb.cells])
        except Exception:  # not a notebook after all: look at the raw text
            pass
    yield name, " ".join(text.split())


def _public_text(book: Path, labs: Path) -> str:
    """The text of the book's pages outside the labs (chapters, landing page, running page):
    what is shown to every reader anyway, whitespace collapsed."""
    labs = Path(labs).resolve()
    texts = []
    for path in sorted(Path(book).glob("*.md")) + sorted(Path(book).glob("*.ipynb")):
        if path.resolve().parent == labs:
            continue
        if path.suffix == ".ipynb":
            texts.extend(c.source for c in nbformat.read(path, as_version=4).cells)
        else:
            texts.append(path.read_text(errors="replace"))
    return " ".join(" ".join(texts).split())


def solution_code_left(folder: Path, labs: Path = LABS, book: Path | None = BOOK) -> list[str]:
    """Every file under ``folder`` (a student build: pages, ``_sources``, search index,
    notebooks, zip members) that holds a line of a lab's solution code (:func:`solution_lines`
    of each ``labs/lab*.ipynb``), as ``"file: line"``; empty when nothing leaked. A solution
    line that a page of ``book`` outside the labs shows too (a library call the landing page
    teaches) is public, not a leak."""
    public = _public_text(book, labs) if book is not None else ""
    lines = sorted({line for path in sorted(Path(labs).glob("*.ipynb"))
                    for line in solution_lines(nbformat.read(path, as_version=4))[0]
                    if line not in public})
    found = []
    for path in sorted(Path(folder).rglob("*")):
        if not path.is_file():
            continue
        for name, text in _texts(path, str(path.relative_to(folder))):
            found.extend(f"{name}: {line}" for line in lines if line in text)
    return found


def solutions_left(html: Path) -> list[str]:
    """The pages of a built book (``html``) that still show a solution (a sphinx-exercise
    solution admonition, ``class="solution ... admonition"``)."""
    return [str(page.relative_to(html)) for page in sorted(Path(html).rglob("*.html"))
            if _SOLUTION_HTML.search(page.read_text(errors="replace"))]


def setup(app):
    """Sphinx extension (``sphinx.local_extensions`` of ``book/_config.yml``). With
    ``roughgp_student_book = True`` every sphinx-exercise solution is removed from the pages,
    and on a page that had one, the outputs of the code cells after the first solution and the
    notes of class :data:`REFERENCE_ONLY`."""
    from docutils import nodes
    from sphinx.transforms import SphinxTransform

    class RemoveSolutions(SphinxTransform):
        default_priority = 11  # after sphinx-exercise merges the gated solutions (10)

        def apply(self):
            if not self.config.roughgp_student_book:
                return
            from sphinx_exercise.nodes import solution_node

            solutions = list(self.document.findall(solution_node))
            if not solutions:
                return
            after, remove = False, []
            for node in self.document.findall(nodes.Element):
                if isinstance(node, solution_node):
                    after = True
                elif REFERENCE_ONLY in node.get("classes", ()):
                    remove.append(node)
                elif after and node.get("nb_element") == "cell_code_output":
                    remove.append(node)
            for node in solutions + remove:
                if node.parent is not None:
                    node.parent.remove(node)

    app.add_config_value("roughgp_student_book", False, "env")
    app.add_transform(RemoveSolutions)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def _discard(out: Path, written: list[Path]) -> None:
    """Remove what a failed ``make student`` wrote into ``out`` (the student notebooks, the zip,
    the student book), and ``out`` itself if that leaves it empty: no half hand-out."""
    for path in [*written, out / "roughgp-labs-student.zip", out / "book" / "_config.yml"]:
        path.unlink(missing_ok=True)
    shutil.rmtree(out / "book" / "_build", ignore_errors=True)
    for folder in (out / "book", out):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m booktools.student",
                                     description="Write the labs without their solutions, and "
                                                 "the lecturer's key beside them.")
    parser.add_argument("--out", type=Path, default=OUT, help=f"folder (default {OUT})")
    parser.add_argument("--no-book", action="store_true",
                        help="write the notebooks and the zip only, not the student book")
    parser.add_argument("--key", type=Path, default=None,
                        help="the lecturer's key (default: lecturer/key.md beside the folder, "
                             "book/_build/lecturer/key.md); never inside the folder")
    args = parser.parse_args(argv)
    args.key = args.key or args.out.parent / "lecturer" / "key.md"
    if args.key.resolve().is_relative_to(args.out.resolve()):
        parser.error(f"the key {args.key} would lie inside the hand-out {args.out}")
    from booktools import lecturer_key  # it reads this module's patterns

    written, ok = [], False
    try:
        code = _write_and_check(args, written)
        ok = code == 0
        return code
    finally:
        if not ok:  # an error, a solution left or a leak: remove this run's hand-out and key
            _discard(args.out, written)
            lecturer_key.remove_key(args.key)
            print(f"error: nothing to hand out; removed what this run wrote in {args.out}, "
                  f"and the lecturer's key {args.key}", file=sys.stderr)


def _write_and_check(args, written: list[Path]) -> int:
    """:func:`main`'s work: write the notebooks (named in ``written`` before they are written,
    so that a failure midway removes them too), the zip and the book, then scan them, and last
    write the lecturer's key (:mod:`booktools.lecturer_key`) to ``args.key``; returns the exit
    code."""
    written.extend(sorted(args.out / p.name for p in LABS.glob("lab*.ipynb")))
    written[:] = write_student_edition(out=args.out)
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
        print(f"wrote {html}: open {html / 'index.html'}")
    leaked = solution_code_left(args.out)
    if leaked:
        print(f"error: solution code left in the student build: {leaked[:5]}", file=sys.stderr)
        return 1
    print(f"checked every file of {args.out}: no solution code")
    from booktools import lecturer_key

    key = lecturer_key.write_key(args.key)
    print(f"wrote {key}: the lecturer's key (the reference solutions and the model answers; "
          f"not part of the hand-out)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
