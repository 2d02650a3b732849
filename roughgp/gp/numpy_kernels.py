r"""Kernels in numpy alone: what a draw on the CPU needs, without torch.

The kernels of :mod:`roughgp.gp.kernels` are GPyTorch kernels (learnable, differentiable);
importing them costs torch's and GPyTorch's seconds of import. A draw of a ground or honed
surface (eq 18-20, :mod:`roughgp.models.surfaces`) or of a turned surface's side flow
(:mod:`roughgp.models.turned`) needs only the ACVF on a lag table, so it takes
:class:`RotatedExponentialACVF` or :class:`MaternACVF` instead: the same functions of
:mod:`roughgp.gp.acvf` with the hyperparameters as plain floats, and the interface the
sampler reads (``acvf``, ``psd``, ``hyperparameters``; :func:`roughgp.sampling.sample_grid`).

The hyperparameters are used as given, in float64; the GPyTorch kernel stores positive ones
through its softplus constraint, which can move them by a few units in the last place (30.0
becomes 29.999999999999908), so a draw from either agrees to rounding, not bit for bit.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import check_finite, check_positive
from roughgp.gp import acvf as _acvf

__all__ = ["RotatedExponentialACVF", "MaternACVF", "is_additive"]


@dataclass(frozen=True)
class RotatedExponentialACVF:
    r"""Eq 18, :math:`\sigma_k^2\exp(-\lVert\Lambda^{-1}T_\phi\boldsymbol\tau\rVert)`, on numpy
    lags of shape (..., 2).

    Attributes:
        variance: :math:`\sigma_k^2 > 0`.
        lengthscales: :math:`(\lambda_a, \lambda_b)`, both > 0.
        angle: :math:`\phi` in radians (finite).
    """

    variance: float
    lengthscales: tuple
    angle: float
    dim = 2

    def __post_init__(self):
        check_positive("variance", self.variance)
        check_positive("lengthscales", self.lengthscales)
        if np.shape(self.lengthscales) != (2,):
            raise ValueError(f"lengthscales must have shape (2,), got "
                             f"{np.shape(self.lengthscales)}")
        check_finite("angle", self.angle)

    def hyperparameters(self) -> dict[str, np.ndarray]:
        """The hyperparameters by the names of
        :class:`roughgp.gp.kernels.RotatedExponentialKernel`."""
        return {"variance": np.float64(self.variance),
                "lengthscales": np.asarray(self.lengthscales, dtype=np.float64),
                "angle": np.float64(self.angle)}

    def acvf(self, lags) -> np.ndarray:
        """The ACVF at ``lags`` of shape (..., 2) (:func:`roughgp.gp.acvf.rotated_exponential`)."""
        return _acvf.rotated_exponential(np.asarray(lags, dtype=np.float64),
                                         **self.hyperparameters())

    def psd(self, freqs) -> np.ndarray:
        """The PSD (eq 5 convention) at ``freqs`` of shape (..., 2)
        (:func:`roughgp.gp.acvf.rotated_exponential_psd`)."""
        return _acvf.rotated_exponential_psd(np.asarray(freqs, dtype=np.float64),
                                             **self.hyperparameters())


@dataclass(frozen=True)
class MaternACVF:
    r"""The isotropic Matérn ACVF (:func:`roughgp.gp.acvf.matern`) on numpy lags of shape
    (..., ``dim``): the numpy twin of :class:`roughgp.gp.kernels.MaternKernel`.

    Attributes:
        variance: :math:`\sigma^2 > 0`.
        lengthscale: :math:`\lambda > 0`.
        nu: the smoothness, one of :data:`roughgp.gp.acvf.MATERN_NUS`.
        dim: D, the number of lag components (>= 1).
    """

    variance: float
    lengthscale: float
    nu: float = 0.5
    dim: int = 1

    def __post_init__(self):
        check_positive("variance", self.variance)
        check_positive("lengthscale", self.lengthscale)
        if self.nu not in _acvf.MATERN_NUS:
            raise ValueError(f"nu must be one of {_acvf.MATERN_NUS}, got {self.nu!r}")
        if not isinstance(self.dim, (int, np.integer)) or self.dim < 1:
            raise ValueError(f"dim must be an integer >= 1, got {self.dim!r}")

    def hyperparameters(self) -> dict[str, np.ndarray]:
        """The hyperparameters by the names of :class:`roughgp.gp.kernels.MaternKernel`."""
        return {"variance": np.float64(self.variance),
                "lengthscale": np.float64(self.lengthscale)}

    def acvf(self, lags) -> np.ndarray:
        """The ACVF at ``lags`` of shape (..., dim) (:func:`roughgp.gp.acvf.matern`)."""
        return _acvf.matern(self._lags(lags), nu=self.nu, **self.hyperparameters())

    def psd(self, freqs) -> np.ndarray:
        """The PSD (eq 5 convention) at ``freqs`` of shape (..., dim)
        (:func:`roughgp.gp.acvf.matern_psd`)."""
        return _acvf.matern_psd(self._lags(freqs), nu=self.nu, **self.hyperparameters())

    def _lags(self, points) -> np.ndarray:
        points = np.asarray(points, dtype=np.float64)
        if points.ndim == 0 or points.shape[-1] != self.dim:
            raise ValueError(f"lags/freqs must have shape (..., {self.dim}) for this "
                             f"{self.dim}-D kernel, got {points.shape}")
        return points


def is_additive(kernel) -> bool:
    """Whether ``kernel`` is a :class:`roughgp.gp.kernels.AdditiveKernel` (eq 22), without
    importing GPyTorch: such a kernel exists only once its module is imported."""
    kernels = sys.modules.get("roughgp.gp.kernels")
    return kernels is not None and isinstance(kernel, kernels.AdditiveKernel)
