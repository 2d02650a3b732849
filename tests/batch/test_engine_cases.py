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


def _blas_threads_and_warns(value):
    import warnings

    from threadpoolctl import threadpool_info
    warnings.warn("a worker's warning", RuntimeWarning)
    return value, max((i["num_threads"] for i in threadpool_info()), default=1)


def test_on_one_thread_runs_a_case_on_one_blas_thread_with_its_warnings_silenced(recwarn):
    """The long runs' cases: run_cases(on_one_thread, [(key, (function, *args), name)])."""
    from distributed import Client

    from roughgp.batch.engine import on_one_thread, run_cases
    results = {}
    with Client(processes=False, n_workers=1, threads_per_worker=1,
                dashboard_address=":0") as client:
        run_cases(on_one_thread, [(k, (_blas_threads_and_warns, k * 10), f"case-{k}")
                                  for k in (1, 2)],
                  client=client, on_result=results.__setitem__)
    assert results == {1: (10, 1), 2: (20, 1)}
    assert not [w for w in recwarn if "a worker's warning" in str(w.message)]
