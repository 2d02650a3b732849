"""One rule decides quick against full (issue 32): ``roughgp reproduce`` leaves it to
:func:`roughgp.common.settings.resolve_full` (``--full`` / ``--quick``, else ``ROUGHGP_FULL``),
and the ledger's checks pick their sizes through :func:`~roughgp.common.settings.pick`, not
with an inline ``X if full else Y``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from roughgp.cli.main import main

LEDGER = Path(__file__).resolve().parents[2] / "roughgp" / "ledger"


@pytest.mark.parametrize("env, argv, expected", [
    (None, [], False), ("1", [], True), ("1", ["--quick"], False), (None, ["--full"], True),
    ("0", ["--full"], True),
])
def test_reproduce_leaves_quick_or_full_to_the_rule(monkeypatch, capsys, env, argv, expected):
    from roughgp import ledger

    if env is None:
        monkeypatch.delenv("ROUGHGP_FULL", raising=False)
    else:
        monkeypatch.setenv("ROUGHGP_FULL", env)
    seen = []

    def run(*, full, **_):
        seen.append(full)
        return []

    monkeypatch.setattr(ledger, "run", run)
    assert main(["reproduce", *argv, "--only", "eq5-duality"]) == 0
    assert seen == [expected]
    assert ("(paper sizes)" in capsys.readouterr().out) == expected


def test_full_and_quick_together_are_refused(capsys):
    try:
        code = main(["reproduce", "--full", "--quick"])
    except SystemExit as exit_:
        code = exit_.code
    assert code == 2 and "not allowed with argument --full" in capsys.readouterr().err


INLINE = re.compile(r"\bif\s+(not\s+)?full\s+else\b|\bif\s+full\s*:")


def test_no_check_of_the_ledger_decides_quick_or_full_inline():
    found = [f"{path.name}:{number}: {line.strip()}"
             for path in sorted(LEDGER.glob("*.py"))
             for number, line in enumerate(path.read_text().splitlines(), 1)
             if INLINE.search(line)]
    assert not found, "decide through roughgp.common.settings.pick / resolve_full:\n" + \
        "\n".join(found)


@pytest.mark.parametrize("line, inline", [
    ("    n = 20 if full else 5", True), ("    if full:", True),
    ("    n = pick(5, 20, full=full)", False), ("    if resolve_full(full):", False),
])
def test_the_inline_pattern_finds_what_it_should(line, inline):
    assert bool(INLINE.search(line)) == inline
