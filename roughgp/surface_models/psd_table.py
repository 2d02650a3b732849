r"""The measured 2-D PSD as a compact log-polar table, and what is drawn from it (beyond the
paper).

The nonparametric stationary model of a measured surface
(:mod:`roughgp.surface_models.measured_psd`) is its power spectral density :math:`C(\mathbf q)` (um^4: um^2 of height per (1/um)^2 of
frequency), the Fourier transform of the ACVF whose parametric forms are eq 18 and its Matérn
variant. This module holds the three steps:

* **Estimate** (:func:`periodogram`): a prewhitened periodogram of the form-removed heights,
  holes allowed. A real surface holds most of its variance at the longest wavelengths (on
  ``data/sample-land.x3p``, 127 um^2 after the cylinder, 7.4 um^2 after an 80 um L-filter), and
  the steps that a mean fill makes at the holes (and, less, the window's sidelobes) leak a
  share of it to every frequency: the plain windowed periodogram made the L-filtered
  simulations' Sq 4.0 um against the measured 2.7 um (5 % of the points missing). So the differences
  of neighbouring heights along x and along y are taken first (a hole, or the edge, makes a
  difference unmeasured), which damps the long wavelengths by :math:`4 \sin^2(\pi q \Delta)`,
  and each is windowed and transformed: the measured points' mean is removed, the holes are set
  to 0, and the differences are multiplied by a Tukey window (:data:`TAPER` of each side
  tapered) and the map of measured points, :math:`u = w\,m\,d`, with :math:`P(\mathbf q) =
  \Delta y \Delta x\,|\mathrm{DFT}(u)|^2 / \sum w^2 m`. The two are summed and divided by
  their summed transmission: :math:`C = (P_x + P_y) / (4 \sin^2(\pi q_x \Delta x) + 4
  \sin^2(\pi q_y \Delta y))` (0 at zero frequency). Prewhitening has its own leak, the other
  way: where the PSD is flat at the lowest frequencies (eq 18 below :math:`1/\lambda`), the
  differences hold little there, and the leak from higher frequencies, divided by the small
  transmission, raised the lowest rings (the simulations' Sal 5.8 um against the measured 4.4
  um). Both leaks only add power, so :func:`estimate` keeps, in each bin of the smoothed
  table, the lower of the plain and the prewhitened estimates where one is more than twice the
  other (:data:`LEAK_RATIO`), and their mean elsewhere: the lower of two noisy estimates of
  the same value is biased low (by 5 % of the variance on eq 18 surfaces, which the scaling to
  the measured variance then moved into the filters' pass band: the L-filtered simulations'
  Sq 2-3 % above the measured). The table is then scaled to the
  measured heights' variance (:func:`~roughgp.surface_models.fit.fit_psd_model`), and, where
  the measurement is filtered, ring by ring so that its variance through the S- and L-filters
  is that of the filtered heights too (:func:`scale_to_band`): a real surface holds most of its
  variance in its longest waves (on the fitted half of ``data/mnt-2-crop.x3p``, 256 x 128
  points, L 0.8 um, the filtered band holds 0.3 % of it), and a table a few per cent off there,
  scaled to the total alone, drew filtered heights of 2.3 times the measured variance.
* **Smooth and store** (:func:`log_polar_table`): each ordinate goes to a bin of
  :data:`N_RADII` logarithmic radial bins from the fundamental frequency (the lowest non-zero
  :math:`|\mathbf q|` of the grid) to the grid's corner frequency and :data:`N_ANGLES`
  angular bins of :math:`\arg \mathbf q` modulo 180 degrees (:math:`C(\mathbf q) = C(-\mathbf
  q)` for real heights); a bin's value is the mean of its ordinates, each first brought to the
  bin's centre along the spectrum's local slope (:func:`_local_slopes` says why): a Daniell
  smoother whose width grows with :math:`|\mathbf q|` (the raw periodogram has a relative
  error of 100 % per ordinate; a bin of :math:`n` ordinates has about :math:`1/\sqrt{n}`, and
  keeps the anisotropy in 5-degree steps). Where a bin holds fewer than :data:`MIN_ORDINATES`
  ordinates (the lowest rings: few grid frequencies lie there), its average takes in
  neighbouring rings first (up to three each way, each brought to the bin's centre along the
  slope) and then neighbouring angles until it holds that many: radial before angular,
  because the PSD changes slowly with log frequency there while the lay's direction is what
  Str and Std measure (angles first made the simulations' Str lower than the measured on 10
  of 30 synthetic maps in sample, radial first on 7). A bin with no ordinate takes the value
  interpolated along its ring (periodic in angle), or, for a ring with none, from the
  neighbouring rings.
  40 x 36 numbers in the file, whatever the map's size. A fit keeps besides, ordinate by
  ordinate, the lowest frequencies and the two frequency axes
  (:func:`low_frequency_core`, :mod:`roughgp.surface_models.psd_core` says why: the widened
  low rings are isotropic, and a lay along a scan axis is a line on an axis that a 5-degree
  bin spreads); its table is then made with each axis ordinate replaced by the mean of its
  neighbours across the axis.
* **Draw** (:func:`psd_at`, :func:`synthesize`): the table is interpolated bilinearly in
  (log frequency, angle) on the log of the PSD. The field is drawn by spectral synthesis on a
  torus of about twice the field's size along each axis (:func:`torus_shape`) and cropped, so
  the field is not periodic (the torus's covariance wraps only at lags beyond the field). The
  torus has frequencies below the measured band (wavelengths longer than the field): they are
  given the table's lowest ring (a flat PSD below the band, the roll-off of a stationary
  surface such as eq 18's); frequencies above the table's corner (a finer spacing than
  measured) get none, so the surface invents no roughness below the measured spacing. The
  torus's variance is :math:`\sum C\,\Delta q`, the table's variance plus that of the flat
  extension; the F-operator of the rest of the chain removes most of the extension again
  (:mod:`roughgp.checking.model_check` compares like with like).

The ACVF (:func:`acvf_grid`) is the inverse DFT of the same PSD on a torus, the covariance of
the synthesised field itself.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft
import scipy.signal.windows

from roughgp.metrology.filters import transmission
from roughgp.surface_models import psd_core

__all__ = ["N_RADII", "N_ANGLES", "TAPER", "MIN_ORDINATES", "LEAK_RATIO", "SLOPE_RANGE",
           "estimate", "low_frequency_core", "periodogram", "polar", "log_polar_table", "psd_at",
           "torus_shape", "MAX_TORUS_POINTS", "synthesize", "population_slices", "acvf_grid",
           "table_variance", "band_transmission", "scale_to_band"]

N_RADII = 40  #: logarithmic radial bins of the stored PSD
N_ANGLES = 36  #: angular bins of the stored PSD (5 degrees each, over 180)
MIN_ORDINATES = 8  #: ordinates a bin's value averages at least (4 independent: +-50 %)
LEAK_RATIO = 2.0  #: one estimate this many times the other: the higher one is taken to leak
TAPER = 0.25  #: share of each axis tapered by the Tukey window (half at each end)
_FLOOR = 1e-12  #: relative floor under the PSD before its log is interpolated


def _windowed_periodogram(h, spacing):
    """The Tukey-windowed periodogram of ``h`` (NaN where unmeasured, mean-filled), normalised
    by the window's weight over the measured points."""
    (ny, nx), (dy, dx) = h.shape, spacing
    measured = np.isfinite(h)
    window = (scipy.signal.windows.tukey(ny, TAPER)[:, None]
              * scipy.signal.windows.tukey(nx, TAPER)[None, :]) * measured
    weight = float(np.sum(window ** 2))
    if not weight > 0:
        raise ValueError("no measured point lies inside the PSD's window")
    mean = float(np.sum(window ** 2 * np.where(measured, h, 0.0)) / weight)
    u = window * np.where(measured, h - mean, 0.0)
    return dy * dx * np.abs(scipy.fft.fft2(u)) ** 2 / weight


