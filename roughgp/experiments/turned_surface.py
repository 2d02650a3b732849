r"""Figures 6 and 7 (section 3.3-3.4): a turned surface fitted with the additive ACVF of eq 22
and the flaw of its simulations.

A turned surface carries its features along one direction, so the paper models it with an
additive ACVF (eq 22), :math:`r(\boldsymbol\tau) = r_x(\tau_x) + r_y(\tau_y)`, one spectral
mixture (eq 21, :math:`Q = 10`) per direction, fitted to a measured surface (figure 6) and
simulated (figure 7, with the Gaussian noise of eq 8). The paper reports that the simulations
carry "additional short wavelengths" and "a decreasing periodicity", and blames local optima of
the multi-modal fit (section 3.4).

Here the measured surface is replaced by the synthetic stand-in
:func:`roughgp.models.turned.turned_surface`. Each part of eq 22 is fitted by the paper's
procedure (:func:`roughgp.inference.fitting.fit_spectral_mixture`) to one mean profile (the
surface's mean over y for :math:`r_x`, over x for :math:`r_y`); the noise variance of eq 8 is
that of the residual. The flaw is measured along x (:mod:`roughgp.metrology.periodicity`): the
autocorrelation at 1 .. 5 feeds and the share of the variance below an eighth of a feed.

:func:`fit_turned_surface` does the fits (cached; ``careful=True`` adds a fit across the feed
that optimises every candidate to convergence), :func:`turned_surface_flaw` simulates from them
and measures the flaw of the data and of the simulations. The chapter "Turned surfaces" and the
ledger's checks of figure 7 both call them.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from roughgp import sampling
from roughgp.common.results_cache import persistent
from roughgp.common.settings import pick
from roughgp.gp import kernels
from roughgp.gp.noise import GaussianNoise
from roughgp.inference import fitting
from roughgp.metrology import levelling, periodicity
from roughgp.models import turned

__all__ = ["SHAPE", "SPACING", "PARAMS", "Q", "SEED", "N_PERIODS", "TurnedSurfaceFits",
           "FlawMeasure", "TurnedSurfaceFlaw", "fit_turned_surface", "simulate_additive",
           "measure_flaw", "turned_surface_flaw", "n_simulations"]

SHAPE = (512, 2048)           # (ny, nx) points: 0.5 mm x 2 mm at 1 um
SPACING = 1.0                 # um
PARAMS = turned.TurnedParameters(tilt=(0.001, 0.002))
Q = 10                        # spectral-mixture components per direction, as in the paper
SEED = 11
N_PERIODS = 5                 # feeds over which the periodicity is measured
CAREFUL = dict(n_optimise=10, screen_iter=1000, maxiter=1000)   # every candidate to convergence


@dataclasses.dataclass(frozen=True)
class TurnedSurfaceFits:
    """The levelled surface and the two parts of eq 22 fitted to its mean profiles.

    Attributes:
        z: the levelled surface, shape (ny, nx), in um.
        x, y: the coordinates across the feed (columns) and along the lay (rows), in um.
        across_feed, along_lay: the mean profiles ``z.mean(axis=0)`` and ``z.mean(axis=1)``.
        fit_x, fit_y: the paper's procedure's fits of eq 21 to them (``SpectralMixtureFit``).
        noise_variance: the residual's variance, the noise of eq 8 (um^2).
        feed, spacing: the turning feed and the grid spacing (um).
        careful_x: the fit across the feed with every candidate optimised to convergence, or
            None when not asked for.
    """
    z: np.ndarray
    x: np.ndarray
    y: np.ndarray
    across_feed: np.ndarray
    along_lay: np.ndarray
    fit_x: object
    fit_y: object
    noise_variance: float
    feed: float
    spacing: float
    careful_x: object = None

    @property
    def careful_gain(self) -> float:
        """Log marginal likelihood of the careful fit across the feed minus the paper's."""
        if self.careful_x is None:
            raise ValueError("careful_x is None: call fit_turned_surface(..., careful=True)")
        return self.careful_x.log_marginal_likelihood - self.fit_x.log_marginal_likelihood


