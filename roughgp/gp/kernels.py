r"""The ACVFs of :mod:`roughgp.gp.acvf` as GPyTorch kernels (eq 18, 21, 22 and the Matérn family).

Each kernel evaluates the *same* plain function of :mod:`roughgp.gp.acvf` on torch tensors, so a
kernel matrix and ``acvf.<function>(lags, ...)`` agree to rounding, and gradients flow to the
learnable, positively constrained hyperparameters (variances, lengthscales, weights).

Every kernel here is stationary and offers, beside GPyTorch's ``kernel(x1, x2)``:

* ``kernel.acvf(lags)``: the ACVF at lags of shape (..., D) -- a NumPy array in gives a
  float64 NumPy array out (detached), a tensor in gives a differentiable tensor out;
* ``kernel.psd(freqs)``: the closed-form PSD in the Fourier convention of eq 5;
* ``kernel.hyperparameters()``: the current constrained values by name.

Batched kernels (``batch_shape``) are not supported: one kernel describes one surface.
"""

from __future__ import annotations

import gpytorch
import numpy as np
import torch
from gpytorch.constraints import Positive

from roughgp.common.checks import check_positive
from roughgp.gp import acvf as _acvf

__all__ = [
    "StationaryKernel",
    "RotatedExponentialKernel",
    "SpectralMixtureKernel",
    "AdditiveKernel",
    "MaternKernel",
]

_DTYPE = torch.float64


def _tensor(name, value, shape):
    t = torch.as_tensor(value, dtype=_DTYPE).clone()  # never share memory with the caller
    if tuple(t.shape) != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)}, got {tuple(t.shape)}")
    return t


class StationaryKernel(gpytorch.kernels.Kernel):
    """Base class: a stationary ACVF ``r(tau)`` of :mod:`roughgp.gp.acvf` as a GPyTorch kernel.

    Subclasses set ``dim`` (D) and implement ``hyperparameters()``, ``_acvf`` and ``_psd``.
    ``forward(x1, x2)`` returns ``r(x2[j] - x1[i])``, the matrix R of eq 10.
    """

    dim: int

    def __init__(self, **kwargs):
        batch_shape = kwargs.get("batch_shape")
        if batch_shape is not None and len(batch_shape) > 0:
            raise ValueError(f"batch_shape must be empty (torch.Size([])), got {batch_shape}")
        super().__init__(**kwargs)

    def hyperparameters(self) -> dict[str, torch.Tensor]:
        """The current hyperparameters (constrained values) by the names of the paper."""
        raise NotImplementedError

    def _acvf(self, lags, **hyper):
        raise NotImplementedError

    def _psd(self, freqs, **hyper):
        raise NotImplementedError(f"{type(self).__name__} has no closed-form PSD")

    def _evaluate(self, method, points):
        shape = tuple(points.shape) if hasattr(points, "shape") else np.shape(points)
        if len(shape) == 0 or shape[-1] != self.dim:
            raise ValueError(f"lags/freqs must have shape (..., {self.dim}) for this "
                             f"{self.dim}-D kernel, got {shape}")
        hyper = self.hyperparameters()
        if isinstance(points, torch.Tensor):
            return method(points, **hyper)
        numpy_hyper = {k: v.detach().cpu().numpy().astype(np.float64) for k, v in hyper.items()}
        return method(np.asarray(points, dtype=np.float64), **numpy_hyper)

    def acvf(self, lags):
        """The ACVF at ``lags`` of shape (..., D); NumPy in -> NumPy out, tensor in -> tensor out."""
        return self._evaluate(self._acvf, lags)

    def psd(self, freqs):
        """The PSD (eq 5 convention) at ``freqs`` of shape (..., D), in cycles per unit length."""
        return self._evaluate(self._psd, freqs)

    def forward(self, x1, x2, diag=False, last_dim_is_batch=False, **params):
        if last_dim_is_batch:
            raise ValueError("last_dim_is_batch=True is not supported by roughgp kernels")
        for name, x in (("x1", x1), ("x2", x2)):
            if x.shape[-1] != self.dim:
                raise ValueError(f"{name} must have {self.dim} columns (D = {self.dim}), "
                                 f"got shape {tuple(x.shape)}")
        if diag:
            return self._acvf(x2 - x1, **self.hyperparameters())
        return self._acvf(x2.unsqueeze(-3) - x1.unsqueeze(-2), **self.hyperparameters())

    def __repr__(self):
        values = ", ".join(f"{k}={v.detach().cpu().numpy().round(6).tolist()}"
                           for k, v in self.hyperparameters().items())
        return f"{type(self).__name__}({values})"


