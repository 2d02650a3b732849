"""roughgp: rough surfaces as Gaussian processes.

An executable companion to Jawaid & Seewig, "Model of rough surfaces with Gaussian
processes" (Surf. Topogr.: Metrol. Prop.). Equation numbers in docstrings are the paper's.

The subpackages, bottom up; each may import only those before it (a test checks it):

* :mod:`roughgp.common`: input checks, grid conventions, devices, settings, the figure style;
* :mod:`roughgp.gp`: the GP itself: ACVFs and PSDs (eq 18, 21, 22, Matérn), GPyTorch kernels,
  eq 5 on a grid, the noise model (eq 8), a profile's exact likelihood;
* :mod:`roughgp.sampling`: draws on a grid (eq 10: Cholesky, Lanczos, circulant embedding),
  the FFT-filter baseline, sampling diagnostics;
* :mod:`roughgp.metrology`: measurements read and written, levelling, ISO texture parameters,
  spectra, periodicity;
* :mod:`roughgp.models`: ARMA (eq 12-14), moving averages (eq 16-17), ground and honed
  surfaces (eq 18-20), synthetic turned data;
* :mod:`roughgp.inference`: the spectral-mixture fit (eq 21), posteriors by MCMC, eq 18 on a
  map with holes;
* :mod:`roughgp.beyond`: beyond the paper: non-Gaussian heights, prescribed roughness, gap
  filling;
* :mod:`roughgp.experiments`: the paper's experiments, one function per claim's computation,
  shared by the chapters and the ledger;
* :mod:`roughgp.ledger`: the claims ledger (one check per claim of the paper);
* :mod:`roughgp.cli`: the ``roughgp`` command.
"""

__version__ = "0.1.0"
