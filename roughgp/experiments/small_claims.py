r"""Three small computations shared by a chapter and the ledger: eq 5, long correlation, eq 8.

* :func:`kernel_duality_table` -- the Wiener-Khinchin theorem (eq 5) on a grid for the book's
  profile ACVFs (exponential and Matérn kernels, the spectral mixture of eq 21) and for
  figure 1's rotated exponential (eq 18): FFT(ACVF) against the closed-form PSD, IFFT(PSD)
  against the ACVF, and the lag-0 deficit against the PSD mass beyond Nyquist
  (chapter ``notation``, check ``eq5-duality``).
* :func:`long_correlation` -- the conclusion's claim that long correlation lengths are "not
  possible with ARMA processes or other digital filter methods" (section 2.3, eq 12-14, 21):
  a sustained periodic ACVF against Yule-Walker AR(p) fits, a Matérn-3/2 kernel for contrast,
  the exponential ACVF of lambda = 500 as an exact AR(1), and the grid-size FFT filter, which
  wraps it (chapter ``arma``, check ``conclusion-long-correlation``).
* :func:`non_gaussian_acvf` -- the conclusion's non-Gaussian surfaces: Johnson-transformed,
  pre-distorted GPs (eq 8, 9; :mod:`roughgp.non_gaussian`), their mean empirical ACVF
  with and without pre-distortion against the target, and their Ssk and Sku (ISO 25178-2)
  against the targets (chapter ``non_gaussian``, check ``conclusion-non-gaussian``).

Each returns a dataclass; the chapter draws and states its numbers from it, the check judges it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from roughgp import non_gaussian, sampling
from roughgp.common.settings import resolve_full
from roughgp.gp import acvf, fourier, kernels
from roughgp.metrology import spectral, texture_heights
from roughgp.models import arma

__all__ = ["DualityTable", "kernel_duality_table", "LongCorrelation", "long_correlation",
           "NonGaussianAcvf", "MomentSummary", "non_gaussian_acvf", "plateau_kernel"]

#: the smooth ACVFs of the table, whose PSD has no mass to speak of beyond Nyquist
SMOOTH = ("Matérn 5/2", "squared exponential", "spectral mixture, Q = 2 (eq 21)")


# ------------------------------------------------------------------ eq 5

@dataclass
class DualityTable:
    """Eq 5 on a grid: ``errors[name]`` and ``errors_fig1`` are the dicts of
    :func:`roughgp.gp.fourier.duality_errors` (forward, inverse, lag0_deficit)."""

    kernels: dict                # name -> profile kernel (1-D)
    errors: dict                 # name -> {"forward", "inverse", "lag0_deficit"}
    fig1: object                 # figure 1's RotatedExponentialKernel
    errors_fig1: dict
    spacing_1d: float
    n_1d: int
    spacing_2d: float
    n_2d: int
    forward: float               # worst forward error over all ACVFs (1-D and figure 1)
    inverse: float               # worst inverse error over the smooth ACVFs (SMOOTH)
    predicted_deficit: float     # exponential: PSD mass beyond Nyquist, closed form
    fig1_deficit_bounds: tuple   # (lower, upper): mass outside |f| = sqrt(2) f_N and f_N


def profile_kernels():
    """The book's profile ACVFs (eq 18 in 1-D, Matérn, eq 21), named as in the chapter."""
    return {
        "exponential (Matérn 1/2)": kernels.MaternKernel(nu=0.5, lengthscale=1.0),
        "Matérn 3/2": kernels.MaternKernel(nu=1.5, lengthscale=1.0),
        "Matérn 5/2": kernels.MaternKernel(nu=2.5, lengthscale=1.0),
        "squared exponential": kernels.MaternKernel(nu=math.inf, lengthscale=1.0),
        "spectral mixture, Q = 2 (eq 21)": kernels.SpectralMixtureKernel(
            2, dim=1, weights=[0.6, 0.4], means=[[0.5], [2.0]], variances=[[0.04], [0.01]]),
    }


