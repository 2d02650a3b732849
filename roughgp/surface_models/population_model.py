r"""Eq 18 over a population of regions: the ``eq18-population`` rung (beyond the paper; issue 40,
item 3, the "hierarchical GPs [36]" of the paper's section 4).

A measurement is one region of a part, and the next region (another patch, another part of
the series) is rougher or smoother, its correlation longer or shorter. A model of one region,
however well fitted, draws surfaces like that region only: checked on another region it says
"outside" far more often than its 10 % (``benchmarks/results/held_out_calibration.md``, the
``hierarchical`` kind). This model describes the population instead, by the normal
random-effects model of :mod:`roughgp.inference.random_effects` on eq 18's parameters
:math:`u = (\log\sigma^2, \log\lambda_a, \log\lambda_b, \theta)`:

.. math::
    \hat u_{i} \mid u_i \sim N(u_i, v_i), \qquad u_i \sim N(\mu, \tau^2)

per parameter (the noise aside), over the regions :math:`i`: **several measurements of the
part**, each one region (eq 18 fitted on the whole of each by the debiased Whittle likelihood,
with its sandwich variance, :mod:`roughgp.inference.tile_fit`), or **the tiles of one map**,
each tile a region. The fit keeps the population's centre :math:`\hat\mu` (the
hyperparameters of eq 18: the typical region), and the spread of a *new* region about it,

.. math::
    s = \sqrt{\hat\tau^2 + \operatorname{se}(\hat\mu)^2},

the predictive spread of the random-effects model: the spread between regions (DerSimonian and
Laird's moment estimate, not set to 0 by a test: a prediction must not assume the regions alike
because a few of them could not tell) plus what the regions leave unknown of the centre. **Each
simulated surface draws its own region** (:mod:`roughgp.surface_models.population_draw`):
:math:`u = \hat\mu + s\,t_{k-2}`, independently per parameter (Student's :math:`t` with
:math:`k - 2` degrees of freedom for :math:`k` regions, at least 1: the prediction interval of a
random-effects meta-analysis, Higgins, Thompson and Spiegelhalter 2009, which widens as
:math:`\hat\tau` itself is less sure), then an eq 18 surface with those parameters plus its
noise. So a check of a new region compares it with surfaces of many regions, as it should: on
synthetic parts of 6 regions checked on a seventh it said "outside" at the check's level where
eq 18 of one region said it in half the cases (``benchmarks/results/population_check.md``).

Limits: the parameters are drawn independently (the regions' correlation between, say,
variance and length is not kept); a region is stationary within itself (the variation is
between measurements or tiles, not a smooth field: that is the ``eq18-field`` rung,
:mod:`roughgp.surface_models.field_model`); with few regions, or regions shorter than a few
correlation lengths, the centre and :math:`\hat\tau` are uncertain and the draws spread as far
(fit at least 4 regions); a region whose lengths reach far beyond the grid is slow to draw (the
circulant embedding then searches a large torus, seconds a draw).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from roughgp.common.checks import surface_array
from roughgp.common.grid import normalize
from roughgp.inference.random_effects import Pooled, pool
from roughgp.inference.tile_fit import PARAMETERS, fit_tiles
from roughgp.inference.whittle_fit import FAR_BEYOND
from roughgp.surface_models.chain import measured_chain
from roughgp.surface_models.model import FittedModel
from roughgp.surface_models.population_draw import SPREAD_NAMES
from roughgp.surface_models.schema import RANGES

__all__ = ["MIN_REGIONS", "LARGEST_LOG_SPREAD", "PopulationFit", "fit_population_model"]

MIN_REGIONS = 2   #: the fewest regions the pooling takes (fit at least 4 for a useful spread)
LARGEST_LOG_SPREAD = RANGES["log_variance_sd"][1]  #: the model file's largest log spread


@dataclasses.dataclass(frozen=True)
class PopulationFit:
    """What :func:`fit_population_model` returns: the model, each region's estimates ``(k,
    5)`` (:data:`~roughgp.inference.tile_fit.PARAMETERS`, NaN where a region gave none) and
    the pooling of the first four (:data:`SPREAD_NAMES`)."""

    model: FittedModel
    estimates: np.ndarray
    pooled: tuple

    def pooled_of(self, name: str) -> Pooled:
        """The pooling of ``name`` (one of the first four
        :data:`~roughgp.inference.tile_fit.PARAMETERS`)."""
        return self.pooled[PARAMETERS.index(name)]


def fit_population_model(maps, spacing=1.0, *, form="plane", s=None, l=None, degree=2,
                         axis="auto", tiles=(2, 2), n_draws=40, seed=0, data=None,
                         device=None) -> PopulationFit:
    """Fit the ``eq18-population`` model (module docstring) to one measured surface (its
    ``tiles`` the regions) or to several (a list of maps ``z[iy, ix]`` of one spacing, um, NaN
    where unmeasured: each map one region, fitted whole).

    Args:
        spacing: scalar or ``(dy, dx)``, um, the spacing of every map.
        form, s, l, degree, axis: the operators, as
            :func:`~roughgp.surface_models.fit.fit_surface_model`, resolved on the first
            map (``"auto"`` cut-offs) and applied alike to each map.
        tiles: ``(m, n)`` tiles of a single map (each at least 16 x 16 points); ignored for
            several maps.
        n_draws, seed: the simulated scores of each region's sandwich covariance and their seed.
        data: the sources' description, kept in the model.
        device: where the Whittle fits run (:mod:`roughgp.common.device`).

    Raises ValueError when fewer than :data:`MIN_REGIONS` regions give an estimate.
    """
    several = isinstance(maps, (list, tuple))
    arrays = [surface_array(z) for z in (maps if several else [maps])]
    if not arrays:
        raise ValueError("maps must hold at least one surface")
    _, (dy, dx) = normalize(arrays[0].shape, spacing)
    start = time.perf_counter()
    estimates, variances, points, shapes, operators, cutoffs = [], [], 0, [], None, None
    for index, arr in enumerate(arrays):
        try:
            # the first map resolves "auto" cut-offs; every other map gets the same operators
            first = (s, l) if cutoffs is None else (cutoffs["s_um"], cutoffs["l_um"])
            texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, *first, degree,
                                                       axis, "form-removed")
            fits = fit_tiles(heights, (dy, dx), tiles=(1, 1) if several else tiles,
                             n_draws=n_draws, seed=seed, device=device)
        except ValueError as exc:
            if not several:
                raise
            raise ValueError(f"map {index + 1} of {len(arrays)}: {exc}") from None
        operators = tuple(texture.operators)
        estimates.append(fits.estimates.reshape(-1, 5))
        variances.append(fits.pooling_variances().reshape(-1, 5))
        points += int(fits.n_points.sum())
        shapes.append(list(arr.shape))
    estimates, variances = np.concatenate(estimates), np.concatenate(variances)
    known = int(np.sum(np.isfinite(estimates[:, 0]) & np.isfinite(variances[:, 0])
                       & (variances[:, 0] > 0)))
    if known < MIN_REGIONS:
        what = "of the maps" if several else f"of the tiles={tuple(tiles)!r}"
        raise ValueError(f"{known} {what} gave an eq 18 fit with a standard error; the "
                         f"population model needs at least {MIN_REGIONS} regions (give more "
                         f"maps, or fewer, larger tiles: a region must hold enough measured "
                         f"points and its correlation lengths, within {FAR_BEYOND:g} times "
                         f"its longer side)")
    pooled = tuple(pool(estimates[:, k], variances[:, k], angle=(k == 3), spread_level=None)
                   for k in range(len(SPREAD_NAMES)))
    spread = [math.hypot(p.tau, p.mean_sd) for p in pooled]
    for name, value in zip(SPREAD_NAMES[:3], spread[:3]):
        if not value <= LARGEST_LOG_SPREAD:
            raise ValueError(f"the regions' {name[:-3]} spreads by {value:.3g} (a factor of "
                             f"{math.exp(value):.3g} per standard deviation), beyond the "
                             f"{LARGEST_LOG_SPREAD:g} of one population: these are not regions "
                             f"of one part (fit them apart)")
    hyper = {"variance_um2": float(np.exp(pooled[0].mean)),
             "lambda_a_um": float(np.exp(pooled[1].mean)),
             "lambda_b_um": float(np.exp(pooled[2].mean)),
             "angle_deg": float(np.degrees(pooled[3].mean)),
             "noise_variance_um2": float(np.exp(np.nanmedian(estimates[:, 4]))),
             **{name: float(np.degrees(value) if name == "angle_sd_deg" else value)
                for name, value in zip(SPREAD_NAMES, spread)},
             "regions": known}
    described = {**(data or {}), "shape": shapes[0] if not several else shapes,
                 "spacing_um": [dy, dx], "points_used": points}
    how = {"method": ("debiased Whittle fits of " + (f"{len(arrays)} maps, each one region"
                                                     if several else
                                                     f"{tiles[0]} x {tiles[1]} tiles, each one "
                                                     f"region")
                      + ", pooled by random effects (roughgp.surface_models.population_model)"),
           "tiles": None if several else [int(t) for t in tiles], "seed": seed,
           "tau": {name: round(p.tau, 6) for name, p in zip(PARAMETERS, pooled)},
           "mean_sd": {name: round(p.mean_sd, 6) for name, p in zip(PARAMETERS, pooled)},
           "homogeneity_p": {name: round(p.p_homogeneity, 6)
                             for name, p in zip(PARAMETERS, pooled)},
           "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("eq18-population", hyper, (dy, dx), None, operators, cutoffs,
                        described, how, "form-removed")
    return PopulationFit(model, estimates, pooled)
