r"""Checks of the paper's outlook that the book built (beyond the paper) and of its conclusion."""

from __future__ import annotations

import math

import numpy as np

from roughgp.common.plotting import row_of_axes
from roughgp.common.settings import pick
from roughgp.ledger.types import Check

__all__ = ["check_sampling", "check_non_gaussian", "check_prescribed", "check_gap_filling", "check_device", "check_long_correlation"]


# ------------------------------------------------------------------ beyond the paper

def check_sampling(full):
    """Sec 2.2 names sampling with the marginal likelihood as the alternative to
    optimising; the paper only optimises. The book samples with emcee: on the conjugate
    white-noise model (eq 11) the chain's posterior is the analytic inverse gamma."""
    from scipy import stats

    from roughgp.inference import posterior
    z = np.random.default_rng(1).normal(0.0, 1.5, 20)
    model = posterior.PosteriorModel(
        (posterior.Parameter("variance", posterior.LogUniform(1e-4, 1e4)),),
        posterior.profile_likelihood(z, 1.0, lambda p, lags: p["variance"] * (lags == 0)))
    result = posterior.sample_posterior(model, n_walkers=12, n_steps=pick(2500, 10000, full=full),
                                        seed=3)
    exact = stats.invgamma(z.size / 2, scale=float(np.sum(z * z)) / 2)
    ess = result.samples["variance"].size / result.autocorr_time["variance"]
    sigma_u = math.sqrt(2 / z.size)                       # sd of log s2, nearly normal
    gap = abs(math.log(np.median(result.samples["variance"]) / exact.median()))
    return Check(f"emcee median {np.median(result.samples['variance']):.3f}, analytic "
                 f"{exact.median():.3f} (|log ratio| {gap:.3f}, 4 Monte-Carlo se = "
                 f"{4 * 1.25 * sigma_u / math.sqrt(ess):.3f})",
                 gap < 4 * 1.25 * sigma_u / math.sqrt(ess))


def check_non_gaussian(full):
    """Conclusion: GPs with Gaussian noise cannot describe strongly non-Gaussian surfaces;
    a Johnson transform of a pre-distorted GP gives a prescribed Ssk and Sku with the
    target ACVF (roughgp.experiments.small_claims.non_gaussian_acvf, as in the chapter
    non_gaussian)."""
    from roughgp.experiments import small_claims
    result = small_claims.non_gaussian_acvf(full)
    (name,) = result.targets
    moments, rms = result.moments[name], result.rms[name]
    ok = all(abs(moments[key].t_stat) <= result.quantile for key in ("Ssk", "Sku"))
    text = [f"{key} {moments[key].mean:.2f} +- {moments[key].sd:.2f} (target "
            f"{moments[key].target:g})" for key in ("Ssk", "Sku")]
    shape = " x ".join(str(n) for n in result.draws[name].shape[1:])
    return Check(", ".join(text) + f" over {result.n_samples} surfaces of {shape}; ACVF RMS "
                 f"error {rms['with']:.4f} with pre-distortion, {rms['without']:.4f} without",
                 bool(ok and rms["with"] < 0.5 * rms["without"]))


def check_prescribed(full):
    """Conclusion, future work [16]: surfaces with predefined roughness parameters. The
    closed-form inversion of Sq, Sal, Str, Std into eq 18 plus noise (roughgp.targets.closed_form),
    then the achieved parameters over several seeds."""
    from roughgp import targets
    from roughgp.experiments.prescribed_targets import target_verdicts
    goal = targets.RoughnessTargets(Sq=0.3, Sal=6.0, Str=0.1, Std=-20.0)
    noise = goal.Sq ** 2 * 0.1 / 1.1                        # sigma^2 / sigma_k^2 = 1/10
    h = targets.hyperparameters_for(**goal.as_dict(), noise_variance=noise)
    n = pick(5, 20, full=full)
    values = targets.achieved_parameters(h, (512, 512), seeds=range(100, 100 + n))
    summary = targets.summarize(values)
    verdicts = target_verdicts(goal, values, targets.sq_prediction(h, (512, 512)))
    ok = all(verdicts.values())
    return Check(", ".join(f"{k} {summary[k][0]:.3g} +- {summary[k][1]:.2g} (target "
                           f"{getattr(goal, k):g})" for k in targets.TARGET_NAMES)
                 + f" over {n} surfaces of 512 x 512", ok)


