"""The student edition of the labs (``make student``): no solution left, and a student who runs
a lab from the top stops at the first blank with the lab's own message.

The reference edition is the other side: every ``notebooks/*.ipynb`` passes its self-checks as an
nbmake test item (conftest.py)."""

import re
import zipfile
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

from booktools import student

LABS = sorted(student.LABS.glob("lab*.ipynb"))


def _code_lines(nb):
    """The code lines (stripped, longer than a trivial line) inside the reference solutions,
    and those outside them (the given code and the self-checks)."""
    inside_lines, outside_lines, inside = [], [], False
    for cell in nb.cells:
        if cell.cell_type == "markdown" and "{solution-start}" in cell.source:
            inside = True
        elif cell.cell_type == "markdown" and "{solution-end}" in cell.source:
            inside = False
        elif cell.cell_type == "code":
            lines = [ln.strip() for ln in cell.source.splitlines() if len(ln.strip()) > 12]
            (inside_lines if inside else outside_lines).extend(lines)
    return inside_lines, outside_lines


def _solution_code(nb):
    return _code_lines(nb)[0]


@pytest.fixture(scope="module")
def edition(tmp_path_factory):
    out = tmp_path_factory.mktemp("student")
    return out, student.write_student_edition(out=out)


def test_every_lab_has_gated_solutions():
    assert len(LABS) == 6
    for path in LABS:
        nb = nbformat.read(path, as_version=4)
        assert _solution_code(nb), f"{path.name}: no solution-start/solution-end code"


def test_no_solution_is_left(edition):
    out, written = edition
    assert [p.name for p in written] == [p.name for p in LABS]
    for ref_path, path in zip(LABS, written):
        text = path.read_text()
        for marker in ("solution-start", "solution-end", "--- solution ---", "{exercise}",
                       ":label:", '"solution"'):
            assert marker not in text, f"{path.name} still holds {marker!r}"
        source = "\n".join(c.source for c in nbformat.read(path, as_version=4).cells
                           if c.cell_type == "code")
        ref = nbformat.read(ref_path, as_version=4)
        solution, given = _code_lines(ref)
        # a solution line that the given code or a self-check repeats may stay
        left = [ln for ln in solution if ln in source and ln not in given]
        assert not left, f"{path.name} still holds solution code: {left[:3]}"
        assert source.count("raise NotImplementedError(") >= 1
    with zipfile.ZipFile(out / "roughgp-labs-student.zip") as z:
        assert sorted(z.namelist()) == sorted(f"roughgp-labs/{p.name}" for p in LABS)


def test_the_given_code_and_the_self_checks_stay(edition):
    _, written = edition
    for ref_path, path in zip(LABS, written):
        ref = nbformat.read(ref_path, as_version=4)
        new = nbformat.read(path, as_version=4)
        checks = [c.source for c in ref.cells if c.cell_type == "code"
                  and c.source.startswith("# self-check")]
        assert checks and checks == [c.source for c in new.cells if c.cell_type == "code"
                                     and c.source.startswith("# self-check")]


@pytest.mark.parametrize("index", range(len(LABS)), ids=[p.stem for p in LABS])
def test_a_student_run_stops_at_the_first_blank(edition, index):
    _, written = edition
    nb = nbformat.read(written[index], as_version=4)
    first_task = re.search(r"^## Task 1: (.*)$", "\n".join(c.source for c in nb.cells), re.M)
    with pytest.raises(CellExecutionError) as info:
        NotebookClient(nb, timeout=300, resources={"metadata": {"path": str(student.LABS)}}
                       ).execute()
    message = str(info.value)
    assert "NotImplementedError" in message and "NameError" not in message
    assert f"Task 1 ({first_task.group(1).strip()}) is not solved yet" in message


_PAGE = """# A lab

:::{exercise} Lab 9, task 1
:nonumber:
:label: lab9-task1

Compute the answer.
:::

:::{solution-start} lab9-task1
:class: dropdown
:::

The answer is FORTY-TWO-SOLUTION.

:::{solution-end}
:::
"""


def _tiny_book(root):
    root.mkdir()
    (root / "_config.yml").write_text(
        "title: tiny\nonly_build_toc_files: true\nexecute:\n  execute_notebooks: 'off'\n"
        "parse:\n  myst_enable_extensions: [colon_fence]\n"
        "sphinx:\n  extra_extensions: [sphinx_exercise]\n"
        f"  local_extensions:\n    student: {student.ROOT / 'booktools'}\n")
    (root / "_toc.yml").write_text("format: jb-book\nroot: lab\n")
    (root / "lab.md").write_text(_PAGE)
    return root


def test_the_student_book_hides_every_solution_the_reference_book_shows(tmp_path):
    book = _tiny_book(tmp_path / "book")
    config = student.student_book_config(tmp_path / "cfg", book, cache=tmp_path / "cache")
    text = config.read_text()
    assert "roughgp_student_book: true" in text and str((tmp_path / "cache").resolve()) in text
    html = student.build_student_book(tmp_path / "student", book)
    page = (html / "lab.html").read_text()
    assert "Compute the answer" in page and "FORTY-TWO-SOLUTION" not in page
    assert student.solutions_left(html) == []
    # the reference build of the same page shows the solution, and the check finds it
    reference = tmp_path / "reference"
    import subprocess
    import sys
    subprocess.run([str(Path(sys.executable).with_name("jupyter-book")), "build",
                    "--path-output", str(reference), str(book)], check=True,
                   capture_output=True)
    shown = reference / "_build" / "html"
    assert "FORTY-TWO-SOLUTION" in (shown / "lab.html").read_text()
    assert student.solutions_left(shown) == ["lab.html"]