class _PositiveParameters:
    """Mixin: register and set positively constrained parameters by name."""

    def _register_positive(self, name, initial):
        check_positive(name, initial)
        self.register_parameter(f"raw_{name}", torch.nn.Parameter(torch.zeros_like(initial)))
        self.register_constraint(f"raw_{name}", Positive())
        self._set_positive(name, initial)

    def _set_positive(self, name, value):
        raw = getattr(self, f"raw_{name}")
        value = _tensor(name, value, raw.shape)
        check_positive(name, value)
        constraint = getattr(self, f"raw_{name}_constraint")
        self.initialize(**{f"raw_{name}": constraint.inverse_transform(value)})


class RotatedExponentialKernel(_PositiveParameters, StationaryKernel):
    r"""Eq 18: :math:`\sigma_k^2\exp(-\lVert\Lambda^{-1}T_\phi\boldsymbol\tau\rVert)` on 2-D inputs.

    Hyperparameters: ``variance`` (:math:`\sigma_k^2`), ``lengthscales``
    (:math:`\lambda_a, \lambda_b`, GPyTorch's ``lengthscale`` of shape (1, 2)) and ``angle``
    (:math:`\phi` in radians, unconstrained; the ACVF has period :math:`\pi` in it).
    PSD: :func:`roughgp.gp.acvf.rotated_exponential_psd`.
    """

    dim = 2
    has_lengthscale = True

    def __init__(self, variance=1.0, lengthscales=(1.0, 1.0), angle=0.0, **kwargs):
        super().__init__(ard_num_dims=2, **kwargs)
        self._register_positive("variance", _tensor("variance", variance, ()))
        self.register_parameter("raw_angle", torch.nn.Parameter(torch.zeros((), dtype=_DTYPE)))
        self.double()
        self.lengthscales = lengthscales
        self.angle = angle

    @property
    def variance(self):
        return self.raw_variance_constraint.transform(self.raw_variance)

    @variance.setter
    def variance(self, value):
        self._set_positive("variance", value)

    @property
    def lengthscales(self):
        return self.lengthscale.reshape(2)

    @lengthscales.setter
    def lengthscales(self, value):
        value = _tensor("lengthscales", value, (2,))
        check_positive("lengthscales", value)
        self.lengthscale = value.reshape(1, 2)

    @property
    def angle(self):
        return self.raw_angle

    @angle.setter
    def angle(self, value):
        value = _tensor("angle", value, ())
        if not torch.isfinite(value):
            raise ValueError(f"angle must be finite, got {value.item()}")
        self.initialize(raw_angle=value)

    def hyperparameters(self):
        return {"variance": self.variance, "lengthscales": self.lengthscales, "angle": self.angle}

    def _acvf(self, lags, **hyper):
        return _acvf.rotated_exponential(lags, **hyper)

    def _psd(self, freqs, **hyper):
        return _acvf.rotated_exponential_psd(freqs, **hyper)


class SpectralMixtureKernel(_PositiveParameters, StationaryKernel):
    r"""Eq 21, the spectral mixture ACVF of Wilson & Adams (2013), in D dimensions.

    Hyperparameters: ``weights`` (Q,) > 0, ``means`` (Q, D) unconstrained (frequencies in
    cycles per unit length), ``variances`` (Q, D) > 0 (the diagonal covariances
    :math:`\Sigma_q`). PSD: :func:`roughgp.gp.acvf.spectral_mixture_psd`.

    Not GPyTorch's ``SpectralMixtureKernel`` for D > 1: GPyTorch sums the components of each
    dimension and multiplies the dimensions; eq 21 multiplies the dimensions inside each
    component and sums the components. In 1-D the two agree.
    """

    def __init__(self, num_mixtures, dim=1, weights=None, means=None, variances=None, **kwargs):
        if not isinstance(num_mixtures, (int, np.integer)) or num_mixtures < 1:
            raise ValueError(f"num_mixtures must be an integer >= 1, got {num_mixtures!r}")
        if not isinstance(dim, (int, np.integer)) or dim < 1:
            raise ValueError(f"dim must be an integer >= 1, got {dim!r}")
        super().__init__(**kwargs)
        self.dim = int(dim)
        q, d = int(num_mixtures), int(dim)
        weights = torch.full((q,), 1.0 / q) if weights is None else weights
        means = torch.linspace(0.0, 0.25, q).repeat(d, 1).T if means is None else means
        variances = torch.full((q, d), 0.01) if variances is None else variances
        self._register_positive("weights", _tensor("weights", weights, (q,)))
        self._register_positive("variances", _tensor("variances", variances, (q, d)))
        self.register_parameter("raw_means", torch.nn.Parameter(_tensor("means", means, (q, d))))
        self.double()

    @property
    def num_mixtures(self):
        return self.raw_weights.shape[0]

    @property
    def weights(self):
        return self.raw_weights_constraint.transform(self.raw_weights)

    @weights.setter
    def weights(self, value):
        self._set_positive("weights", value)

    @property
    def variances(self):
        return self.raw_variances_constraint.transform(self.raw_variances)

    @variances.setter
    def variances(self, value):
        self._set_positive("variances", value)

    @property
    def means(self):
        return self.raw_means

    @means.setter
    def means(self, value):
        value = _tensor("means", value, self.raw_means.shape)
        if not torch.all(torch.isfinite(value)):
            raise ValueError("means must be finite")
        self.initialize(raw_means=value)

    def hyperparameters(self):
        return {"weights": self.weights, "means": self.means, "variances": self.variances}

    def _acvf(self, lags, **hyper):
        return _acvf.spectral_mixture(lags, **hyper)

    def _psd(self, freqs, **hyper):
        return _acvf.spectral_mixture_psd(freqs, **hyper)