def check_gap_filling(full):
    """Conclusion, ref [48]: the model can interpolate non-measured points. The chapter's
    scenario (roughgp.experiments.gap_filling: a ground surface of eq 18 with 10 % dropouts, a
    scratch and a blob), filled by the GP posterior mean with the known hyperparameters and
    with those fitted on the measured points alone, against linear interpolation in the
    chapter's window, and the coverage of +-2 posterior sd. 128 x 128 (full: 256 x 256, the
    chapter's quick size)."""
    from roughgp.experiments.gap_filling import compare_gap_filling
    result = compare_gap_filling(pick(128, 256, full=full))
    rmse, window, inside = result.rmse, result.window_rmse, result.coverage
    holds = (all(f.converged for f in result.fills.values())
             and window["GP"]["all"] < window["linear"]["all"]
             and rmse["fitted"]["all"] <= 1.05 * rmse["known"]["all"]
             and all(0.90 <= v["all"] <= 0.98 for v in inside.values()))
    h, n = result.fitted.groove, result.n
    return Check(f"{n} x {n}, {result.scenario.missing.mean():.0%} missing: RMSE GP "
                 f"{rmse['known']['all']:.2f} (hyperparameters known), "
                 f"{rmse['fitted']['all']:.2f} (fitted on the measured points: sigma_k^2 "
                 f"{h.variance:.1f}, lambda {h.lengthscales[0]:.0f} / {h.lengthscales[1]:.1f}, "
                 f"phi {math.degrees(h.angle):.1f} deg); in the window GP "
                 f"{window['GP']['all']:.2f}, linear {window['linear']['all']:.2f}; truth "
                 f"inside +-2 sd: {inside['known']['all']:.3f} / {inside['fitted']['all']:.3f} "
                 f"({result.n_samples} draws: {result.expected_coverage:.3f} expected)",
                 bool(holds), _gap_filling_figure(window))


def _gap_filling_figure(window_rmse):
    """Bars: RMSE per hole type in the window, GP against the interpolants."""
    fig, (ax,) = row_of_axes(width=5.5)
    kinds = list(next(iter(window_rmse.values())))
    width = 0.8 / len(window_rmse)
    for i, (method, by_kind) in enumerate(window_rmse.items()):
        ax.bar(np.arange(len(kinds)) + i * width, [by_kind[k] for k in kinds], width,
               label=method)
    ax.set_xticks(np.arange(len(kinds)) + 0.4 - width / 2, kinds)
    ax.set(ylabel="RMSE against the truth", title="missing points in the window")
    ax.legend()
    return fig


def check_device(full):
    """Beyond the paper, scale: the device= paths (roughgp.common.device) give the numpy paths'
    numbers, on torch's CPU and, where torch sees one, on a GPU."""
    from roughgp import sampling
    from roughgp.filling import global_fill as gap_filling
    from roughgp.common import device as devices
    from roughgp.gp import kernels
    from roughgp.inference import posterior
    from roughgp.models import surfaces
    kernel = kernels.RotatedExponentialKernel(variance=2.0, lengthscales=(6.0, 2.0),
                                              angle=math.pi / 6)
    z = surfaces.ground((24, 24), variance=2.0, lengthscales=(6.0, 2.0), angle=0.5,
                        noise_variance=0.1, seed=3)
    params = {"variance": 2.0, "lambda_a": 6.0, "lambda_b": 2.0, "angle": 0.5,
              "noise_variance": 0.1}
    gappy = surfaces.ground((96, 96), variance=2.0, lengthscales=(6.0, 2.0),
                            angle=math.pi / 6, noise_variance=0.1, seed=4)
    gappy[np.random.default_rng(5).random(gappy.shape) < 0.1] = np.nan
    reference = {
        "draw": sampling.sample_grid(kernel, (20, 20), method="cholesky", seed=1),
        "loglik": posterior.ground_patch_model(z).log_likelihood(params),
        "fill": gap_filling.fill_gaps(gappy, kernel, noise_variance=0.1, n_samples=0).mean}
    holds, text = True, []
    for name in devices.available():
        got = {
            "draw": sampling.sample_grid(kernel, (20, 20), method="cholesky", seed=1,
                                         device=name),
            "loglik": posterior.ground_patch_model(z, device=name).log_likelihood(params),
            "fill": gap_filling.fill_gaps(gappy, kernel, noise_variance=0.1, n_samples=0,
                                          device=name).mean}
        gaps = (float(np.max(np.abs(got["draw"] - reference["draw"]))),
                abs(got["loglik"] - reference["loglik"]) / abs(reference["loglik"]),
                float(np.max(np.abs(got["fill"] - reference["fill"]))))
        holds &= gaps[0] < 1e-9 and gaps[1] < 1e-9 and gaps[2] < 1e-4
        text.append(f"{name}: Cholesky draw {gaps[0]:.1e}, patch log-likelihood "
                    f"(relative) {gaps[1]:.1e}, gap-fill mean {gaps[2]:.1e}")
    if "cuda" not in devices.available():
        text.append("no GPU here; on an NVIDIA H200 (benchmarks/results) the gap filling of "
                    "512 x 512 ran 36 times and a 128 x 128 Cholesky draw 94 times faster "
                    "than numpy")
    return Check("largest differences from numpy: " + "; ".join(text), bool(holds))


