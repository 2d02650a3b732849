r"""Checks of the claims on the GP and on ARMA (sections 2.1-2.3: eq 5, figure 1, eq 12-17).

Each ``check_*(full) -> Check`` recomputes our value with the library, at quick sizes by
default and the paper's with ``full=True``, and says whether the verdict's condition holds.
"""

from __future__ import annotations

import math

from roughgp.ledger.types import Check

__all__ = ["check_duality", "check_figure1", "check_ma_finite", "check_arma_linear", "check_gp_is_arma", "check_ar_not_gp", "check_moving_average"]


# ------------------------------------------------------------------ section 2.1

def check_duality(full):
    """Eq 5 on a grid: FFT(ACVF) = PSD (within aliasing) for the book's profile ACVFs and
    figure 1's; IFFT(PSD) = ACVF to rounding where the PSD has no mass beyond Nyquist
    (roughgp.experiments.small_claims.kernel_duality_table, as in the chapter notation)."""
    from roughgp.experiments import small_claims
    table = small_claims.kernel_duality_table(full)
    n_acvfs = len(table.errors) + 1
    return Check(f"FFT(ACVF) vs PSD: {table.forward:.1e} of the peak ({n_acvfs} ACVFs); "
                 f"IFFT(PSD) vs ACVF for smooth ACVFs: {table.inverse:.1e}",
                 table.forward < 1e-4 and table.inverse < 1e-10)


def check_figure1(full):
    """Figure 1: eq 18 with phi = 30 deg decays slowest along phi, with 1/e at lambda_a
    along and lambda_b across (roughgp.experiments.arma_relations.figure1_ridge, as in the
    chapter notation)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.figure1_ridge()
    holds = abs(r.slowest_deg - 30.0) <= 0.1 and abs(r.along - math.exp(-1)) < 1e-12 \
        and abs(r.across - math.exp(-1)) < 1e-12
    return Check(f"slowest decay at {r.slowest_deg:.2f} deg; r = {r.along:.4f}, {r.across:.4f} of "
                 f"sigma_k^2 at lambda_a along / lambda_b across (1/e = 0.3679)", holds)


# ------------------------------------------------------------------ section 2.3

def check_ma_finite(full):
    """MA(q) is a linear process (eq 13) with finitely many weights: ACVF zero beyond q
    (roughgp.experiments.arma_relations.ma_finite, as in the chapter arma)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.ma_finite()
    holds = r.weights_beyond_q == 0 and r.acvf_beyond_q == 0 and r.gap < 1e-14
    return Check(f"weights beyond b_{len(r.ma)}: {r.weights_beyond_q:.0e}; ACVF beyond lag "
                 f"{len(r.ma)}: {r.acvf_beyond_q:.0e}", bool(holds))


def check_arma_linear(full):
    """A stationary ARMA is a causal linear process (eq 14): the truncated MA(K) ACVF
    converges to the ARMA's (roughgp.experiments.arma_relations.arma_truncation, as in the
    chapter arma)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.arma_truncation()
    errors = r.errors
    holds = errors[-1] < 1e-12 and all(b < a for a, b in zip(errors, errors[1:]) if a > 1e-14)
    return Check(f"max ACVF error with K = {', '.join(str(k) for k in r.truncations)} weights: "
                 + ", ".join(f"{e:.0e}" for e in errors), bool(holds))


def check_gp_is_arma(full):
    """A sampled GP is an ARMA: exponential -> AR(1), Matern 3/2 -> ARMA(2, 1), exactly
    (roughgp.experiments.arma_relations.sampled_gp_as_arma, as in the chapter arma)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.sampled_gp_as_arma()
    gap_ou, gap_m32 = r.gap_ou / r.variance, r.gap_m32 / r.variance
    return Check(f"exponential (lambda = {r.lengthscale:g}) as AR(1): {gap_ou:.0e}; Matern 3/2 "
                 f"as ARMA(2, 1): {gap_m32:.0e} of r(0)", gap_ou < 1e-13 and gap_m32 < 1e-12)


def check_ar_not_gp(full):
    """Not every AR process is a sampled GP of its kind: AR(1) with a < 0 alternates
    (roughgp.experiments.arma_relations.negative_ar1, as in the chapter arma)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.negative_ar1()
    refused = bool(r.refusal)
    return Check(f"AR(1), a = {r.a:g}: ACVF signs {''.join('+' if v > 0 else '-' for v in r.acvf)}; "
                 f"no OU process maps to it: {refused}", r.alternates and refused)


def check_moving_average(full):
    """Eq 16-17: white noise smoothed by a feature map beta has the ACVF int beta beta
    (roughgp.experiments.arma_relations.feature_maps, as in the chapter arma): exact for a
    Gaussian map, first order in h for the one-sided exponential, which is an AR(1)."""
    from roughgp.experiments import arma_relations
    r = arma_relations.feature_maps()
    gauss, expo = r.gaussian_errors, r.exponential_errors
    first_order = all(abs(a / b - 2) < 0.1 for a, b in zip(expo, expo[1:]))
    return Check(f"Gaussian feature map -> squared-exponential kernel: max error "
                 f"{max(gauss):.0e}; one-sided exponential map: error halves with h "
                 f"({expo[0]:.1e} at h = {r.steps[0]:g}, {expo[-1]:.1e} at h = {r.steps[-1]:g}), "
                 f"as AR(1) to {r.ar1_gap:.0e}",
                 max(gauss) < 1e-12 and first_order and r.ar1_gap < 1e-12)
