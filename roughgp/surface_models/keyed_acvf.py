"""A model's ACVF as a function of lags that says which model it is, for the sampler's caches.

:func:`roughgp.sampling.sample_grid` caches a circulant embedding by the kernel's identity
(:func:`~roughgp.sampling.kernel_identity.kernel_identity`); a plain function has none, so every
draw from it searched its embedding again. A check draws 19 to 99 surfaces from one model: for
the 2-D spectral mixture with Johnson heights on a 256 x 128 half that search took about 2
minutes per draw. :class:`KeyedACVF` carries the model's equation and hyperparameters as its
``cache_key()``.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

__all__ = ["KeyedACVF", "model_key"]


def model_key(equation: str, hyperparameters: dict, context=()) -> tuple:
    """The identity of a model's ACVF: its equation, a digest of its hyperparameters (any
    nesting of numbers and lists) and ``context``, the numbers beyond them that the ACVF
    depends on (a tabulated ACVF: the spacing and shape of its table)."""
    text = json.dumps(hyperparameters, sort_keys=True,
                      default=lambda value: np.asarray(value).tolist())
    return (equation, hashlib.sha256(text.encode()).hexdigest(),
            tuple(float(d) for d in context))


class KeyedACVF:
    """``function`` (lags ``(..., D)`` -> ACVF values) with the identity ``key``."""

    def __init__(self, function, key: tuple):
        self.function = function
        self.key = key

    def __call__(self, lags):
        return self.function(lags)

    def cache_key(self) -> tuple:
        return self.key
