"""A measured surface with unmeasured (NaN) points, filled end to end (beyond the paper).

The pipeline of ``roughgp fill``, as one call: level the surface (least-squares plane,
:func:`roughgp.metrology.levelling.level`), fit eq 18 plus white noise (eq 8) on the measured
points alone (:func:`roughgp.inference.block_fit.fit_ground_to_valid_points`), fill the missing
points with the GP posterior mean (and sd) of the levelled surface
(:func:`roughgp.beyond.gap_filling.fill_gaps`), and add the plane back, so that the filled map
is in the measurement's own heights.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from roughgp.beyond.gap_filling import GapFill, fill_gaps
from roughgp.common.grid import normalize
from roughgp.inference.block_fit import BlockFit, fit_ground_to_valid_points
from roughgp.metrology.levelling import LevelFit, level

__all__ = ["MeasuredFill", "fill_measured_surface"]


@dataclasses.dataclass
class MeasuredFill:
    """What :func:`fill_measured_surface` returns.

    Attributes:
        filled: the measured heights, with the missing ones filled by the posterior mean plus
            the removed plane (the measurement's own heights).
        sd: posterior sd of the latent surface at the filled points, 0 at measured ones
            (and everywhere without draws).
        missing: boolean map of the filled points.
        plane: the least-squares plane removed before the fit and added back.
        fit: the eq 18 fit on the measured points (:class:`~roughgp.inference.block_fit.BlockFit`).
        gaps: the fill of the levelled surface (:class:`~roughgp.beyond.gap_filling.GapFill`).
    """

    filled: np.ndarray
    sd: np.ndarray
    missing: np.ndarray
    plane: LevelFit
    fit: BlockFit
    gaps: GapFill


def fill_measured_surface(z, *, spacing=1.0, n_samples=16, seed=None, block=24, n_blocks=12,
                          device=None) -> MeasuredFill:
    """Level, fit eq 18 on the measured points, fill the NaN points, add the plane back.

    Args:
        z: height map ``z[iy, ix]`` with NaN where not measured (at least one).
        spacing: scalar or ``(dy, dx)``.
        n_samples: pathwise draws for the sd (0: the mean only).
        seed: int or None: the fit's blocks and the draws.
        block, n_blocks: the fit's blocks (:func:`~roughgp.inference.block_fit.fit_ground_to_valid_points`).
        device: None (numpy) or a torch device for the fill (:mod:`roughgp.common.device`).
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a surface z[iy, ix], got shape {z.shape}")
    missing = np.isnan(z)
    if not missing.any():
        raise ValueError("z has no missing (NaN) point: nothing to fill")
    _, (dy, dx) = normalize(z.shape, spacing)
    levelled, plane = level(z, spacing=(dy, dx), return_coefficients=True)
    fit = fit_ground_to_valid_points(levelled, spacing=(dy, dx), block=block, n_blocks=n_blocks,
                                     seed=seed)
    gaps = fill_gaps(levelled, fit.kernel, noise_variance=fit.noise_variance,
                     spacing=(dy, dx), n_samples=n_samples, seed=seed, device=device)
    iy, ix = np.indices(z.shape)
    tilt = plane.offset + plane.slope[0] * iy * dy + plane.slope[1] * ix * dx
    filled = np.where(missing, gaps.mean + tilt, z)
    sd = np.where(missing, gaps.sd, 0.0)
    return MeasuredFill(filled=filled, sd=sd, missing=missing, plane=plane, fit=fit, gaps=gaps)
