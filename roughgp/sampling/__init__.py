"""Draws of the GP on a grid (eq 10), and how good they are.

Modules: :mod:`~roughgp.sampling.grid_sampler` (:func:`sample_grid` with the methods
``cholesky``, ``lanczos`` (the paper's), ``circulant`` (exact, O(N log N)) and ``auto``),
:mod:`~roughgp.sampling.block_levinson` (the Cholesky draw of a 2-D grid row by row, in
:math:`2 n_y^2 n_x^3` flops), :mod:`~roughgp.sampling.circulant` (circulant embedding: the
torus search, explicit clipping), :mod:`~roughgp.sampling.truncation` (the smooth truncation of the ACVF beyond the
grid's lags, which keeps R and shrinks the torus toward (2n)^D), :mod:`~roughgp.sampling.fft_filter` (the classic FFT filter, the speed baseline),
:mod:`~roughgp.sampling.diagnostics` (the covariance error of section 3.1 and its expectation).

The public names of :mod:`~roughgp.sampling.grid_sampler` are re-exported here, so
``from roughgp import sampling; sampling.sample_grid(...)`` works.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`.
"""

from roughgp.sampling.grid_sampler import (
                                           SamplingInfo,
                                           acvf_of,
                                           choose_method,
                                           covariance_index,
                                           grid_covariance,
                                           sample_grid,
)

__all__ = ["SamplingInfo", "acvf_of", "choose_method", "covariance_index", "grid_covariance",
           "sample_grid"]
