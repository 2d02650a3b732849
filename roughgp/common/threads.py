"""One BLAS thread for small dense linear algebra (beyond the paper: how it runs, not what).

The likelihoods of eq 12 on small matrices (a patch of a few hundred points, a block of the
block composite likelihood, a kriging window), the block Levinson recursion of eq 10 and the
triangulations of the interpolation baselines make many calls on matrices of a few hundred rows
or fewer. OpenBLAS's threads gain nothing there, and on a machine whose cores are busy they
make each call many times slower (its idle threads spin for the next call): a 144 x 144
Cholesky took 1.0 ms on one thread and 209 ms on OpenBLAS's two while other processes kept both
cores busy (the 2-core reference machine, 2026-12-02), and SciPy's Delaunay triangulation with
its interpolants (a 2 x 2 LAPACK solve per triangle) ran 4 times slower on two threads beside
two busy processes than on one (2026-12-03).

So the policy is: **one BLAS thread by default for the work of a command, and the libraries'
own thread count only for a dense factorisation too large to be small** (more than
:data:`SMALL_DENSE_ROWS` rows). :func:`one_blas_thread` limits the BLAS libraries loaded in
this process to one thread for the duration of a ``with`` block (set and restored in about
20 us; nests); :func:`blas_threads_for` chooses by a factorisation's size and, for a large one,
gives the threads back even inside an outer :func:`one_blas_thread`; :func:`single_blas_thread`
decorates a function whose work is many small calls. The ``roughgp`` command runs every
sub-command inside :func:`one_blas_thread`. Nothing here sets an environment variable, and the
numbers do not depend on it: OpenBLAS's results on one thread and on two agree to rounding, and
the ledger's claims are checked under both (``roughgp reproduce --setups``).
"""

from __future__ import annotations

import contextlib
import functools
import sys

__all__ = ["SMALL_DENSE_ROWS", "one_blas_thread", "blas_threads_for", "single_blas_thread",
           "default_blas_threads"]

SMALL_DENSE_ROWS = 1024
"""Dense matrices up to this many rows are factorised on one BLAS thread."""

_controller = None
_with_scipy = False   # whether SciPy's BLAS was loaded when the controller listed the libraries
_defaults = 1         # the BLAS libraries' largest thread count when roughgp first looked


def _blas_controller():
    """threadpoolctl's controller of the BLAS libraries loaded now: listed again once SciPy's
    own OpenBLAS has been loaded (importing SciPy here would cost the quick commands 0.2 s)."""
    global _controller, _with_scipy, _defaults
    scipy_loaded = "scipy.linalg" in sys.modules
    if _controller is None or (scipy_loaded and not _with_scipy):
        from threadpoolctl import ThreadpoolController

        _controller, _with_scipy = ThreadpoolController(), scipy_loaded
        threads = [lib["num_threads"] for lib in _controller.info() if lib["user_api"] == "blas"]
        _defaults = max([_defaults, *threads])
    return _controller


def default_blas_threads() -> int:
    """The BLAS libraries' own thread count (the largest of numpy's and SciPy's), as it was
    when roughgp first limited it: what a large factorisation runs on."""
    _blas_controller()
    return int(_defaults)


def one_blas_thread():
    """A context manager: the BLAS libraries (numpy's, scipy's) run on one thread inside it."""
    return _blas_controller().limit(limits=1, user_api="blas")


def blas_threads_for(rows):
    """A context manager for a dense factorisation of ``rows`` rows: :func:`one_blas_thread`
    up to :data:`SMALL_DENSE_ROWS` rows; above, the libraries' own thread count
    (:func:`default_blas_threads`), restored inside an outer :func:`one_blas_thread` too."""
    if rows <= SMALL_DENSE_ROWS:
        return one_blas_thread()
    controller = _blas_controller()
    threads = default_blas_threads()
    if threads <= 1:
        return contextlib.nullcontext()
    return controller.limit(limits=threads, user_api="blas")


def single_blas_thread(function):
    """Decorator: ``function`` runs inside :func:`one_blas_thread` (for work made of many small
    BLAS or LAPACK calls)."""
    @functools.wraps(function)
    def limited(*args, **kwargs):
        with one_blas_thread():
            return function(*args, **kwargs)

    return limited
