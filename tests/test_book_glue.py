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


def _is_bookkeeping(node) -> bool:
    """An ``assert`` or a ``glue(...)`` call: what the reader need not see."""
    if isinstance(node, ast.Assert):
        return True
    return (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id == "glue")


def bookkeeping_shown(cells) -> list[str]:
    """Where a visible code cell (not tagged remove-input, remove-cell or hide-input) holds an
    assert or a glue call, at any depth (inside a loop or a function too)."""
    shown = []
    for i, c in enumerate(cells):
        if c["cell_type"] != "code" or HIDDEN & set(c.get("metadata", {}).get("tags", [])):
            continue
        tree = ast.parse("".join(c["source"]))
        shown += [f"cell {i}, line {n.lineno}" for n in ast.walk(tree) if _is_bookkeeping(n)]
    return shown


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_bookkeeping_stays_out_of_the_readers_way(path):
    # a chapter's visible code cells hold no glue call or assert, not even inside a loop that
    # prints: those go into a following cell tagged remove-input
    shown = bookkeeping_shown(_cells(path))
    assert not shown, f"glue or assert shown to the reader: {shown}"


def test_bookkeeping_inside_a_loop_is_found():
    cells = [{"cell_type": "code", "metadata": {}, "source": [
                 "for k in range(3):\n", "    print(k)\n", "    assert k < 3\n",
                 "    glue('k', k, display=False)\n"]},
             {"cell_type": "code", "metadata": {"tags": ["remove-input"]},
              "source": ["assert True\n"]}]
    assert bookkeeping_shown(cells) == ["cell 0, line 3", "cell 0, line 4"]