@dataclasses.dataclass(frozen=True)
class FlawMeasure:
    """The flaw measures of a set of surfaces (along x, averaged over the rows).

    Attributes:
        periodicity: (n, n_periods): the autocorrelation at 1 .. n_periods feeds, per surface.
        short_share: (n,): the share of the variance below ``cutoff`` wavelength, per surface.
        examples: the first few surfaces (up to 3), for figures.
        cutoff: the short-wavelength cutoff (um).
    """
    periodicity: np.ndarray
    short_share: np.ndarray
    examples: np.ndarray
    cutoff: float

    @property
    def mean_periodicity(self) -> np.ndarray:
        return self.periodicity.mean(axis=0)

    @property
    def sd_periodicity(self) -> np.ndarray:
        """Standard deviation over the surfaces (nan for a single surface)."""
        if len(self.periodicity) < 2:
            return np.full(self.periodicity.shape[1], np.nan)
        return self.periodicity.std(axis=0, ddof=1)

    @property
    def mean_short_share(self) -> float:
        return float(self.short_share.mean())


@dataclasses.dataclass(frozen=True)
class TurnedSurfaceFlaw:
    """Figure 7's flaw: the data's measures against simulations from eq 22.

    Attributes:
        fits: the fits simulated from (:class:`TurnedSurfaceFits`).
        data: the measured (synthetic) surface's flaw measures.
        paper: the simulations from the paper's procedure's fits.
        careful: the simulations with the careful fit across the feed, or None.
        n_sim: simulated surfaces per model.
    """
    fits: TurnedSurfaceFits
    data: FlawMeasure
    paper: FlawMeasure
    careful: FlawMeasure | None
    n_sim: int

    @property
    def data_periodicity(self) -> np.ndarray:
        return self.data.periodicity[0]

    @property
    def data_short_share(self) -> float:
        return float(self.data.short_share[0])


def _level_turned_surface(shape, seed):
    raw = turned.turned_surface(shape, SPACING, PARAMS, seed=seed)
    return levelling.level(raw, spacing=SPACING)


@functools.lru_cache(maxsize=2)
@persistent
def _paper_fits(shape, q, seed):
    z = _level_turned_surface(shape, seed)
    x = np.arange(shape[1]) * SPACING
    y = np.arange(shape[0]) * SPACING
    across, along = z.mean(axis=0), z.mean(axis=1)
    fit_x = fitting.fit_spectral_mixture(x, across, q, seed=seed)
    fit_y = fitting.fit_spectral_mixture(y, along, q, seed=seed)
    residual = z - across[None, :] - along[:, None] + z.mean()
    return TurnedSurfaceFits(z, x, y, across, along, fit_x, fit_y, float(residual.var()),
                             PARAMS.feed, SPACING)


@functools.lru_cache(maxsize=2)
@persistent
def _careful_fits(shape, q, seed):
    fits = _paper_fits(shape, q, seed)
    careful_x = fitting.fit_spectral_mixture(fits.x, fits.across_feed, q, seed=seed, **CAREFUL)
    return dataclasses.replace(fits, careful_x=careful_x)


def fit_turned_surface(shape=SHAPE, *, q=Q, seed=SEED, careful=False) -> TurnedSurfaceFits:
    """Level the synthetic turned surface and fit eq 22's two parts to its mean profiles.

    Args:
        shape: (ny, nx) grid points (the chapter's and the ledger's: ``SHAPE``).
        q: components per direction (the paper: 10).
        seed: seeds the surface and both fits.
        careful: also fit across the feed with every candidate optimised to convergence
            (``careful_x``).

    The results are cached (the last two of each kind), so a chapter's or the ledger's
    several uses share one fit.
    """
    shape = (int(shape[0]), int(shape[1]))
    if careful:
        return _careful_fits(shape, int(q), int(seed))
    return _paper_fits(shape, int(q), int(seed))