def _fig1_deficit_bounds(fig1_lengthscales, spacing):
    """Mass of figure 1's PSD outside the discs |f| = sqrt(2) f_N (lower) and f_N (upper)."""
    nyquist = 1 / (2 * spacing)
    la, lb = fig1_lengthscales
    upper = 1 / math.sqrt(1 + (2 * math.pi * lb * nyquist) ** 2)
    lower = 1 / math.sqrt(1 + (2 * math.pi * la * math.sqrt(2) * nyquist) ** 2)
    return lower, upper


def kernel_duality_table(full=None, *, spacing_1d=0.01, n_1d=2 ** 14 + 1, spacing_2d=0.01,
                         band=5.0, fig1=None):
    """Eq 5 for every profile ACVF of :func:`profile_kernels` on ``n_1d`` lags and for figure
    1's ACVF (eq 18, phi = 30 deg, lambda = (0.5, 0.1)) on a 1025² grid (2049² with ``full``;
    ``None``: ``ROUGHGP_FULL``). Forward errors over ``|f| <= band``."""
    fig1 = fig1 or dict(variance=1.0, lengthscales=(0.5, 0.1), angle=math.pi / 6)
    n_2d = 2049 if resolve_full(full) else 1025
    profile = profile_kernels()
    errors = {name: fourier.duality_errors(k.acvf, k.psd, n_1d, spacing_1d, band=band)
              for name, k in profile.items()}
    fig1_kernel = kernels.RotatedExponentialKernel(**fig1)
    errors_fig1 = fourier.duality_errors(fig1_kernel.acvf, fig1_kernel.psd, (n_2d, n_2d),
                                         spacing_2d, band=band)
    forward = max([e["forward"] for e in errors.values()] + [errors_fig1["forward"]])
    predicted = 1 - 2 / math.pi * math.atan(2 * math.pi * 1.0 / (2 * spacing_1d))
    return DualityTable(profile, errors, fig1_kernel, errors_fig1, spacing_1d, n_1d, spacing_2d,
                        n_2d, forward, max(errors[name]["inverse"] for name in SMOOTH), predicted,
                        _fig1_deficit_bounds(fig1["lengthscales"], spacing_2d))


# ------------------------------------------------------------------ long correlation

@dataclass
class LongCorrelation:
    """AR(p) against a periodic and a Matérn-3/2 ACVF; AR(1) and the FFT filter against the
    exponential ACVF of a long lengthscale."""

    lag_axis: np.ndarray         # (n_lags + 1, 1), grid units
    r_periodic: np.ndarray       # eq 21 component + short exponential + nugget
    r_matern: np.ndarray
    orders: tuple
    fit_error: dict              # "periodic"/"Matern-3/2" -> max |AR(p) ACVF - r| / r(0) per order
    fits: dict                   # (name, p) -> the AR(p)'s ACVF on lag_axis
    yule_walker_gap: float       # worst |AR(p) ACVF - r| / r(0) over lags 0..p (exact in theory)
    lengthscale: float           # the exponential ACVF's lambda
    exp_lags: np.ndarray         # 0 .. n_grid - 1
    ar1_gap: float               # max |AR(1) ACVF - exp(-lag/lambda)|
    filter_acvf: np.ndarray      # the grid-size FFT filter's ACVF (periodised)
    wrap_lag: int
    filter_at_wrap: float
    true_at_wrap: float
    circulant_clipped: float     # circulant embedding's clipped share (0: exact)


def periodic_acvf(lag_axis):
    """Feed marks: one narrow eq 21 component (f = 0.05), exponential of lambda = 3 and
    variance 0.3, nugget 0.05 at lag 0."""
    periodic = kernels.SpectralMixtureKernel(1, dim=1, weights=[1.0], means=[[0.05]],
                                             variances=[[1e-6]])
    short_range = kernels.MaternKernel(nu=0.5, variance=0.3, lengthscale=3.0)
    r = periodic.acvf(lag_axis) + short_range.acvf(lag_axis)
    r[0] += 0.05
    return r


