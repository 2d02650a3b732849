"""The numerical set-up of a run, and a switch that perturbs it (how it runs, not what).

A verdict that flips with the last bits of a BLAS reduction or with which local optimum a
multi-start optimiser reaches is not a reproduction: on another CPU, BLAS kernel or thread count
the same seeded optimiser follows another path (a 2-core AMD EPYC with OpenBLAS's Haswell
kernels reached another optimum of figure 7's fit than the machine the chapter was written on,
and a claim's verdict flipped). To find such claims before a reader's machine does, every
optimiser start and Markov chain start in roughgp goes through :func:`perturbed_start`. Unset,
it returns the start unchanged (bit for bit, so the same seed gives the same result as
always). With the environment variable ``ROUGHGP_START_JITTER`` set to a positive integer
``k``, each start moves by a seeded Gaussian step of :data:`JITTER` (1e-6) in the optimiser's
own (mostly logarithmic) coordinates: a change far below any statistical meaning, of the order
by which two machines' optimiser paths have drifted apart after a few iterations. ``k`` seeds
the step together with the start's own bytes, so it does not depend on the order of calls.

:func:`setup` reports a run's set-up (the jitter seed and the BLAS libraries' thread counts);
the claims ledger runs its optimiser-dependent claims under several set-ups and fails when a
verdict differs (:mod:`roughgp.ledger.setups`, ``roughgp reproduce --setups``).
"""

from __future__ import annotations

import hashlib
import os

import numpy as np

__all__ = ["ENV", "JITTER", "start_jitter", "perturbed_start", "setup"]

ENV = "ROUGHGP_START_JITTER"
JITTER = 1e-6
"""The standard deviation of a start's perturbation, in the optimiser's coordinates."""


def start_jitter() -> int:
    """The seed of the start perturbation: ``ROUGHGP_START_JITTER`` as an integer >= 0 (0 or
    unset: no perturbation); a ValueError naming the variable otherwise."""
    text = os.environ.get(ENV, "").strip()
    if not text:
        return 0
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value < 2**32:
        raise ValueError(f"{ENV} must be an integer in [0, 2**32), got {text!r}")
    return value


def perturbed_start(start, lower=None, upper=None) -> np.ndarray:
    """``start`` (an optimiser's or a sampler's starting point, any shape) unchanged, or, under
    ``ROUGHGP_START_JITTER`` = k > 0, moved by a Gaussian step of sd :data:`JITTER` seeded by k
    and the start's bytes, and clipped to ``[lower, upper]`` where given (None or infinite:
    unbounded)."""
    start = np.asarray(start, dtype=np.float64)
    seed = start_jitter()
    if seed == 0:
        return start
    digest = hashlib.sha256(start.tobytes()).digest()
    rng = np.random.default_rng([seed, int.from_bytes(digest[:8], "little")])
    moved = start + JITTER * rng.standard_normal(start.shape)
    if lower is not None or upper is not None:
        low = -np.inf if lower is None else np.where(np.isfinite(lower), lower, -np.inf)
        high = np.inf if upper is None else np.where(np.isfinite(upper), upper, np.inf)
        moved = np.clip(moved, low, high)
    return moved


def setup() -> dict:
    """This process's numerical set-up: ``{"start_jitter": k, "blas_threads": n}`` (n: the BLAS
    libraries' own thread count, what a large factorisation runs on,
    :func:`roughgp.common.threads.default_blas_threads`; small ones run on one thread)."""
    from roughgp.common.threads import default_blas_threads

    return {"start_jitter": start_jitter(), "blas_threads": default_blas_threads()}
