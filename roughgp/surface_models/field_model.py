r"""Eq 18 whose parameters vary over the part: the ``eq18-field`` rung (beyond the paper;
issue 40, items 3 and 4; the paper's future work: "non-stationary surfaces [37, 47]" and
"hierarchical GPs [36]").

**Fit.** After the F-operator the map is cut into ``m x n`` tiles and eq 18 plus noise is
fitted on each by the debiased Whittle likelihood, with its sandwich covariance
(:mod:`roughgp.inference.tile_fit`: local likelihood on disjoint windows). Each parameter
(log variance, log lengths, the lay angle, log noise) is then pooled over the tiles by the
normal random-effects model (:mod:`roughgp.inference.random_effects`): a population mean
(or a plane in position, or a step between two zones at a boundary between two columns or rows
of tiles, where a Wald test at 1 % keeps it), a spread between tiles
:math:`\tau` with its test of homogeneity, and each tile's value shrunk towards the
population by its precision. A stationary map gives :math:`\hat\tau = 0` for most
parameters and comes back (nearly) stationary; a roughness gradient or a turning lay keeps its
variation. The model file holds the shrunk values at the tile centres (the anchors), the
noise as the tiles' median (one number: a small tile's noise is often at its bound, where its
standard error means nothing, and the pooled value followed those tiles), and in ``fit`` the
pooling's tests and ``anchor_sd``, each field's standard error at the anchors (log scale, the
angle in radians; :math:`\tau` integrated out and the forms averaged:
:mod:`roughgp.inference.pooled_errors`; how often they hold the truth on synthetic maps is
recorded in ``benchmarks/results/field_recovery.md``).

**Draw** (:mod:`roughgp.surface_models.field_draw`). The fields are interpolated bilinearly
between the anchors (log scale for the variance and the lengths, the angle as its difference
from the mean lay), continued linearly to the outer tiles' edges and held constant beyond; a
field with a step (the model file's ``steps``) is interpolated on each side of its boundary
from that side's anchors alone, and jumps there; the surface is drawn by the K-kernel blend of
:func:`roughgp.models.nonstationary.sample_nonstationary` (``FIELD_KERNELS`` kernels; its
local variance is exact, its correlation approximate: see that module). Positions count from
the fitted map's first point, so a draw of the fitted shape lies on the fitted map.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from roughgp.common.checks import surface_array
from roughgp.common.grid import normalize
from roughgp.inference.random_effects import Pooled, pool
from roughgp.inference.tile_fit import PARAMETERS, TileFits, fit_tiles
from roughgp.metrology.filters import Texture
from roughgp.surface_models.chain import measured_chain
from roughgp.surface_models.model import FittedModel

__all__ = ["FieldModelFit", "fit_field_model"]

_LOGS = {"variance_um2": 0, "lambda_a_um": 1, "lambda_b_um": 2}


@dataclasses.dataclass(frozen=True)
class FieldModelFit:
    """What :func:`fit_field_model` returns: the model, the measurement's chain, the tiles'
    fits and the pooling of each parameter (:data:`~roughgp.inference.tile_fit.PARAMETERS`
    order)."""

    model: FittedModel
    texture: Texture
    tiles: TileFits
    pooled: tuple

    def pooled_of(self, name: str) -> Pooled:
        """The pooling of ``name`` (one of :data:`~roughgp.inference.tile_fit.PARAMETERS`)."""
        return self.pooled[PARAMETERS.index(name)]


def fit_field_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                    tiles=(4, 4), n_draws=40, seed=0, data=None,
                    device=None) -> FieldModelFit:
    """Fit the ``eq18-field`` model to a measured surface ``z[iy, ix]`` (um, NaN where
    unmeasured; module docstring).

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, s, l, degree, axis: the operators, as
            :func:`~roughgp.surface_models.fit.fit_surface_model` (the model describes the
            heights after F; the filters act on its simulations as on the measurement).
        tiles: ``(m, n)`` tiles, each at least 16 x 16 points (the anchors are their centres).
        n_draws, seed: the simulated scores of each tile's sandwich covariance and their seed.
        data: the source's description, kept in the model.
        device: where the Whittle fits run (:mod:`roughgp.common.device`).
    """
    arr = surface_array(z)
    _, (dy, dx) = normalize(arr.shape, spacing)
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, s, l, degree, axis,
                                               "form-removed")
    fits = fit_tiles(heights, (dy, dx), tiles=tiles, n_draws=n_draws, seed=seed,
                     device=device)
    known = np.isfinite(fits.estimates[..., 0])
    if known.sum() < 2:
        raise ValueError(f"tiles={tuple(tiles)!r}: {int(known.sum())} tile(s) hold enough "
                         f"measured points for a fit; the field model needs at least 2 (use "
                         f"fewer tiles)")
    variances = fits.pooling_variances()
    positions = np.stack(np.meshgrid(fits.centres_x, fits.centres_y), axis=-1)
    pooled = tuple(pool(fits.estimates[..., k], variances[..., k], angle=(k == 3),
                        positions=positions) for k in range(len(PARAMETERS)))
    fields = {name: np.exp(pooled[k].shrunk) for name, k in _LOGS.items()}
    fields["angle_deg"] = np.degrees(pooled[3].shrunk)
    steps = {name: {"axis": pooled[k].step[0], "at_um": pooled[k].step[1]}
             for name, k in (*_LOGS.items(), ("angle_deg", 3)) if pooled[k].step}
    finite = heights[np.isfinite(heights)]
    hyper = {"anchors_x_um": [float(x) for x in fits.centres_x],
             "anchors_y_um": [float(y) for y in fits.centres_y],
             **{name: np.asarray(values).tolist() for name, values in fields.items()},
             **({"steps": steps} if steps else {}),
             "noise_variance_um2": float(np.exp(np.nanmedian(fits.estimates[..., 4]))),
             "mean_um": float(finite.mean())}
    missing = ~np.isfinite(heights)
    described = {**(data or {}), "shape": list(arr.shape), "spacing_um": [dy, dx],
                 "missing_fraction": float(missing.mean()),
                 "points_used": int(fits.n_points.sum())}
    how = {"method": "local debiased Whittle fits on tiles, pooled by random effects "
                     "(roughgp.surface_models.field_model)",
           "tiles": [int(t) for t in fits.tiles], "seed": seed,
           "tau": {name: round(p.tau, 6) for name, p in zip(PARAMETERS, pooled)},
           "homogeneity_p": {name: round(p.p_homogeneity, 6)
                             for name, p in zip(PARAMETERS, pooled)},
           "trend_p": {name: None if math.isnan(p.p_trend) else round(p.p_trend, 6)
                       for name, p in zip(PARAMETERS, pooled)},
           "step_p": {name: None if math.isnan(p.p_step) else round(p.p_step, 6)
                      for name, p in zip(PARAMETERS, pooled)},
           "anchor_sd": {name: np.round(p.shrunk_sd, 6).tolist()
                         for name, p in zip(PARAMETERS[:4], pooled[:4])},
           "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("eq18-field", hyper, (dy, dx), None, tuple(texture.operators), cutoffs,
                        described, how, "form-removed")
    return FieldModelFit(model, texture, fits, pooled)