def simulate_additive(fits: TurnedSurfaceFits, fit_across, n, seed) -> np.ndarray:
    """``n`` surfaces from eq 22 (``fit_across`` across the feed, ``fits.fit_y`` along the lay)
    plus the Gaussian noise of eq 8 of variance ``fits.noise_variance``, around the data's mean.

    The latent draw is seeded by ``seed``, the noise by ``seed + 1``.
    """
    kernel = kernels.AdditiveKernel(fit_across.kernel(), fits.fit_y.kernel())
    latent = sampling.sample_grid(kernel, fits.z.shape, spacing=fits.spacing, n_samples=n,
                                  seed=seed)
    noisy = GaussianNoise(fits.noise_variance).sample(latent, seed=seed + 1)
    return fits.z.mean() + noisy


def measure_flaw(surfaces, feed, spacing=SPACING, n_periods=N_PERIODS) -> FlawMeasure:
    """Periodicity at 1 .. ``n_periods`` feeds and the share of wavelengths below an eighth of
    a feed, along x, for each surface of ``surfaces`` (a sequence of (ny, nx) arrays)."""
    cutoff = feed / 8
    per = np.array([periodicity.periodicity(s, feed, spacing, n_periods) for s in surfaces])
    short = np.array([periodicity.short_wavelength_share(s, cutoff, spacing)
                      for s in surfaces])
    return FlawMeasure(per, short, np.array(surfaces[:3]), cutoff)


def n_simulations(full=None) -> int:
    """Simulated surfaces per model: 40 at the full size, 8 quick
    (:func:`roughgp.common.settings.pick`)."""
    return pick(8, 40, full=full)


def _simulate_and_measure(fits, fit_across, n, seed):
    return measure_flaw(simulate_additive(fits, fit_across, n, seed), fits.feed, fits.spacing)


@functools.lru_cache(maxsize=2)
def _paper_flaw(shape, q, seed, n):
    fits = _paper_fits(shape, q, seed)
    data = measure_flaw([fits.z], fits.feed, fits.spacing)
    paper = _simulate_and_measure(fits, fits.fit_x, n, seed + 1)
    return TurnedSurfaceFlaw(fits, data, paper, None, n)


@functools.lru_cache(maxsize=2)
def _careful_flaw(shape, q, seed, n):
    result = _paper_flaw(shape, q, seed, n)
    fits = _careful_fits(shape, q, seed)
    careful = _simulate_and_measure(fits, fits.careful_x, n, seed + 1)
    return dataclasses.replace(result, fits=fits, careful=careful)


def turned_surface_flaw(full=None, *, shape=SHAPE, q=Q, seed=SEED, careful=False,
                        n_sim=None) -> TurnedSurfaceFlaw:
    """Figure 7: simulate from :func:`fit_turned_surface`'s fits and measure the flaw.

    Args:
        full: 40 simulated surfaces per model, else 8 (overridden by ``n_sim``); None: as
            ``ROUGHGP_FULL`` says (:func:`roughgp.common.settings.resolve_full`).
        shape, q, seed: as for :func:`fit_turned_surface`; the simulations are seeded by
            ``seed + 1`` (latent) and ``seed + 2`` (noise), the same for both models.
        careful: also simulate with the careful fit across the feed (``careful``).
        n_sim: simulated surfaces per model.

    Cached like the fits; the result keeps three simulated surfaces per model, not all.
    """
    shape = (int(shape[0]), int(shape[1]))
    n = n_simulations(full) if n_sim is None else int(n_sim)
    if careful:
        return _careful_flaw(shape, int(q), int(seed), n)
    return _paper_flaw(shape, int(q), int(seed), n)
