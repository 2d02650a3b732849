"""The numbers a chapter's prose states are glued (myst-nb): every ``{glue:...}`key``` in a
markdown cell has a ``glue("key", ...)`` in a code cell of the same notebook, so the book build
cannot meet an unknown key and text and computation cannot drift apart."""

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
