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
and measures the flaw of the data and of the simulations, and :func:`flaw_shown` judges it (the
one threshold of the chapter "Turned surfaces" and the ledger's checks of figure 7).

Which optimum the fits reach depends on the machine's arithmetic: the likelihood of eq 21 with
Q = 10 has many optima within tens of log-likelihood units, and the same seeded search ends at
another one after a different rounding. :func:`optima_record` and :func:`summarise_optima` hold
the figures over several numerical set-ups (``benchmarks/turned_surface_optima.py`` runs the
whole computation under start jitters 0 .. 7, :mod:`roughgp.common.numerics`), so the chapter
states what holds over all of them and what does not.
"""

from __future__ import annotations

import dataclasses
import functools
import json
from pathlib import Path

import numpy as np

from roughgp import sampling
from roughgp.common.results_cache import persistent
from roughgp.common.settings import pick
from roughgp.gp import kernels
from roughgp.gp.noise import GaussianNoise
from roughgp.inference import fitting
from roughgp.metrology import levelling, periodicity
from roughgp.models import turned

__all__ = ["SHAPE", "SPACING", "PARAMS", "Q", "SEED", "N_PERIODS", "PERIODICITY_LOSS",
           "SHORT_EXCESS", "TurnedSurfaceFits", "FlawMeasure", "TurnedSurfaceFlaw",
           "fit_turned_surface", "simulate_additive", "measure_flaw", "turned_surface_flaw",
           "n_simulations", "flaw_shown", "FEED_BINS", "feed_error_bins", "optima_record", "recorded_optima", "OptimaSummary",
           "summarise_optima", "optima_table", "OPTIMA_RECORDED"]

SHAPE = (512, 2048)           # (ny, nx) points: 0.5 mm x 2 mm at 1 um
SPACING = 1.0                 # um
PARAMS = turned.TurnedParameters(tilt=(0.001, 0.002))
Q = 10                        # spectral-mixture components per direction, as in the paper
SEED = 11
N_PERIODS = 5                 # feeds over which the periodicity is measured
CAREFUL = dict(n_optimise=10, screen_iter=1000, maxiter=1000)   # every candidate to convergence
PERIODICITY_LOSS = 0.1        # the flaw: periodicity at N_PERIODS feeds this much below the data's
SHORT_EXCESS = 2.0            # ... or a short-wavelength share this many times the data's
FEED_BINS = 0.5               # the feed found: the fit's dominant period within half a frequency bin


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
    """Simulated surfaces per model: 40 at the full size, 16 quick
    (:func:`roughgp.common.settings.pick`)."""
    return pick(16, 40, full=full)


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


def feed_error_bins(fit, fits: TurnedSurfaceFits) -> float:
    """How far ``fit``'s dominant period (a fit across the feed) lies from the feed, in
    frequency bins of the mean profile across the feed: ``(1 / period - 1 / feed) L`` with ``L``
    its length. A profile of ``L / feed`` feeds (8 here) resolves frequencies to one bin, ``1 /
    L``: a period within half a bin (:data:`FEED_BINS`) is the feed as far as the data can tell.
    (The paper procedure's fit splits the feed's line among several components a fraction of a
    bin apart, and which of them weighs most moves with the optimum reached: a tolerance of 1 %,
    0.08 bins, failed on one of six numerical set-ups.)"""
    length = fits.across_feed.size * fits.spacing
    return float((1.0 / fit.dominant_period - 1.0 / fits.feed) * length)


def flaw_shown(simulated: FlawMeasure, data: FlawMeasure) -> tuple[bool, bool]:
    """Figure 7's two flaws in ``simulated`` against ``data`` (each averaged over its
    surfaces): ``(periodicity_lost, short_excess)``, the periodicity at :data:`N_PERIODS` feeds
    more than :data:`PERIODICITY_LOSS` below the data's, and a short-wavelength share above
    :data:`SHORT_EXCESS` times the data's."""
    lost = simulated.mean_periodicity[-1] < data.mean_periodicity[-1] - PERIODICITY_LOSS
    excess = simulated.mean_short_share > SHORT_EXCESS * data.mean_short_share
    return bool(lost), bool(excess)


def optima_record(result: TurnedSurfaceFlaw, start_jitter: int) -> dict:
    """What :func:`summarise_optima` needs of one careful :func:`turned_surface_flaw` run under
    the start jitter ``start_jitter``: both fits' log marginal likelihoods (across the feed), the
    careful fit's optima, and the flaw measures (means and sd over the simulations)."""
    if result.careful is None:
        raise ValueError("result must come from turned_surface_flaw(..., careful=True)")
    fits = result.fits

    def measures(m):
        return {"periodicity": m.mean_periodicity.tolist(),
                "periodicity_sd": m.sd_periodicity.tolist(),
                "short_share": m.mean_short_share,
                "short_share_sd": float(m.short_share.std(ddof=1))}

    return {"start_jitter": int(start_jitter), "shape": list(fits.z.shape),
            "n_sim": result.n_sim,
            "paper_log_ml": fits.fit_x.log_marginal_likelihood,
            "careful_log_ml": fits.careful_x.log_marginal_likelihood,
            "careful_optima": sorted(c.final_log_likelihood for c in fits.careful_x.candidates
                                     if c.optimised),
            "data": {"periodicity": result.data_periodicity.tolist(),
                     "short_share": result.data_short_share},
            "paper": measures(result.paper), "careful": measures(result.careful)}