def estimate(h, spacing):
    """``(table, f_min, f_max)``: the smoothed log-polar PSD of heights ``h`` (NaN where
    unmeasured): in each bin the mean of the plain and the prewhitened estimates, or the lower
    where one exceeds the other :data:`LEAK_RATIO` times (:func:`periodogram`,
    :func:`log_polar_table`; module docstring)."""
    qy, qx, p = periodogram(h, spacing, prewhiten=False)
    (a, f_min, f_max), (b, _, _) = (log_polar_table(qy, qx, p),
                                    log_polar_table(*periodogram(h, spacing)))
    return _combined(a, b), f_min, f_max


def _combined(a, b):
    """The mean of the plain and prewhitened estimates ``a``, ``b``, or the lower where one
    exceeds the other :data:`LEAK_RATIO` times."""
    return np.where(_leaks(a, b), np.minimum(a, b), 0.5 * (a + b))


def _leaks(a, b):
    """Where one estimate exceeds the other :data:`LEAK_RATIO` times."""
    return (a > LEAK_RATIO * b) | (b > LEAK_RATIO * a)


def low_frequency_core(h, spacing):
    """``(table, f_min, f_max, core)``: :func:`estimate`'s table made with the ordinates on
    the two frequency axes replaced by their neighbours across the axis (:func:`_off_axes`), and
    its :class:`~roughgp.surface_models.psd_core.PsdCore`: the
    periodogram over the table at the ordinates within the core's radius and along the two
    axes (each ordinate the mean of the plain and the prewhitened, or the lower estimate's
    where the table's bins took the lower, the prewhitened on an axis from the differences
    along it alone; :mod:`~roughgp.surface_models.psd_core` says why)."""
    qy, qx, p = periodogram(h, spacing, prewhiten=False)
    (p_x, gain_x), (p_y, gain_y) = along = _differenced(np.asarray(h, dtype=np.float64), spacing,
                                                        qy, qx)
    w = _whitened(*along)
    # on an axis the differences across it transmit nothing and only leak: each axis from
    # the differences along it (at qy = 0 those along x)
    with np.errstate(invalid="ignore", divide="ignore"):
        w[0, 1:], w[1:, 0] = p_x[0, 1:] / gain_x[0, 1:], p_y[1:, 0] / gain_y[1:, 0]
    (a, f_min, f_max), (b, _, _) = (log_polar_table(qy, qx, _off_axes(c)) for c in (p, w))
    table = _combined(a, b)
    ky, kx, radius, step = psd_core.core_indices(np.shape(h), spacing)

    def ratios(rows, cols):
        y, x = qy[rows], qx[cols]
        at_a, at_b = psd_at(a, f_min, f_max, y, x), psd_at(b, f_min, f_max, y, x)
        pw = p[np.ix_(rows, cols)], w[np.ix_(rows, cols)]
        ordinate = np.where(_leaks(at_a, at_b), np.where(at_a < at_b, *pw), 0.5 * (pw[0] + pw[1]))
        back = psd_at(table, f_min, f_max, y, x)
        with np.errstate(invalid="ignore", divide="ignore"):
            out = np.clip(np.where(back > 0, ordinate / back, 1.0), *psd_core.RATIO_RANGE)
        out[(y == 0)[:, None] & (x == 0)[None, :]] = 1.0
        return out
    (ny, nx), ay, ax = np.shape(h), *psd_core.axis_halves(np.shape(h))
    disc = ratios(np.arange(-ky, ky + 1) % ny, np.arange(-kx, kx + 1) % nx)
    along_x = ratios(np.array([0]), np.arange(-ax, ax + 1) % nx)[0]
    along_y = ratios(np.arange(-ay, ay + 1) % ny, np.array([0]))[:, 0]
    return table, f_min, f_max, psd_core.PsdCore(disc, step, radius, along_x, along_y)


