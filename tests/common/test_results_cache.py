"""Tests of roughgp.common.results_cache: results kept on disk only when the variable names a
folder, computed as usual otherwise."""

from __future__ import annotations

import numpy as np

from roughgp.common.results_cache import ENV, persistent

CALLS = []


@persistent
def _expensive(n, seed=0):
    CALLS.append((n, seed))
    return np.random.default_rng(seed).normal(size=n)


def test_unset_computes_every_call(monkeypatch):
    monkeypatch.delenv(ENV, raising=False)
    CALLS.clear()
    a, b = _expensive(5, seed=1), _expensive(5, seed=1)
    assert len(CALLS) == 2 and np.array_equal(a, b)


def test_set_computes_once_per_argument_and_reads_the_rest(tmp_path, monkeypatch):
    monkeypatch.setenv(ENV, str(tmp_path))
    CALLS.clear()
    a = _expensive(5, seed=1)
    b = _expensive(5, seed=1)
    c = _expensive(5, seed=2)
    assert CALLS == [(5, 1), (5, 2)]
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert any(tmp_path.iterdir())
