"""The engine's helpers for the project's long runs (roughgp.batch.engine): the records the
benchmark scripts append as their cases end."""


def test_appending_records_keeps_each_finished_case_and_skips_failures(tmp_path, capsys):
    """The benchmarks' on_result: a record a line as each case ends, failures printed only."""
    import json

    from roughgp.batch.engine import appending_records
    out = tmp_path / "deep" / "records.jsonl"
    record = appending_records(out, lambda r: f"value {r['value']}", 3)
    record("a", {"value": 1})
    record("b", ValueError("no"))
    record("c", {"value": 3})
    assert [json.loads(line) for line in out.read_text().splitlines()] == [{"value": 1},
                                                                            {"value": 3}]
    printed = capsys.readouterr().out
    assert "[1/3] a: value 1" in printed and "b: failed: ValueError('no')" in printed
    assert "[2/3] c: value 3" in printed