def _off_axes(c):
    """The periodogram ``c`` (FFT order) with each ordinate on a frequency axis replaced by the
    mean of its two neighbours across the axis: what the table holds there is then the
    spectrum beside a line, and the line itself is the core's (:func:`low_frequency_core`)."""
    c = np.array(c, dtype=np.float64)
    c[0, :], c[:, 0] = 0.5 * (c[1, :] + c[-1, :]), 0.5 * (c[:, 1] + c[:, -1])
    return c


def periodogram(h, spacing, prewhiten=True):
    r"""``(qy, qx, C)``: the prewhitened, windowed 2-D periodogram of heights ``h`` (NaN where
    unmeasured) on the DFT's frequencies (1/um, FFT order) and its values (um^4; module
    docstring): the periodograms of the differences along x and along y, summed and divided
    by the differences' summed transmission :math:`4 \sin^2(\pi q_x \Delta x) + 4
    \sin^2(\pi q_y \Delta y)`; ``prewhiten=False``: the windowed periodogram of the heights
    themselves."""
    h = np.asarray(h, dtype=np.float64)
    (ny, nx), (dy, dx) = h.shape, spacing
    measured = np.isfinite(h)
    if measured.sum() < 16 or min(h.shape) < 4:
        raise ValueError(f"the PSD needs at least 16 measured points on a grid of at least "
                         f"4 x 4, got {measured.sum()} on {h.shape}")
    qy, qx = scipy.fft.fftfreq(ny, dy), scipy.fft.fftfreq(nx, dx)
    if not prewhiten:
        return qy, qx, _windowed_periodogram(h, spacing)
    return qy, qx, _whitened(*_differenced(h, spacing, qy, qx))


