r"""The lowest frequencies of a measured PSD, kept ordinate by ordinate (beyond the paper).

The log-polar table of :mod:`roughgp.surface_models.psd_table` averages at least
:data:`~roughgp.surface_models.psd_table.MIN_ORDINATES` periodogram ordinates per bin. At the
lowest rings a grid holds few ordinates (the ring at 1 to 1.14 times the fundamental frequency
of a 256 x 128 grid holds one pair), so those bins widen over neighbouring rings and then over
the whole ring, and a bin with no ordinate takes its ring's values: the longest waves of the
table are isotropic whatever the surface's lay. The draws then hold isotropic long waves, and
their Str (the texture aspect ratio, which the longest correlation length sets) came out
higher than the measured: on synthetic eq 18 maps of 256 x 128 points with lengths 16 and 4
points, the draws' median Str was 1.25 to 1.5 times each map's. And a lay along a scan axis
(the usual set-up of an instrument) puts its power on a line, the ``qx = 0`` or ``qy = 0``
axis of the periodogram, which a 5-degree bin spreads over a wedge: the draws' lines are short
and their Sal too long. Smoothing the ordinates over their 3 x 3 neighbours was worse (a
neighbour at the second ordinate lies 27 degrees away), so the core is not smoothed.

Measured in sample (the measured-psd model with Gaussian heights fitted to each map, the map
ranked among 19 draws; 0-19, 9.5 expected): on 32 synthetic eq 18 maps of 256 x 128 points
(lengths 8 to 32 points, ratios 1 to 8, random angles), Str's mean rank 6.2 with the table alone
and 8.1 with the core, outside on 6 and 3 of the 32; Sal's 11.0 and 11.2, outside on 4 and 2. On
12 maps with a lay along y (``tests/surface_models/test_psd_core.py``), the measured Sal below
every draw on 11 of 12 with the table alone and on none with the core. The draws' Str stays a
little above the map's where the lengths are long (a draw's own periodogram adds its noise to
the map's, which the core copies; drawn from the raw periodogram itself as much): 1.0 to 1.3
times on maps of lengths 16 to 32 and 4 to 8 points. Left out of the table altogether, the axes'
ordinates emptied the bins beside an axis on the lower rings, which then took values from 10
degrees away: an eq 18 surface whose lay lies along an axis drew Sal 21 % too long; the table is
made with each axis ordinate replaced by the mean of its neighbours across the axis instead.

The core holds, on the fitted grid's frequencies within :data:`CORE_STEPS` steps of the coarser
axis (its ``radius``) and along the two axes, each periodogram ordinate divided by the table's
value there (``ratio``, ``axis_x``, ``axis_y``; the table made with each axis ordinate replaced
by the mean of its two neighbours across the axis, so that a line's power is not counted twice):
the table's scalings (to the measured variance, to the filtered band, a tile's variance in the
tile bootstrap) then apply to it as to the table. :func:`factor` reads the ratio at any
frequency, bilinear between the fitted grid's ordinates (linear in the PSD, not its log: a
single ordinate's error is exponential, and a geometric mean of two is biased low), tapered over
the outer quarter of the radius into the factor outside it: the axes' ratios, read linearly
along each axis and fading to 1 one step off it, and 1 elsewhere. The zero frequency's ratio is
1.

In a model file the core is five optional hyperparameters of a measured-psd model
(:data:`KEYS`); a file without them draws from the table alone, as before 2026-12-07.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["CORE_STEPS", "TAPER_SHARE", "RATIO_RANGE", "MAX_HALF", "MAX_AXIS", "KEYS", "PsdCore",
           "core_indices", "axis_halves", "factor", "from_hyperparameters", "to_hyperparameters",
           "check_core"]

CORE_STEPS = 16  #: the core's radius, in frequency steps of the coarser axis of the fitted grid
TAPER_SHARE = 0.25  #: the outer share of the radius over which the ratio is tapered to 1
RATIO_RANGE = (1e-9, 1e9)  #: a stored ratio's allowed range (each ordinate is clipped to it)
MAX_HALF = 64  #: the most ordinates the core reaches along each axis (a file of <= 129 x 129)
MAX_AXIS = 4096  #: the most ordinates kept along each frequency axis, each way
#: the hyperparameters of a model file that hold the core
KEYS = ("core_ratio", "core_step_per_um", "core_radius_per_um", "core_axis_x", "core_axis_y")


class PsdCore(NamedTuple):
    """The ratio of the periodogram to the table on a grid of ``(2 ky + 1, 2 kx + 1)``
    frequencies, zero frequency at its centre; ``step``: ``(dqy, dqx)``, 1/um; ``radius``:
    1/um; ``axis_x``, ``axis_y``: the ratios along the frequency axes (at ``qy = 0`` for
    ``qx = k dqx``, ``k`` from ``-ax`` to ``ax``, and at ``qx = 0`` for ``qy = k dqy``)."""

    ratio: np.ndarray
    step: tuple
    radius: float
    axis_x: np.ndarray
    axis_y: np.ndarray


def core_indices(shape, spacing):
    """``(ky, kx, radius, step)``: the core's half-sizes in ordinates of a field of ``shape``
    at ``spacing``, its radius (:data:`CORE_STEPS` steps of the coarser axis, within the
    grid's Nyquist frequencies and :data:`MAX_HALF` ordinates) and its frequency steps
    (1/um)."""
    step = tuple(1.0 / (n * d) for n, d in zip(shape, spacing))
    ky, kx = (min(math.ceil(CORE_STEPS * max(step) / s), (n - 1) // 2, MAX_HALF)
              for s, n in zip(step, shape))
    return ky, kx, min(CORE_STEPS * max(step), ky * step[0], kx * step[1]), step


def axis_halves(shape):
    """``(ay, ax)``: the ordinates kept each way along the ``qy`` and ``qx`` axes of a field
    of ``shape`` (its Nyquist frequency, at most :data:`MAX_AXIS`)."""
    return tuple(min(n // 2, MAX_AXIS) for n in shape)


def _along(ratios, q, step, across, across_step):
    """The factor near one frequency axis: the ratios read linearly along it (1 beyond them),
    fading linearly to 1 at one step ``across_step`` off it."""
    half = len(ratios) // 2
    along = np.interp(q / step, np.arange(-half, half + 1), ratios, left=1.0, right=1.0)
    return 1.0 + (along - 1.0) * np.clip(1.0 - np.abs(across) / across_step, 0.0, 1.0)


def factor(core, qy, qx):
    """The core's factor on the PSD at the frequencies ``qy`` x ``qx`` (1-D axes, 1/um):
    within the radius bilinear in the ratio between the fitted grid's ordinates, tapered over
    the outer :data:`TAPER_SHARE` of the radius into the factor outside it, which is the
    axes' ratios within one step of an axis and 1 elsewhere (module docstring)."""
    qy, qx = np.meshgrid(np.asarray(qy, dtype=np.float64), np.asarray(qx, dtype=np.float64),
                         indexing="ij")
    out = np.ones(qy.shape)
    if core is None:
        return out
    (sy, sx), near_x, near_y = core.step, np.abs(qy) < core.step[0], np.abs(qx) < core.step[1]
    out[near_x] = _along(core.axis_x, qx[near_x], sx, qy[near_x], sy)
    out[near_y] *= _along(core.axis_y, qy[near_y], sy, qx[near_y], sx)
    r = np.hypot(qy, qx)
    inside = r < core.radius
    if not inside.any():
        return out
    import scipy.ndimage   # here: the model file's schema imports this module at start-up
    ny, nx = core.ratio.shape
    u = qy[inside] / core.step[0] + ny // 2
    v = qx[inside] / core.step[1] + nx // 2
    ratio = scipy.ndimage.map_coordinates(core.ratio, [u, v], order=1, mode="nearest")
    weight = np.clip((core.radius - r[inside]) / (TAPER_SHARE * core.radius), 0.0, 1.0)
    out[inside] += (ratio - out[inside]) * weight
    return out


def from_hyperparameters(hp):
    """The :class:`PsdCore` of a measured-psd model's hyperparameters, or None (a file written
    before the core)."""
    if "core_ratio" not in hp:
        return None
    return PsdCore(np.asarray(hp["core_ratio"], dtype=np.float64),
                   tuple(float(s) for s in hp["core_step_per_um"]),
                   float(hp["core_radius_per_um"]),
                   np.asarray(hp["core_axis_x"], dtype=np.float64),
                   np.asarray(hp["core_axis_y"], dtype=np.float64))


def to_hyperparameters(core) -> dict:
    """The model file's fields of ``core`` (:data:`KEYS`), the ratios to 6 significant
    digits."""
    def rounded(values):
        return [float(f"{v:.6g}") for v in np.asarray(values, dtype=np.float64)]
    return {"core_ratio": [rounded(row) for row in np.asarray(core.ratio)],
            "core_step_per_um": [float(s) for s in core.step],
            "core_radius_per_um": float(core.radius),
            "core_axis_x": rounded(core.axis_x), "core_axis_y": rounded(core.axis_y)}


def check_core(hp, error=ValueError):
    """Raise ``error`` unless the core's fields of ``hp`` are all there or none is, the ratio
    an odd-sized grid of at most 129 x 129 finite numbers in :data:`RATIO_RANGE`, the axes'
    ratios odd-sized lists of such numbers, the steps two numbers > 0 and the radius > 0,
    within the grid's extent along each axis."""
    present = [k for k in KEYS if k in hp]
    if not present:
        return
    if len(present) != len(KEYS):
        raise error(f"a measured-psd model's core needs all of {', '.join(KEYS)}; got only "
                    f"{', '.join(present)}")
    try:
        ratio = np.asarray(hp["core_ratio"], dtype=np.float64)
        step = np.asarray(hp["core_step_per_um"], dtype=np.float64)
        radius = float(hp["core_radius_per_um"])
        axes = [np.asarray(hp[k], dtype=np.float64) for k in ("core_axis_x", "core_axis_y")]
    except (TypeError, ValueError):
        raise error("core_ratio must be a list of rows of numbers, core_step_per_um two numbers, "
                    "core_radius_per_um a number and core_axis_x, core_axis_y lists of "
                    "numbers") from None
    low, high = RATIO_RANGE
    for name, axis in zip(("core_axis_x", "core_axis_y"), axes):
        if axis.ndim != 1 or len(axis) % 2 == 0 or not 3 <= len(axis) <= 2 * MAX_AXIS + 1:
            raise error(f"{name} must be a list of an odd number (3 to {2 * MAX_AXIS + 1}) of "
                        f"numbers, got shape {axis.shape}")
        if not (np.all(np.isfinite(axis)) and axis.min() >= low and axis.max() <= high):
            raise error(f"{name} must hold finite numbers in [{low:g}, {high:g}]")
    most = 2 * MAX_HALF + 1
    if ratio.ndim != 2 or any(n % 2 == 0 or not 3 <= n <= most for n in ratio.shape):
        raise error(f"core_ratio must be a grid of an odd number (3 to {most}) of rows and of "
                    f"columns, got shape {ratio.shape}")
    if not (np.all(np.isfinite(ratio)) and ratio.min() >= low and ratio.max() <= high):
        raise error(f"core_ratio must hold finite numbers in [{low:g}, {high:g}]")
    if step.shape != (2,) or not np.all(np.isfinite(step)) or not np.all(step > 0):
        raise error(f"core_step_per_um must be two numbers > 0, got {hp['core_step_per_um']!r}")
    if not (math.isfinite(radius) and radius > 0):
        raise error(f"core_radius_per_um must be a number > 0, got {radius!r}")
    reach = [(n // 2) * s for n, s in zip(ratio.shape, step)]
    if radius > min(reach) * (1 + 1e-9):
        raise error(f"core_radius_per_um ({radius:g}) reaches beyond the core_ratio grid "
                    f"({reach[0]:g} x {reach[1]:g} 1/um)")
