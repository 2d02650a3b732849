r"""The feed marks of a periodic machined profile (turned, milled, shaped, fly-cut): the feed,
the mark's shape and each mark's shift and depth (beyond the paper; issue 41, the remedy
section 3.4 asks for: "hierarchical GPs [36]").

A turned surface is a deterministic kinematic trace, the tool nose repeated at the feed, plus
random roughness: the paper's figure 7 draws it from a stationary Gaussian process (eq 22),
which gives every spectral line a random amplitude and phase and so cannot keep the marks'
shape. This module measures the trace itself, on a profile across the marks (on a surface,
the mean profile across the lay):

* the **feed** :math:`P`: the periodogram's highest line among periods that fit at least
  :data:`MIN_MARKS` times in the profile and span at least :data:`MIN_MARK_SAMPLES` samples,
  refined to the period whose fold explains the most variance (41 periods within half a
  frequency bin either side);
* the **mark** :math:`m(u)`, :math:`0 \le u < P`: the profile folded at the feed (the mean of
  the heights at each phase, one bin per sample), its mean removed, its origin at its highest
  point (on a turned profile the cusp between two marks);
* per mark :math:`k` a **shift** :math:`s_k` (the mark's position against the nominal
  :math:`x_0 + kP`, searched within :math:`\pm P / 8` in quarter samples) and a **depth**
  :math:`d_k` (the mean height of the profile over the mark, less the mark's), refined once
  by folding again with the marks aligned.

The profile the marks describe is the lower envelope of the mark's copies, each moved by its
shift and sunk by its depth, :math:`\mu(x) = \min_k \big[\tilde m(x - x_0 - (k - 1)P - s_k)
+ d_k\big]`, as a cutting tool leaves its passes (the kinematic trace of
:mod:`roughgp.models.turned`): the mark's highest point is where two copies meet, and a copy
moved away from its neighbour leaves a higher cusp. :math:`\tilde m` is the mark continued
beyond its feed along its flanks (:meth:`FeedMarks.extended_mark`). With no shifts and depths
the envelope is the mark repeated. The fold averages cusps that lie at slightly different
places (the marks' shifts and depths move them) into a rounded, lower top; where the mark's
flanks are convex near its ends (a tool's arcs meeting at a cusp), the last thirty-second of
the feed at either end is continued from the flank instead (a quadratic fitted from a
thirty-second to an eighth of the feed from the end), so that the envelope makes the cusps
sharp again; a concave end (a rounded crest) is kept as folded.

Whether the profile holds a mark at all is measured, not assumed, out of sample: the period
and the mark found on one half of the profile must explain at least :data:`REPRODUCIBLE` of the
other half's variance, both ways round (:attr:`FeedMarks.reproducibility`, the lesser share),
or :func:`feed_marks` raises :class:`NoPeriodError`. A stationary random profile shares no
mark between its halves, whatever line its periodogram's largest happens to be (the share is
near or below 0); a turned profile shares nearly its whole variance. The calibration is in
``tests/metrology/test_feed_marks.py``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from roughgp.common.checks import check_positive

__all__ = ["MIN_MARKS", "MIN_MARK_SAMPLES", "REPRODUCIBLE", "EDGE_SAMPLES", "NoPeriodError",
           "FeedMarks", "feed_marks", "map_marks", "row_depths"]

#: the fewest marks a profile must hold (the halves of the test each hold two)
MIN_MARKS = 4
#: the fewest samples a mark must span
MIN_MARK_SAMPLES = 4
#: the least share of one half's variance that the mark found on the other half must explain
REPRODUCIBLE = 0.5
#: the samples at each end of the mark through which it is continued (the tool's flank)
EDGE_SAMPLES = 4
_SHIFT_RANGE = 1 / 8      # of the feed, either side
_PERIODS_TRIED = 41


class NoPeriodError(ValueError):
    """The profile holds no reproducible feed mark (module docstring)."""


@dataclasses.dataclass(frozen=True)
class FeedMarks:
    """The feed marks of a profile (module docstring); lengths in um, heights in um.

    Attributes:
        feed: the period :math:`P`.
        origin: :math:`x_0`, where a mark begins (the mark's highest point), in
            ``[0, feed)`` from the profile's first point.
        mark: the mark's shape, mean zero, at ``u = j * feed / mark.size``.
        shifts, depths: per mark :math:`k = 0 .. K - 1` (the first begins at
            ``origin - feed``, so that the marks cover the profile).
        reproducibility: the least share of one half's variance that the mark found on the
            other half explains (module docstring).
        explained: the share of the profile's variance that :meth:`profile` explains.
    """

    feed: float
    origin: float
    mark: np.ndarray
    shifts: np.ndarray
    depths: np.ndarray
    reproducibility: float
    explained: float

    @property
    def centres(self) -> np.ndarray:
        """The nominal centres of the marks, :math:`x_0 + (k - 1/2) P` (um)."""
        return self.origin + (np.arange(self.shifts.size) - 0.5) * self.feed

    def mark_at(self, u) -> np.ndarray:
        """The mark's shape at phases ``u`` (um, any real: taken modulo the feed), periodic
        linear interpolation."""
        n = self.mark.size
        t = np.mod(np.asarray(u, dtype=np.float64) / self.feed, 1.0) * n
        j = np.floor(t).astype(int) % n
        w = t - np.floor(t)
        return (1 - w) * self.mark[j] + w * self.mark[(j + 1) % n]

    def window(self, x, shifts=None) -> np.ndarray:
        """The index of the mark each position ``x`` lies in: mark ``k`` spans
        ``[x0 + (k - 1) P, x0 + k P)``, moved by its shift (interpolated between the centres
        at the boundaries)."""
        shifts = self.shifts if shifts is None else np.asarray(shifts, dtype=np.float64)
        x = np.asarray(x, dtype=np.float64)
        pos = (x - self.origin - np.interp(x, self.centres, shifts)) / self.feed + 1.0
        return np.clip(np.floor(pos).astype(int), 0, shifts.size - 1)

    @property
    def height(self) -> float:
        """The height of the mark as its copies leave it (the peak-to-valley height of the
        mark repeated, the envelope's cusps included; the mark's own samples may reach higher
        at its continued ends)."""
        u = np.arange(2 * self.mark.size) * self.feed / self.mark.size
        zeros = np.zeros(4)
        repeated = dataclasses.replace(self, origin=0.0, shifts=zeros, depths=zeros)
        return float(np.ptp(repeated.profile(u + self.feed / 2)))

    def extended_mark(self, u) -> np.ndarray:
        """The mark at phases ``u`` of one copy (um, not taken modulo the feed): the mark on
        ``[0, P - P/n)`` (its samples), continued beyond its first and its last sample along
        the line through its :data:`EDGE_SAMPLES` samples there, upward only (the tool's flank,
        or flat where the mark ends flat)."""
        u = np.asarray(u, dtype=np.float64)
        n, step = self.mark.size, self.feed / self.mark.size
        q = min(EDGE_SAMPLES, n // 2)
        last = self.feed - step
        # the slopes towards the ends, over the last q samples at either end
        rise_end = max(0.0, (self.mark[n - 1] - self.mark[n - 1 - q]) / (q * step))
        rise_start = max(0.0, (self.mark[0] - self.mark[q]) / (q * step))
        inside = self.mark_at(u)
        before = self.mark[0] + rise_start * (-u)
        after = self.mark[n - 1] + rise_end * (u - last)
        return np.where(u < 0, before, np.where(u >= last, after, inside))

    def profile(self, x, shifts=None, depths=None) -> np.ndarray:
        r""":math:`\mu(x)` at positions ``x`` (um from the profile's first point), with these
        marks' shifts and depths or others of the same length; ``depths`` of shape ``(K, n)``
        (a depth per mark and row of a surface) gives the trace of ``n`` rows, ``(n, x.size)``.
        The lower envelope of the mark's copies (module docstring).
        """
        shifts = self.shifts if shifts is None else np.asarray(shifts, dtype=np.float64)
        depths = self.depths if depths is None else np.asarray(depths, dtype=np.float64)
        x = np.asarray(x, dtype=np.float64)
        count = shifts.size
        k = self.window(x, shifts)
        out = None
        for j in (k - 1, k, k + 1):
            j = np.clip(j, 0, count - 1)
            copy = self.extended_mark(x - self.origin - (j - 1) * self.feed - shifts[j])
            copy = copy + (depths[j] if depths.ndim == 1 else depths[j].T)
            out = copy if out is None else np.minimum(out, copy)
        return out


def _fold(phase, values, n_bins):
    """Bin means of ``values`` at ``phase`` in [0, 1), empty bins interpolated periodically."""
    bins = np.minimum((phase * n_bins).astype(int), n_bins - 1)
    total = np.bincount(bins, values, n_bins)
    count = np.bincount(bins, None, n_bins)
    full = count > 0
    means = np.zeros(n_bins)
    means[full] = total[full] / count[full]
    if not full.all():
        centres = np.arange(n_bins)
        means[~full] = np.interp(centres[~full], centres[full], means[full], period=n_bins)
    return means


def _explained(x, p, period, spacing):
    n_bins = max(MIN_MARK_SAMPLES, int(round(period / spacing)))
    phase = np.mod(x / period, 1.0)
    folded = _fold(phase, p, n_bins)
    fitted = folded[np.minimum((phase * n_bins).astype(int), n_bins - 1)]
    return 1.0 - np.var(p - fitted) / np.var(p)


def _period(x, p, spacing, feed, min_marks=MIN_MARKS):
    """The feed: given (checked), or the periodogram's line refined by the fold."""
    n = p.size
    length = n * spacing
    if feed is not None:
        check_positive("feed", feed)
        if not MIN_MARK_SAMPLES * spacing <= feed <= length / min_marks:
            raise ValueError(f"feed must be in [{MIN_MARK_SAMPLES} spacings, the profile's "
                             f"length / {MIN_MARKS}] = [{MIN_MARK_SAMPLES * spacing:g}, "
                             f"{length / MIN_MARKS:g}] um (at least {MIN_MARKS} marks of at "
                             f"least {MIN_MARK_SAMPLES} samples), got {feed!r}")
        return float(feed)
    power = np.abs(np.fft.rfft(p)) ** 2
    k = np.arange(power.size)
    allowed = (k >= min_marks) & (k <= n / MIN_MARK_SAMPLES)
    if not allowed.any():
        raise NoPeriodError(f"the profile of {n} points is too short to hold {MIN_MARKS} marks "
                            f"of {MIN_MARK_SAMPLES} samples")
    line = int(k[allowed][np.argmax(power[allowed])])
    frequencies = np.linspace(line - 0.5, line + 0.5, _PERIODS_TRIED) / length
    frequencies = frequencies[frequencies * length >= min_marks]
    shares = [_explained(x, p, 1.0 / f, spacing) for f in frequencies]
    return float(1.0 / frequencies[int(np.argmax(shares))])


def _align(x, p, marks: FeedMarks, spacing):
    """Each mark's shift (grid search, quarter samples) and depth against ``marks.mark``."""
    feed, count = marks.feed, marks.shifts.size
    window = marks.window(x, np.zeros(count))
    reach = _SHIFT_RANGE * feed
    trial = np.arange(-reach, reach + spacing / 8, spacing / 4)
    shifts, depths = np.zeros(count), np.zeros(count)
    for k in range(count):
        inside = window == k
        if inside.sum() < 0.5 * feed / spacing:   # a partial mark at an end: no shift
            depths[k] = np.nan if not inside.any() else float(np.mean(
                p[inside] - marks.mark_at(x[inside] - marks.origin)))
            continue
        u = x[inside, None] - marks.origin - trial[None, :]
        diff = p[inside, None] - marks.mark_at(u)
        best = int(np.argmin(diff.var(axis=0)))
        shifts[k], depths[k] = trial[best], float(diff[:, best].mean())
    depths = np.where(np.isnan(depths), np.nanmean(depths), depths)
    return shifts, depths


def _folded_mark(x, p, marks: FeedMarks, shifts, depths, n_bins):
    """The mark folded with each mark moved back by its shift and raised by its depth."""
    k = marks.window(x, shifts)
    phase = np.mod((x - marks.origin - shifts[k]) / marks.feed, 1.0)
    return _fold(phase, p - depths[k], n_bins)


def _sharpened(mark):
    """The mark with its ends continued from its flanks where they are convex (a cusp the fold
    rounded: module docstring): the samples within a thirty-second of the feed of either end
    replaced by the quadratic fitted to the flank from a thirty-second to an eighth of the feed
    from that end. A fold of 16 samples or fewer (``round(n / 32)`` is 0) is kept as it is: its
    flanks hold fewer than the 3 samples a quadratic needs (on a FRT map with no feed marks, the
    marks that a search tried had 8 to 15 samples, and numpy warned the user of a fit through 2
    points)."""
    n = mark.size
    near = round(n / 32)
    far = max(near + 3, round(n / 8))
    if near < 1 or far >= n // 2:
        return mark
    out = mark.copy()
    j = np.arange(n, dtype=np.float64)
    for flank, end in ((np.arange(n - far, n - near), np.arange(n - near, n)),
                       (np.arange(near, far), np.arange(0, near))):
        centre = j[flank].mean()   # centred: a well-conditioned fit
        quadratic = np.polyfit(j[flank] - centre, mark[flank], 2)
        if quadratic[0] >= 0:       # convex: the rounded top of a cusp; concave ends are kept
            out[end] = np.polyval(quadratic, j[end] - centre)
    return out


def _held_out_share(x, p, valid, spacing, feed):
    """The least share of one half's variance that the mark found on the other half (its
    period and its fold, at the same phase) explains, over both ways round."""
    half = p.size // 2
    shares = []
    for fit, test in ((slice(0, half), slice(half, None)), (slice(half, None), slice(0, half))):
        xf, pf, vf = x[fit], p[fit], valid[fit]
        xt, pt = x[test][valid[test]], p[test][valid[test]]
        try:
            period = _period(xf - xf[0], pf - pf[vf].mean() * vf, spacing, feed,
                             MIN_MARKS // 2)
        except (NoPeriodError, ValueError):
            return 0.0
        n_bins = max(MIN_MARK_SAMPLES, int(round(period / spacing)))
        mark = _fold(np.mod(xf[vf] / period, 1.0), pf[vf] - pf[vf].mean(), n_bins)
        phase = np.mod(xt / period, 1.0)
        predicted = mark[np.minimum((phase * n_bins).astype(int), n_bins - 1)]
        centred = pt - pt.mean()
        shares.append(1.0 - np.var(centred - predicted) / np.var(centred))
    return float(min(shares))


def feed_marks(profile, spacing=1.0, *, feed=None) -> FeedMarks:
    """The feed marks of ``profile`` (heights in um at ``spacing`` um, NaN where unmeasured;
    module docstring).

    Args:
        profile: 1-D, at least ``MIN_MARKS * MIN_MARK_SAMPLES`` points, at least half measured.
        spacing: > 0, um.
        feed: the feed in um when known (then not searched): at least
            :data:`MIN_MARK_SAMPLES` spacings, at most the profile's length /
            :data:`MIN_MARKS`.

    Raises:
        NoPeriodError: the profile holds no reproducible mark (the mark of one half explains
            less than :data:`REPRODUCIBLE` of the other's variance), or is too short for one.
    """
    check_positive("spacing", spacing)
    p = np.asarray(profile, dtype=np.float64)
    if p.ndim != 1:
        raise ValueError(f"profile must be 1-D, got shape {p.shape}")
    if p.size < MIN_MARKS * MIN_MARK_SAMPLES:
        raise NoPeriodError(f"the profile of {p.size} points is too short to hold {MIN_MARKS} "
                            f"marks of {MIN_MARK_SAMPLES} samples")
    valid = np.isfinite(p)
    if valid.mean() < 0.5:
        raise ValueError(f"profile must be at least half measured, got {valid.mean():.0%}")
    x_all = np.arange(p.size) * spacing
    x, p = x_all[valid], p[valid] - p[valid].mean()
    if not np.var(p) > 0:
        raise NoPeriodError("the profile is constant: it holds no mark")
    filled = np.zeros(valid.size)
    filled[valid] = p
    period = _period(x_all, filled, spacing, feed)
    n_bins = max(MIN_MARK_SAMPLES, int(round(period / spacing)))
    count = int(math.ceil(x_all[-1] / period)) + 2          # mark 0 begins at origin - feed
    zeros = np.zeros(count)
    mark = _fold(np.mod(x / period, 1.0), p, n_bins)
    origin = float(np.argmax(mark) * period / n_bins)
    marks = FeedMarks(period, origin, np.roll(mark, -int(np.argmax(mark))) - mark.mean(),
                      zeros, zeros, 0.0, 0.0)
    for _ in range(2):
        shifts, depths = _align(x, p, marks, spacing)
        mark = _sharpened(_folded_mark(x, p, marks, shifts, depths, n_bins))
        marks = dataclasses.replace(marks, mark=mark - mark.mean(), shifts=shifts,
                                    depths=depths)
    reproducibility = _held_out_share(x_all, filled, valid, spacing, feed)
    explained = float(1.0 - np.var(p - marks.profile(x)) / np.var(p))
    marks = dataclasses.replace(marks, reproducibility=reproducibility, explained=explained)
    if not reproducibility >= REPRODUCIBLE:
        raise NoPeriodError(f"no feed mark in the profile: the mark found on one half of it "
                            f"explains {max(reproducibility, 0.0):.2f} of the other half's "
                            f"variance, below "
                            f"{REPRODUCIBLE} (a periodic machined profile: near its whole "
                            f"variance; the best period of the whole: {period:.4g} um)")
    return marks


def map_marks(z, spacing=1.0, *, feed=None) -> FeedMarks:
    """The feed marks of a surface ``z[iy, ix]`` whose marks run along y (across x): those of
    its mean profile across the lay, the mean of each column's measured points (NaN where a
    column has none)."""
    z = np.asarray(z, dtype=np.float64)
    valid = np.isfinite(z)
    count = valid.sum(axis=0)
    total = np.where(valid, z, 0.0).sum(axis=0)
    profile = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    return feed_marks(profile, spacing, feed=feed)


def row_depths(z, marks: FeedMarks, spacing=1.0) -> np.ndarray:
    """Each mark's depth in each row of a surface ``z[iy, ix]`` whose marks run along y
    (across x), against ``marks`` (of its mean profile): shape ``(K, ny)``, the mean height of
    the row over the mark, less the mark's (NaN where the row measures none of the mark)."""
    z = np.asarray(z, dtype=np.float64)
    x = np.arange(z.shape[1]) * spacing
    window = marks.window(x)
    trace = marks.mark_at(x - marks.origin - marks.shifts[window])
    diff = z - trace[None, :]
    valid = np.isfinite(diff)
    out = np.full((marks.shifts.size, z.shape[0]), np.nan)
    for k in np.unique(window):
        cols = window == k
        n = valid[:, cols].sum(axis=1)
        total = np.where(valid[:, cols], diff[:, cols], 0.0).sum(axis=1)
        out[k] = np.where(n > 0, total / np.maximum(n, 1), np.nan)
    return out
