r"""Figure 2 of the paper (section 3.1): a ground surface, drawn exactly, and how it is judged.

A ground surface is the GP with the rotated anisotropic exponential ACVF of **eq 18** seen
through the Gaussian noise of **eq 8** (the surface of **eq 9**); figure 2 draws it on
:math:`2000 \times 2000` points with :math:`\phi = \pi/6`, :math:`\sigma_k^2 = 10`,
:math:`\lambda_a = 500`, :math:`\lambda_b = 5`, :math:`\sigma^2 = 1`
(:data:`roughgp.models.surfaces.FIGURE_2`). The computations, each returning a result object:

* :func:`figure2_surface` (cached): the latent draw by exact circulant embedding, with the
  embedding's report, and the surface (the same draw plus :class:`~roughgp.gp.noise.GaussianNoise`,
  from one random stream: equal to :func:`roughgp.models.surfaces.ground` with the same seed);
* :func:`figure2_acvf_deviation`: the latent surface's empirical ACVF on the grid lags along
  and across the grooves against eq 18 at the same lags, less :math:`\operatorname{Var}(\bar g)`,
  in units of the estimate's predicted standard deviation;
* :func:`figure2_texture`: the ISO 25178-2 parameters *Std*, *Sq*, *Sal*, *Str* of the surface
  and of further surfaces of the same model, with the model's predictions for them.

The chapter ``book/ground.ipynb`` draws and states its numbers from these results; the ledger's
claims ``fig2-simulation`` and ``fig2-acvf`` judge them.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time

import numpy as np

from roughgp.common.checks import as_generator
from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.gp.noise import GaussianNoise
from roughgp.metrology import spectral, texture
from roughgp.models import surfaces
from roughgp.sampling import diagnostics
from roughgp.sampling.grid_sampler import sample_grid

__all__ = ["GroundSurface", "DirectionalAcvf", "AcvfDeviation", "GroundTexture",
           "figure2_surface", "figure2_acvf_deviation", "figure2_texture"]

SEED = 2
"""The seed of the chapter's (and the ledger's) figure 2."""

NOISE_VARIANCE = 1.0
"""sigma^2 of eq 8 (the paper: 1 in all cases)."""


@dataclasses.dataclass(frozen=True)
class GroundSurface:
    """One ground surface of eq 9 and how it was drawn.

    ``latent`` (g, eq 18) and ``surface`` (z = g + noise, eq 8) are read-only arrays
    ``[iy, ix]``; ``torus_shape``, ``min_eigenvalue`` (relative to r(0)) and
    ``clipped_fraction`` are the circulant embedding's report (exact when nothing is clipped
    and no eigenvalue is negative); ``seconds`` is the time the draw took.
    """

    parameters: surfaces.GrooveParameters
    shape: tuple
    noise_variance: float
    seed: int
    latent: np.ndarray
    surface: np.ndarray
    torus_shape: tuple
    min_eigenvalue: float
    clipped_fraction: float
    seconds: float

    @property
    def kernel(self) -> RotatedExponentialKernel:
        """The eq 18 kernel of the latent draw."""
        return self.parameters.kernel()

    @property
    def residual_variance(self) -> float:
        """The variance of z - g: the noise of eq 8 that was added."""
        return float((self.surface - self.latent).var())


@dataclasses.dataclass(frozen=True)
class DirectionalAcvf:
    """The empirical ACVF on the grid lags near one direction, sorted by ``distance``.

    ``estimate``: the latent surface's (unbiased, demeaned) ACVF; ``model``: eq 18 at the
    same lags; ``deviation``: ``max |estimate - (model - Var(mean))| / sd`` of the estimate.
    """

    name: str
    angle: float
    distance: np.ndarray
    estimate: np.ndarray
    model: np.ndarray
    deviation: float


@dataclasses.dataclass(frozen=True)
class AcvfDeviation:
    """The ACVF of a ground surface against eq 18, along and across the grooves.

    ``mean_variance``: Var(mean of g), the amount the demeaned estimate is lowered by;
    ``spread``: the bound on the estimate's standard deviation at any lag (its value at lag
    zero); ``along``, ``across``: :class:`DirectionalAcvf`.
    """

    mean_variance: float
    spread: float
    along: DirectionalAcvf
    across: DirectionalAcvf

    @property
    def largest(self) -> float:
        """The larger of the two directions' deviations, in sd."""
        return max(self.along.deviation, self.across.deviation)


@dataclasses.dataclass(frozen=True)
class GroundTexture:
    """ISO 25178-2 parameters of ground surfaces of one model, with the model's predictions.

    ``seeds``: the surfaces' seeds (the first is the given surface's); ``std``, ``sq``,
    ``sal``, ``str``: one value per surface; ``angles``, ``power``: the first surface's angular
    spectrum; ``expected_sq`` (sqrt of sigma_k^2 + sigma^2 - Var(mean)) with ``sq_spread``
    (its delta-method sd); ``predicted_sal`` (lambda_b ln(5 sigma_k^2 / (sigma_k^2 + sigma^2)))
    and ``predicted_str`` (lambda_b / lambda_a).
    """

    seeds: tuple
    std: np.ndarray
    sq: np.ndarray
    sal: np.ndarray
    str: np.ndarray
    angles: np.ndarray
    power: np.ndarray
    expected_sq: float
    sq_spread: float
    predicted_sal: float
    predicted_str: float


