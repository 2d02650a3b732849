r"""Spurious measured points (spikes, pits) found with the GP, and the metrologists' methods
beside it (beyond the paper; its conclusion names the application).

An optical instrument reports, besides the points it could not measure (NaN), points it
measured wrong: spikes and pits at steep flanks, dust, edges. :func:`detect_spurious` scores
every measured point by its **leave-one-out predictive residual over the predictive sd** under
eq 18 plus white noise (eq 8), computed window by window: for the measured points :math:`O` of
a ``tile`` core and its ``margin``, with :math:`K = K_{OO} + \sigma^2 I`,

.. math::
    s_i = \frac{y_i - \mu_{-i}}{\sqrt{v_{-i}}} = \frac{[K^{-1} y]_i}{\sqrt{[K^{-1}]_{ii}}},

the standard identity of the leave-one-out GP posterior (Rasmussen & Williams 2006, eq 5.12):
one Cholesky factor per window gives the scores of all its core's points. Under the model
:math:`s_i` is standard normal, so the threshold :math:`|s_i| > t` with
:math:`t = \Phi^{-1}(1 - \alpha/2)` flags a fraction :math:`\alpha` of the points of a clean
surface (:data:`FALSE_ALARM` = 1e-4, :data:`THRESHOLD` = 3.89).

**Robust to the outliers themselves, by iterative hard rejection.** The first fit (block
composite likelihood, :func:`roughgp.inference.block_fit.fit_ground_to_valid_points`) sees the
spikes: its noise variance grows, the LOO sd with it, and a 3-sd spike hides; a spike also
pulls the LOO prediction of its neighbours. So: fit, score, flag; refit without the flagged
points; score again, every point predicted from the points of its window that the fit kept;
and so on, at most ``rounds`` (:data:`ROUNDS`) times. This is iteratively reweighted
fitting with weights 0 or 1, the M-estimation view of a contaminated-normal noise model
whose outlier component takes the points beyond :math:`t`. A Student-t likelihood would need
a non-Gaussian posterior (Laplace or EP) in every window;
the hard rejection keeps the exact Gaussian algebra.

**The rounds converge by construction.** The points left out of the next fit are those left
out of this one plus those this round flags: the set only grows, so it reaches a fixed point
(a round that flags no new point) in finitely many rounds, and the rounds stop there. The
points reported as spurious are those the last fit scores beyond the threshold, each predicted
from the points of its window that are not left out: a point flagged in an early round (a
neighbour of a spike, before the spike was left out) that the last fit finds consistent is not
reported, though it stays out of the fit. The earlier rule (the next fit leaves out exactly
this round's flags) could oscillate: on a 96 x 96 crop of the bullet land the rounds flagged
27, 22, 33, 32 points and stopped at the cap of 4; the growing set left out 27, 31, 36, 40,
43, 43 points (a fixed point after 6 rounds) and reported 34. A fixed point is certain, yet
not within the cap: on the whole maps (``benchmarks/spurious_points_full.py``) ``opd-1.opd``
reached it after 4 rounds and ``di-1.di`` after 1, while the bullet land and ``sur-2.sur`` were
still growing at the cap of 8, by 21 and 26 points in the last round (0.01 % of their points;
on the land 5096, 7865, 9080, 9317, 9443, 9507, 9559, 9580 flagged so far after each round).
``SpuriousPoints.converged`` says which; the reported points are the last fit's either way.
On the whole land the earlier rule flagged 5096, 6868, 7120, 6451 points (stopped at its cap
of 4, 3.08 %); the growing set reports 6756 (3.22 %).

Measured (:func:`roughgp.experiments.spurious_points.benchmark`, 96 x 96 points, seed 0,
the earlier rule of the rounds): with 1 % of
the points injected (spikes and pits of 3-20 sd), a single non-robust pass (``rounds=1``) found
90.2 % of them on the eq 18 and on the plateau-honed surface (its fitted noise variance 15.9
against 0.089 after the refits on a 128 x 128 eq 18 surface whose true value is 0.1); the
iterated detector found 100 % on both, with false alarms of 1.1e-4 and 2.2e-4 of the other
points (one and two points; without the noise floor below, which brought them to 0). With the
growing set, on the chapter's 64 x 64 surfaces (seed 0, shares 0, 0.1 % and 1 %) it found
100 % with no false alarm on both kinds. The chapter "Spurious points" tabulates it.

**A noise floor.** A refit without the flagged points can drive the fitted noise variance to
almost nothing on a surface that is smooth at the pixel scale, and every leave-one-out sd with
it. The scores therefore use :math:`\max(\sigma^2_{\rm fit}, \sigma^2_{\rm floor})` with
:func:`noise_floor`: the robust variance of the second differences over 6, along the grid axis
where it is smaller. For white noise it is the noise variance; the surface's own curvature only
adds to it, so it bounds the noise from above, and the MAD ignores the spikes. The height
quantisation step was the other candidate: its :math:`q^2/12` is a true lower bound, but on
``data/sur-2.sur`` (:math:`q` = 0.1 nm) it is far below the leave-one-out sd and would change
nothing. On eq 18 (noise 0.1) the floor is about 0.77 (the rough surface's curvature), yet the
detection rate stays 100 % and the false alarms 0 on the 96 x 96 surfaces of both kinds, seeds
0 and 1, shares 0, 0.1 % and 1 % (measured with
:func:`roughgp.experiments.spurious_points.inject`).

The false-alarm rate holds where the model describes the surface. Where it does not, the
detector flags far more, and the flagged share is then itself a model check. With the earlier
rule of the rounds, on a 128 x 128 crop of ``data/sur-2.sur`` the rounds flagged 103, 385,
835 and 944 points (5.8 %) without the
floor, 103, 385, 835 and 882 (5.4 %) with it: the first fit's noise (sd 1.3 nm) covers a band
of speckled heights at one side of the crop; the refits without the flagged points lower it
(to a variance of 1.4e-13 um^2 in the last round), and more of the band scores beyond the
threshold. The floor (0.36 nm, set by the crop's quiet part) does not stop that, and is not
meant to: the band scatters more than the rest, which one noise variance cannot describe. On
the whole map (484 x 563) it flagged 7.0 % without the floor, 6.1 % with it (16580 points;
rounds 6105, 10780, 15644, 16580; the first fit's noise variance 1.5e-6 um^2, the last's
3.3e-10; 65 s). (The crop's numbers are from refits warm-started at the previous fit; they now
start afresh, which halves their time; on the whole land the flags were the same.) With the
growing set the whole map had 6105, 11407, 16340, 18051, 18604, 18834, 18928, 18954 points
flagged so far after each round (the cap) and reports 16910 (6.2 %).

The metrologists' methods, on the same heights (:data:`METHODS`):

* ``"k Sq"``: :math:`|z - \bar z| > k\,S_q` with :math:`k = 3` (Gwyddion's "mask outliers");
* ``"median"``: the residual of a :data:`MEDIAN_SIZE`-point median filter (Gwyddion /
  MountainsMap "remove outliers"), flagged beyond :math:`t` robust sd (1.4826 MAD);
* ``"robust filter"``: the residual of the robust Gaussian regression filter (ISO 16610-71,
  :func:`roughgp.metrology.robust_filters.robust_gaussian_filter`, nesting index
  :data:`ROBUST_CUTOFF_POINTS` spacings), flagged beyond :math:`t` robust sd.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.ndimage
from scipy.stats import norm

from roughgp.common.checks import check_integer, check_positive, check_varies, surface_array
from roughgp.common.grid import normalize
from roughgp.common.threads import one_blas_thread
from roughgp.filling.local_fill import lag_table
from roughgp.inference.block_fit import fit_ground_to_valid_points
from roughgp.metrology.form import remove_form
from roughgp.metrology.robust_filters import robust_gaussian_filter
from roughgp.sampling.grid_sampler import acvf_of

__all__ = ["FALSE_ALARM", "THRESHOLD", "ROUNDS", "K_SQ", "MEDIAN_SIZE", "ROBUST_CUTOFF_POINTS",
           "METHODS",
           "SpuriousPoints", "loo_scores", "noise_floor", "detect_spurious", "flag_k_sq",
           "flag_median", "flag_robust_filter", "flag_by", "describe_flagged"]

FALSE_ALARM = 1e-4  #: the nominal share of the points of a clean surface flagged
#: a point whose absolute score exceeds this is flagged (3.89)
THRESHOLD = float(norm.isf(FALSE_ALARM / 2))
ROUNDS = 8  #: the detector's fit-and-score rounds at most
K_SQ = 3.0  #: the k of k Sq thresholding
MEDIAN_SIZE = 5  #: the median filter's window (points per side)
ROBUST_CUTOFF_POINTS = 8  #: the robust filter's nesting index, in sampling spacings
METHODS = ("GP", "k Sq", "median", "robust filter")
_MAD = 1.482602218505602  # the sd of a normal per unit median absolute deviation


@dataclass(frozen=True)
class SpuriousPoints:
    """What :func:`detect_spurious` returns.

    Attributes:
        flagged: boolean map of the measured points judged spurious.
        scores: the LOO standardised residuals (NaN where unmeasured).
        threshold: the absolute score beyond which a point is flagged.
        rounds: fit-and-score rounds run; history: the points flagged in any round so far,
            after each (it never shrinks).
        kernel, noise_variance: the last fit's (without the points flagged before it).
        floor: the least noise variance scored with (:func:`noise_floor`; 0: none); the
            scores use ``max(noise_variance, floor)``.
        seconds: wall time.
        first_flagged, first_seconds, first_noise_variance: the points flagged after the
            first round (the non-robust detector, ``rounds=1``), the time to it, its fit's
            noise variance.
        excluded: every point flagged in any round (a superset of ``flagged``): where the
            rounds converged, the points the last fit left out; at the cap, those and the
            last round's new points.
        converged: True where the last round flagged no new point (``excluded`` is the
            rounds' fixed point); False where ``rounds`` ran out first.
    """

    flagged: np.ndarray
    scores: np.ndarray
    threshold: float
    rounds: int
    history: tuple
    kernel: object
    noise_variance: float
    floor: float
    seconds: float
    first_flagged: np.ndarray
    first_seconds: float
    first_noise_variance: float
    excluded: np.ndarray
    converged: bool

    @property
    def count(self) -> int:
        return int(self.flagged.sum())

    def summary(self) -> str:
        """One line: how many were flagged, of how many, and where (:func:`describe_flagged`)."""
        return describe_flagged(self.flagged, np.isfinite(self.scores))


def describe_flagged(flagged, measured, most=5) -> str:
    """How many points are flagged, of how many measured, and where (the first ``most`` as
    (row, column), largest clusters first)."""
    n, total = int(flagged.sum()), int(np.count_nonzero(measured))
    if n == 0:
        return f"no point flagged of {total} measured"
    labels, count = scipy.ndimage.label(flagged)
    sizes = np.bincount(labels.ravel())[1:]
    order = np.argsort(-sizes, kind="stable")[:most]
    centres = scipy.ndimage.center_of_mass(flagged, labels, order + 1)
    where = ", ".join(f"({int(round(r))}, {int(round(c))})" + (f" x{sizes[i]}" if sizes[i] > 1
                                                               else "")
                      for i, (r, c) in zip(order, centres))
    more = f", ... ({count - len(order)} more groups)" if count > len(order) else ""
    return (f"{n} of {total} measured points flagged spurious ({n / total:.3%}) in {count} "
            f"groups; at (row, column): {where}{more}")


def loo_scores(residual, kernel, *, noise_variance, spacing=1.0, excluded=None, tile=8,
               margin=6) -> np.ndarray:
    r"""The standardised leave-one-out residual of every measured point of ``residual`` (module
    docstring), from the measured points of its window that are not ``excluded``; an excluded
    point is scored against its prediction from the others. A point alone in its window (an
    isolated speck in a region the instrument could not measure) is scored against the prior,
    :math:`(y_i - \bar y)/\sqrt{k(0) + \sigma^2}`: the same identity with nothing else
    observed, so with the same false-alarm rate. NaN where unmeasured."""
    z = surface_array(residual, "residual")
    tile = check_integer("tile", tile, 1)
    margin = check_integer("margin", margin, 1)
    shape, sp = normalize(z.shape, spacing)
    ny, nx = shape
    measured = np.isfinite(z)
    excluded = np.zeros(shape, bool) if excluded is None else np.asarray(excluded, bool) & measured
    observed = measured & ~excluded
    if observed.sum() < 2:
        raise ValueError("fewer than 2 measured points to score")
    table = lag_table(acvf_of(kernel), shape, sp)
    variance = float(table[ny - 1, nx - 1]) + noise_variance
    offset = float(np.mean(z[observed]))
    centred = np.where(measured, z - offset, 0.0)
    scores = np.full(shape, np.nan)
    iy, ix = np.indices(shape)
    with one_blas_thread():
        for r0 in range(0, ny, tile):
            for c0 in range(0, nx, tile):
                core = np.s_[r0:r0 + tile, c0:c0 + tile]
                if not measured[core].any():
                    continue
                win = np.s_[max(r0 - margin, 0):r0 + tile + margin,
                            max(c0 - margin, 0):c0 + tile + margin]
                obs = observed[win]
                oy, ox = iy[win][obs], ix[win][obs]
                if oy.size == 0:  # nothing observed near: scored against the prior
                    ty, tx = np.nonzero(measured[core])
                    scores[ty + r0, tx + c0] = centred[ty + r0, tx + c0] / math.sqrt(variance)
                    continue
                k_oo = table[oy[:, None] - oy[None, :] + ny - 1,
                             ox[:, None] - ox[None, :] + nx - 1]
                k_oo[np.diag_indices_from(k_oo)] += noise_variance
                chol = scipy.linalg.cho_factor(k_oo, lower=True, check_finite=False)
                alpha = scipy.linalg.cho_solve(chol, centred[oy, ox], check_finite=False)
                # the observed points of the core: [K^-1]_ii = ||L^-1 e_i||^2
                in_core = (oy >= r0) & (oy < r0 + tile) & (ox >= c0) & (ox < c0 + tile)
                idx = np.flatnonzero(in_core)
                if idx.size:
                    unit = np.zeros((oy.size, idx.size))
                    unit[idx, np.arange(idx.size)] = 1.0
                    half = scipy.linalg.solve_triangular(chol[0], unit, lower=True,
                                                         check_finite=False)
                    diag = np.sum(half * half, axis=0)
                    scores[oy[idx], ox[idx]] = alpha[idx] / np.sqrt(diag)
                # the excluded points of the core: predicted from the observed ones
                ty, tx = np.nonzero(excluded[core])
                if ty.size:
                    ty, tx = ty + r0, tx + c0
                    k_ot = table[oy[:, None] - ty[None, :] + ny - 1,
                                 ox[:, None] - tx[None, :] + nx - 1]
                    half = scipy.linalg.solve_triangular(chol[0], k_ot, lower=True,
                                                         check_finite=False)
                    sd = np.sqrt(np.clip(variance - np.sum(half * half, axis=0), 1e-300, None))
                    scores[ty, tx] = (centred[ty, tx] - k_ot.T @ alpha) / sd
    return scores


def noise_floor(residual) -> float:
    r"""A robust upper bound of the white-noise variance of the heights ``residual`` (NaN:
    unmeasured): the second differences along each grid axis,
    :math:`d_i = z_{i-1} - 2 z_i + z_{i+1}`, have variance :math:`6\sigma^2` plus the
    surface's own curvature, so :math:`(1.4826\,\mathrm{MAD}(d))^2 / 6` bounds
    :math:`\sigma^2` from above; the smaller of the two axes is returned. The MAD ignores a few
    spikes (it breaks down at half the points). 0 where fewer than 3 points in a row are
    measured."""
    z = np.asarray(residual, dtype=np.float64)
    bounds = []
    for axis in (0, 1):
        d = np.diff(z, 2, axis=axis)
        d = d[np.isfinite(d)]
        if d.size:
            bounds.append(_robust_sd(d) ** 2 / 6.0)
    return float(min(bounds)) if bounds else 0.0


def detect_spurious(z, *, spacing=1.0, form="plane", degree=2, axis="auto",
                    threshold=THRESHOLD, rounds=ROUNDS, seed=0, block=24, n_blocks=12,
                    tile=8, margin=6, floor=True, progress=None) -> SpuriousPoints:
    """Flag the spurious measured points of a surface ``z[iy, ix]`` (NaN: unmeasured) by the
    GP's LOO scores under a fit that leaves out the flagged points (module docstring).

    Args:
        spacing: scalar or ``(dy, dx)``.
        form, degree, axis: the F-operator removed first
            (:func:`~roughgp.metrology.form.remove_form`; None: none).
        threshold: the absolute score beyond which a point is flagged, > 0 (default
            :data:`THRESHOLD`: a share :data:`FALSE_ALARM` of a clean surface's points).
        rounds: fit-and-score rounds at most, >= 1 (1: no robustness); the rounds stop
            earlier where one flags no new point (module docstring).
        seed, block, n_blocks: the block fit's
            (:func:`~roughgp.inference.block_fit.fit_ground_to_valid_points`).
        tile, margin: the scoring windows (points).
        floor: score with the noise variance at least :func:`noise_floor` of the heights
            (module docstring); False: the fitted one, however small.
        progress: optional callback ``(rounds done, rounds at most)`` after each round.
    """
    start = time.perf_counter()
    z = surface_array(z)
    check_positive("threshold", threshold)
    rounds = check_integer("rounds", rounds, 1)
    if not isinstance(floor, (bool, np.bool_)):
        raise ValueError(f"floor must be True or False, got {floor!r}")
    _, sp = normalize(z.shape, spacing)
    residual = remove_form(z, sp, form, degree=degree, axis=axis)[0]
    check_varies("the heights after the F-operator", residual, z)
    measured = np.isfinite(residual)
    least = noise_floor(residual) if floor else 0.0
    excluded = np.zeros(z.shape, bool)  # the points left out of the fit: they only grow
    history, fit, first, converged = [], None, None, False
    for _ in range(rounds):
        fit = fit_ground_to_valid_points(residual, spacing=sp, mask=excluded, block=block,
                                         n_blocks=n_blocks, seed=seed)
        scores = loo_scores(residual, fit.kernel, noise_variance=max(fit.noise_variance, least),
                            spacing=sp, excluded=excluded, tile=tile, margin=margin)
        beyond = measured & (np.abs(np.nan_to_num(scores)) > threshold)
        if first is None:
            first = (beyond, time.perf_counter() - start, float(fit.noise_variance))
        grown = excluded | beyond
        history.append(int(grown.sum()))
        if progress is not None:
            progress(len(history), rounds)
        if np.array_equal(grown, excluded):  # no new point: the last fit is final
            converged = True
            break
        excluded = grown
    return SpuriousPoints(beyond, scores, float(threshold), len(history), tuple(history),
                          fit.kernel, float(fit.noise_variance), float(least),
                          time.perf_counter() - start, *first, excluded, converged)


# --------------------------------------------------------------------------- the metrologists'

def _robust_sd(r):
    r = r[np.isfinite(r)]
    return _MAD * float(np.median(np.abs(r - np.median(r))))


def flag_k_sq(residual, k=K_SQ) -> np.ndarray:
    """Points farther than ``k`` Sq from the mean height (NaN: never flagged)."""
    z = np.asarray(residual, dtype=np.float64)
    h = z - np.nanmean(z)
    sq = math.sqrt(float(np.nanmean(h * h)))
    return np.isfinite(z) & (np.abs(np.nan_to_num(h)) > k * sq)


def flag_median(residual, size=MEDIAN_SIZE, threshold=THRESHOLD) -> np.ndarray:
    """Points whose residual from a ``size`` x ``size`` median filter exceeds ``threshold``
    robust sd of those residuals (NaN points take their nearest measured height first)."""
    z = np.asarray(residual, dtype=np.float64)
    measured = np.isfinite(z)
    nearest = scipy.ndimage.distance_transform_edt(~measured, return_distances=False,
                                                   return_indices=True)
    r = z - scipy.ndimage.median_filter(z[tuple(nearest)], size=size, mode="nearest")
    return measured & (np.abs(np.nan_to_num(r)) > threshold * _robust_sd(r))


def flag_robust_filter(residual, spacing=1.0, cutoff_points=ROBUST_CUTOFF_POINTS,
                       threshold=THRESHOLD) -> np.ndarray:
    """Points whose residual from the robust Gaussian regression filter (nesting index
    ``cutoff_points`` spacings) exceeds ``threshold`` robust sd of those residuals."""
    z = np.asarray(residual, dtype=np.float64)
    _, sp = normalize(z.shape, spacing)
    r = z - robust_gaussian_filter(z, sp, cutoff_points * max(sp))
    return np.isfinite(z) & (np.abs(np.nan_to_num(r)) > threshold * _robust_sd(r))


def flag_by(method, z, *, spacing=1.0, form="plane", seed=0) -> np.ndarray:
    """The flagged points of ``z`` by one of :data:`METHODS` (after the F-operator ``form``)."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if method == "GP":
        return detect_spurious(z, spacing=spacing, form=form, seed=seed).flagged
    _, sp = normalize(np.shape(z), spacing)
    residual = remove_form(np.asarray(z, dtype=np.float64), sp, form)[0]
    if method == "k Sq":
        return flag_k_sq(residual)
    if method == "median":
        return flag_median(residual)
    return flag_robust_filter(residual, sp)
