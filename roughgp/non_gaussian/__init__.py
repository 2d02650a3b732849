r"""Non-Gaussian heights with a prescribed skewness and kurtosis (beyond the paper).

The paper's model (eq 9) splits a rough surface into a stationary GP
:math:`G \sim \mathcal{GP}(0, r)` (eq 7), which carries the correlation, and a noise model
:math:`p(z \mid g)` (eq 8), which sets the height distribution. With the Gaussian noise the
paper uses, the heights are Gaussian (Ssk = 0, Sku = 3) whatever the ACVF; the conclusion names
the limit: stationary GPs with Gaussian noise models cannot describe surfaces whose roughness
"exhibits strong non-Gaussian distribution", and leaves non-Gaussian surfaces to future work.

This module takes the degenerate noise model :math:`p(z \mid g) = \delta(z - T(g))` of eq 8: a
memoryless transform of a standard GP,

.. math::  Z(\mathbf x) = T(X(\mathbf x)), \qquad X \sim \mathcal{GP}(0, \rho_X),\ \rho_X(0) = 1,

with :math:`T` the translation of the **Johnson system** (Johnson 1949), used for rough surfaces
by Hu & Tonder (1992), Watson & Spedding and Bakolas (2003):

.. math::  Z = \xi + \lambda\, f^{-1}\!\left(\frac{X - \gamma}{\delta}\right),\qquad
   f^{-1} = \sinh\ (S_U),\quad \operatorname{expit}\ (S_B),\quad \exp\ (S_L),\quad
   \text{identity}\ (S_N).

Every attainable pair (skewness, kurtosis) with Sku > Ssk² + 1 has exactly one Johnson member:
S_U above the lognormal line, S_B below it, S_L on it, S_N at (0, 3). :func:`johnson_for` fits
(gamma, delta) to the shape and (xi, lambda) to zero mean and the target variance.

The transform changes the correlation: for correlated standard normals with correlation
:math:`\rho_X`, expanding T in normalised Hermite polynomials :math:`h_k = He_k/\sqrt{k!}`,
:math:`T = \sum_k b_k h_k`, gives (Mehler's formula)

.. math::  \rho_Z = g(\rho_X) = \frac{\sum_{k \ge 1} b_k^2 \rho_X^k}{\sum_{k \ge 1} b_k^2},

exact for any memoryless T. g is increasing (Price's theorem: :math:`g' \propto
E[T'(X_1)T'(X_2)] > 0` for increasing T), g(0) = 0, g(1) = 1, and its range is
:math:`[g(-1), 1]`: correlations below g(-1) cannot be produced by any Gaussian input.
**Pre-distortion** draws X with :math:`\rho_X(\tau) = g^{-1}(r(\tau)/r(0))` so that Z has the
target ACVF r; that input ACVF must itself be positive definite on the grid, which the circulant
embedding checks (and, when it is not, clips and reports).

Modules: :mod:`~roughgp.non_gaussian.johnson` (the Johnson family and its fit to a
skewness and kurtosis), :mod:`~roughgp.non_gaussian.hermite` (the correlation map g and
the pre-distorted ACVF), :mod:`~roughgp.non_gaussian.draws` (the surface). Their public
names are re-exported here.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`, :mod:`roughgp.models`.
"""

from roughgp.non_gaussian.draws import NonGaussianInfo, non_gaussian_surface
from roughgp.non_gaussian.hermite import (
                                                 CorrelationMap,
                                                 PredistortedACVF,
                                                 correlation_map,
                                                 predistort,
)
from roughgp.non_gaussian.johnson import (
                                                 FAMILIES,
                                                 Johnson,
                                                 Moments,
                                                 johnson_for,
                                                 lognormal_kurtosis,
)

__all__ = ["Johnson", "Moments", "johnson_for", "lognormal_kurtosis", "CorrelationMap",
           "correlation_map", "PredistortedACVF", "predistort", "NonGaussianInfo",
           "non_gaussian_surface", "FAMILIES"]
