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


def _solution_code(nb):
    return student.solution_lines(nb)[0]


@pytest.fixture(scope="module")
def edition(tmp_path_factory):
    out = tmp_path_factory.mktemp("student")
    return out, student.write_student_edition(out=out)


def test_every_lab_has_gated_solutions():
    assert len(LABS) >= 8
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
        # a solution line that the given code, a self-check or a task's text repeats may stay
        source = " ".join(source.split())
        left = [ln for ln in _solution_code(ref) if ln in source]
        assert not left, f"{path.name} still holds solution code: {left[:3]}"
        assert "reference solutions are collapsed" not in text
        assert student.REFERENCE_ONLY not in text
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

**Question.** Why forty-two?

:::{solution-start} lab9-task1
:class: dropdown
:::

**Answer.** A SECOND-GATED-SOLUTION of the same exercise, as the labs' written answers are.

:::{solution-end}
:::
"""


def _cell(kind, source, output=None):
    if kind == "markdown":
        return nbformat.v4.new_markdown_cell(source)
    cell = nbformat.v4.new_code_cell(source, execution_count=1)
    if output:
        cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text=output)]
    return cell


def _tiny_lab():
    """A lab with stored outputs (the tiny book does not execute): a given cell, a task, its
    solution (code with an output), a self-check, and a note of the reference edition."""
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [
        _cell("markdown", "# Lab 8\n\nThe lab's introduction."),
        _cell("markdown", f":::{{note}}\n:class: {student.REFERENCE_ONLY}\n"
                          "REFERENCE-ONLY-NOTE: the solutions are collapsed.\n:::"),
        _cell("code", "GIVEN_NUMBER = 6", "GIVEN-OUTPUT\n"),
        _cell("markdown", "## Task 1: the answer\n\n:::{exercise} Lab 8, task 1\n:nonumber:\n"
                          ":label: lab8-task1\n\nCompute `answer_value`.\n:::"),
        _cell("markdown", ":::{solution-start} lab8-task1\n:class: dropdown\n:::"),
        _cell("code", "answer_value = GIVEN_NUMBER * 7  # the solution",
              "SOLUTION-OUTPUT\n"),
        _cell("markdown", ":::{solution-end}\n:::"),
        _cell("code", "# self-check\nassert answer_value == 42\nprint(answer_value)",
              "SELF-CHECK-OUTPUT-42\n"),
    ]
    return nb


def _tiny_book(root):
    """A page with a written solution, and a lab in ``../notebooks`` that the book reaches
    through the link ``labs`` (as the real book does)."""
    root.mkdir()
    notebooks = root.parent / "notebooks"
    notebooks.mkdir()
    nbformat.write(_tiny_lab(), notebooks / "lab8.ipynb")
    (root / "labs").symlink_to(notebooks, target_is_directory=True)
    (root / "_config.yml").write_text(
        "title: tiny\nonly_build_toc_files: true\nexecute:\n  execute_notebooks: 'off'\n"
        "parse:\n  myst_enable_extensions: [colon_fence]\n"
        "sphinx:\n  extra_extensions: [sphinx_exercise]\n"
        f"  local_extensions:\n    student: {student.ROOT / 'booktools'}\n")
    (root / "_toc.yml").write_text("format: jb-book\nroot: lab\nchapters:\n  - file: labs/lab8\n")
    (root / "lab.md").write_text(_PAGE)
    return root


def test_the_student_book_hides_every_solution_the_reference_book_shows(tmp_path):
    book = _tiny_book(tmp_path / "book")
    config = student.student_book_config(tmp_path / "cfg", book, cache=tmp_path / "cache")
    text = config.read_text()
    assert "roughgp_student_book: true" in text and str((tmp_path / "cache").resolve()) in text
    html = student.build_student_book(tmp_path / "student", book)
    page = (html / "lab.html").read_text()
    assert "Compute the answer" in page and "Why forty-two?" in page
    assert "FORTY-TWO-SOLUTION" not in page and "SECOND-GATED-SOLUTION" not in page
    assert student.solutions_left(html) == []
    # the reference build of the same page shows the solution, and the check finds it
    reference = tmp_path / "reference"
    import subprocess
    import sys
    subprocess.run([str(Path(sys.executable).with_name("jupyter-book")), "build",
                    "--path-output", str(reference), str(book)], check=True,
                   capture_output=True)
    shown = reference / "_build" / "html"
    # an exercise may have several gated solutions (its code, then a written answer): each is
    # merged on its own (sphinx-exercise labels each), and each is shown
    page = (shown / "lab.html").read_text()
    assert "FORTY-TWO-SOLUTION" in page and "SECOND-GATED-SOLUTION" in page
    assert page.count("Solution to") == 2
    assert student.solutions_left(shown) == ["lab.html", "labs/lab8.html"]


def test_no_file_of_the_student_build_holds_solution_code(tmp_path):
    """Every file of the student build (pages, _sources, search index, notebooks, zip) is
    searched for the solution's code: nothing in the student build, and the same search finds
    it in the reference build, in the page, its _sources and the executed notebook."""
    book = _tiny_book(tmp_path / "book")
    out = tmp_path / "student"
    labs = tmp_path / "notebooks"
    student.write_student_edition(labs, out)
    html = student.build_student_book(out / "book", book)
    assert student.solution_code_left(out, labs=labs, book=book) == []
    assert sorted(p.name for p in out.rglob("*.ipynb")) == ["lab8.ipynb", "lab8.ipynb"]
    page = (html / "labs" / "lab8.html").read_text()
    assert "GIVEN-OUTPUT" in page and "Compute" in page
    for hidden in ("SOLUTION-OUTPUT", "SELF-CHECK-OUTPUT-42", "REFERENCE-ONLY-NOTE"):
        assert hidden not in page
    served = nbformat.read(html / "_sources" / "labs" / "lab8.ipynb", as_version=4)
    assert "raise NotImplementedError" in served.cells[-2].source
    assert not (out / "book" / "_build" / "jupyter_execute").exists()
    # the reference build of the same book: the search finds the solution in each place
    reference = tmp_path / "reference"
    import subprocess
    import sys
    subprocess.run([str(Path(sys.executable).with_name("jupyter-book")), "build",
                    "--path-output", str(reference), str(book)], check=True,
                   capture_output=True)
    leaks = student.solution_code_left(reference, labs=labs, book=book)
    where = {leak.split(":")[0] for leak in leaks}
    assert {"_build/html/labs/lab8.html", "_build/html/_sources/labs/lab8.ipynb"} <= where, leaks
    assert "answer_value = GIVEN_NUMBER * 7 # the solution" in leaks[0]
    shown = (reference / "_build" / "html" / "labs" / "lab8.html").read_text()
    assert "SELF-CHECK-OUTPUT-42" in shown and "REFERENCE-ONLY-NOTE" in shown


def test_a_failed_student_build_leaves_nothing_in_the_hand_out(tmp_path):
    """A build that fails (here a broken reference, an error under -W) leaves neither the
    reference runs (jupyter_execute, doctrees) nor a half-built book behind."""
    book = _tiny_book(tmp_path / "book")
    (book / "lab.md").write_text(_PAGE + "\nSee {doc}`no-such-page`.\n")
    out = tmp_path / "student" / "book"
    with pytest.raises(RuntimeError, match="did not build"):
        student.build_student_book(out, book)
    assert not (out / "_build").exists() and not (out / "_config.yml").exists()


def test_make_student_removes_its_hand_out_when_it_fails(tmp_path, monkeypatch, capsys):
    out = tmp_path / "student"
    out.mkdir()
    (out / "kept.txt").write_text("not written by make student")

    def broken_build(folder):
        (folder / "_build" / "jupyter_execute").mkdir(parents=True)
        (folder / "_build" / "html").mkdir()
        raise RuntimeError("the student book did not build")
    monkeypatch.setattr(student, "build_student_book", broken_build)
    with pytest.raises(RuntimeError):
        student.main(["--out", str(out)])
    assert sorted(p.name for p in out.iterdir()) == ["kept.txt"]
    assert "nothing to hand out" in capsys.readouterr().err
    # a leak found by the scan: exit 1, and nothing handed out either
    monkeypatch.setattr(student, "solution_code_left", lambda folder: ["lab1.ipynb: x = 1"])
    assert student.main(["--out", str(out), "--no-book"]) == 1
    assert sorted(p.name for p in out.iterdir()) == ["kept.txt"]
    (out / "kept.txt").unlink()
    assert student.main(["--out", str(out), "--no-book"]) == 1
    assert not out.exists(), "an output folder left empty is removed"


@pytest.mark.parametrize("lab", LABS, ids=lambda p: p.stem)
def test_no_self_check_shows_a_solution(lab):
    """A self-check tests the student's result; it never holds an expression of the reference
    solution (which the student edition would hand out with the task)."""
    from booktools.student import self_check_leaks

    assert self_check_leaks(nbformat.read(lab, as_version=4)) == []


def test_a_self_check_that_shows_the_solution_is_found():
    from booktools.student import self_check_leaks

    cells = [nbformat.v4.new_markdown_cell(":::{solution-start} t1\n:::"),
             nbformat.v4.new_code_cell("freqs = fourier.frequency_grid(N, d)\nsq = float(np.std(z))"),
             nbformat.v4.new_markdown_cell(":::{solution-end}\n:::"),
             nbformat.v4.new_code_cell("# self-check\nassert np.allclose(freqs, "
                                       "fourier.frequency_grid(N, d))\nassert sq > 0")]
    nb = nbformat.v4.new_notebook(cells=cells)
    assert self_check_leaks(nb) == ["cell 3: fourier.frequency_grid(N, d)"]


def test_the_student_notebooks_hold_no_raw_role():
    """A notebook opened in Jupyter shows MyST roles as raw text: the student edition writes
    them out ({doc}`../running` as "the book's page running")."""
    assert student.plain_roles("see {doc}`../running` and {doc}`the ladder <model_ladder>`") \
        == "see the book's page running and the ladder"
    for lab in LABS:
        text = "\n".join(c.source for c in student.student_notebook(
            nbformat.read(lab, as_version=4)).cells if c.cell_type == "markdown")
        assert not re.search(r"\{(doc|ref|numref|cite[:a-z]*)\}`", text), lab.name