def _ar_fits(r, orders, n_lags):
    """Yule-Walker AR(p) for each order: relative errors, the fits and the lags-0..p gap."""
    errors, fits, gap = [], {}, 0.0
    for p in orders:
        ar, sigma2 = arma.yule_walker(r[:p + 1], p)
        implied = arma.arma_acvf(ar, [], sigma2, n_lags + 1)
        gap = max(gap, float(np.abs(implied[:p + 1] - r[:p + 1]).max() / r[0]))
        errors.append(float(np.abs(implied - r).max() / r[0]))
        fits[p] = implied
    return errors, fits, gap


def _exponential_versus_filters(n, lam, seed):
    """AR(1) (eq 12 as a sampled OU process), the grid-size FFT filter and circulant
    embedding for the exponential ACVF of lengthscale ``lam`` on ``n`` points."""
    ar, ma, s2 = arma.ou_to_ar1(1.0, lam, 1.0)
    lags = np.arange(n, dtype=float)
    ar1_gap = float(np.abs(arma.arma_acvf(ar, ma, s2, n) - np.exp(-lags / lam)).max())
    # the FFT filter on the grid itself has the circulant covariance with eigenvalues S(f_k)
    filter_acvf = np.fft.ifft(acvf.matern_psd(np.fft.fftfreq(n)[:, None], 1.0, lam, 0.5)).real
    _, info = sampling.sample_grid(kernels.MaternKernel(nu=0.5, lengthscale=lam), (n,),
                                   method="circulant", seed=seed, return_info=True)
    return lags, ar1_gap, filter_acvf, float(info.clipped_fraction)


def long_correlation(*, n_lags=600, orders=(2, 4, 8, 16, 32, 64, 128, 256), n_grid=2000,
                     lengthscale=500.0, seed=1):
    """AR(p) fits (Yule-Walker) of :func:`periodic_acvf` and of a Matérn-3/2 kernel
    (variance 1.35, lambda = 20) over lags 0..``n_lags``; the exponential ACVF of
    ``lengthscale`` on ``n_grid`` points as AR(1), FFT filter and circulant draw (``seed``)."""
    lag_axis = np.arange(n_lags + 1.0)[:, None]
    curves = {"periodic": periodic_acvf(lag_axis),
              "Matern-3/2": kernels.MaternKernel(nu=1.5, variance=1.35,
                                                 lengthscale=20.0).acvf(lag_axis)}
    fit_error, fits, gap = {}, {}, 0.0
    for name, r in curves.items():
        fit_error[name], by_order, name_gap = _ar_fits(r, orders, n_lags)
        fits.update({(name, p): v for p, v in by_order.items()})
        gap = max(gap, name_gap)
    lags, ar1_gap, filter_acvf, clipped = _exponential_versus_filters(n_grid, lengthscale, seed)
    wrap = n_grid // 2
    return LongCorrelation(lag_axis, curves["periodic"], curves["Matern-3/2"], tuple(orders),
                           fit_error, fits, gap, lengthscale, lags, ar1_gap, filter_acvf, wrap,
                           float(filter_acvf[wrap]), math.exp(-wrap / lengthscale), clipped)


# ------------------------------------------------------------------ non-Gaussian heights

@dataclass
class MomentSummary:
    """One height parameter over the surfaces against its target."""

    target: float
    mean: float
    sd: float
    t_stat: float                # (mean - target) / (sd / sqrt(n))


