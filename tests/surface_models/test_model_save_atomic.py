"""FittedModel.save writes a model file whole or not at all, for library callers too."""

from __future__ import annotations

from pathlib import Path

import pytest

from roughgp.surface_models.model import FittedModel
from test_model_schema import EQ18, EQ21


def test_an_interrupted_save_leaves_the_old_file_and_no_partial_one(tmp_path, monkeypatch):
    path = EQ18.save(tmp_path / "m.json")
    before = path.read_text()
    real = Path.write_text

    def half_then_interrupt(self, text, *args, **kwargs):
        real(self, text[: len(text) // 2], *args, **kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(Path, "write_text", half_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        EQ21.save(path)
    monkeypatch.undo()
    assert path.read_text() == before and FittedModel.load(path) == EQ18
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json"]


def test_a_save_makes_missing_folders_and_writes_the_named_file(tmp_path):
    path = EQ21.save(tmp_path / "new" / "folder" / "p.json")
    assert path == tmp_path / "new" / "folder" / "p.json" and FittedModel.load(path) == EQ21
