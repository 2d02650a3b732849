"""Hyperparameters from data: fits and posteriors (sections 2.2 and 3.3).

Modules: :mod:`~roughgp.inference.fitting` (the spectral-mixture fit of eq 21 on a profile),
:mod:`~roughgp.inference.posterior` (priors, likelihoods, ready-made models and the emcee
sampler: "sampling with the marginal likelihood"), :mod:`~roughgp.inference.mixture_posterior`
(the spectral mixture's posterior: relabelling, posterior predictive profiles),
:mod:`~roughgp.inference.block_fit` (eq 18 plus noise on the measured points of a map with
holes).

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`, :mod:`roughgp.models`,
:mod:`roughgp.non_gaussian`, :mod:`roughgp.targets`.
"""