@dataclass
class NonGaussianAcvf:
    """Per case (name -> ...): the surfaces with and without pre-distortion, their mean
    unbiased empirical ACVF, RMS errors against the target and the achieved moments."""

    targets: dict                # name -> (Ssk, Sku)
    kernel: object
    n_samples: int
    seed: int
    max_lag: int
    lags: np.ndarray             # (2 max_lag + 1, 2 max_lag + 1, 2)
    target_acvf: np.ndarray
    draws: dict                  # name -> (n_samples, *shape), pre-distorted
    infos: dict                  # name -> non_gaussian.NonGaussianInfo
    naive: dict                  # name -> draws without pre-distortion (not for Gaussian)
    acvf_with: dict              # name -> mean empirical ACVF
    acvf_without: dict
    predicted_without: dict      # name -> r(0) g(r / r(0))
    rms: dict                    # name -> {"with", "without", "without vs r(0) g(rho)"}
    moments: dict                # name -> {"Ssk", "Sku", "Sq"} -> MomentSummary
    quantile: float              # t_{0.999} with n_samples - 1 degrees of freedom


def plateau_kernel():
    """The chapter's target ACVF: exponential (Matérn 1/2), lengthscale 8, r(0) = 1, in 2-D."""
    return kernels.MaternKernel(nu=0.5, dim=2, variance=1.0, lengthscale=8.0)


def mean_acvf(surfaces, max_lag):
    """The unbiased empirical ACVF averaged over surfaces."""
    return np.mean([spectral.empirical_acvf(z, max_lag=max_lag, unbiased=True)[1]
                    for z in surfaces], axis=0)


def _rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def _moments(surfaces, target, variance):
    params = [texture_heights.height_parameters(z) for z in surfaces]
    out = {}
    for key, goal in zip(("Ssk", "Sku", "Sq"), (*target, math.sqrt(variance))):
        values = np.array([p[key] for p in params])
        sd = float(values.std(ddof=1))
        out[key] = MomentSummary(goal, float(values.mean()), sd,
                                 float((values.mean() - goal) / (sd / math.sqrt(len(values)))))
    return out


def _draw(kernel, shape, target, seed, n_samples, predistortion):
    return non_gaussian.non_gaussian_surface(kernel, shape, skewness=target[0],
                                             kurtosis=target[1], seed=seed,
                                             n_samples=n_samples, predistortion=predistortion)


def non_gaussian_acvf(full=None, *, targets=None, kernel=None, shape=(512, 512), seed=3,
                      n_samples=None, max_lag=16):
    """Johnson surfaces (:func:`roughgp.non_gaussian.non_gaussian_surface`) for each
    (Ssk, Sku) of ``targets`` (default: the plateau-like (-1.5, 6)) with the ACVF of
    ``kernel`` (default :func:`plateau_kernel`): ``n_samples`` surfaces (5, or 20 with
    ``full``) with and, for non-Gaussian targets, without pre-distortion from one ``seed``."""
    targets = dict(targets or {"plateau": (-1.5, 6.0)})
    kernel = kernel or plateau_kernel()
    n = n_samples or (20 if resolve_full(full) else 5)
    draws, infos, naive, with_, without, predicted, rms, moments = ({} for _ in range(8))
    lags = target_acvf = None
    for name, target in targets.items():
        draws[name], infos[name] = _draw(kernel, shape, target, seed, n, True)
        if lags is None:
            lags = spectral.empirical_acvf(draws[name][0], max_lag=max_lag)[0]
            target_acvf = kernel.acvf(lags)
        moments[name] = _moments(draws[name], target, float(target_acvf[(max_lag,) * lags.shape[-1]]))
        with_[name] = mean_acvf(draws[name], max_lag)
        if tuple(target) == (0.0, 3.0):
            continue
        naive[name], _ = _draw(kernel, shape, target, seed, n, False)
        without[name] = mean_acvf(naive[name], max_lag)
        predicted[name] = infos[name].correlation_map(target_acvf)
        rms[name] = {"with": _rms(with_[name], target_acvf),
                     "without": _rms(without[name], target_acvf),
                     "without vs r(0) g(rho)": _rms(without[name], predicted[name])}
    return NonGaussianAcvf(targets, kernel, n, seed, max_lag, lags, target_acvf, draws, infos,
                           naive, with_, without, predicted, rms, moments,
                           float(stats.t.ppf(0.999, n - 1)))