def _whitened(x, y):
    """The prewhitened periodogram from the differences' ``(P, G)`` along x and along y:
    :math:`(P_x + P_y) / (G_x + G_y)`, 0 where both transmit nothing."""
    gain = x[1] + y[1]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(gain > 0, (x[0] + y[0]) / gain, 0.0)


def _differenced(h, spacing, qy, qx):
    """``((P_x, G_x), (P_y, G_y))``: the windowed periodograms of the differences of ``h``
    along x and along y and their transmissions :math:`4 \\sin^2(\\pi q \\Delta)`."""
    along_x = np.pad(np.diff(h, axis=1), ((0, 0), (0, 1)), constant_values=np.nan)
    along_y = np.pad(np.diff(h, axis=0), ((0, 1), (0, 0)), constant_values=np.nan)
    (dy, dx), shape = spacing, np.shape(h)
    gain_x = np.broadcast_to(4 * np.sin(np.pi * qx * dx)[None, :] ** 2, shape)
    gain_y = np.broadcast_to(4 * np.sin(np.pi * qy * dy)[:, None] ** 2, shape)
    return ((_windowed_periodogram(along_x, spacing), gain_x),
            (_windowed_periodogram(along_y, spacing), gain_y))


def polar(qy, qx):
    """``(r, theta)`` on the grid of the frequency axes ``qy`` x ``qx``: the radius and the
    direction modulo 180 degrees (radians), the coordinates of the log-polar table."""
    qy, qx = np.meshgrid(qy, qx, indexing="ij")
    return np.hypot(qy, qx), np.mod(np.arctan2(qy, qx), math.pi)


def log_polar_table(qy, qx, c, n_radii=N_RADII, n_angles=N_ANGLES):
    """``(table, f_min, f_max)``: the periodogram ``c`` on ``(qy, qx)`` averaged in
    ``n_radii`` x ``n_angles`` log-polar bins from the fundamental ``f_min`` to the corner
    ``f_max`` (1/um; NaN ordinates left out), each ordinate first brought to its bin's centre
    along the spectrum's local slope (:func:`_local_slopes`); empty bins interpolated (module
    docstring)."""
    r, theta = polar(qy, qx)
    f_min, f_max = float(r[r > 0].min()), float(r.max())
    keep = (r > 0) & np.isfinite(c)   # an ordinate left out is NaN
    r, theta, c = r[keep], theta[keep], np.asarray(c)[keep]
    step = math.log(f_max / f_min) / n_radii
    position = (np.log(r) - math.log(f_min)) / step     # in bins; bin i spans [i, i + 1)
    ir = np.clip(position.astype(int), 0, n_radii - 1)
    ia = np.clip((theta / (math.pi / n_angles)).astype(int), 0, n_angles - 1)
    flat, size = ir * n_angles + ia, n_radii * n_angles

    def binned(values):
        return np.bincount(flat, weights=values, minlength=size).reshape(n_radii, -1)
    counts = np.bincount(flat, minlength=size).reshape(n_radii, -1)
    slope = _local_slopes(binned(c), binned(position), counts)
    offset = position - (ir + 0.5)                        # from the bin's centre, in bins
    (sums,), counts = _widen((binned(c * np.exp(-slope[ir, ia] * offset)),), counts, slope)
    with np.errstate(invalid="ignore", divide="ignore"):
        table = sums / counts
    return _fill_empty(table), f_min, f_max


#: the range of the local slopes (d log C / d bin) :func:`_local_slopes` keeps: -8 a bin is
#: a PSD falling as the frequency to the -71 at 40 bins over a 128-point grid's band
SLOPE_RANGE = (-8.0, 4.0)


