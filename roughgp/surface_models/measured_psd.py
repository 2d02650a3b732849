r"""A nonparametric stationary model of a measured surface: its own smoothed PSD (beyond the
paper).

Eq 18 and its Matérn variant are parametric forms of a stationary Gaussian surface's ACVF;
the measured PSD is the nonparametric one, what practitioners generate rough surfaces from. It
bounds what any stationary Gaussian model can do on a file: a parameter that the measured-psd
model leaves outside in :func:`roughgp.checking.model_check.check_model` is not reproduced by
the stationary Gaussian family at all (non-Gaussian heights, spikes, non-stationarity), not
merely by eq 18's form.

:func:`roughgp.surface_models.fit.fit_psd_model` applies the F-operator (the same cut-off
arguments, with the same meaning, as :func:`~roughgp.surface_models.fit.fit_surface_model`; the
model is of stage ``"form-removed"`` and its simulations go through the S- and L-filters as the
measurement did), estimates the PSD of the form-removed heights with their holes, smooths it
into a 40 x 36 log-polar table and scales the table so that its variance over the measured band
equals that of the measured heights (the variance is conserved), and its variance through the
measurement's S- and L-filters that of the filtered heights; the lowest frequencies and the
two frequency axes are kept ordinate by ordinate (:mod:`roughgp.surface_models.psd_core`);
:mod:`roughgp.surface_models.psd_table` says how, and how fields are drawn from it on any shape
and spacing. This module holds the model's covariance and draws, which
:class:`~roughgp.surface_models.model.FittedModel` uses. The model's white noise
is part of the PSD (its flat high-frequency floor): ``noise_variance_um2`` is 0.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.ndimage

from roughgp.surface_models import psd_core, psd_table

__all__ = ["TabulatedACVF", "draw_psd_model", "band_variance", "fitted_shape", "passed_sd",
           "remap_scale"]


def _table(model):
    """``(table, f_min, f_max, core)`` of ``model`` (``core`` None in a file written before
    the core, :mod:`~roughgp.surface_models.psd_core`)."""
    hp = model.hyperparameters
    return (np.asarray(hp["psd_um4"], dtype=np.float64), float(hp["frequency_min_per_um"]),
            float(hp["frequency_max_per_um"]), psd_core.from_hyperparameters(hp))


def fitted_shape(model):
    """The shape of the field the measured PSD was fitted on (the model file's ``data.shape``;
    else the field whose lowest frequency is the model's ``frequency_min_per_um``): the grid
    its ACVF is tabulated on."""
    shape = model.recorded_shape
    if shape is not None:
        return shape
    f_min = _table(model)[1]
    return tuple(max(2, round(1.0 / (f_min * d))) for d in model.spacing)


def band_variance(model) -> float:
    """The variance of ``model``'s PSD over the measured band, on the DFT grid of the field it
    was fitted on (um^2)."""
    table, f_min, f_max, core = _table(model)
    return psd_table.table_variance(table, f_min, f_max, model.spacing, fitted_shape(model),
                                    core=core)


def passed_sd(model, shape, spacing, l_um) -> float:
    r"""The standard deviation over realisations of what the Gaussian L-filter of cut-off
    ``l_um`` passes of a field of ``shape`` at ``spacing`` drawn from ``model``'s PSD (um):
    :math:`\sqrt{\sum C(\mathbf q) H_L(q) \Delta q}` on the torus the field is drawn on
    (:func:`~roughgp.surface_models.psd_table.band_transmission`), what the IAAFT remap of
    the band above the cut-off scales its draw by (:func:`roughgp.surface_models.iaaft.remap_sd`
    for the other models). Read from the PSD itself: the ACVF on a window of lags, its spectrum
    clipped at 0, leaks a share of the long waves into the band, and a real surface's long
    waves hold hundreds of times the band's variance (0.0019 against 0.0015 um on the fitted
    half of data/mnt-2-crop.x3p, whose simulations' Sq then fell to 0.72 of the measured)."""
    table, f_min, f_max, core = _table(model)
    torus = psd_table.torus_shape(shape, spacing, f_min)
    return math.sqrt(psd_table.table_variance(table, f_min, f_max, spacing, torus, l_um=l_um,
                                              core=core))


def remap_scale(model, shape, spacing, l_um=None) -> float:
    """The standard deviation over realisations of the field of ``shape`` that ``model``'s IAAFT
    remap acts on (:mod:`roughgp.surface_models.iaaft`): :func:`passed_sd` for a measured-psd
    model with an L-filter (``l_um``), :func:`roughgp.surface_models.iaaft.remap_sd` of its
    kernel otherwise."""
    if l_um is not None and model.equation == "measured-psd":
        return passed_sd(model, shape, spacing, l_um)
    from roughgp.surface_models import iaaft
    return iaaft.remap_sd(model.kernel(), model.noise_variance, shape, spacing, l_um)


def draw_psd_model(model, shape, spacing, rng, count, transform=None):
    """``count`` Gaussian fields of ``shape`` at ``spacing`` from ``model``'s PSD
    (:func:`~roughgp.surface_models.psd_table.synthesize`), plus its mean; ``transform`` (a
    rank remap) applied to each torus field, mean included, before the crop."""
    table, f_min, f_max, core = _table(model)
    mean = float(model.hyperparameters.get("mean_um", 0.0))
    shifted = None if transform is None else (lambda field: transform(field + mean) - mean)
    fields = psd_table.synthesize(table, f_min, f_max, shape, spacing, rng, count, shifted,
                                  core=core)
    return fields + mean


class TabulatedACVF:
    """The measured-psd model's ACVF as a function of lags ``(..., 2)`` in (x, y) order, um:
    the inverse DFT of its PSD on the torus its fields are drawn on
    (:func:`~roughgp.surface_models.psd_table.acvf_grid`), interpolated bilinearly between
    the grid's lags (exact on them); the covariance of the synthesised fields."""

    def __init__(self, model):
        self.model = model
        self.spacing = tuple(float(d) for d in model.spacing)
        self._grid = None

    def _grid_for(self, reach):
        if self._grid is None or any(r >= n // 2 for r, n in zip(reach, self._grid.shape)):
            table, f_min, f_max, core = _table(self.model)
            field = tuple(max(int(r) + 2, n) for r, n in zip(reach, fitted_shape(self.model)))
            self._grid = psd_table.acvf_grid(table, f_min, f_max, field, self.spacing, core)
        return self._grid

    def __call__(self, lags):
        lags = np.asarray(lags, dtype=np.float64)
        jx, jy = lags[..., 0] / self.spacing[1], lags[..., 1] / self.spacing[0]
        grid = self._grid_for((math.ceil(np.max(np.abs(jy), initial=0)),
                               math.ceil(np.max(np.abs(jx), initial=0))))
        coords = np.stack([np.mod(jy, grid.shape[0]).ravel(), np.mod(jx, grid.shape[1]).ravel()])
        values = scipy.ndimage.map_coordinates(grid, coords, order=1, mode="grid-wrap")
        return values.reshape(lags.shape[:-1])
