"""Many measurement files, one table: the steps of the single commands (texture, fit, check,
fill, simulate --from) run file by file on a Dask cluster (``roughgp batch``).

Modules: :mod:`~roughgp.batch.records` (the plan of a batch, each file's seed, its record
written atomically and the resume rule) ← :mod:`~roughgp.batch.steps` (one file through the
steps, calling the library as the single commands do) ← :mod:`~roughgp.batch.table` (the
records as one tidy table, CSV and Parquet) ← :mod:`~roughgp.batch.engine` (the files
scheduled on a Dask ``LocalCluster`` or an existing scheduler, records written as files end,
progress).

May import: every package below it, :mod:`roughgp.api` and down.
"""
