r"""Predictive simulations from a tile bootstrap of the fitted heights (beyond the paper; issue
40, items 2 and 3).

A model fitted on one crop of a surface describes that crop: its variance is the crop's, its
height distribution (the IAAFT marginal, :mod:`roughgp.surface_models.iaaft`) is the crop's
sample. Another crop of the same part is rougher or smoother, its heights otherwise skewed,
and the simulations of the crop's model, all alike in amplitude and distribution, put it
outside (``benchmarks/iaaft_held_out.py``; the chapter "Which model reproduces which
measurement"). The parametric bootstrap of :mod:`roughgp.checking.predictive` refits copies
drawn from the model itself: it carries the fit's sampling error under a stationary model,
not the variation of the surface from region to region, and it cannot refit the measured
heights' distribution other than from the model's own draws.

The tile bootstrap carries both from the data themselves (the block bootstrap of Künsch,
Ann. Statist. 17, 1217 (1989), and Hall 1985 for spatial data, with the tiles as blocks):
the fitted heights (after the model's form removal; with an L-filter, the filtered heights
for the IAAFT marginal too) are cut into :data:`TILES` tiles, and each bootstrap model is the
fitted model with the heights of as many tiles drawn with replacement:

- its variance scaled by theirs over the fitted heights' (the measured PSD's table, or eq 18's
  variance and noise);
- its height distribution theirs: the IAAFT quantile table of the drawn tiles, its tails
  beyond :data:`~roughgp.surface_models.pareto_tails.TAIL_SHARE` generalized Pareto
  (:mod:`roughgp.surface_models.pareto_tails`; a resample of the measured table could only
  lose the deepest pit, never find a deeper one), or their skewness and kurtosis (Johnson);
- for a measured-psd model, its spectrum's shape theirs too: the table times the drawn tiles'
  mean periodogram over all the tiles', in coarse log-polar bins
  (:mod:`roughgp.surface_models.tile_spectra`), then scaled to the variance above (so the
  lengths, the lay and the direction vary as the tiles' do). eq 18's lengths stay the fit's.

Tiles drawn with replacement spread less than crops do: the waves longer than a tile, and the
correlation of neighbouring tiles, which the crop's variance carries, are drawn as if each tile
were independent of the next. The bootstrap's spread of a crop's log variance is 0.81-0.93
times the spread between independent crops for the eq 18 cases of the synthetic runs (128 x
128 points, 1000 draws each), 0.65 where the lengths are 3/4 of a tile (the tests) and
0.36-0.88 on the real maps' fitted halves (``book/running.md``). :func:`tile_spread_factor`
measures that share on draws of the fitted model itself on the fitted grid and its holes (the
model's sd of the crops' log variance over the bootstrap's mean sd, at least 1), and each
bootstrap model's variance ratio is raised to that power: the log ratio stretched about the
fitted variance (the block bootstrap corrected by the model, as a parametric bootstrap
calibrates a nonparametric one). The drawn tiles' heights are stretched about their mean to
that variance before their distribution is taken (an IAAFT model's amplitude is its quantile
table's, whatever its spectrum's variance: stretched, the table carries the widened spread);
their shape (skewness, kurtosis, tails) and the spectrum's shape are drawn as before.

The spread of the bootstrap models stands for the spread of a crop of the part about the
fitted one: on a stationary surface the sampling spread of a crop's variance, distribution
and spectrum, on a part that varies the variation between its regions as far as the fitted
crop shows it (a crop that saw one region only cannot know another's). What it buys on
synthetic and real maps is recorded in ``benchmarks/iaaft_held_out.py`` and
``benchmarks/real_out_of_sample.py``.
"""

from __future__ import annotations

import dataclasses
import numbers

import numpy as np

from roughgp.common.checks import check_integer, check_varies
from roughgp.surface_models.chain import apply_operators, form_removed, marginal_of
from roughgp.surface_models.model import FittedModel

__all__ = ["TILES", "MIN_TILE", "EQUATIONS", "MAX_MODELS", "SPREAD_DRAWS", "SPREAD_RESAMPLES",
           "tile_bootstrap_refusal", "tile_heights", "tile_spread_factor",
           "tile_bootstrap_models"]

TILES = (4, 4)   #: the tiles the fitted heights are cut into (rows, columns)
MIN_TILE = 16    #: the fewest points along a tile's side
MAX_MODELS = 99  #: the most bootstrap models
SPREAD_DRAWS = 200       #: the model's draws :func:`tile_spread_factor` measures the spread on
SPREAD_RESAMPLES = 200   #: the bootstrap resamples of each draw's tiles
#: the equations whose variance the bootstrap scales: the hyperparameters scaled
EQUATIONS = {"measured-psd": ("psd_um4",),
             "eq18": ("variance_um2", "noise_variance_um2"),
             "eq18-matern": ("variance_um2", "noise_variance_um2")}