#: a run of :func:`optima_record` under start jitters 0 .. 7 (one per line), by
#: ``benchmarks/turned_surface_optima.py``
OPTIMA_RECORDED = (Path(__file__).resolve().parents[2] / "benchmarks" / "results"
                   / "turned_surface_optima.jsonl")


def recorded_optima(path=OPTIMA_RECORDED) -> list[dict] | None:
    """The records of a recorded run (:data:`OPTIMA_RECORDED`), or None where there is none."""
    path = Path(path)
    if not path.is_file():
        return None
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@dataclasses.dataclass(frozen=True)
class OptimaSummary:
    """Figure 7 over several numerical set-ups (:func:`summarise_optima`).

    Attributes:
        n: the set-ups.
        gain: (min, max) of the careful fit's log ML over the paper procedure's.
        careful_log_ml: (min, max) of the careful fit's log ML: how far apart the best optima
            found lie.
        periodicity_gain: (min, max) of the careful simulations' periodicity at the last feed
            minus the paper procedure's.
        periodicity_raised, short_lowered: in how many set-ups the careful optimum raised the
            periodicity at the last feed, and lowered the short-wavelength share.
        flaw_kept: in how many set-ups the careful optimum's simulations still show both flaws
            (:func:`flaw_shown`'s thresholds).
        short_ratio: (min, max) of the careful simulations' short-wavelength share over the
            data's.
        data_periodicity: the data's periodicity at the last feed.
        careful_periodicity: (min, max) of the careful simulations' periodicity there.
    """
    n: int
    gain: tuple
    careful_log_ml: tuple
    periodicity_gain: tuple
    periodicity_raised: int
    short_lowered: int
    flaw_kept: int
    short_ratio: tuple
    data_periodicity: float
    careful_periodicity: tuple


def summarise_optima(records) -> OptimaSummary:
    """:class:`OptimaSummary` of :func:`optima_record` s (at least one)."""
    records = list(records)
    if not records:
        raise ValueError("records must hold at least one optima_record")

    def span(values):
        return (float(min(values)), float(max(values)))

    gain = [r["careful_log_ml"] - r["paper_log_ml"] for r in records]
    per_gain = [r["careful"]["periodicity"][-1] - r["paper"]["periodicity"][-1] for r in records]
    ratio = [r["careful"]["short_share"] / r["data"]["short_share"] for r in records]
    kept = sum(r["careful"]["periodicity"][-1] < r["data"]["periodicity"][-1] - PERIODICITY_LOSS
               and r["careful"]["short_share"] > SHORT_EXCESS * r["data"]["short_share"]
               for r in records)
    lowered = sum(r["careful"]["short_share"] < r["paper"]["short_share"] for r in records)
    return OptimaSummary(len(records), span(gain), span([r["careful_log_ml"] for r in records]),
                         span(per_gain), sum(g > 0 for g in per_gain), lowered, int(kept),
                         span(ratio), float(records[0]["data"]["periodicity"][-1]),
                         span([r["careful"]["periodicity"][-1] for r in records]))


def optima_table(records):
    """The records as a table for a page (a pandas ``Styler``): per set-up the log marginal
    likelihoods of both fits across the feed, and per fit the simulations' periodicity at the
    last feed and short-wavelength share over the data's."""
    import pandas as pd

    rows = {}
    for r in records:
        data = r["data"]["short_share"]
        rows[r["start_jitter"]] = {
            ("log ML", "paper's procedure"): r["paper_log_ml"],
            ("log ML", "careful"): r["careful_log_ml"],
            (f"periodicity at {N_PERIODS} feeds", "paper's procedure"):
                r["paper"]["periodicity"][-1],
            (f"periodicity at {N_PERIODS} feeds", "careful"): r["careful"]["periodicity"][-1],
            ("short share / data's", "paper's procedure"): r["paper"]["short_share"] / data,
            ("short share / data's", "careful"): r["careful"]["short_share"] / data}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.columns = pd.MultiIndex.from_tuples(table.columns)
    table.index.name = "start jitter"
    formats = {c: "{:.0f}" if c[0] == "log ML" else "{:.2f}" for c in table.columns}
    return table.style.format(formats).set_caption(
        f"figure 7 under {len(table)} numerical set-ups (start jitter 0: unperturbed)")