def _read_only(array):
    array = np.asarray(array)
    array.setflags(write=False)
    return array


def figure2_surface(seed: int = SEED, *, parameters: surfaces.GrooveParameters = surfaces.FIGURE_2,
                    shape: tuple = surfaces.FIGURE_2_SHAPE,
                    noise_variance: float = NOISE_VARIANCE) -> GroundSurface:
    """Figure 2's ground surface: eq 18 drawn exactly by circulant embedding, plus eq 8's noise.

    ``seed`` must be an int >= 0. The latent draw and then the noise come from one stream
    seeded by it, so the surface equals ``surfaces.ground(shape, **asdict(parameters),
    noise_variance=noise_variance, seed=seed)``. The last call is cached (the arrays are
    read-only), so the chapter's or the ledger's several uses draw it once.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0 (the result is cached), got {seed!r}")
    parameters = surfaces.GrooveParameters(float(parameters.variance),
                                           tuple(float(v) for v in parameters.lengthscales),
                                           float(parameters.angle))
    return _cached_surface(int(seed), parameters, tuple(int(n) for n in shape),
                           float(noise_variance))


@functools.lru_cache(maxsize=1)
def _cached_surface(seed, parameters, shape, noise_variance):
    rng = as_generator(seed)
    start = time.perf_counter()
    latent, info = sample_grid(parameters.kernel(), shape, method="circulant", seed=rng,
                               return_info=True)
    surface = GaussianNoise(noise_variance).sample(latent[0], seed=rng)
    return GroundSurface(parameters, shape, noise_variance, seed, _read_only(latent[0]),
                         _read_only(surface), tuple(info.torus_shape),
                         float(info.min_eigenvalue), float(info.clipped_fraction),
                         time.perf_counter() - start)


def _directional(name, angle, reach, lags, acvf_hat, kernel, mean_variance, spread):
    mask, distance = spectral.near_direction(lags, angle, half_width=0.5)
    keep = (distance >= 0) & (distance <= reach)
    order = np.argsort(distance[keep], kind="stable")
    estimate = acvf_hat[mask][keep][order]
    model = kernel.acvf(lags[mask][keep][order])
    deviation = float(np.abs(estimate - (model - mean_variance)).max() / spread)
    return DirectionalAcvf(name, angle, distance[keep][order], estimate, model, deviation)


def figure2_acvf_deviation(ground: GroundSurface, *, max_lag: int = 700,
                           reach: tuple = (800.0, 40.0)) -> AcvfDeviation:
    """The latent surface's empirical ACVF against eq 18, along and across the grooves.

    ``max_lag``: the largest lag of the estimate per axis; ``reach``: the largest distance
    kept along and across the grooves (the lags within half a grid unit of each line).
    """
    kernel = ground.kernel
    lags, acvf_hat = spectral.empirical_acvf(ground.latent, max_lag=max_lag, unbiased=True)
    mean_variance = float(diagnostics.grid_mean_variance(kernel, ground.shape))
    spread = float(diagnostics.sample_variance_sd(kernel, ground.shape))
    angle = ground.parameters.angle
    along, across = (_directional(name, a, r, lags, acvf_hat, kernel, mean_variance, spread)
                     for name, a, r in (("along", angle, reach[0]),
                                        ("across", angle + math.pi / 2, reach[1])))
    return AcvfDeviation(mean_variance, spread, along, across)


def _sq_prediction(ground):
    kernel, shape, noise = ground.kernel, ground.shape, ground.noise_variance
    expected = math.sqrt(ground.parameters.variance + noise
                         - diagnostics.grid_mean_variance(kernel, shape, noise_variance=noise))
    spread = diagnostics.sample_variance_sd(kernel, shape, noise_variance=noise) / (2 * expected)
    return expected, float(spread)


def _repeat(ground, seed):
    return surfaces.ground(ground.shape, **dataclasses.asdict(ground.parameters),
                           noise_variance=ground.noise_variance, seed=seed)


def figure2_texture(ground: GroundSurface, n_repeats: int) -> GroundTexture:
    """Std, Sq, Sal and Str of ``ground`` and of ``n_repeats`` further surfaces of its model
    (seeds ``ground.seed + 1``, ...), with the model's Sq, Sal and Str."""
    seeds = (ground.seed,) + tuple(range(ground.seed + 1, ground.seed + 1 + n_repeats))
    values = [texture.areal_parameters(ground.surface)]
    values += [texture.areal_parameters(_repeat(ground, seed)) for seed in seeds[1:]]
    angles, power = texture.angular_spectrum(ground.surface)
    column = {name: np.array([v[name] for v in values]) for name in ("Std", "Sq", "Sal", "Str")}
    expected_sq, sq_spread = _sq_prediction(ground)
    p = ground.parameters
    factor = math.log(5 * p.variance / (p.variance + ground.noise_variance))
    return GroundTexture(seeds, column["Std"], column["Sq"], column["Sal"], column["Str"],
                         np.asarray(angles), np.asarray(power), expected_sq, sq_spread,
                         p.lengthscales[1] * factor, p.lengthscales[1] / p.lengthscales[0])
