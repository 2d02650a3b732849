r"""Ground and honed surfaces of the paper (sections 3.1 and 3.2).

* A **ground** surface is the GP of eq 18 (a rotated anisotropic exponential ACVF: grooves
  along the direction ``angle``, correlation length ``lengthscales[0]`` along them and
  ``lengthscales[1]`` across) seen through the Gaussian noise model of eq 8 (eq 9).
* A **one-step honed** surface is the pointwise minimum of two independent ground surfaces
  with mirrored angles ``+phi`` and ``-phi`` (eq 19); a **P-step** honed surface is the
  minimum of P one-step honed surfaces, each with its own hyperparameters (eq 20).

The paper uses noise of variance :math:`\sigma^2 = 1` "in all cases"; it does not say whether
the noise enters each ground surface of eq 19 or only the final minimum. Here it enters each
ground surface (the ``z`` of eq 19 are realised surfaces, eq 9), which is what ``ground``
returns; ``latent=True`` drops it everywhere.

The figures' hyperparameters are named presets: :data:`FIGURE_2` (with :data:`FIGURE_2_SHAPE`)
and :data:`FIGURE_3` (a tuple of two honing steps, with :data:`FIGURE_3_SHAPE`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import as_generator as _rng
from roughgp.gp.noise import GaussianNoise
from roughgp.gp.numpy_kernels import RotatedExponentialACVF
from roughgp.sampling.grid_sampler import sample_grid

__all__ = ["GrooveParameters", "ground", "honed", "honing_stack", "FIGURE_2", "FIGURE_2_SHAPE", "FIGURE_3",
           "FIGURE_3_SHAPE"]


@dataclass(frozen=True)
class GrooveParameters:
    """Hyperparameters of eq 18: one grinding step (or one step of a honing process).

    Attributes:
        variance: :math:`\\sigma_k^2 > 0`, the latent height variance.
        lengthscales: :math:`(\\lambda_a, \\lambda_b)`, along and across the grooves (> 0).
        angle: :math:`\\phi`, the groove direction in radians, counter-clockwise from x.
    """

    variance: float
    lengthscales: tuple
    angle: float

    def kernel(self, mirrored: bool = False):
        """The eq 18 kernel as a GPyTorch kernel (a
        :class:`roughgp.gp.kernels.RotatedExponentialKernel`, for fitting), with the angle
        ``-phi`` when ``mirrored`` (eq 19). Imports torch and GPyTorch."""
        from roughgp.gp.kernels import RotatedExponentialKernel
        angle = -self.angle if mirrored else self.angle
        return RotatedExponentialKernel(self.variance, self.lengthscales, angle)

    def covariance(self, mirrored: bool = False) -> RotatedExponentialACVF:
        """The eq 18 ACVF in numpy alone (:mod:`roughgp.gp.numpy_kernels`), with the angle
        ``-phi`` when ``mirrored`` (eq 19): what the draws of :func:`ground` and
        :func:`honed` use, so that a draw on the CPU never imports torch."""
        angle = -self.angle if mirrored else self.angle
        return RotatedExponentialACVF(self.variance, tuple(self.lengthscales), angle)


#: Figure 2: phi = pi/6, sigma_k^2 = 10, lambda_a = 500, lambda_b = 5 on 2000 x 2000 points.
FIGURE_2 = GrooveParameters(variance=10.0, lengthscales=(500.0, 5.0), angle=math.pi / 6)
FIGURE_2_SHAPE = (2000, 2000)

#: Figure 3: two honing steps, phi_{1,2} = pi/4; sigma_{k,1}^2 = 45, lambda_{a,1} = 500,
#: lambda_{b,1} = 30; sigma_{k,2}^2 = 0.2, lambda_{a,2} = 5, lambda_{b,2} = 3; 512 x 512 points.
FIGURE_3 = (GrooveParameters(variance=45.0, lengthscales=(500.0, 30.0), angle=math.pi / 4),
            GrooveParameters(variance=0.2, lengthscales=(5.0, 3.0), angle=math.pi / 4))
FIGURE_3_SHAPE = (512, 512)


def _check_surface_shape(shape):
    shape = (shape,) if np.ndim(shape) == 0 else tuple(shape)
    if len(shape) != 2:
        raise ValueError(f"shape must be (ny, nx) for a surface, got {shape!r}")
    return shape


def _draw_ground(parameters: GrooveParameters, shape, *, mirrored, noise, spacing, rng, method,
                 device=None):
    latent = sample_grid(parameters.covariance(mirrored), shape, spacing=spacing, seed=rng,
                         method=method, device=device)[0]
    return latent if noise is None else noise.sample(latent, seed=rng)


def ground(shape, *, variance, lengthscales, angle, noise_variance=1.0, spacing=1.0, seed=None,
           method="circulant", latent=False, device=None) -> np.ndarray:
    """A ground surface (section 3.1): a draw of eq 18 plus Gaussian noise (eq 8, 9).

    Args:
        shape: ``(ny, nx)``.
        variance, lengthscales, angle: eq 18 (see :class:`GrooveParameters`);
            ``**dataclasses.asdict(FIGURE_2)`` gives figure 2's.
        noise_variance: :math:`\\sigma^2 \\ge 0` of eq 8 (the paper: 1).
        spacing: grid spacing, scalar or ``(dy, dx)``, in the lengthscales' unit.
        seed: int, None or ``numpy.random.Generator``; the same seed gives the same surface.
        method: the sampler of :func:`roughgp.sampling.sample_grid`; ``"circulant"`` is exact.
        latent: return the latent GP draw alone (no noise).
        device: None (numpy) or a torch device such as ``"cuda"`` for the latent draw
            (:func:`roughgp.sampling.sample_grid`, :mod:`roughgp.common.device`).

    Returns:
        The surface ``z[iy, ix]``, in the height unit of ``sqrt(variance)``.
    """
    shape = _check_surface_shape(shape)
    parameters = GrooveParameters(variance, tuple(lengthscales), angle)
    noise = None if latent else GaussianNoise(noise_variance)
    return _draw_ground(parameters, shape, mirrored=False, noise=noise, spacing=spacing,
                        rng=_rng(seed), method=method, device=device)


def honing_stack(shape, steps, *, noise_variance=1.0, spacing=1.0, seed=None,
                 method="circulant", latent=False, device=None) -> np.ndarray:
    """The ground surfaces a honed surface is the minimum of (eq 19, 20).

    Args: as :func:`honed`.

    Returns:
        Shape ``(P, 2, ny, nx)``: for each step ``p`` its ground surfaces with the angles
        ``+phi_p`` (index 0) and ``-phi_p`` (index 1), independent draws in that order from
        ``seed``. :func:`honed` is their minimum over the first two axes.
    """
    shape = _check_surface_shape(shape)
    steps = tuple(steps)
    if not steps or not all(isinstance(s, GrooveParameters) for s in steps):
        raise ValueError(f"steps must be a non-empty sequence of GrooveParameters, got {steps!r}")
    noise = None if latent else GaussianNoise(noise_variance)
    rng = _rng(seed)
    return np.stack([[_draw_ground(step, shape, mirrored=mirrored, noise=noise, spacing=spacing,
                                   rng=rng, method=method, device=device)
                      for mirrored in (False, True)]
                     for step in steps])


def honed(shape, steps, *, noise_variance=1.0, spacing=1.0, seed=None, method="circulant",
          latent=False, device=None) -> np.ndarray:
    """A P-step honed surface (section 3.2, eq 19 and 20).

    Each step ``p`` draws two independent ground surfaces with the step's hyperparameters and
    the angles ``+phi_p`` and ``-phi_p`` and keeps their pointwise minimum (eq 19); the
    honed surface is the pointwise minimum over the steps (eq 20). The steps are
    independent, as the paper requires; :func:`honing_stack` returns the ground surfaces.

    Args:
        shape: ``(ny, nx)``.
        steps: a sequence of :class:`GrooveParameters`, one per honing step (:data:`FIGURE_3`).
        noise_variance, spacing, seed, method, latent, device: as in :func:`ground`; the
            noise enters every ground surface.

    Returns:
        The honed surface ``z[iy, ix]``.
    """
    stack = honing_stack(shape, steps, noise_variance=noise_variance, spacing=spacing,
                         seed=seed, method=method, latent=latent, device=device)
    return stack.min(axis=(0, 1))
