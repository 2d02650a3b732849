r"""Checks of the verdicts on measured data (beyond the paper: the chapter measured_surfaces).

The paper fits its models to measurements that are not public; the chapter runs its loop (fit
eq 18, simulate, check, fill) on the open files of ``data/``. Each check calls the chapter's
computation (:mod:`roughgp.experiments.measured_surfaces`): the land's fit once for the first
two rows (cached), the check with fewer simulations and one file's cross-validation on a
crop by default, the chapter's sizes with ``full=True``.
"""

from __future__ import annotations

import functools

import numpy as np

from roughgp.common.plotting import row_of_axes
from roughgp.common.settings import pick, resolve_full
from roughgp.ledger.types import Check

__all__ = ["check_land_lay", "check_land_model", "check_measured_fill"]

QUICK_SIMULATIONS = 9              # the chapter: 19
QUICK_CV = ("opd-1.opd", 160)      # one file, its central 160 x 160 points


@functools.lru_cache(maxsize=1)
def _land_fit(seed=0):
    from roughgp.experiments import measured_surfaces as ms
    return ms.land_fit(seed=seed)


def check_land_lay(full):
    """Eq 18 (sec 3.1) fitted to the measured striated bullet land (holes left out, block
    composite likelihood): the fitted lay angle phi lies along the striations (y), with a weak
    anisotropy lambda_a / lambda_b (the chapter's assertions)."""
    from roughgp.experiments import measured_surfaces as ms
    _, fit = _land_fit(0)
    hp = fit.model.hyperparameters
    deviation, ratio = ms.lay_deviation_deg(fit), hp["lambda_a_um"] / hp["lambda_b_um"]
    return Check(f"phi = {hp['angle_deg']:.1f} deg, {deviation:.1f} deg from the striations; "
                 f"lambda_a = {hp['lambda_a_um']:.3g} um, lambda_b = {hp['lambda_b_um']:.3g} um "
                 f"(ratio {ratio:.2f}; figure 2: 100)",
                 all(ms.land_fit_verdicts(fit).values()))


def check_land_model(full):
    """The land's ISO 25178-2 parameters among simulations of its fitted eq 18 model: the
    heavy-tailed heights (Sku) lie far outside the Gaussian model's range, Sq above twice the
    simulations' median (the fit before the L-filter describes the waviness), the texture
    direction Std inside, the aspect ratio Str below (the chapter's assertions)."""
    from roughgp.checking.model_check import plot_model_check
    from roughgp.experiments import measured_surfaces as ms
    land, fit = _land_fit(0)
    n = pick(QUICK_SIMULATIONS, 19, full=full)
    check = ms.land_check(land, fit, n_simulations=n, seed=0)
    by_name = {p.name: p for p in check.parameters}
    sku, std, str_ = by_name["Sku"], by_name["Std"], by_name["Str"]
    holds = all(ms.land_check_verdicts(check).values())
    fig = plot_model_check(check, title=f"bullet land among {n} simulations")
    return Check(f"outside the range of {n} simulations: {', '.join(check.outside)}; Sku "
                 f"{sku.measured:.3g} (simulations at most {sku.high:.3g}); Std {std.measured:.1f}"
                 f" deg inside; Str {str_.measured:.2f} (simulations at least {str_.low:.2f})",
                 bool(holds), fig)


def _score(cv):
    """The judgement of one file: (GP < cubic, GP < linear, calibrated coverage)."""
    return cv.rmse["GP"] < cv.rmse["cubic"], cv.rmse["GP"] < cv.rmse["linear"], \
        cv.calibrated_coverage


def check_measured_fill(full):
    """Cross-validated fill on real measurements: 2 % of the measured points hidden in small
    discs, filled by the GP (fitted without them; its smoothness and band from the fill's
    self-check on other measured points) and by linear and cubic interpolation; the GP's RMSE
    and the coverage of its calibrated band. Quick: the Wyko file opd-1, its central 160 x 160
    points; full: the chapter's four files with its verdicts
    (:func:`~roughgp.experiments.measured_surfaces.fill_verdicts`)."""
    from roughgp.experiments import measured_surfaces as ms
    if resolve_full(full):
        cvs = {name: ms.cross_validated_fill(name, form=form, seed=0)
               for name, form in ms.CV_FILES.items()}
        holds = all(ms.fill_verdicts(cvs).values())
    else:
        name, size = QUICK_CV
        cvs = {f"{name} ({size} x {size})": ms.cross_validated_fill(
            name, form=ms.CV_FILES[name], crop=ms.centre_crop(name, size), seed=0)}
        (cv,) = cvs.values()
        better_cubic, better_linear, coverage = _score(cv)
        holds = better_cubic and better_linear and abs(coverage - 0.95) < 0.03
    text = "; ".join(f"{name}: RMSE GP (nu {cv.nu:g}) {cv.rmse['GP']:.3g}, linear "
                     f"{cv.rmse['linear']:.3g}, cubic {cv.rmse['cubic']:.3g} um at "
                     f"{int(cv.hidden.sum())} hidden points, the calibrated band "
                     f"(by hole size and depth) covers {cv.calibrated_coverage:.1%}"
                     for name, cv in cvs.items())
    return Check(text, bool(holds), _fill_figure(cvs))


def _fill_figure(cvs):
    """Bars: hidden-point RMSE per method (relative to linear), per file."""
    fig, (ax,) = row_of_axes(width=5.5)
    methods = ("GP", "linear", "cubic")
    width = 0.8 / len(methods)
    for i, method in enumerate(methods):
        ax.bar(np.arange(len(cvs)) + i * width,
               [cv.rmse[method] / cv.rmse["linear"] for cv in cvs.values()], width,
               label=method)
    ax.set_xticks(np.arange(len(cvs)) + width,
                  [f"{k}\n{cv.calibrated_coverage:.1%} in the band"
                   for k, cv in cvs.items()], fontsize=8.5)
    ax.set(ylabel="RMSE at hidden points / linear's", title="cross-validated fill")
    ax.legend(fontsize=8.5)
    fig.tight_layout()
    return fig
