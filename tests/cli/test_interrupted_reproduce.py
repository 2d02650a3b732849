"""Issue 44 part 2: a SIGINT during ``reproduce --out rs`` left an empty ``rs/figures`` (made
before the first check); the folder is now made with the first figure."""

from __future__ import annotations

import dataclasses

from roughgp.ledger import runner
from cli_run import run as _run


def test_an_interrupted_reproduce_leaves_no_empty_figures_folder(capsys, tmp_path, monkeypatch):
    def interrupted(full):
        raise KeyboardInterrupt

    first = next(c for c in runner.CLAIMS if c.check is not None)
    monkeypatch.setattr(runner, "CLAIMS", (dataclasses.replace(first, check=interrupted),))
    out = tmp_path / "rs"
    code, _, err = _run(capsys, "reproduce", "--only", first.key, "--out", out)
    assert code == 130 and "interrupted" in err, err
    assert not (out / "figures").exists() and not out.exists()
