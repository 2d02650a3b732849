"""roughgp: rough surfaces as Gaussian processes.

An executable companion to Jawaid & Seewig, "Model of rough surfaces with Gaussian
processes" (Surf. Topogr.: Metrol. Prop.). Equation numbers in docstrings are the paper's.

The verbs (:mod:`roughgp.api`), importable from here without importing numpy or torch::

    roughgp.read(path)                      # a measurement: heights in µm, NaN unmeasured
    roughgp.fit(surface, model="eq18")      # a model of it (a model file with .save)
    roughgp.simulate(model, shape, seed=1)  # new surfaces like it
    roughgp.check(model, surface)           # does the model reproduce it?
    roughgp.fill(surface)                   # its unmeasured points filled
    roughgp.texture(surface)                # its ISO texture parameters

The subpackages, bottom up; each may import only those before it (a test checks it, and that
no module imports another round a circle):

* :mod:`roughgp.common`: input checks, grid conventions, devices, settings, the figure style;
* :mod:`roughgp.gp`: the GP itself: ACVFs and PSDs (eq 18, 21, 22, Matérn), GPyTorch kernels,
  eq 5 on a grid, the noise model (eq 8), a profile's exact likelihood;
* :mod:`roughgp.sampling`: draws on a grid (eq 10: Cholesky, Lanczos, circulant embedding),
  the FFT-filter baseline, sampling diagnostics;
* :mod:`roughgp.io`: measurement files read and written (text, ``.npy``, ``.x3p``,
  instruments), a reading's plausibility, a file's provenance;
* :mod:`roughgp.metrology`: levelling and form removal, ISO filters, texture parameters,
  spectra, periodicity;
* :mod:`roughgp.models`: the paper's models: ARMA (eq 12-14), moving averages (eq 16-17),
  ground and honed surfaces (eq 18-20), synthetic turned data;
* :mod:`roughgp.non_gaussian`: heights with a prescribed skewness and kurtosis (the Johnson
  system, a pre-distorted ACVF);
* :mod:`roughgp.targets`: ground surfaces with prescribed Sq, Sal, Str, Std;
* :mod:`roughgp.inference`: the spectral-mixture fit (eq 21), eq 18 on a map with holes,
  posteriors by MCMC;
* :mod:`roughgp.filling`: gap filling (the GP posterior, globally or by moving windows), the
  self-check on held-out points, spurious points;
* :mod:`roughgp.surface_models`: models of measured surfaces: the ladder (eq 18, Matérn, the
  2-D spectral mixture, the measured PSD; Gaussian, Johnson or IAAFT heights), their fit, the
  model file;
* :mod:`roughgp.checking`: the model check, its ranks, the calibrated check;
* :mod:`roughgp.api`: the verbs above;
* :mod:`roughgp.batch`: many files through the commands' steps on a Dask cluster, one table
  (``roughgp batch``);
* :mod:`roughgp.experiments`: the paper's experiments, one function per claim's computation,
  shared by the chapters and the ledger;
* :mod:`roughgp.ledger`: the claims ledger (one check per claim of the paper);
* :mod:`roughgp.cli`: the ``roughgp`` command.
"""

from roughgp.api import check, fill, fit, read, simulate, texture
from roughgp.common.version import VERSION as __version__

__all__ = ["read", "fit", "simulate", "check", "fill", "texture", "__version__"]
