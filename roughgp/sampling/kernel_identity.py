"""What identifies a kernel's ACVF for the sampler's caches (:mod:`roughgp.sampling.grid_sampler`
keeps the last few circulant embeddings by it): a roughgp kernel's type and hyperparameters, or
a function's own ``cache_key()``."""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import as_numpy

__all__ = ["kernel_identity"]


def kernel_identity(kernel):
    """What identifies a kernel's ACVF for the caches: its type and hyperparameters, a
    function's own ``cache_key()`` (e.g. the pre-distorted ACVF of a kernel), or None (a plain
    function: no way to tell whether it changed)."""
    own = getattr(kernel, "cache_key", None)
    if callable(own):
        return own()
    hyper = getattr(kernel, "hyperparameters", None)
    if hyper is None:
        return None
    state = tuple((k, tuple(np.atleast_1d(as_numpy(v)).ravel().tolist()))
                  for k, v in hyper().items())
    return (type(kernel).__name__, getattr(kernel, "nu", None), state)
