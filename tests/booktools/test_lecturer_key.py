"""The lecturer's key (``make student`` writes it beside the student edition): every reference
solution and every model answer of the labs in one document, every question of a lab answered,
the key never inside the hand-out, and the hand-out still without any answer."""

import nbformat
import pytest

from booktools import lecturer_key, student

LABS = sorted(student.LABS.glob("lab*.ipynb"))


def _gated_cells(nb):
    """The cells inside the gated solutions of ``nb``."""
    inside = False
    for cell in nb.cells:
        if cell.cell_type == "markdown" and student.SOLUTION_START.search(cell.source):
            inside = True
        elif cell.cell_type == "markdown" and student.SOLUTION_END.search(cell.source):
            inside = False
        elif inside:
            yield cell


def _answers(nb):
    return [c.source for c in _gated_cells(nb) if c.cell_type == "markdown"]


@pytest.fixture(scope="module")
def key(tmp_path_factory):
    return lecturer_key.write_key(tmp_path_factory.mktemp("lecturer") / "key.md").read_text()


def test_every_gated_solution_of_every_lab_is_in_the_key(key):
    for path in LABS:
        nb = nbformat.read(path, as_version=4)
        title = nb.cells[0].source.splitlines()[0].lstrip("# ")
        assert f"## {title}" in key, path.name
        cells = list(_gated_cells(nb))
        assert cells, f"{path.name}: no gated solution"
        for cell in cells:
            shown = (cell.source.rstrip() if cell.cell_type == "code"
                     else lecturer_key.key_text(cell.source))
            assert shown in key, f"{path.name}: the key misses {cell.source[:60]!r}"
    assert key.index("## Lab 1:") < key.index("## Lab 2:") < key.index("## Lab 8:")
    assert "Questions without a model answer" not in key
    assert "{glue" not in key and "{doc}" not in key


@pytest.mark.parametrize("lab", LABS, ids=lambda p: p.stem)
def test_every_question_of_a_lab_is_followed_by_its_answer(lab):
    nb = nbformat.read(lab, as_version=4)
    questions = [c for c in nb.cells if c.cell_type == "markdown"
                 and lecturer_key.QUESTION.search(c.source)]
    assert questions, f"{lab.name} asks no question"
    assert lecturer_key.unanswered_questions(nb) == []
    # each answer of the key comes with the question it answers
    answered = [q for task in lecturer_key.lab_tasks(nb) for q, _ in task.answers]
    assert len(answered) == len(questions) and None not in answered


def _lab(*cells):
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell(s) if kind == "md" else nbformat.v4.new_code_cell(s)
                for kind, s in cells]
    return nb


_EXERCISE = ("md", "## Task 1: the answer\n\n:::{exercise} Lab 9, task 1\n:nonumber:\n"
                   ":label: lab9-task1\n\nCompute `answer_value`.\n:::")
_CODE = [("md", ":::{solution-start} lab9-task1\n:class: dropdown\n:::"),
         ("code", "answer_value = 6 * 7  # the solution"),
         ("md", ":::{solution-end}\n:::"),
         ("code", "# self-check\nassert answer_value == 42")]
_QUESTION = ("md", "**Questions.** (1) Why 42? (2) Why not 43?")


def _answer(label="lab9-task1", text="**Answer.** (1) SIX-TIMES-SEVEN. (2) It is odd."):
    return [("md", f":::{{solution-start}} {label}\n:class: dropdown\n:::"), ("md", text),
            ("md", ":::{solution-end}\n:::")]


def test_an_unanswered_question_is_found():
    """On a small synthetic lab: a question with no gated answer after it, one gated with
    another exercise's label, and one whose gated cell is no answer are each reported."""
    assert lecturer_key.unanswered_questions(_lab(_EXERCISE, *_CODE, _QUESTION)) == [
        "cell 5 (lab9-task1): **Questions.** (1) Why 42? (2) Why not 43?"]
    for wrong in (_answer(label="lab9-task2"), _answer(text="Some note.")):
        assert len(lecturer_key.unanswered_questions(_lab(_EXERCISE, *_CODE, _QUESTION,
                                                          *wrong))) == 1
    # the answer must follow the question at once
    late = _lab(_EXERCISE, *_CODE, _QUESTION, ("md", "More text."), *_answer())
    assert len(lecturer_key.unanswered_questions(late)) == 1
    assert lecturer_key.unanswered_questions(_lab(_EXERCISE, *_CODE, _QUESTION,
                                                  *_answer())) == []


