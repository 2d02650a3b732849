"""The book's Markdown pages and the README fit the book's text column: no line of a fenced
code block is longer than the column holds, so that no code block gets a horizontal scroll
bar. A long command is split with ``\\`` continuations, its comment on a line of its own above
it; a command's printed output is re-wrapped to the column."""

import re
from pathlib import Path

import pytest

from roughgp.common.page_text import PAGE_COLUMNS

ROOT = Path(__file__).resolve().parents[1]

# the book column's width in monospace characters: its 688 CSS px hold 81 characters of the
# theme's monospace font
MAX = PAGE_COLUMNS

# a CommonMark code fence: three or more backticks or tildes, then the info string
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})(.*)$")
# the MyST directives whose body is shown as code; any other directive ({note},
# {eval-rst}, {bibliography}, ...) is no code block, though a code block nested in it is
CODE_DIRECTIVES = {"code-block", "code", "code-cell", "sourcecode"}

PAGES = sorted((ROOT / "book").glob("*.md")) + [ROOT / "README.md"]


def _is_code(info: str) -> bool:
    directive = re.match(r"\{([\w-]+)\}", info)
    return directive is None or directive.group(1) in CODE_DIRECTIVES


def code_lines(text: str):
    """(line number, line) of each line inside a fenced code block of the Markdown ``text``."""
    fences = []  # the open fences, innermost last: (character, length, is code)
    for number, line in enumerate(text.splitlines(), 1):
        fence = FENCE.match(line)
        inside_code = bool(fences) and fences[-1][2]
        if fence:
            mark, info = fence.group(1), fence.group(2).strip()
            closes = (fences and not info and mark[0] == fences[-1][0]
                      and len(mark) >= fences[-1][1])
            if closes:
                fences.pop()
                continue
            if not inside_code:
                fences.append((mark[0], len(mark), _is_code(info)))
                continue
        if inside_code:
            yield number, line


def too_long_code_lines(text: str, width: int = MAX) -> list[tuple[int, int]]:
    """(line number, length) of each line of a fenced code block of ``text`` longer than
    ``width`` characters."""
    return [(number, len(line)) for number, line in code_lines(text) if len(line) > width]


@pytest.mark.parametrize("page", PAGES, ids=lambda page: str(page.relative_to(ROOT)))
def test_every_code_line_fits_the_book_column(page):
    long = too_long_code_lines(page.read_text(encoding="utf-8"))
    assert not long, "\n".join(
        f"{page.relative_to(ROOT)}:{number}: {length} characters, the column holds {MAX}"
        for number, length in long)


def test_the_check_says_no_to_a_long_code_line_and_yes_to_a_short_one():
    short, long = "x" * MAX, "y" * (MAX + 1)
    assert too_long_code_lines(f"```bash\n{short}\n```\n") == []
    page = f"# A page\n\n{long} (prose wraps)\n\n```bash\n{short}\n{long}\n```\n\n{long}\n"
    assert too_long_code_lines(page) == [(7, MAX + 1)]
    # a tilde fence, a fence of four backticks around a shorter one, a code block nested in a
    # directive; a directive's own body is no code
    assert too_long_code_lines(f"~~~\n{long}\n~~~\n") == [(2, MAX + 1)]
    assert too_long_code_lines(f"````md\n```\n{long}\n```\n````\n{long}\n") == [(3, MAX + 1)]
    assert too_long_code_lines(f"````{{note}}\n{long}\n```python\n{long}\n```\n````\n") == [
        (4, MAX + 1)]


NOTEBOOKS = sorted((ROOT / "book").glob("*.ipynb")) + sorted((ROOT / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda path: str(path.relative_to(ROOT)))
def test_every_code_line_of_a_notebooks_text_fits_the_book_column(path):
    """The code blocks written in a chapter's or a lab's Markdown cells (commands, snippets)."""
    import nbformat

    nb = nbformat.read(path, as_version=4)
    long = [(index, number, length) for index, cell in enumerate(nb.cells)
            if cell.cell_type == "markdown"
            for number, length in too_long_code_lines(cell.source)]
    assert not long, "\n".join(
        f"{path.relative_to(ROOT)}: cell {index}, line {number}: {length} characters, the "
        f"column holds {MAX}" for index, number, length in long)


def comment_lines(text: str) -> list[int]:
    """The numbers of the prose lines of the MyST ``text`` that begin with ``%`` (after
    spaces): MyST reads such a line as a comment and drops it from the page, so a percentage
    wrapped to the start of a line vanishes with the rest of its line."""
    inside = {number for number, _ in code_lines(text)}
    return [number for number, line in enumerate(text.splitlines(), 1)
            if number not in inside and re.match(r"\s*%", line)]


def test_the_comment_check_finds_a_wrapped_percentage_and_not_one_in_code():
    page = "Sq lies outside in 12\n  % of the tiles.\n\n```bash\n% a shell prompt\n```\n"
    assert comment_lines(page) == [2]
    assert comment_lines("Sq lies outside in 12 % of the tiles.\n") == []


@pytest.mark.parametrize("path", PAGES[:-1] + NOTEBOOKS,
                         ids=lambda path: str(path.relative_to(ROOT)))
def test_no_line_of_prose_begins_with_a_percent_sign(path):
    """A page's or a chapter's or a lab's prose loses no line to a MyST comment."""
    import nbformat

    if path.suffix == ".md":
        texts = [("", path.read_text(encoding="utf-8"))]
    else:
        texts = [(f"cell {index}, ", cell.source) for index, cell in
                 enumerate(nbformat.read(path, as_version=4).cells)
                 if cell.cell_type == "markdown"]
    found = [f"{where}line {number}" for where, text in texts for number in comment_lines(text)]
    assert not found, f"{path.relative_to(ROOT)}: a line begins with %: " + "; ".join(found)
