r"""The fill's 95 % band calibrated by the depth of a point in its hole (beyond the paper).

A filled point's error grows with its distance to the nearest measured point, its *depth*
:math:`d` (1 at a hole's edge, about :math:`w/2` at the centre of a hole :math:`w` points
across): at the edge the GP interpolates, at the centre of a large hole it extrapolates from
one side, where the fitted covariance is least trustworthy. One band factor calibrated on small
held-out discs (:mod:`roughgp.filling.self_check`) is then too narrow in large holes and too
wide in small ones: on the maps of ``data/`` with holes of 2 to 40 points across, it held from
about 30 % to 100 % of the true heights per map and hole size
(:mod:`roughgp.experiments.hole_coverage`).

:func:`calibrate_hole_band` holds out measured points **in the shapes of the measurement's own
holes** (copies of them moved to random places) and calibrates one factor per class of hole and
depth:

1. The holes to fill (connected missing points) are grouped by their largest depth into the
   classes of :data:`DEPTH_EDGES` (1-2, 2-4, 4-8, ... points deep; a hole ``w`` points across
   is about ``w/2`` deep); for each class present, holes of that class are drawn (at least
   :data:`COPIES_PER_CLASS` and :data:`POINTS_PER_CLASS` points), those deeper than
   :data:`MAX_DEPTH_SHARE` of the map's shorter side or :data:`MAX_DEPTH` points left out,
   the classes taken from the smallest up while all the copies hold at most
   :data:`MAX_HELD_OUT` points (the work is bounded whatever the map).
2. The copies are held out in rounds (at least 2 points apart, each round at most
   :data:`ROUND_SHARE` of the measured points, at most :data:`MAX_ROUNDS` rounds; a copy
   anywhere at least half of it is measured: not preferably clear of the map's own holes,
   which gather where the surface is hardest), each round filled by the moving-window
   kriging of the fill itself (:func:`~roughgp.filling.local_fill.fill_gaps_locally`, the
   kernel fitted on the map), and each held-out point scored, :math:`|e|/s` with :math:`s`
   the predictive sd of a new measurement times the map's roughness around the copy
   (:func:`~roughgp.filling.local_scale.local_scale`, the copies held out), with its depth
   (the distance to the nearest point still measured) and its copy's class (the copy's
   largest depth, as placed).
3. For each hole class ``h`` and depth class ``k <= h``, the factor is the split-conformal
   quantile of the scores there (:func:`~roughgp.filling.self_check.conformal_factor`): the
   edge of a large hole, filled from one side, is not the edge of a small one, filled from
   all sides. A pair reached by fewer than :data:`MIN_COPIES` copies is not calibrated.
4. At a point to fill the band is the factor of its hole's class and its depth, times the
   roughness around its hole, times the predictive sd: wider where the map is rougher than
   on the whole (a flank, a worn zone), narrower where it is smoother.

In a hole of a class the map could not hold out (beyond the caps or the budget, or too few
copies placed) the band is widened, not extrapolated: its factor is the largest calibrated one
or the *marginal* factor, the conformal quantile of :math:`|z - \bar z|/\sqrt{r(0) + \sigma^2}`
over the measured points, whichever is larger: what the band must hold far from any data (the
GP's mean tends to the map's mean and its sd to the prior's). :class:`HoleBand` says up to
which hole size the band was calibrated.

The kernel is fitted with the held-out points in (a few hyperparameters from the whole map,
the same for every round; the self-check's smaller discs, which choose the smoothness, are
held out of the fit). The guarantee is for holes like the copies: the map's own shapes, at
random places. A hole at a steep flank or a defect may still be harder than its roughness
around it says.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.ndimage

from roughgp.filling.hole_geometry import DEPTH_EDGES, depth_class, hole_class, hole_depth
from roughgp.filling.local_fill import fill_gaps_locally
from roughgp.filling.local_scale import local_scale
from roughgp.filling.self_check import LEVEL, conformal_factor, predictive_sd
from roughgp.sampling.grid_sampler import acvf_of

__all__ = ["DEPTH_EDGES", "COPIES_PER_CLASS", "POINTS_PER_CLASS", "MIN_COPIES", "ROUND_SHARE",
           "MAX_ROUNDS", "MAX_DEPTH_SHARE", "MAX_DEPTH", "MAX_HELD_OUT", "HoleBand", "hole_depth",
           "hole_class", "depth_class", "marginal_factor", "calibrate_hole_band"]

COPIES_PER_CLASS = 40   #: copies of holes drawn for each class of the map's holes, at least; ...
POINTS_PER_CLASS = 1000  #: ... and enough for this many points (small holes: many copies)
MIN_COPIES = 20         #: fewer copies reaching a depth class: that class is not calibrated
ROUND_SHARE = 0.08     #: at most this share of the measured points held out in one round
MAX_ROUNDS = 24        #: at most this many rounds (fills) per calibration
MAX_DEPTH_SHARE = 1 / 6   #: a copied hole's depth at most this share of the shorter side ...
MAX_DEPTH = 24        #: ... and at most this many points (holes about 48 points across)
MAX_HELD_OUT = 100_000   #: the copies of all classes hold at most this many points together


def marginal_factor(residual, variance, noise_variance, level=LEVEL) -> float:
    """The factor a band needs far from any data: the conformal quantile of
    :math:`|z - \\bar z| / \\sqrt{r(0) + \\sigma^2}` over the measured (finite) points of
    ``residual``, ``variance`` = :math:`r(0)` of the kernel."""
    z = np.asarray(residual, dtype=np.float64)
    z = z[np.isfinite(z)]
    return conformal_factor(np.abs(z - z.mean()) / math.sqrt(variance + noise_variance), level)


@dataclass(frozen=True)
class HoleBand:
    """What :func:`calibrate_hole_band` returns: the band's factor per class of hole and depth.

    Attributes:
        factors: ``factors[h][k]``: the factor at depth class ``k`` in holes of class ``h``
            (the class of a hole's largest depth; both classes of :data:`DEPTH_EDGES`), NaN
            where not calibrated.
        copies: ``copies[h]``: the held-out copies of holes of class ``h``.
        held_out: the number of measured points held out (all rounds).
        rounds: the fills run.
        marginal: :func:`marginal_factor` (the band's factor far from any data).
        hole_classes: the classes of the holes to fill.
        deepest_hole: the largest depth among the holes to fill (points).
        deepest_copy: the largest depth among the held-out copies of calibrated classes.
        seconds: wall time.
        scale: the local roughness :math:`\\ell` at each point to fill
            (:func:`~roughgp.filling.local_scale.local_scale`; 1 elsewhere), by which the
            factors multiply there: the scores were divided by it on the copies (None: 1).
    """

    factors: tuple
    copies: tuple
    held_out: int
    rounds: int
    marginal: float
    hole_classes: tuple
    deepest_hole: float
    deepest_copy: float
    seconds: float
    scale: np.ndarray | None = field(default=None, compare=False, repr=False)

    @property
    def calibrated_classes(self) -> tuple:
        """The hole classes with a calibrated factor at every depth class they hold."""
        return tuple(h for h in range(len(DEPTH_EDGES))
                     if all(np.isfinite(self.factors[h][k]) for k in range(h + 1)))

    @property
    def calibrated_width(self) -> float:
        """The largest hole (points across, about ``2 depth``) the band is calibrated for: the
        largest held-out copy of a calibrated class (0: none)."""
        return 2 * self.deepest_copy if self.calibrated_classes else 0.0

    @property
    def uncalibrated_classes(self) -> tuple:
        """The classes of holes to fill that are not calibrated (their points get
        :attr:`widened_factor`)."""
        return tuple(h for h in self.hole_classes if h not in self.calibrated_classes)

    @property
    def widened_factor(self) -> float:
        """The factor in holes of an uncalibrated class: the largest of the calibrated factors
        and the marginal one (module docstring)."""
        calibrated = [f for row in self.factors for f in row if np.isfinite(f)]
        return max([self.marginal] + calibrated)

    def factor_map(self, missing) -> np.ndarray:
        """The band's factor at each point of ``missing`` (by its hole's class and its depth,
        times the local roughness :attr:`scale`; 0 at measured points): the band is this times
        the predictive sd."""
        missing = np.asarray(missing, dtype=bool)
        if not missing.any():
            return np.zeros(missing.shape)
        depth = hole_depth(missing)
        labels, deepest = hole_class(missing, depth)
        holes = np.concatenate([[0], depth_class(deepest)])[labels]
        depths = np.clip(depth_class(depth), 0, None)
        table = np.asarray(self.factors, dtype=float)
        out = table[holes, np.minimum(depths, holes)]
        widened = ~np.isfinite(out)
        for h in self.uncalibrated_classes:
            widened |= holes == h
        scale = np.ones(missing.shape) if self.scale is None else self.scale
        if scale.shape != missing.shape:
            raise ValueError(f"missing must have the shape of the calibrated map "
                             f"{scale.shape}, got {missing.shape}")
        out = np.where(widened, self.widened_factor, out) * scale
        # untested holes: never below what the band must hold far from any data
        out = np.where(widened, np.maximum(out, self.marginal), out)
        return np.where(missing, out, 0.0)

    def summary(self, spacing_um=None) -> str:
        """One line: what was held out, the largest hole calibrated for and what was done in
        larger holes."""
        width = self.calibrated_width
        size = (f"{width:.0f} points across" if spacing_um is None or not math.isfinite(width)
                else f"{width:.0f} points ({width * spacing_um:.3g} um) across")
        if not self.calibrated_classes:
            return (f"band not calibrated by hole size (too few copies of holes held out, "
                    f"{self.held_out} points): its factor is the widened "
                    f"{self.widened_factor:.3g}")
        edges = [_class_name(h) for h in self.calibrated_classes]
        text = (f"band calibrated by hole size and depth on {sum(self.copies)} held-out copies "
                f"of the map's holes ({self.held_out} points, {self.rounds} fills, "
                f"{self.seconds:.1f} s; holes "
                f"{', '.join(edges)} points deep), for holes up to {size}")
        if self.uncalibrated_classes:
            text += (f"; the largest hole to fill is about {2 * self.deepest_hole:.0f} "
                     f"points across: in holes of a size not calibrated the band takes the "
                     f"untested, widened factor {self.widened_factor:.3g}")
        elif 2 * self.deepest_hole > width:
            text += (f"; the largest hole to fill, about {2 * self.deepest_hole:.0f} points "
                     f"across, takes the factors of its size class")
        if self.scale is not None:
            text += "; each hole's band scaled by the map's roughness around it"
        return text


def _class_name(k: int) -> str:
    lo = DEPTH_EDGES[k]
    hi = DEPTH_EDGES[k + 1] if k + 1 < len(DEPTH_EDGES) else math.inf
    return f"{lo:g}-{hi:g}" if math.isfinite(hi) else f">{lo:g}"


def _hole_shapes(labels, deepest, max_depth, rng):
    """The shapes to hold out: per class of the holes' largest depths ``deepest``, shapes
    (boolean masks) of that class's own holes (``labels``), drawn with replacement, those
    deeper than ``max_depth`` left out: :data:`COPIES_PER_CLASS`, or more where they hold fewer
    than :data:`POINTS_PER_CLASS` points; classes from the smallest up, until all the shapes
    would hold over :data:`MAX_HELD_OUT` points."""
    classes = depth_class(deepest)
    boxes = scipy.ndimage.find_objects(labels)
    shapes, points = [], 0
    for c in np.unique(classes):
        holes = np.flatnonzero((classes == c) & (deepest <= max_depth))
        if not holes.size:
            continue
        areas = np.array([np.count_nonzero(labels[boxes[k]] == k + 1) for k in holes])
        count = max(COPIES_PER_CLASS, math.ceil(POINTS_PER_CLASS / float(areas.mean())))
        drawn = rng.choice(holes.size, count)
        if points + int(areas[drawn].sum()) > MAX_HELD_OUT:
            break
        shapes += [labels[boxes[holes[i]]] == holes[i] + 1 for i in drawn]
        points += int(areas[drawn].sum())
    return shapes


def _place_rounds(measured, shapes, rng):
    """The shapes placed in rounds: ``[[points, ...], ...]`` with ``points`` the flat indices
    of a placed shape's measured points; a shape sits at a random place where at least half of
    it is on the map and measured (a hole may be cut by the map's edge), at least 2 points from
    any other shape of its round.

    Uniformly, not preferably where the map is measured all around nor wholly within the map:
    the map's own holes gather where the surface is hard to measure and to fill (the steep flank
    of a land, a defect), and such a flank may run along the map's edge. On sample-land's
    central 256 x 256 points (its last 40 rows the land's flank, 15 % of them missing, none
    elsewhere), copies placed clear of the holes and within the map left the band holding 86 %
    of held-out heights in holes 21 to 40 points across
    (``benchmarks/results/hole_coverage.md``, 2026-12-05)."""
    ny, nx = measured.shape
    budget = ROUND_SHARE * measured.sum()
    pending = list(shapes)
    rounds = []
    while pending and len(rounds) < MAX_ROUNDS:
        taken = np.zeros((ny + 4, nx + 4), dtype=bool)   # padded by the gap
        placed, left, used = [], [], 0
        for shape in pending:
            h, w = shape.shape
            halo = scipy.ndimage.binary_dilation(np.pad(shape, 2), iterations=2,
                                                 structure=np.ones((3, 3)))
            for _ in range(40):
                # the shape's corner: up to half the shape beyond the map's edge, as a hole's
                oy = int(rng.integers(-(h // 2), ny - h + h // 2 + 1))
                ox = int(rng.integers(-(w // 2), nx - w + w // 2 + 1))
                y0, y1, x0, x1 = max(oy, 0), min(oy + h, ny), max(ox, 0), min(ox + w, nx)
                inside = shape[y0 - oy:y1 - oy, x0 - ox:x1 - ox]
                ty0, tx0 = max(oy, 0), max(ox, 0)   # the halo in the padded frame, clipped
                ty1, tx1 = min(oy + h + 4, ny + 4), min(ox + w + 4, nx + 4)
                if (taken[ty0:ty1, tx0:tx1]
                        & halo[ty0 - oy:ty1 - oy, tx0 - ox:tx1 - ox]).any():
                    continue
                points = inside & measured[y0:y1, x0:x1]
                n = int(points.sum())
                if n < 0.5 * shape.sum() or used + n > budget:
                    continue
                taken[y0 + 2:y1 + 2, x0 + 2:x1 + 2] |= inside
                gy, gx = np.nonzero(points)
                placed.append(np.ravel_multi_index((gy + y0, gx + x0), measured.shape))
                used += n
                break
            else:
                left.append(shape)
        if not placed:
            break
        rounds.append(placed)
        pending = left
    return rounds


def calibrate_hole_band(residual, kernel, *, noise_variance, spacing, fill_missing=None,
                        seed=None, tile=8, margin=6) -> HoleBand:
    """Calibrate the band's factor per class of hole and depth on held-out copies of the holes
    of ``residual`` (module docstring).

    Args:
        residual: form-removed heights, NaN where not measured.
        kernel, noise_variance: the fitted model (eq 18 or a Matérn variant; eq 8's noise).
        spacing: scalar or ``(dy, dx)``.
        fill_missing: boolean map of the points the fill will fill (default: the NaN points);
            the holes that are copied.
        seed: the copies' random stream (an int or None).
        tile, margin: the kriging windows, those of the fill
            (:func:`~roughgp.filling.local_fill.fill_gaps_locally`).
    """
    start = time.perf_counter()
    residual = np.asarray(residual, dtype=np.float64)
    measured = np.isfinite(residual)
    to_fill = ~measured if fill_missing is None else np.asarray(fill_missing, dtype=bool)
    rng = np.random.default_rng(None if seed is None else (int(seed), 2))
    variance = float(acvf_of(kernel)(np.zeros((1, 2)))[0])
    marginal = marginal_factor(residual, variance, noise_variance)
    n = len(DEPTH_EDGES)
    empty = ((math.nan,) * n,) * n
    if not to_fill.any() or not measured.any():
        return HoleBand(empty, (0,) * n, 0, 0, marginal, (), 0.0, 0.0,
                        time.perf_counter() - start)
    to_fill_depth = hole_depth(to_fill)
    labels, deepest = hole_class(to_fill, to_fill_depth)
    hole_classes = tuple(int(h) for h in np.unique(depth_class(deepest)))
    max_depth = min(MAX_DEPTH_SHARE * min(residual.shape), MAX_DEPTH)
    rounds = _place_rounds(measured, _hole_shapes(labels, deepest, max_depth, rng), rng)
    scores, depths, holes, groups, copy_depths = [], [], [], [], []
    copy_id = 0
    for placed in rounds:
        held = np.zeros(residual.shape, dtype=bool)
        for points in placed:
            held.flat[points] = True
        fill = fill_gaps_locally(residual, kernel, noise_variance=noise_variance,
                                 spacing=spacing, mask=held, predict=held, tile=tile,
                                 margin=margin)
        depth = hole_depth(~measured | held)
        scale = local_scale(residual, ~measured | held, depth)
        for points in placed:
            s = predictive_sd(fill.sd.flat[points], noise_variance) * scale.flat[points]
            scores.append(np.abs(fill.mean.flat[points] - residual.flat[points])
                          / np.maximum(s, np.finfo(float).tiny))
            d = depth.flat[points]
            depths.append(depth_class(d))
            holes.append(np.full(points.size, depth_class(d.max())))   # as placed
            copy_depths.append(float(d.max()))
            groups.append(np.full(points.size, copy_id))
            copy_id += 1
    factors = np.full((n, n), math.nan)
    copies = [0] * n
    if rounds:
        scores, depths = np.concatenate(scores), np.concatenate(depths)
        holes, groups = np.concatenate(holes), np.concatenate(groups)
        for h in range(n):
            copies[h] = int(np.unique(groups[holes == h]).size)
            for k in range(h + 1):
                inside = (holes == h) & (depths == k)
                if np.unique(groups[inside]).size >= MIN_COPIES:
                    factors[h, k] = conformal_factor(scores[inside])
    band = HoleBand(tuple(tuple(float(f) for f in row) for row in factors), tuple(copies),
                    int(np.size(scores)) if rounds else 0, len(rounds), marginal, hole_classes,
                    float(deepest.max()), 0.0, 0.0)
    widest = max([d for d in copy_depths if int(depth_class(d)) in band.calibrated_classes],
                 default=0.0)
    return dataclasses.replace(band, deepest_copy=widest,
                               scale=local_scale(residual, to_fill, to_fill_depth),
                               seconds=time.perf_counter() - start)
