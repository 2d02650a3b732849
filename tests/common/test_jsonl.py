"""roughgp.common.jsonl: recorded runs read one JSON object a line, a broken line named."""

from __future__ import annotations

import pytest

from roughgp.common.jsonl import read_records


def test_records_are_read_and_blank_lines_skipped(tmp_path):
    path = tmp_path / "run.jsonl"
    path.write_text('{"a": 1}\n\n{"a": 2}\n', encoding="utf-8")
    assert read_records(path) == [{"a": 1}, {"a": 2}]
    assert read_records(tmp_path / "missing.jsonl") == []


def test_a_broken_line_is_named(tmp_path):
    path = tmp_path / "run.jsonl"
    path.write_text('{"a": 1}\n{"a": \n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"run.jsonl:2: not a JSON record"):
        read_records(path)


def test_write_records_replaces_the_file_and_reads_back(tmp_path):
    from roughgp.common.jsonl import write_records
    path = tmp_path / "records.jsonl"
    path.write_text('{"old": true}\n')
    write_records(path, [{"a": 1}, {"b": [2, 3]}])
    assert read_records(path) == [{"a": 1}, {"b": [2, 3]}]
    assert [p.name for p in tmp_path.iterdir()] == ["records.jsonl"]   # no partial file left