def tile_bootstrap_refusal(model: FittedModel) -> str | None:
    """Why ``model`` cannot be tile-bootstrapped, or None."""
    if model.equation not in EQUATIONS:
        return (f"the tile bootstrap scales the variance of {', '.join(EQUATIONS)} models; "
                f"this is a {model.equation} model")
    if model.stage != "form-removed":
        return (f"the tile bootstrap redraws the form-removed heights the model describes; "
                f"this model is of stage {model.stage!r}")
    return None


def _edges(n, count):
    return np.linspace(0, n, count + 1).round().astype(int)


def tile_heights(z, spacing, model: FittedModel, tiles=TILES) -> tuple[list, list]:
    """``(heights, filtered)``: the tiles (:data:`TILES` by default) of the fitted map ``z``
    (um, NaN where unmeasured) after the model's operators (``model.cutoffs``): their
    form-removed heights, and the heights the model's IAAFT marginal was taken from (the
    filtered ones with an L-filter, else the same), each a list of arrays in row order."""
    tiles = tuple(int(n) for n in tiles)
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 2 or len(tiles) != 2:
        raise ValueError(f"z must be a surface and tiles two counts, got {arr.shape} and "
                         f"{tiles}")
    if min(tiles) < 1 or arr.shape[0] < tiles[0] * MIN_TILE or arr.shape[1] < tiles[1] * \
            MIN_TILE:
        raise ValueError(f"tiles: {tiles[0]} x {tiles[1]} tiles of a {arr.shape[0]} x "
                         f"{arr.shape[1]} map are shorter than {MIN_TILE} points a side")
    spacing = model.spacing if spacing is None else spacing
    heights = form_removed(arr, spacing, model.cutoffs).sl
    check_varies("the heights after the F-operator", heights, arr)
    banded = isinstance(model.marginal, dict) and "above_l_um" in model.marginal
    filtered = apply_operators(arr, spacing, model.cutoffs).sl if banded else heights
    ey, ex = _edges(arr.shape[0], tiles[0]), _edges(arr.shape[1], tiles[1])
    cut = [(slice(ey[i], ey[i + 1]), slice(ex[j], ex[j + 1]))
           for i in range(tiles[0]) for j in range(tiles[1])]
    return [heights[s] for s in cut], [filtered[s] for s in cut]


def _stretched(heights, variance_ratio):
    """``heights`` about their mean, their variance times ``variance_ratio``."""
    mean = np.nanmean(heights)
    return mean + np.sqrt(variance_ratio) * (heights - mean)


def _marginal(model, heights, filtered):
    method = model.marginal_method
    if method == "gaussian":
        return None
    if method == "johnson":
        return marginal_of(heights, "johnson")
    from roughgp.surface_models.pareto_tails import pareto_tails_table
    from roughgp.surface_models.order_scores import scores_for_table
    quantiles, tail, _ = pareto_tails_table(filtered, len(model.marginal["quantiles_um"]))
    scores = scores_for_table(model.marginal, tail, len(quantiles))
    return {**model.marginal, "quantiles_um": quantiles, "tail_probability": tail,
            **({} if scores is None else {"order_scores": scores})}


def _resampled_log_variances(heights, picks) -> np.ndarray:
    """The log variance of the pooled heights of each row of tile indices ``picks``, over all
    the tiles' (from each tile's count, sum and sum of squares of its measured heights)."""
    moments = np.array([[np.sum(~np.isnan(h)), np.nansum(h), np.nansum(h * h)]
                        for h in heights])
    n, s, q = (moments[:, k][picks].sum(axis=-1) for k in range(3))
    n0, s0, q0 = moments.sum(axis=0)
    return np.log((q / n - (s / n) ** 2) / (q0 / n0 - (s0 / n0) ** 2))