def _local_slopes(sums, places, counts):
    """The PSD's slope, d log C per bin, at each bin (:data:`SLOPE_RANGE`): the plain window
    averages (``sums / counts``), each placed at its ordinates' mean position (``places /
    counts``, in bins), read off at the bins' centres (linear in log C between the two nearest,
    per angle, the end ones extended flat), and differenced along the radius.

    Why: a bin's ordinates crowd towards its outer edge (their number grows as the frequency
    squared) and a widened low bin reaches three rings out, so its plain average stands for a
    higher frequency than its centre; and where the PSD falls steeply an average over a wide
    window exceeds the value at its mean position (it is convex in log frequency). Read back
    at the centres, the plain averages lost 5-12 % of the power around an eq 18 spectrum's
    knee; each ordinate brought to its bin's centre along the local slope first (``c
    exp(-slope (position - centre))``), and each neighbouring ring in a widened window to the
    window's centre, the read-back is within 4 % there on a 128 x 128 grid for lengths of 2 and
    8 points (``tests/surface_models/test_psd_bands.py``)."""
    (sums, places), counts = _widen((sums, places), counts)
    n_radii, n_angles = sums.shape
    with np.errstate(invalid="ignore", divide="ignore"):
        values, places = sums / counts, places / counts
    centres = np.arange(n_radii) + 0.5
    at_centres = np.full(values.shape, np.nan)
    for j in range(n_angles):
        have = np.isfinite(values[:, j]) & (values[:, j] > 0)
        if have.sum() < 2:
            at_centres[have, j] = values[have, j]
            continue
        order = np.argsort(places[have, j], kind="stable")
        x, y = places[have, j][order], np.log(values[have, j][order])
        at_centres[have, j] = np.exp(np.interp(centres[have], x, y))
    log_table = np.log(np.maximum(_fill_empty(at_centres), _FLOOR * np.nanmax(at_centres)))
    return np.clip(np.gradient(log_table, axis=0), *SLOPE_RANGE)


