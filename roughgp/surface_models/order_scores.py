r"""The normal scores at which a correlated surface holds its measured heights' ranks: the key of
the IAAFT quantile table (:mod:`roughgp.surface_models.iaaft`; beyond the paper).

The IAAFT marginal gives a simulation the measured heights through their quantile function: the
point of a Gaussian draw whose normal score is :math:`t` (the draw over its standard deviation
over realisations) gets the measured height the table keys at :math:`t`. Keyed at the Hazen
positions, the :math:`r`-th lowest of :math:`n` measured heights sits at
:math:`\Phi^{-1}((r + 1/2) / n)`, the normal scores of :math:`n` *independent* points: the
highest of the 16 384 of a 128 x 128 map at 3.99. A correlated surface holds fewer independent
heights than points. Its highest point lies nearer its mean (on average 3.6 to 3.9 sd on the
maps below), and its points spread less about their own mean than over realisations. So the
draws, whose highest points reach 3.6 to 3.9 too, met the measured maximum only rarely, and
their spread fell short: on 12 synthetic Gaussian maps of eq 18 (128 x 128, the cases of
:mod:`roughgp.experiments.iaaft_held_out`; the measured-PSD model with IAAFT heights fitted to
each, checked in sample with 19 simulations) the measured Sp, Sv, Sz and Sq ranked 13.2, 13.1,
14.5 and 12.2 on average among the simulations (9.5 for a model that describes the map; 0 to
19); on their lognormal kind Sp and Sz 15.2 and 14.4.

:func:`order_scores` keys the table at the model's own order statistics instead: the mean, over
:data:`N_DRAWS` Gaussian draws of the fitted model on the measured grid (its holes and its
operators as the measured heights had them: the F-operator, and the S- and L-filters for a table
of the filtered heights), of each draw's quantile at each of the table's probabilities, over the
remap's standard deviation (:func:`~roughgp.surface_models.measured_psd.remap_scale`, of the
population the remap acts on: where it depends on the shape, as eq 18's with an L-filter does,
the keys and a draw of the fitted size then share it), made
symmetric (a Gaussian draw and its negative are equally likely; without it the keys' noise,
the same for every map fitted with one seed, tilted the highest against the lowest). A draw as
extreme as the model's typical surface then gets the measured extremes, a rougher one more. On
the same maps the mean ranks became 10.8, 9.6, 10.5 and 9.5 (Sp, Sv, Sz, Sq); on the lognormal
kind 11.8, 4.2, 10.7 and 10.5: Sp and Sz in place, Sv as before (4.7 with the Hazen keys: the
lognormal's short lower tail is drawn deeper than measured, a bias the keys do not touch).
These were throw-away runs; ``tests/surface_models/test_order_scores.py`` holds the Gaussian
case. The draws are those of the model the fit made (a plug-in: the model's own error is not
in the key), and a model drawn from another (a bootstrap of its tiles,
:mod:`roughgp.checking.tile_bootstrap`) keeps its scores (:func:`scores_for_table`): they are
a property of the correlation, not of the heights.

A model file without ``order_scores`` (written before 2026-12-07) keys its table at the Hazen
positions, as it was drawn then.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.special

from roughgp.surface_models.iaaft import hazen_scores, values_at_scores

__all__ = ["N_DRAWS", "FEWEST_DRAWS", "draws_for", "order_scores", "with_order_scores",
           "scores_for_table"]

N_DRAWS = 32  #: Gaussian draws averaged on maps of up to 256 x 256 points (:func:`draws_for`)
FEWEST_DRAWS = 8  #: ... and on the largest maps, whose quantiles vary less from draw to draw
_CHUNK_POINTS = N_DRAWS * 65536  #: the most points drawn at once (2 M points: 16 MiB)


def draws_for(points) -> int:
    """The Gaussian draws :func:`order_scores` averages for a map of ``points`` points:
    :data:`N_DRAWS` up to 65 536 points, fewer in proportion on larger maps (a 512 x 512 map
    drew 32 in 3.6 s), at least :data:`FEWEST_DRAWS`."""
    return int(min(N_DRAWS, max(FEWEST_DRAWS, math.ceil(N_DRAWS * 65536 / max(points, 1)))))


def order_scores(model, z, spacing, *, n_draws=None, seed=0) -> list:
    """The ``order_scores`` of ``model``'s IAAFT marginal (module docstring), fitted to the map
    ``z`` (um, NaN where unmeasured) at ``spacing`` ``(dy, dx)``: the mean of ``n_draws``
    (default :func:`draws_for` the map's size; an integer in [2, 1000]) Gaussian draws'
    quantiles at the table's probabilities, through the measured heights' holes and operators,
    over the remap's sd. ``seed``: an integer >= 0 (the same seed, the same scores). Strictly
    increasing."""
    from roughgp.common.checks import check_integer
    from roughgp.surface_models.chain import form_removed, rest_of_chain
    from roughgp.surface_models.measured_psd import remap_scale
    from roughgp.surface_models.psd_table import population_slices
    check_integer("seed", seed, 0, None)
    if model.marginal_method != "iaaft":
        raise ValueError(f"order scores key an IAAFT marginal; the model's heights are "
                         f"{model.marginal_method}")
    marginal = model.marginal
    cut = marginal.get("above_l_um")
    z = np.asarray(z, dtype=np.float64)
    n_draws = draws_for(z.size) if n_draws is None else n_draws
    check_integer("n_draws", n_draws, 2, 1000)
    holes = ~np.isfinite(z)
    tail = float(marginal["tail_probability"])
    p = scipy.special.ndtr(hazen_scores(tail, len(marginal["quantiles_um"])))
    gaussian = dataclasses.replace(model, marginal=None)
    rng = np.random.default_rng([int(seed), 0x05C0])
    total = np.zeros(p.size)
    for draw in _draws(gaussian, z.shape, spacing, rng, int(n_draws)):
        # the heights the table was made of (chain.marginal_of): after F alone, or the filtered
        if cut is None and model.stage != "filtered":
            heights = form_removed(np.where(holes, np.nan, draw), spacing, model.cutoffs).sl
        else:
            heights = rest_of_chain(model, draw, spacing, holes).sl
        h = heights[np.isfinite(heights)]
        lowest = 0.5 / h.size
        total += np.quantile(h - h.mean(), np.clip(p, lowest, 1.0 - lowest), method="hazen")
    # the sd the remap divides by: of the population it acts on (twice the fitted points), so
    # that a draw of the fitted size meets the keys in the same units even where the sd
    # depends on the shape (iaaft.remap_sd with an L-filter)
    population = tuple(part.stop for part in population_slices(z.shape))
    scores = total / (int(n_draws) * remap_scale(model, population, spacing, cut))
    # a Gaussian draw and its negative are equally likely: the lowest score is minus the highest
    scores = 0.5 * (scores - scores[::-1])
    # strictly increasing (the table's ends may share a clipped probability)
    step = 1e-9 * max(float(np.ptp(scores)), 1.0)
    return (scores + step * (np.arange(scores.size) - 0.5 * (scores.size - 1))).tolist()


def _draws(model, shape, spacing, rng, n_draws):
    """``n_draws`` Gaussian draws of ``model``, at most :data:`_CHUNK_POINTS` points at a time
    (all at once on maps of up to 65 536 points: one call, as the recorded runs drew them)."""
    chunk = max(1, _CHUNK_POINTS // math.prod(shape))
    for start in range(0, n_draws, chunk):
        yield from model.simulate(shape, seed=rng, spacing=spacing,
                                  n_samples=min(chunk, n_draws - start))


def with_order_scores(model, z, spacing, *, seed=0):
    """``model`` with its IAAFT marginal keyed at :func:`order_scores` (``model`` unchanged
    when its marginal is not IAAFT)."""
    if model.marginal_method != "iaaft":
        return model
    scores = order_scores(model, z, spacing, seed=seed)
    return dataclasses.replace(model, marginal={**model.marginal, "order_scores": scores})


def scores_for_table(marginal, tail_probability, n_quantiles):
    """The ``order_scores`` of ``marginal`` at the probabilities of another
    table of ``n_quantiles`` quantiles from ``tail_probability`` (a tile bootstrap's,
    :mod:`roughgp.checking.tile_bootstrap`): interpolated in the Hazen score, and straight on
    beyond as a table's heights are (:func:`~roughgp.surface_models.iaaft.values_at_scores`);
    None when ``marginal`` has none."""
    if marginal.get("order_scores") is None:
        return None
    return values_at_scores(marginal["order_scores"], marginal["tail_probability"],
                            hazen_scores(tail_probability, n_quantiles)).tolist()
