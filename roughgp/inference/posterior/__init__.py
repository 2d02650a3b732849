r"""Posterior sampling of GP hyperparameters (with the noise variance) by MCMC.

Section 2.2 of the paper: the hyperparameters "are usually optimized by maximizing the
marginal likelihood ... or by sampling with the marginal likelihood".
:mod:`roughgp.inference.fitting` does the first; this package does the second, in four
modules: :mod:`~roughgp.inference.posterior.priors` (priors in an unconstrained
parameterisation and :class:`PosteriorModel`), :mod:`~roughgp.inference.posterior.likelihoods`
(a profile's exact Toeplitz likelihood, a small patch's dense one),
:mod:`~roughgp.inference.posterior.models` (eq 21 on a profile, eq 18 on a patch) and
:mod:`~roughgp.inference.posterior.mcmc` (emcee, with the refusal to report a chain shorter
than 50 autocorrelation times). Their public names are re-exported here.
"""

from roughgp.inference.posterior.likelihoods import (
                                                     MAX_GRID_POINTS,
                                                     grid_likelihood,
                                                     profile_likelihood,
)
from roughgp.inference.posterior.mcmc import (
                                                     PosteriorSamples,
                                                     ShortChainError,
                                                     main_mode,
                                                     sample_posterior,
)
from roughgp.inference.posterior.models import (
                                                     ground_patch_model,
                                                     maximum_a_posteriori,
                                                     order_lengthscales,
                                                     spectral_mixture_profile_model,
)
from roughgp.inference.posterior.priors import (
                                                     LogNormal,
                                                     LogUniform,
                                                     Parameter,
                                                     PosteriorModel,
                                                     Uniform,
                                                     UniformAngle,
)

__all__ = [
    "LogUniform", "LogNormal", "Uniform", "UniformAngle", "Parameter", "PosteriorModel",
    "PosteriorSamples", "ShortChainError", "profile_likelihood", "grid_likelihood",
    "spectral_mixture_profile_model", "ground_patch_model", "sample_posterior",
    "maximum_a_posteriori", "order_lengthscales", "main_mode", "MAX_GRID_POINTS",
]