#: the windows a bin's average may grow through, (radial, angular) half-widths in bins:
#: first along the radius (the PSD changes slowly with log frequency at the lowest rings, where
#: bins are few), then along the angle, keeping the anisotropy as long as possible
_WINDOWS = tuple((hr, 0) for hr in range(4)) + tuple((3, ha) for ha in range(1, N_ANGLES // 2 + 1))


def _windowed(values, hr, ha, slope=None):
    """``values`` summed over the window of half-widths ``(hr, ha)`` around each bin; with
    ``slope``, each ring ``m`` bins out weighted ``exp(-slope m)`` (brought to the centre)."""
    n_radii, n_angles = values.shape
    padded = np.pad(values, ((hr, hr), (0, 0)))
    rings = sum(padded[k:k + n_radii] * (1.0 if slope is None else np.exp(-slope * (k - hr)))
                for k in range(2 * hr + 1))
    if 2 * ha + 1 >= n_angles:
        return np.repeat(rings.sum(axis=1, keepdims=True), n_angles, axis=1)
    return sum(np.roll(rings, k, axis=1) for k in range(-ha, ha + 1))


def _widen(sums, counts, slope=None):
    """Each non-empty bin's sums (a tuple of arrays, each windowed as :func:`_windowed` with
    ``slope``) and count over the first window of :data:`_WINDOWS` that holds
    :data:`MIN_ORDINATES` ordinates (the last, three rings each way and the whole ring, where
    none does)."""
    out_s = tuple(np.full(counts.shape, np.nan) for _ in sums)
    out_c = np.zeros(counts.shape)
    todo = counts > 0
    for hr, ha in _WINDOWS:
        c = _windowed(counts.astype(float), hr, ha)
        take = todo & ((c >= MIN_ORDINATES) | ((hr, ha) == _WINDOWS[-1]))
        for out, values in zip(out_s, sums):
            out[take] = _windowed(values, hr, ha, slope)[take]
        out_c[take] = c[take]
        todo &= ~take
        if not todo.any():
            break
    return out_s, out_c


def _fill_empty(table):
    """Empty bins (NaN) from their ring (periodic in angle), then rings from their
    neighbours."""
    table = table.copy()
    n_radii, n_angles = table.shape
    angles = np.arange(n_angles)
    full = np.zeros(n_radii, dtype=bool)
    for i, ring in enumerate(table):
        have = np.isfinite(ring)
        if have.any():
            table[i] = np.interp(angles, angles[have], ring[have], period=n_angles)
            full[i] = True
    radii = np.arange(n_radii)
    for j in range(n_angles):
        table[~full, j] = np.interp(radii[~full], radii[full], table[full, j])
    return table


def psd_at(table, f_min, f_max, qy, qx, core=None):
    """The stored PSD at the frequencies ``qy`` x ``qx`` (1-D axes, 1/um): bilinear in (log
    frequency, angle) on the log PSD; the lowest ring below the band, 0 above ``f_max`` and
    at zero frequency (module docstring); times the ``core``'s factor where one is given
    (:func:`roughgp.surface_models.psd_core.factor`)."""
    table = np.asarray(table, dtype=np.float64)
    n_radii, n_angles = table.shape
    log_table = np.log(np.maximum(table, _FLOOR * table.max()))
    r, theta = polar(qy, qx)
    step = math.log(f_max / f_min) / n_radii
    with np.errstate(divide="ignore"):
        u = np.clip((np.log(r) - math.log(f_min)) / step - 0.5, 0.0, n_radii - 1.0)
    v = theta / (math.pi / n_angles) - 0.5
    i0 = np.minimum(np.floor(u).astype(int), n_radii - 2) if n_radii > 1 else \
        np.zeros(u.shape, int)
    a = u - i0
    j0 = np.floor(v).astype(int)
    b = v - j0
    j0, j1 = np.mod(j0, n_angles), np.mod(j0 + 1, n_angles)
    i1 = np.minimum(i0 + 1, n_radii - 1)
    value = ((1 - a) * ((1 - b) * log_table[i0, j0] + b * log_table[i0, j1])
             + a * ((1 - b) * log_table[i1, j0] + b * log_table[i1, j1]))
    out = np.exp(value)
    if core is not None:
        out *= psd_core.factor(core, qy, qx)
    out[(r == 0) | (r > f_max * (1 + 1e-9))] = 0.0
    return out


#: the most points of the torus a field is drawn on
MAX_TORUS_POINTS = 1 << 26


def torus_shape(shape, spacing, f_min):
    """The torus a field of ``shape`` at ``spacing`` is drawn on: each side at least twice the
    field's and twice the longest measured wavelength ``1 / f_min`` (so that a small field
    still has the measured band's variance), FFT-friendly; a ``ValueError`` beyond
    :data:`MAX_TORUS_POINTS`."""
    torus = tuple(int(scipy.fft.next_fast_len(max(2 * n, math.ceil(2.0 / (f_min * d))),
                                              real=True)) for n, d in zip(shape, spacing))
    if math.prod(torus) > MAX_TORUS_POINTS:
        raise ValueError(f"drawing {shape[0]} x {shape[1]} points at a spacing of {spacing[0]:g} x "
                         f"{spacing[1]:g} um from this PSD needs a torus of {torus[0]} x "
                         f"{torus[1]} points, more than {MAX_TORUS_POINTS} (2**26): draw a "
                         f"smaller field or at a coarser spacing")
    return torus


def _amplitude(table, f_min, f_max, torus, spacing, core=None):
    (my, mx), (dy, dx) = torus, spacing
    c = psd_at(table, f_min, f_max, scipy.fft.fftfreq(my, dy), scipy.fft.rfftfreq(mx, dx), core)
    return np.sqrt(c / (dy * dx))


def synthesize(table, f_min, f_max, shape, spacing, rng, n_samples=1, transform=None,
               core=None):
    """``n_samples`` fields of ``shape`` drawn from the PSD table by spectral synthesis on a
    torus (:func:`torus_shape`), cropped: Gaussian, mean 0, the torus's variance
    :math:`\\sum C \\Delta q` (module docstring); ``transform``, when given, is applied to
    each torus field before the crop; ``core``: the ordinates kept of the lowest frequencies
    and the axes (:mod:`~roughgp.surface_models.psd_core`). Returns ``(n_samples, ny, nx)``."""
    torus = torus_shape(shape, spacing, f_min)
    amplitude = _amplitude(table, f_min, f_max, torus, spacing, core)
    out = np.empty((n_samples, *shape))
    for k in range(n_samples):
        white = rng.standard_normal(torus)
        field = scipy.fft.irfft2(scipy.fft.rfft2(white) * amplitude, s=torus)
        if transform is not None:  # on a population of twice the field's points
            field = transform(field[population_slices(shape)])
        out[k] = field[:shape[0], :shape[1]]
    return out


def population_slices(shape):
    r"""The region a rank remap is made on before the field of ``shape`` is cropped from it:
    :math:`\lceil\sqrt 2\,n\rceil` points along each side, twice the field's points
    (:mod:`roughgp.surface_models.iaaft`)."""
    return tuple(slice(0, math.ceil(math.sqrt(2.0) * n)) for n in shape)


def acvf_grid(table, f_min, f_max, shape, spacing, core=None):
    """The ACVF of the synthesised field at the lags of a grid: ``acvf[jy, jx]`` for lags
    ``(jy dy, jx dx)`` (FFT order, negative lags wrapped) on the torus of a field of
    ``shape`` (:func:`torus_shape`), um^2: the inverse DFT of the PSD (``core`` as in
    :func:`psd_at`)."""
    torus = torus_shape(shape, spacing, f_min)
    amplitude = _amplitude(table, f_min, f_max, torus, spacing, core)
    return scipy.fft.irfft2(amplitude ** 2, s=torus)


def table_variance(table, f_min, f_max, spacing, shape, s_um=None, l_um=None, core=None):
    """The variance of the table over the measured band on the DFT grid of a field of
    ``shape``: :math:`\\sum C \\Delta q` over the frequencies from ``f_min`` on (um^2); with
    ``s_um`` or ``l_um``, what the Gaussian S- and L-filters pass of it,
    :math:`\\sum C H \\Delta q` (:func:`band_transmission`); ``core`` as in :func:`psd_at`."""
    (ny, nx), (dy, dx) = shape, spacing
    qy, qx = scipy.fft.fftfreq(ny, dy), scipy.fft.fftfreq(nx, dx)
    c = psd_at(table, f_min, f_max, qy, qx, core)
    if s_um is not None or l_um is not None:
        c = c * band_transmission(polar(qy, qx)[0], s_um, l_um)
    return float(c.sum() / (ny * dy * nx * dx))


def band_transmission(q, s_um=None, l_um=None):
    """The power transmission at frequencies ``q`` (1/um) of the Gaussian S-filter (low pass)
    and L-filter (high pass) of nesting indices ``s_um`` and ``l_um`` (either None: not
    applied; ISO 16610-61's weighting, :func:`roughgp.metrology.filters.transmission`)."""
    q = np.asarray(q, dtype=np.float64)
    out = np.ones(q.shape)
    with np.errstate(divide="ignore"):
        wavelength = np.where(q > 0, 1.0 / np.where(q > 0, q, 1.0), np.inf)
    if l_um is not None:
        out *= (1.0 - transmission(wavelength, l_um)) ** 2
    if s_um is not None:
        out *= transmission(wavelength, s_um) ** 2
    return out


def scale_to_band(table, f_min, f_max, spacing, shape, variance, band_variance, s_um=None,
                  l_um=None, rounds=2, core=None):
    r"""The table scaled ring by ring, :math:`C'(\mathbf q) = C(\mathbf q)\,(a H(q) + b (1 -
    H(q)))` with :math:`H` the filters' power transmission (:func:`band_transmission`), so
    that on the DFT grid of a field of ``shape`` its variance is ``variance`` and its variance
    through the filters ``band_variance`` (um^2). A real surface holds most of its variance at
    the longest wavelengths: scaled to the total alone, a table whose long waves are a few per
    cent off moves the filtered band by far more (module docstring). Where no positive
    :math:`a, b` solve both, the table is scaled to the band's variance alone. ``core`` as in
    :func:`psd_at` (its ratios scale with the table)."""
    (ny, nx), (dy, dx) = shape, spacing
    qy, qx = scipy.fft.fftfreq(ny, dy), scipy.fft.fftfreq(nx, dx)
    r, _ = polar(qy, qx)
    h = band_transmission(r, s_um, l_um)
    n_radii = table.shape[0]
    centres = f_min * np.exp((np.arange(n_radii) + 0.5) * math.log(f_max / f_min) / n_radii)
    h_rings = band_transmission(centres, s_um, l_um)[:, None]
    table = np.asarray(table, dtype=np.float64)
    for _ in range(rounds):
        c = psd_at(table, f_min, f_max, qy, qx, core) / (ny * dy * nx * dx)
        system = np.array([[np.sum(c * h * h), np.sum(c * h * (1 - h))],
                           [np.sum(c * h), np.sum(c * (1 - h))]])
        try:
            a, b = np.linalg.solve(system, [band_variance, variance])
        except np.linalg.LinAlgError:
            a = b = -1.0
        if not (a > 0 and b > 0 and math.isfinite(a) and math.isfinite(b)):
            a = b = band_variance / float(np.sum(c * h))
        table = table * (a * h_rings + b * (1 - h_rings))
    return table