def test_a_task_with_code_and_an_answer_gets_a_blank_for_each():
    """Two gated solutions of one exercise (the code, then the answer to its question): the
    student edition puts its own blank in place of each, the key shows both."""
    nb = _lab(_EXERCISE, *_CODE, _QUESTION, *_answer())
    cells = student.student_notebook(nb).cells
    text = "\n".join(c.source for c in cells)
    assert "SIX-TIMES-SEVEN" not in text and "6 * 7" not in text
    assert "raise NotImplementedError('Task 1 (the answer) is not solved yet" in cells[1].source
    assert [c.source for c in cells[-2:]] == [_QUESTION[1],
                                              "**Your answer (Task 1 (the answer)).** ..."]
    (task,) = lecturer_key.lab_tasks(nb)
    assert (task.label, task.heading) == ("lab9-task1", "Task 1: the answer")
    assert task.text == "Compute `answer_value`."
    assert task.code == ["answer_value = 6 * 7  # the solution"]
    assert task.answers == [(_QUESTION[1], _answer()[1][1])]
    shown = lecturer_key.lab_key(nb, "lab9.ipynb")
    assert shown.index("### Task 1: the answer") < shown.index("```python\nanswer_value = 6 * 7")
    assert shown.index("**Questions.** (1) Why 42?") < shown.index("**Answer.** (1) SIX")


def test_a_gated_solution_must_name_an_exercise_above_it():
    with pytest.raises(ValueError, match="lab9-task2 names no exercise"):
        lecturer_key.lab_tasks(_lab(_EXERCISE, *_CODE, *_answer(label="lab9-task2")))


def test_the_key_writes_the_book_roles_out():
    assert lecturer_key.key_text("**Answer.** $\\tau$ = {glue:text}`lab6_tau1:.0f` steps; see "
                                 "{doc}`../measured_surfaces` and {glue}`lab6_ratio3`.") == (
        "**Answer.** $\\tau$ = [lab6_tau1] steps; see the book's page measured_surfaces and "
        "[lab6_ratio3].")


def test_the_student_edition_holds_none_of_the_answers(tmp_path):
    written = student.write_student_edition(out=tmp_path)
    for ref_path, path in zip(LABS, written):
        ref = nbformat.read(ref_path, as_version=4)
        cells = nbformat.read(path, as_version=4).cells
        text = " ".join(" ".join(c.source for c in cells).split())
        answers = _answers(ref)
        for answer in answers:
            lines = [" ".join(line.split()) for line in answer.splitlines()]
            left = [line for line in lines if len(line) >= 30 and line in text]
            assert not left, f"{path.name} holds an answer: {left[:2]}"
        assert "**Answer" not in text
        blanks = [c for c in cells if c.source.startswith("**Your answer (Task")]
        assert len(blanks) == len(answers), path.name


def test_make_student_writes_the_key_beside_the_hand_out(tmp_path, monkeypatch, capsys):
    out = tmp_path / "build" / "student"
    assert student.main(["--out", str(out), "--no-book"]) == 0
    key = tmp_path / "build" / "lecturer" / "key.md"
    assert key.is_file() and "the lecturer's key" in capsys.readouterr().out
    assert not [p for p in out.rglob("*") if p.name == key.name or "lecturer" in p.name]
    assert "**Answer." in key.read_text()
    assert not any("**Answer." in p.read_text(errors="replace") for p in out.glob("*.ipynb"))
    # a key inside the hand-out is refused before anything is written
    with pytest.raises(SystemExit):
        student.main(["--out", str(tmp_path / "other"), "--no-book",
                      "--key", str(tmp_path / "other" / "key.md")])
    assert not (tmp_path / "other").exists()
    # a run that fails (here a leak found by the scan) removes the key with the hand-out
    monkeypatch.setattr(student, "solution_code_left", lambda folder: ["lab1.ipynb: x = 1"])
    assert student.main(["--out", str(out), "--no-book"]) == 1
    assert not key.exists() and not key.parent.exists() and not out.exists()
