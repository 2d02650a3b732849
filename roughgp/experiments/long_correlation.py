r"""The conclusion's long correlation lengths in the paper's own setting: eq 18 in 2-D.

The conclusion says the GP approach simulates "long correlation lengths that are not possible
with ARMA processes or other digital filter methods". In 1-D the exponential ACVF of any
length is an AR(1) (:func:`roughgp.experiments.small_claims.long_correlation`); the paper's
long lengthscale, though, is figure 2's rotated anisotropic exponential (eq 18,
:math:`\lambda_a = 500`, :math:`\lambda_b = 5`, :math:`\phi = \pi/6`) on a
:math:`2000 \times 2000` grid. :func:`long_correlation_2d` checks the digital filters there:

* 2-D AR recursions (:mod:`roughgp.models.arma2d`, quarter-plane and non-symmetric half-plane
  supports of orders 1..p) fitted to eq 18 by the 2-D Yule-Walker equations; their ACVF
  against eq 18 over the lags :math:`|\tau_x|, |\tau_y| \le` ``window`` (600: past
  :math:`\lambda_a` along the grooves) and along the grooves, and the same fits with a short
  :math:`\lambda_a` for contrast (the fits converge there);
* the grid-size FFT filter (:func:`roughgp.sampling.fft_filter`, the classic digital filter):
  its ACVF is eq 18 periodised at the grid size, so it wraps;
* the FFT filter on a larger torus, i.e. circulant embedding of figure 2's draw
  (:func:`roughgp.experiments.ground.figure2_surface`): exact when no eigenvalue is clipped.

The ledger's check ``conclusion-long-correlation`` judges the result.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from roughgp.experiments import ground
from roughgp.gp import acvf as acvfs
from roughgp.models import arma2d, surfaces

__all__ = ["ARFit", "LongCorrelation2D", "ar_fits", "long_correlation_2d"]

ORDERS = (1, 2, 4, 8, 16)
FULL_ORDERS = (1, 2, 4, 8, 16, 24)
SHORT_LAMBDA_A = 20.0          # the contrast: figure 2's lambda_b and phi, a short lambda_a


@dataclasses.dataclass(frozen=True)
class ARFit:
    """One 2-D AR fit of eq 18: ``max_error``, the largest ``|ACVF - eq 18|`` over the window in
    units of :math:`\\sigma_k^2`; ``along``: its ACVF along the grooves (units of
    :math:`\\sigma_k^2`) at :attr:`LongCorrelation2D.along_lags`."""

    kind: str
    order: int
    n_coefficients: int
    sigma2: float
    max_error: float
    along: np.ndarray


@dataclasses.dataclass(frozen=True)
class LongCorrelation2D:
    """2-D AR fits, the grid-size FFT filter and circulant embedding against eq 18.

    ``fits``: (kind, order) -> :class:`ARFit` with figure 2's hyperparameters; ``short_fits``:
    the same with ``short_lambda_a``; ``along_lags``: distances along the grooves (grid units,
    rounded to lattice points ``along_points``); ``true_along``: eq 18 there (/ sigma_k^2);
    ``filter_*``: the FFT filter on the ``grid`` x ``grid`` torus; ``torus_shape``,
    ``min_eigenvalue``, ``clipped_fraction``: the circulant embedding of figure 2's draw.
    """

    parameters: surfaces.GrooveParameters
    window: int
    fft_size: int
    orders: tuple
    kinds: tuple
    fits: dict
    short_lambda_a: float
    short_fits: dict
    along_lags: np.ndarray
    along_points: np.ndarray
    true_along: np.ndarray
    grid: int
    filter_along: np.ndarray
    filter_max_error: float
    torus_shape: tuple
    min_eigenvalue: float
    clipped_fraction: float

    def best(self, kind: str, short: bool = False) -> ARFit:
        """The fit of ``kind`` with the smallest window error over the orders."""
        fits = self.short_fits if short else self.fits
        return min((f for (k, _), f in fits.items() if k == kind), key=lambda f: f.max_error)

    @property
    def filter_wrap_error(self) -> float:
        """The largest ``|filter ACVF - eq 18|`` along the grooves (units of sigma_k^2)."""
        return float(np.abs(self.filter_along - self.true_along).max())


def _window(values, window):
    """The lags -window..window of a torus-indexed ACVF ``values[k_y, k_x]``."""
    shifted = np.roll(values, (window, window), axis=(0, 1))
    return shifted[:2 * window + 1, :2 * window + 1]


def _window_lags(window):
    ky, kx = np.mgrid[-window:window + 1, -window:window + 1]
    return np.stack([kx, ky], axis=-1).astype(np.float64)


def ar_fits(parameters: surfaces.GrooveParameters, orders=ORDERS, kinds=arma2d.SUPPORTS, *,
            window: int = 600, fft_size: int = 4096, along_points=None) -> dict:
    """(kind, order) -> :class:`ARFit`: 2-D Yule-Walker AR fits of eq 18 with ``parameters``,
    their ACVF on a ``fft_size`` torus against eq 18 on the lags within ``window``."""
    kernel = parameters.kernel()
    truth = kernel.acvf(_window_lags(window))
    fits = {}
    for kind in kinds:
        for p in orders:
            support = arma2d.ar_support(p, kind)
            coefficients, sigma2 = arma2d.yule_walker_2d(kernel.acvf, support)
            model = arma2d.ar_acvf_2d(coefficients, support, sigma2, fft_size)
            error = float(np.abs(_window(model, window) - truth).max() / parameters.variance)
            along = (np.empty(0) if along_points is None else
                     model[along_points[:, 1] % fft_size, along_points[:, 0] % fft_size]
                     / parameters.variance)
            fits[kind, int(p)] = ARFit(kind, int(p), len(support), sigma2, error, along)
    return fits


def _grid_filter_acvf(parameters, grid):
    """The grid-size FFT filter's ACVF (eigenvalues S(f_k) on the grid's own frequencies),
    indexed [k_y, k_x]: eq 18 periodised at ``grid``."""
    f = np.fft.fftfreq(grid)
    freqs = np.stack(np.meshgrid(f, f, indexing="ij")[::-1], axis=-1)
    psd = acvfs.rotated_exponential_psd(freqs, parameters.variance, parameters.lengthscales,
                                        parameters.angle)
    del freqs
    return np.fft.ifft2(psd).real


def long_correlation_2d(*, parameters: surfaces.GrooveParameters = surfaces.FIGURE_2,
                        orders=ORDERS, kinds=arma2d.SUPPORTS, window: int = 600,
                        fft_size: int = 4096, short_lambda_a: float = SHORT_LAMBDA_A,
                        grid: int = surfaces.FIGURE_2_SHAPE[0], max_along: float = 1000.0,
                        ground_surface: ground.GroundSurface | None = None) -> LongCorrelation2D:
    """Eq 18 (figure 2's hyperparameters) against 2-D AR fits of ``orders`` (and the same fits
    with ``short_lambda_a``), the grid-size FFT filter on ``grid`` points and circulant
    embedding (``ground_surface``, by default :func:`ground.figure2_surface`, cached).

    Along the grooves the lags run 0..``max_along`` (grid units) on the nearest lattice points.
    """
    if not 0 < window < fft_size // 2 or max_along > min(fft_size, grid) / 2:
        raise ValueError(f"window ({window}) and max_along ({max_along}) must lie within half "
                         f"of fft_size ({fft_size}) and of grid ({grid})")
    t = np.arange(0.0, max_along + 1.0, 10.0)
    points = np.rint(np.stack([t * math.cos(parameters.angle),
                               t * math.sin(parameters.angle)], axis=-1)).astype(int)
    kernel = parameters.kernel()
    true_along = kernel.acvf(points.astype(np.float64)) / parameters.variance
    fits = ar_fits(parameters, orders, kinds, window=window, fft_size=fft_size,
                   along_points=points)
    short = surfaces.GrooveParameters(parameters.variance,
                                      (float(short_lambda_a), parameters.lengthscales[1]),
                                      parameters.angle)
    short_fits = ar_fits(short, orders, ("half",), window=window, fft_size=fft_size // 2)
    filtered = _grid_filter_acvf(parameters, grid)
    filter_along = filtered[points[:, 1] % grid, points[:, 0] % grid] / parameters.variance
    filter_error = float(np.abs(_window(filtered, window) - kernel.acvf(_window_lags(window))).max()
                         / parameters.variance)
    del filtered
    drawn = ground.figure2_surface() if ground_surface is None else ground_surface
    return LongCorrelation2D(parameters, int(window), int(fft_size), tuple(orders), tuple(kinds),
                             fits, float(short_lambda_a), short_fits, t, points, true_along,
                             int(grid), filter_along, filter_error, tuple(drawn.torus_shape),
                             float(drawn.min_eigenvalue), float(drawn.clipped_fraction))
