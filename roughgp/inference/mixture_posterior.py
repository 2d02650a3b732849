r"""The posterior of a profile's spectral mixture (eq 21): labels and predictive profiles.

The Q components of eq 21 are exchangeable: permuting their labels leaves the ACVF
unchanged, so the posterior of :func:`roughgp.inference.posterior.spectral_mixture_profile_model`
has Q! mirrored copies of every mode (label switching). :func:`relabel_components`
puts every draw into one labelling; :func:`predictive_profiles` draws new profiles from
posterior draws of the hyperparameters (the posterior predictive), whose texture
parameters can be set against the data's.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from roughgp.common.checks import as_generator, check_integer, check_positive
from roughgp.gp.acvf import spectral_mixture

__all__ = ["relabel_components", "component_count", "predictive_profiles"]

_ORDERS = ("peak", "weight", "mean")


def component_count(samples: Mapping) -> int:
    """The number Q of components in ``samples`` (keys ``w_i``, ``mu_i``, ``v_i``,
    i = 1..Q, as :func:`roughgp.inference.posterior.spectral_mixture_profile_model` names them)."""
    q = 0
    while all(f"{k}_{q + 1}" in samples for k in ("w", "mu", "v")):
        q += 1
    if q == 0:
        raise ValueError(f"samples must hold w_1, mu_1 and v_1, got {sorted(samples)}")
    return q


def relabel_components(samples: Mapping, by: str = "peak") -> dict:
    r"""Samples of eq 21 with the components of every draw sorted.

    Args:
        samples: dict with ``w_i``, ``mu_i``, ``v_i`` arrays (i = 1..Q; others are copied
            unchanged), e.g. :attr:`roughgp.inference.posterior.PosteriorSamples.samples`.
        by: ``"peak"``: decreasing spectral peak :math:`w_i / \sqrt{v_i}` (the PSD of eq 21
            at the component's mean; component 1 is then the sharpest strong line, a turned
            profile's feed), ``"weight"``: decreasing :math:`w_i`, ``"mean"``: increasing
            frequency :math:`\mu_i`.

    Returns:
        a new dict: draw k's component 1 is its first in that order, and so on.
    """
    if by not in _ORDERS:
        raise ValueError(f"by must be one of {_ORDERS}, got {by!r}")
    q = component_count(samples)
    w, mu, v = (np.array([np.asarray(samples[f"{k}_{i}"], dtype=np.float64)
                          for i in range(1, q + 1)]) for k in ("w", "mu", "v"))
    key = {"peak": -w / np.sqrt(v), "weight": -w, "mean": mu}[by]
    order = np.argsort(key, axis=0, kind="stable")                 # (Q, draws)
    out = {k: np.array(val, dtype=np.float64, copy=True) for k, val in samples.items()}
    for name, values in (("w", w), ("mu", mu), ("v", v)):
        sorted_values = np.take_along_axis(values, order, axis=0)
        for i in range(q):
            out[f"{name}_{i + 1}"] = sorted_values[i]
    return out


def predictive_profiles(samples: Mapping, n_points, spacing=1.0, *, n_draws=100, seed=None,
                        noise=True) -> np.ndarray:
    r"""Profiles drawn from the posterior predictive of eq 21 (plus the noise of eq 8).

    For each of ``n_draws`` hyperparameter draws picked at random from ``samples``, one
    zero-mean profile of ``n_points`` points at ``spacing`` is drawn exactly (Cholesky of
    the Toeplitz covariance :math:`k(|i - j| \Delta x) + \sigma^2 \delta_{ij}`).

    Args:
        samples: dict of posterior draws (``w_i``, ``mu_i``, ``v_i``, ``noise_variance``).
        n_points: points per profile, 2 ... 8192.
        spacing: > 0, in the units the frequencies ``mu_i`` are per.
        n_draws: >= 1 profiles.
        seed: int >= 0, None or a Generator (picks the draws and the profiles).
        noise: add the white noise ``noise_variance`` (a measured profile has it).

    Returns:
        array (n_draws, n_points).
    """
    import scipy.linalg

    q = component_count(samples)
    check_integer("n_points", n_points, 2)
    if n_points > 8192:
        raise ValueError(f"n_points must be <= 8192 (a dense Cholesky per draw), got {n_points}")
    check_positive("spacing", spacing)
    check_integer("n_draws", n_draws, 1)
    if noise and "noise_variance" not in samples:
        raise ValueError("samples must hold noise_variance when noise=True")
    rng = as_generator(seed)
    size = np.asarray(samples["w_1"]).size
    picks = rng.integers(size, size=n_draws)
    lags = np.arange(n_points) * float(spacing)
    out = np.empty((n_draws, n_points))
    for row, k in enumerate(picks):
        w, mu, v = (np.array([np.asarray(samples[f"{name}_{i}"])[k] for i in range(1, q + 1)],
                             dtype=np.float64) for name in ("w", "mu", "v"))
        r = np.asarray(spectral_mixture(lags[:, None], w, mu[:, None], v[:, None]))  # eq 21
        jitter = float(np.asarray(samples["noise_variance"])[k]) if noise else 0.0
        jitter = max(jitter, 1e-10 * r[0])                  # a pure line is singular
        factor = scipy.linalg.cholesky(scipy.linalg.toeplitz(r + jitter * (lags == 0)), lower=True)
        out[row] = factor @ rng.standard_normal(n_points)
    return out