def tile_spread_factor(model: FittedModel, z, *, spacing=None, tiles=TILES, seed=0,
                       draws=SPREAD_DRAWS) -> float:
    """How much wider a crop's log variance spreads than the tile bootstrap draws it (module
    docstring), measured on ``draws`` surfaces of ``model``'s Gaussian latent (its noise
    included) on the grid of ``z`` with its holes: the sd over the draws of their heights' log
    variance (after the model's F-operator, as :func:`tile_heights`) over the mean, over the
    draws, of the sd of :data:`SPREAD_RESAMPLES` bootstrap resamples of each draw's tiles; at
    least 1 (the bootstrap is never narrowed). It depends on the model, the grid and its holes,
    not on the measured heights. ``seed``: an integer >= 0; the same seed gives the same
    factor."""
    check_integer("seed", seed, 0, None)
    check_integer("draws", draws, 2, None)
    why = tile_bootstrap_refusal(model)
    if why:
        raise ValueError(why)
    arr = np.asarray(z, dtype=np.float64)
    holes = np.isnan(arr)
    latent = dataclasses.replace(model, marginal=None)
    rng = np.random.default_rng([int(seed), 7])
    n_tiles = int(np.prod(tiles))
    per_call = max(1, min(draws, (1 << 22) // arr.size))
    crops, spreads = [], []
    for start in range(0, draws, per_call):
        count = min(per_call, draws - start)
        surfaces = latent.simulate(arr.shape, seed=rng, spacing=spacing, n_samples=count)
        for surface in surfaces:
            heights, _ = tile_heights(np.where(holes, np.nan, surface), spacing, model, tiles)
            pooled = np.concatenate([h.ravel() for h in heights])
            crops.append(np.log(np.nanvar(pooled)))
            picks = rng.integers(0, n_tiles, (SPREAD_RESAMPLES, n_tiles))
            spreads.append(np.std(_resampled_log_variances(heights, picks)))
    return max(1.0, float(np.std(crops, ddof=1) / np.mean(spreads)))


def tile_bootstrap_models(model: FittedModel, z, n_models, *, spacing=None, tiles=TILES,
                          seed=0, spread=None) -> tuple:
    """``n_models`` bootstrap models of ``model`` from the tiles of the map ``z`` it was fitted
    on (module docstring).

    Args:
        model: a surface model of :data:`EQUATIONS`, stage ``"form-removed"``
            (:func:`tile_bootstrap_refusal`).
        z: the fitted map (um, NaN where unmeasured), as given to the fit.
        n_models: B, an integer in [1, :data:`MAX_MODELS`].
        spacing: ``(dy, dx)`` of ``z`` (default: the model's).
        tiles: rows and columns of tiles, each at least :data:`MIN_TILE` points a side.
        seed: an integer >= 0; the same seed gives the same models.
        spread: the power the tiles' variance ratios are raised to (default
            :func:`tile_spread_factor` of the model on ``z``'s grid, with ``seed``); a number
            >= 1 (1: the plain tile bootstrap).

    Returns:
        a tuple of B FittedModels.
    """
    check_integer("n_models", n_models, 1, MAX_MODELS)
    check_integer("seed", seed, 0, None)
    why = tile_bootstrap_refusal(model)
    if why:
        raise ValueError(why)
    if spread is not None and not (isinstance(spread, numbers.Real) and not
                                   isinstance(spread, (bool, np.bool_)) and 1 <= spread < np.inf):
        raise ValueError(f"spread must be a finite number >= 1, got {spread!r}")
    heights, filtered = tile_heights(z, spacing, model, tiles)
    if spread is None:
        spread = tile_spread_factor(model, z, spacing=spacing, tiles=tiles, seed=seed)
    pooled = np.concatenate([h.ravel() for h in heights])
    variance = float(np.nanvar(pooled))
    shaped = _ShapedTable(model, heights, spacing) if model.equation == "measured-psd" else None
    rng = np.random.default_rng([int(seed), 5])
    out = []
    for _ in range(int(n_models)):
        pick = rng.integers(0, len(heights), len(heights))
        h = np.concatenate([heights[k].ravel() for k in pick])
        f = np.concatenate([filtered[k].ravel() for k in pick])
        drawn = float(np.nanvar(h)) / variance
        ratio = drawn ** float(spread)
        h, f = _stretched(h, ratio / drawn), _stretched(f, ratio / drawn)
        hp = dict(model.hyperparameters)
        for name in EQUATIONS[model.equation]:
            hp[name] = (np.asarray(hp[name], dtype=np.float64) * ratio).tolist()
        if shaped is not None:
            hp["psd_um4"] = shaped(pick, ratio).tolist()
        out.append(dataclasses.replace(model, hyperparameters=hp,
                                       marginal=_marginal(model, h, f)))
    return tuple(out)


class _ShapedTable:
    """A measured-psd model's table given the spectrum's shape of a draw of tiles
    (:func:`~roughgp.surface_models.tile_spectra.shape_factor`) and ``ratio`` times the
    model's variance over the measured band."""

    def __init__(self, model, heights, spacing):
        from roughgp.surface_models import measured_psd, psd_core, tile_spectra
        hp = model.hyperparameters
        self.table = np.asarray(hp["psd_um4"], dtype=np.float64)
        self.band = (float(hp["frequency_min_per_um"]), float(hp["frequency_max_per_um"]))
        self.grid = (tuple(model.spacing), measured_psd.fitted_shape(model))
        self.core = psd_core.from_hyperparameters(hp)
        self.variance = measured_psd.band_variance(model)
        self.ordinates = tile_spectra.tile_ordinates(
            heights, model.spacing if spacing is None else spacing, *self.band)

    def __call__(self, pick, ratio):
        from roughgp.surface_models import psd_table, tile_spectra
        table = self.table * tile_spectra.shape_factor(*self.ordinates, pick)
        band = psd_table.table_variance(table, *self.band, *self.grid, core=self.core)
        return table * (ratio * self.variance / band)
