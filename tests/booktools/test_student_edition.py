"""The student edition of the labs (``make student``): no solution left, and a student who runs
a lab from the top stops at the first blank with the lab's own message.

The reference edition is the other side: every ``book/labs/*.ipynb`` passes its self-checks as a
notebook test item (conftest.py)."""

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