# ------------------------------------------------------------------ conclusion

def check_long_correlation(full):
    """Conclusion: the GP approach simulates long correlation lengths "not possible with
    ARMA processes or other digital filter methods", checked in the paper's 2-D setting
    (eq 18 with figure 2's lambda_a = 500, roughgp.experiments.long_correlation): 2-D
    quarter- and half-plane AR fits (Yule-Walker) against eq 18, the same fits with a short
    lambda_a, the grid-size FFT filter and circulant embedding (an FFT filter on a larger
    torus). The 1-D side (AR(1) is the exponential of any length) is the chapter arma's."""
    from roughgp.experiments import long_correlation
    orders = pick(long_correlation.ORDERS, long_correlation.FULL_ORDERS, full=full)
    result = long_correlation.long_correlation_2d(orders=orders)
    quarter, half = result.best("quarter"), result.best("half")
    short = result.short_fits["half", max(orders)]
    ar_misses = min(quarter.max_error, half.max_error) > 0.10
    holds = (ar_misses and short.max_error < 0.02 and result.filter_max_error < 0.05
             and result.clipped_fraction == 0.0 and result.min_eigenvalue >= 0.0)
    top = max(orders)
    text = (f"2-D AR fits of eq 18 (lambda_a = {result.parameters.lengthscales[0]:g}), orders "
            f"1-{top}: best max |ACVF error| within +-{result.window} lags "
            f"{quarter.max_error:.2f} sigma_k^2 (quarter plane, order {quarter.order}), "
            f"{half.max_error:.2f} (half plane, order {half.order}); half plane of order "
            f"{top} ({result.fits['half', top].n_coefficients} coefficients): "
            f"{result.fits['half', top].max_error:.2f}; with lambda_a = "
            f"{result.short_lambda_a:g} the same order gets {short.max_error:.3f}. "
            f"Grid-size FFT filter ({result.grid} x {result.grid}): "
            f"{result.filter_max_error:.3f} sigma_k^2 over the same lags (its images fall "
            f"across the grooves); on the circulant torus {result.torus_shape[0]} x "
            f"{result.torus_shape[1]} exact (clipped {result.clipped_fraction:g})")
    return Check(text, bool(holds), _long_correlation_figure(result))


def _long_correlation_figure(result):
    """Top: the AR fits' window error against the order; bottom: ACVFs along the grooves."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(6.0, 6.6))
    for kind, style in (("quarter", "s-"), ("half", "o-")):
        errors = [result.fits[kind, p].max_error for p in result.orders]
        axes[0].plot(result.orders, errors, style, label=f"{kind}-plane AR, $\\lambda_a$ = "
                     f"{result.parameters.lengthscales[0]:g}")
    axes[0].plot(result.orders, [result.short_fits["half", p].max_error for p in result.orders],
                 "o--", label=f"half-plane AR, $\\lambda_a$ = {result.short_lambda_a:g}")
    axes[0].axhline(result.filter_max_error, color="k", ls=":",
                    label=f"grid-size FFT filter ({result.grid}²)")
    axes[0].set(xscale="log", yscale="log", xlabel="AR order p",
                ylabel="max |ACVF − eq 18| / $\\sigma_k^2$",
                title=f"lags within ±{result.window} (grid units)")
    axes[0].legend(fontsize=9)
    axes[1].plot(result.along_lags, result.true_along, "k", lw=2, label="eq 18 (= circulant)")
    for kind, p in (("half", 2), ("half", max(result.orders)), ("quarter", max(result.orders))):
        axes[1].plot(result.along_lags, result.fits[kind, p].along, lw=1,
                     label=f"{kind}-plane AR, order {p}")
    axes[1].plot(result.along_lags, result.filter_along, "C3:", lw=2,
                 label="grid-size FFT filter")
    axes[1].set(xlabel="lag along the grooves (grid unit)", ylabel="ACVF / $\\sigma_k^2$",
                title="figure 2's eq 18 along φ = 30°")
    axes[1].legend(fontsize=9)
    return fig
