"""The numbers a chapter's prose states are glued (myst-nb): every ``{glue:...}`key``` in a
markdown cell has a ``glue("key", ...)`` in a code cell of the same notebook, so the book build
cannot meet an unknown key and text and computation cannot drift apart."""

import ast
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted(p for p in (ROOT / "book").rglob("*.ipynb") if "_build" not in p.parts
                   and ".ipynb_checkpoints" not in p.parts)
REFERENCE = re.compile(r"\{glue(?::[a-z]+)?\}`([^`:]+)")
GLUED = re.compile(r"""glue\(\s*(?:f?["'])([^"']+)["']""")


def _cells(path):
    return json.loads(path.read_text(encoding="utf-8"))["cells"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_every_glue_reference_is_glued(path):
    cells = _cells(path)
    referenced = {key.strip() for c in cells if c["cell_type"] == "markdown"
                  for key in REFERENCE.findall("".join(c["source"]))}
    glued = {key for c in cells if c["cell_type"] == "code"
             for key in GLUED.findall("".join(c["source"]))}
    # an f-string key such as f"lobe_{name}" stands for every key of its pattern
    patterns = [re.compile("^" + re.sub(r"\\\{[^}]*\\\}", ".+", re.escape(key)) + "$")
                for key in glued if "{" in key]
    unknown = {key for key in referenced - glued if not any(p.match(key) for p in patterns)}
    assert not unknown, f"glue keys used but never glued: {unknown}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebooks_are_committed_without_outputs(path):
    for c in _cells(path):
        if c["cell_type"] == "code":
            assert c.get("outputs") == [] and c.get("execution_count") is None, path.name


HIDDEN = {"remove-input", "remove-cell", "hide-input"}


def _is_bookkeeping(statement) -> bool:
    """An ``assert`` or a ``glue(...)`` call: what the reader need not see."""
    if isinstance(statement, ast.Assert):
        return True
    return (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Call)
            and isinstance(statement.value.func, ast.Name) and statement.value.func.id == "glue")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_bookkeeping_stays_out_of_the_readers_way(path):
    # a chapter's visible code cells hold no top-level glue call or assert: those go into a
    # following cell tagged remove-input (asserts inside a loop that prints stay where they are)
    shown = []
    for i, c in enumerate(_cells(path)):
        if c["cell_type"] != "code" or HIDDEN & set(c.get("metadata", {}).get("tags", [])):
            continue
        body = ast.parse("".join(c["source"])).body
        shown += [f"cell {i}, line {s.lineno}" for s in body if _is_bookkeeping(s)]
    assert not shown, f"glue or assert shown to the reader: {shown}"
