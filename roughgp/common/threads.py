"""One BLAS thread for small dense linear algebra (beyond the paper: how it runs, not what).

The likelihoods of eq 12 on small matrices (a patch of a few hundred points, a block of the
block composite likelihood, a kriging window) factorise many matrices of a few hundred rows.
OpenBLAS's threads gain nothing there, and on a machine whose cores are busy they make each
factorisation many times slower: a 144 x 144 Cholesky took 1.0 ms on one thread and 209 ms on
OpenBLAS's two while other processes kept both cores busy (the 2-core reference machine,
2026-12-02). :func:`one_blas_thread` limits the BLAS libraries loaded in this process to one
thread for the duration of a ``with`` block; the limit is set and restored in about 20 us.
"""

from __future__ import annotations

import contextlib

__all__ = ["SMALL_DENSE_ROWS", "one_blas_thread", "blas_threads_for"]

SMALL_DENSE_ROWS = 1024
"""Dense matrices up to this many rows are factorised on one BLAS thread."""

_controller = None


def one_blas_thread():
    """A context manager: the BLAS libraries (numpy's, scipy's) run on one thread inside it."""
    global _controller
    if _controller is None:
        import scipy.linalg  # noqa: F401  (scipy's BLAS loaded before the libraries are listed)
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController()
    return _controller.limit(limits=1, user_api="blas")


def blas_threads_for(rows):
    """A context manager for a dense factorisation of ``rows`` rows: :func:`one_blas_thread`
    up to :data:`SMALL_DENSE_ROWS` rows, the libraries' own setting above."""
    return one_blas_thread() if rows <= SMALL_DENSE_ROWS else contextlib.nullcontext()
