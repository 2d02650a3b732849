r"""An exact height distribution in the IAAFT manner (Schreiber & Schmitz, Phys. Rev. Lett. 77,
635 (1996); beyond the paper).

A Gaussian surface model reproduces a covariance (eq 18, its Matérn variant, or the measured
PSD) and the Gaussian heights of eq 8. A measured surface's heights are often skewed or
heavy-tailed. The Johnson marginal (:mod:`roughgp.non_gaussian`) matches their first
four moments; the IAAFT marginal matches their whole distribution: the model file keeps the
measured heights' quantile function, :data:`N_QUANTILES` quantiles (um) at probabilities
:math:`p_i = \Phi(t_i)` with normal scores :math:`t_i` equally spaced from
:math:`\Phi^{-1}(p_0)` to :math:`\Phi^{-1}(1 - p_0)`, :math:`p_0 = 1/(2n)` for :math:`n`
measured heights (``tail_probability``): the Hazen plotting position of the lowest of them, so
the first and last quantiles are the measured extremes (:func:`quantile_table`). Equal steps in
the normal score put the quantiles densely in the tails, where the extremes and the
kurtosis are decided: 1001 quantiles equally spaced in probability left the top 0.1 % of a
lognormal surface's heights to a straight line up to its maximum, which raised its skewness
from 3.8 to 4.2 in the simulations. A simulation is made as follows (:func:`iaaft`):

1. draw the Gaussian field of the model (its covariance, its noise);
2. keep the amplitudes of its DFT, :math:`A = |\mathrm{DFT}(x_0)|`, scaled to the target
   distribution's variance (the model's spectral shape, the distribution's power; at zero
   frequency the target distribution's sum, its mean);
3. *rank remap*: replace the field's values, in their rank order, by a sample of the target
   distribution made once per simulation from the draw of step 1: its normal scores through
   the quantile function (below), interpolated linearly in the normal score between the
   stored quantiles, and beyond the measured extremes continued straight with the slope of
   the table's outermost unit of normal score. The stored quantiles are keyed at the normal
   scores where the model's own correlated surfaces hold those ranks (the marginal's
   ``order_scores``, :mod:`roughgp.surface_models.order_scores`), not at the Hazen positions
   of independent points: keyed there, the measured extremes and Sq lay above most
   simulations';
4. *spectrum*: replace the DFT amplitudes of the result by :math:`A`, keeping its phases;
5. repeat 3-4 until the rank order no longer changes between two remaps (the stated stopping
   rule) or after ``iterations`` rounds (:data:`ITERATIONS` by default), and end on a remap.
   The DFT amplitudes' relative L2 distance from the target, measured on a 256 x 256 eq 18
   field remapped to a lognormal distribution, falls with the rounds: 0.25 after 1, 0.13
   after 5, 0.089 after 10, 0.053 after 20, 0.023 after 50 (0.36 s for 20 rounds on this
   machine). Heavier tails converge more slowly: on three 128 x 128 lognormal targets, 0.13
   to 0.24 after 20 rounds, 0.04 to 0.15 after 200. 10 is the default, a compromise with the
   check's time: its 19 simulations of a 512 x 512 map remap 19 fields of 524k points, and 20
   rounds made the check 85 s (on the shared 2-core machine).

The remap is done on a field of twice the points asked for (:math:`\sqrt 2` times each side,
:func:`~roughgp.surface_models.psd_table.population_slices`; for the measured-psd model, a
corner of its torus) and the field is cropped from it: the measured
heights are one sample of their distribution, and a simulation must be another, with its own
sampling spread. A remap on the field itself gave every simulation the measured Sq, Sku, Sp,
... to the last digit but for the F-operator's refit, so the check
(:mod:`roughgp.checking.model_check`) put the measurement outside by hairs (Sq 1.985 against
1.962 to 1.985 on a lognormal eq 18 surface).

**With an L-filter** the texture parameters that :mod:`roughgp.checking.model_check` compares
are those of the filtered heights, and a surface's spikes and pits sit in the band the filter
passes: the distribution of the form-removed heights, dominated by the long waves, does not
carry them (``data/sample-land.x3p``, 256 x 256, cylinder, L 80 um: the filtered heights'
kurtosis is 43; the simulations of a measured-psd model with the IAAFT marginal of the
form-removed heights had 4.3 to 10). So the marginal then stores the quantiles of the
*filtered* measured heights (``above_l_um``: the cut-off), and the remap is applied to the
draw's band above the cut-off alone (:func:`iaaft_above`: the draw minus its Gaussian-filtered
long waves), the long waves added back unchanged. The Gaussian filter is no sharp cut: what it
passes of the sum is the remapped band, less the remapped band's own long waves, plus the
Gaussian draw's waves near the cut-off; that mix is nearer a Gaussian than the target. The
measured-psd model with this marginal, fitted on the left half of ``data/matrix-3.txt`` and
checked there, drew filtered heights of Sa / Sq 0.723 to 0.739 against the measured 0.7185
and kurtosis 4.7 to 5.6 against 5.69, so Sa, Sk and Sku fell outside in sample. So the
band is remapped again (:func:`band_rounds`): what the filter passes of the sum is rank-remapped
to the same values and the difference added, until that correction is at most
:data:`BAND_TOLERANCE` of the band (rms), shrinks by less than a tenth a round, or after
:data:`BAND_ROUNDS` rounds. The correction falls round by round (0.024, 0.006 on matrix-3;
0.14, 0.06, 0.04, 0.02, 0.016, 0.011, 0.009 on ``data/sur-2.sur``), and the in-sample check of
that model on five maps of ``data/`` (two seeds each) left fewer parameters outside:
matrix-3 2 and 3 before, 0 and 0 after; sur-2 2 and 3, 0 and 1; sample-land 3 and 3, 2 and 1;
nms-1 7 and 8, 3 and 4; al3d-1 1 and 2, 0 and 0. It costs a Gaussian filter and a sort a round
(0.17 s a 256 x 256 simulation before, 0.29 s with 3 rounds).

**Each simulation's sample carries the spread of a correlated surface.** Step 3's sample is
not drawn point by point: it is the Gaussian draw itself through the target's quantile
function, :math:`Q(\Phi(x / s))` at each point (:func:`remap_sd` gives :math:`s`, the draw's
standard deviation over realisations: the model's ACVF at lag 0 plus its noise, or, with an
L-filter, what the filter passes of its spectrum). A sample drawn point by point varies from
simulation to simulation as if the field's points were independent; a correlated surface's
Sq, skewness and kurtosis vary far more (a field holds only so many correlation areas). On a
128 x 128 Gaussian eq 18 map the standard deviations of the simulations' log Sq, skewness and
kurtosis were 0.76, 0.59 and 0.47 times those of the same model's Gaussian draws with the
sample drawn point by point (only the crop from a field of twice the points gave it any
spread), and are 0.94, 0.80 and 0.84 times with the draw's own scores (``test_iaaft.py``).
What it does not do is make the measured heights a model of the whole surface: they are the
fitted crop's sample, and another crop's sample lies as far again from it
(``benchmarks/iaaft_held_out.py``; the chapter "Which model reproduces which measurement").

The population has exactly the target distribution (step 3 is last) and a DFT amplitude
spectrum close to the Gaussian draw's (step 4 is exact before the last remap; the tests
measure how close). Everything random is in step 1's draw (step 3's sample is made of it),
drawn from the model's seeded generator: the same seed gives the same surface. A fixed set of
values (the plotting positions) gave every simulation the same population extremes: half of
them had the very same maximum. The DFT treats the field as periodic; its amplitudes include
the draw's edges, and the iterations keep them.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft
import scipy.ndimage
import scipy.special

from roughgp.metrology.filters import ALPHA

__all__ = ["N_QUANTILES", "ITERATIONS", "BAND_ROUNDS", "BAND_TOLERANCE", "quantile_table",
           "quantile_values", "values_at_scores", "marginal_values", "hazen_scores", "iaaft",
           "iaaft_above", "band_rounds", "remap_sd"]

N_QUANTILES = 1001  #: quantiles stored: probabilities 0, 0.001, ..., 1 (the extremes included)
ITERATIONS = 10  #: the most rounds of remap and spectrum (fewer when the ranks settle)
BAND_ROUNDS = 10  #: with an L-filter: the most rounds of the band's remap (:func:`band_rounds`)
BAND_TOLERANCE = 0.01  #: ... until the correction is at most this share of the band (rms)


def hazen_scores(tail_probability, n_quantiles) -> np.ndarray:
    """The ``n_quantiles`` normal scores, equally spaced, from the Hazen position of the lowest
    of the measured heights, ``tail_probability``, to that of the highest."""
    t0 = float(scipy.special.ndtri(tail_probability))
    return np.linspace(t0, -t0, n_quantiles)


def quantile_table(heights, n_quantiles=N_QUANTILES) -> tuple:
    """``(quantiles, tail_probability)``: the quantiles (um) of the finite ``heights`` at equal
    steps of the normal score between the plotting positions of the lowest and the highest
    (module docstring): the first and last are the measured extremes."""
    h = np.asarray(heights, dtype=np.float64)
    h = h[np.isfinite(h)]
    if h.size < 16:
        raise ValueError(f"the IAAFT marginal needs at least 16 measured heights, got {h.size}")
    if not np.ptp(h) > 0:
        raise ValueError("the heights are all equal: no height distribution to match")
    tail = 0.5 / h.size
    p = scipy.special.ndtr(hazen_scores(tail, n_quantiles))
    q = np.quantile(h, np.clip(p, tail, 1.0 - tail), method="hazen")
    q[0], q[-1] = h.min(), h.max()
    return np.maximum.accumulate(q).tolist(), tail


def _probabilities(n, rng):
    if rng is None:
        return (np.arange(n) + 0.5) / n
    return np.sort(rng.uniform(0.0, 1.0, n))


def quantile_values(quantiles, tail_probability, n, rng=None):
    """``n`` values of the distribution whose quantile function is tabulated in ``quantiles``
    (:func:`quantile_table`), ascending: at the plotting positions ``(r + 1/2) / n``, or, with
    a generator ``rng``, at ``n`` sorted uniform random probabilities (a random sample)."""
    return values_at_scores(quantiles, tail_probability,
                            scipy.special.ndtri(_probabilities(n, rng)))


def values_at_scores(quantiles, tail_probability, t, keys=None):
    """The heights at the normal scores ``t`` of the distribution tabulated in ``quantiles``
    (:func:`quantile_table`): interpolated in the table, and beyond the measured extremes
    straight on in the normal score with the slope of the table's outermost unit. ``keys``:
    the increasing normal scores the quantiles sit at
    (an IAAFT marginal's ``order_scores``, :mod:`roughgp.surface_models.order_scores`);
    default the Hazen positions of ``tail_probability``."""
    q = np.asarray(quantiles, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    scores = hazen_scores(tail_probability, q.size) if keys is None else \
        np.asarray(keys, dtype=np.float64)
    values = np.interp(t, scores, q)
    # beyond the measured extremes (more points than measured): straight on in the normal score
    # with the slope of the outermost normal-score unit of the table
    k = min(int(np.searchsorted(scores, scores[0] + 1.0)), q.size - 1)
    low_slope = (q[k] - q[0]) / (scores[k] - scores[0])
    high_slope = (q[-1] - q[-1 - k]) / (scores[-1] - scores[-1 - k])
    values = np.where(t < scores[0], q[0] + low_slope * (t - scores[0]), values)
    return np.where(t > scores[-1], q[-1] + high_slope * (t - scores[-1]), values)


def _remap(x, values):
    order = np.argsort(x, axis=None)  # quicksort: 0.045 s for 524k points, stable 0.073 s
    out = np.empty(x.size)
    out[order] = values
    return out.reshape(x.shape), order


def marginal_values(marginal, t):
    """The heights at the normal scores ``t`` of an IAAFT ``marginal`` (a model's
    ``marginal`` field): :func:`values_at_scores` of its quantiles, keyed at its
    ``order_scores`` where it has them (a file written before 2026-12-07 has none)."""
    return values_at_scores(marginal["quantiles_um"], marginal["tail_probability"], t,
                            marginal.get("order_scores"))


def iaaft(field, values, iterations=ITERATIONS):
    """``(surface, rounds)``: the Gaussian ``field`` (a surface or a profile) given the
    distribution ``values`` (``field.size`` values, ascending: the model's sample,
    :meth:`~roughgp.surface_models.model.FittedModel.simulate`, or :func:`quantile_values`)
    and the DFT amplitudes of ``field`` (module docstring);
    ``rounds``: the rounds run."""
    field = np.asarray(field, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    if values.shape != (field.size,):
        raise ValueError(f"values must hold one value per point ({field.size}), got "
                         f"{values.shape}")
    scale = math.sqrt(np.var(values) / max(np.var(field), np.finfo(float).tiny))
    amplitude = np.abs(scipy.fft.rfftn(field)) * scale
    amplitude[(0,) * field.ndim] = abs(values.sum())  # the mean is the distribution's
    x, order = _remap(field, values)
    rounds = 0
    for rounds in range(1, int(iterations) + 1):
        spectrum = scipy.fft.rfftn(x)
        spectrum *= amplitude / np.maximum(np.abs(spectrum), np.finfo(float).tiny)
        x, new_order = _remap(scipy.fft.irfftn(spectrum, s=field.shape), values)
        if np.array_equal(new_order, order):
            break
        order = new_order
    return x, rounds


#: the ISO 16610-21 Gaussian weighting function's constant, sqrt(ln 2 / pi)
def _filter_sigma(l_um) -> float:
    """The standard deviation (um) of the Gaussian L-filter of cut-off ``l_um`` (ISO 16610-21:
    its weighting function is :math:`\\exp(-\\pi (x / (\\alpha \\lambda_c))^2)`,
    :data:`~roughgp.metrology.filters.ALPHA`)."""
    return ALPHA * l_um / math.sqrt(2.0 * math.pi)


def iaaft_above(field, remap, l_um, spacing, rounds=BAND_ROUNDS):
    """``field`` split by the Gaussian L-filter of cut-off ``l_um`` (ISO 16610-21, the edges
    reflected: the population is a crop, not a torus; a periodic filter there put steps at its
    edges and 8 of 13 parameters of data/sample-land.x3p outside, 3 without) into the long
    waves it takes out and the rest; the rest given the target distribution by ``remap``
    (:func:`iaaft`), the long waves added back; then up to ``rounds`` - 1 rank remaps of what
    the filter passes of the sum (:func:`band_rounds`, module docstring)."""
    sigma = _filter_sigma(l_um)
    sigmas = [sigma / d for d in np.broadcast_to(spacing, (field.ndim,))]
    low = scipy.ndimage.gaussian_filter(field, sigmas, mode="reflect")
    band = remap(field - low)
    return band_rounds(low + band, np.sort(band, axis=None), sigmas, rounds)[0]


def band_rounds(surface, values, sigmas, rounds=BAND_ROUNDS, tolerance=BAND_TOLERANCE):
    """``(surface, residuals)``: ``surface`` corrected until what the Gaussian filter of
    ``sigmas`` (points) passes of it has the distribution ``values`` (ascending, one per point):
    each round adds the rank remap of that band minus the band. ``residuals``: each round's
    correction, rms, over the band's rms. It stops after ``rounds`` - 1 rounds, when the
    correction is at most ``tolerance`` or when it shrank by less than a tenth since the round
    before (module docstring)."""
    residuals = []
    for _ in range(int(rounds) - 1):
        band = surface - scipy.ndimage.gaussian_filter(surface, sigmas, mode="reflect")
        correction = _remap(band, values)[0] - band
        residuals.append(math.sqrt(np.mean(correction ** 2)
                                   / max(np.mean(band ** 2), np.finfo(float).tiny)))
        surface = surface + correction
        if residuals[-1] <= tolerance or (len(residuals) > 1
                                          and residuals[-1] > 0.9 * residuals[-2]):
            break
    return surface, residuals


def remap_sd(acvf, noise_variance, shape, spacing, l_um=None) -> float:
    """The standard deviation over realisations of what the remap acts on (module docstring):
    a field of ``shape`` at ``spacing`` of the Gaussian model whose latent ACVF is ``acvf`` (a
    roughgp kernel or a function of lags ``(..., D)``, um) plus white noise of
    ``noise_variance`` (um^2); with ``l_um``, what the Gaussian L-filter of that cut-off
    passes of it (:func:`iaaft_above`), from the ACVF's spectrum on the ``2 n - 1`` lags of
    each axis (the negative ordinates of a covariance the torus cannot embed set to 0)."""
    from roughgp.common.grid import centred_lags
    from roughgp.sampling.grid_sampler import acvf_of
    spacing = tuple(float(d) for d in np.broadcast_to(spacing, (len(shape),)))
    if l_um is None:
        zero = np.zeros((1, len(shape)))
        return math.sqrt(float(acvf_of(acvf)(zero)[0]) + noise_variance)
    table = np.asarray(acvf_of(acvf)(centred_lags(tuple(2 * n - 1 for n in shape), spacing)),
                       dtype=np.float64)
    spectrum = np.clip(scipy.fft.fftn(scipy.fft.ifftshift(table)).real, 0.0, None)
    gain = np.ones(table.shape)   # the mean line's transmission, exp(-pi (alpha l f)^2)
    for axis, (n, d) in enumerate(zip(table.shape, spacing)):
        along = np.exp(-math.pi * (ALPHA * l_um * scipy.fft.fftfreq(n, d)) ** 2)
        gain = gain * along.reshape([-1 if k == axis else 1 for k in range(len(shape))])
    passed = (1.0 - gain) ** 2
    return math.sqrt(float(np.mean(spectrum * passed)) + noise_variance * float(np.mean(passed)))
