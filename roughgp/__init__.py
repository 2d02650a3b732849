"""roughgp: rough surfaces as Gaussian processes.

An executable companion to Jawaid & Seewig, "Model of rough surfaces with Gaussian
processes" (Surf. Topogr.: Metrol. Prop.). Equation numbers in docstrings are the paper's.

Modules, bottom up: :mod:`roughgp.acvf` (ACVFs and PSDs as plain functions),
:mod:`roughgp.kernels` (the same as GPyTorch kernels), :mod:`roughgp.fourier` (the
Wiener-Khinchin transforms of eq 5 on a grid), :mod:`roughgp.spectral` (periodogram,
Welch, empirical ACVF), :mod:`roughgp.sampling` (draws of eq 10), :mod:`roughgp.plotting`
(the book's figure style); then the models: :mod:`roughgp.arma` (section 2.3),
:mod:`roughgp.surfaces` (ground and honed, eq 18-20), :mod:`roughgp.texture` (ISO
parameters), :mod:`roughgp.toeplitz` and :mod:`roughgp.fitting` (the spectral-mixture fit of
section 3.3), :mod:`roughgp.posterior` (hyperparameter posteriors with emcee),
:mod:`roughgp.data` (synthetic turned profiles and surfaces) and :mod:`roughgp.readers` /
:mod:`roughgp.levelling` (the user's own measurements). Beyond the paper:
:mod:`roughgp.non_gaussian`, :mod:`roughgp.targets`, :mod:`roughgp.gap_filling` with
:mod:`roughgp.block_fit`, and :mod:`roughgp.device` (the ``device=`` argument: the same calls
through torch on a GPU).
"""

__version__ = "0.1.0"