class AdditiveKernel(StationaryKernel):
    r"""Eq 22: :math:`r(\boldsymbol\tau) = r_x(\tau_x) + r_y(\tau_y)` from two 1-D kernels.

    ``kernel_x`` acts on the first input column, ``kernel_y`` on the second. Its spectrum is
    concentrated on the frequency axes (see :func:`roughgp.gp.acvf.additive`), so ``psd`` raises.
    Unlike ``gpytorch.kernels.AdditiveKernel`` it keeps the two parts addressable by axis
    (``kernel.kernel_x``), which lets a sampler draw each part as a profile.
    """

    dim = 2

    def __init__(self, kernel_x: StationaryKernel, kernel_y: StationaryKernel, **kwargs):
        for name, k in (("kernel_x", kernel_x), ("kernel_y", kernel_y)):
            if not isinstance(k, StationaryKernel) or k.dim != 1:
                raise ValueError(f"{name} must be a 1-D roughgp StationaryKernel (dim = 1), "
                                 f"got {k!r}")
        super().__init__(**kwargs)
        self.kernel_x = kernel_x
        self.kernel_y = kernel_y

    def hyperparameters(self):
        return {**{f"x.{k}": v for k, v in self.kernel_x.hyperparameters().items()},
                **{f"y.{k}": v for k, v in self.kernel_y.hyperparameters().items()}}

    def acvf(self, lags):
        return _acvf.additive(lags, self.kernel_x.acvf, self.kernel_y.acvf)

    def _acvf(self, lags, **hyper):
        return self.acvf(lags)

    def psd(self, freqs):
        raise NotImplementedError(
            "the additive ACVF of eq 22 has a line spectrum S_x(f_x) delta(f_y) + delta(f_x) S_y(f_y); "
            "use kernel_x.psd and kernel_y.psd")

    def __repr__(self):
        return f"AdditiveKernel(kernel_x={self.kernel_x!r}, kernel_y={self.kernel_y!r})"


class MaternKernel(_PositiveParameters, StationaryKernel):
    r"""Isotropic Matérn ACVF with ``nu`` in {0.5, 1.5, 2.5, inf} in D dimensions, with its
    variance included (:func:`roughgp.gp.acvf.matern`). ``nu=0.5`` with ``dim=1`` is the
    exponential (Ornstein-Uhlenbeck) kernel of a profile, ``nu=inf`` the squared exponential.
    """

    has_lengthscale = True

    def __init__(self, nu=0.5, dim=1, variance=1.0, lengthscale=1.0, **kwargs):
        if nu not in _acvf.MATERN_NUS:
            raise ValueError(f"nu must be one of {_acvf.MATERN_NUS}, got {nu!r}")
        if not isinstance(dim, (int, np.integer)) or dim < 1:
            raise ValueError(f"dim must be an integer >= 1, got {dim!r}")
        super().__init__(**kwargs)
        self.nu = nu
        self.dim = int(dim)
        self._register_positive("variance", _tensor("variance", variance, ()))
        self.double()
        value = _tensor("lengthscale", lengthscale, ())
        check_positive("lengthscale", value)
        self.lengthscale = value.reshape(1, 1)

    @property
    def variance(self):
        return self.raw_variance_constraint.transform(self.raw_variance)

    @variance.setter
    def variance(self, value):
        self._set_positive("variance", value)

    def hyperparameters(self):
        return {"variance": self.variance, "lengthscale": self.lengthscale.reshape(())}

    def _acvf(self, lags, **hyper):
        return _acvf.matern(lags, nu=self.nu, **hyper)

    def _psd(self, freqs, **hyper):
        return _acvf.matern_psd(freqs, nu=self.nu, **hyper)

    def __repr__(self):
        return f"MaternKernel(nu={self.nu}, dim={self.dim}, " + super().__repr__().split("(", 1)[1]

