"""An opt-in disk cache of expensive experiment results, shared between processes.

The book's chapters and its claims ledger run in separate kernels and some compute the same
result (the careful fits of figure 7 take a minute). When the environment variable
``ROUGHGP_RESULTS_CACHE`` names a folder, functions decorated with :func:`persistent` keep their
results there (``joblib.Memory``: keyed by the function's code and its arguments, written
atomically) and a second process reads them instead of computing again. The folder must be
emptied when the library changes, since the key does not cover the functions called: the book's
notebook cache (``booktools/notebook_cache.py``) sets the variable to a folder inside its own
cache, which it empties whenever ``roughgp/``, the lock or the data change. Unset (the default,
and for every user of the library), nothing is stored and every call computes.
"""

from __future__ import annotations

import functools
import os

__all__ = ["ENV", "persistent"]

ENV = "ROUGHGP_RESULTS_CACHE"


def persistent(function):
    """Decorator: ``function(*args)`` from the folder of ``$ROUGHGP_RESULTS_CACHE`` when set
    (computed and stored there on a miss), computed as usual when not. Arguments and results
    must pickle; results must not be mutated by callers."""
    @functools.wraps(function)
    def cached(*args, **kwargs):
        folder = os.environ.get(ENV, "").strip()
        if not folder:
            return function(*args, **kwargs)
        import joblib

        from roughgp.common.numerics import start_jitter

        jitter = start_jitter()   # a perturbed run's results are kept apart
        location = folder if jitter == 0 else os.path.join(folder, f"start-jitter-{jitter}")
        memory = joblib.Memory(location=location, verbose=0)
        return memory.cache(function)(*args, **kwargs)

    return cached
