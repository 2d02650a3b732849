"""Tests of roughgp.common.threads: small dense algebra on one BLAS thread, the setting restored."""

from __future__ import annotations

import numpy as np
import scipy.linalg  # noqa: F401  (its BLAS listed from the start)
from threadpoolctl import threadpool_info

from roughgp.common.threads import one_blas_thread


def _blas_threads():
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_one_thread_inside_and_the_setting_restored_after():
    before = _blas_threads()
    assert before                                   # numpy's and scipy's OpenBLAS are listed
    with one_blas_thread():
        assert _blas_threads() == [1] * len(before)
        a = np.random.default_rng(0).normal(size=(50, 50))
        np.linalg.cholesky(a @ a.T + 50 * np.eye(50))
    assert _blas_threads() == before
    with one_blas_thread(), one_blas_thread():      # nested: still one, then restored
        assert _blas_threads() == [1] * len(before)
    assert _blas_threads() == before


def test_the_size_decides_for_a_dense_factorisation():
    from roughgp.common.threads import SMALL_DENSE_ROWS, blas_threads_for, default_blas_threads

    before = _blas_threads()
    with blas_threads_for(SMALL_DENSE_ROWS):
        assert _blas_threads() == [1] * len(before)
    with blas_threads_for(SMALL_DENSE_ROWS + 1):
        # every BLAS at the libraries' own count (a test process may have loaded one BLAS under
        # OMP_NUM_THREADS=1 and another after: ``before`` need not agree across them)
        threads = default_blas_threads()
        assert _blas_threads() == ([threads] * len(before) if threads > 1 else before)
    assert _blas_threads() == before


def test_a_large_factorisation_gets_the_threads_back_inside_one_thread():
    from roughgp.common.threads import SMALL_DENSE_ROWS, blas_threads_for, default_blas_threads

    before = _blas_threads()
    with one_blas_thread():
        with blas_threads_for(SMALL_DENSE_ROWS + 1):
            assert max(_blas_threads()) == default_blas_threads()
        assert _blas_threads() == [1] * len(before)
        with blas_threads_for(SMALL_DENSE_ROWS):
            assert _blas_threads() == [1] * len(before)
    assert _blas_threads() == before


def test_single_blas_thread_decorates_a_function():
    from roughgp.common.threads import single_blas_thread

    @single_blas_thread
    def threads_inside(x):
        return x, _blas_threads()

    before = _blas_threads()
    assert threads_inside(3) == (3, [1] * len(before))
    assert _blas_threads() == before
