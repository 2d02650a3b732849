r"""Checks of the claims on the GP and on ARMA (sections 2.1-2.3: eq 5, figure 1, eq 12-17).

Each ``check_*(full) -> Check`` recomputes our value with the library, at quick sizes by
default and the paper's with ``full=True``, and says whether the verdict's condition holds.
"""

from __future__ import annotations

import math

import numpy as np

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
    along and lambda_b across."""
    from roughgp.gp import acvf
    variance, (la, lb), phi = 1.0, (0.5, 0.1), math.pi / 6
    angles = np.radians(np.arange(-90.0, 90.0, 0.05))
    unit = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    r = acvf.rotated_exponential(0.3 * unit, variance, (la, lb), phi)
    slowest = math.degrees(angles[np.argmax(r)])
    along = acvf.rotated_exponential(la * np.array([[math.cos(phi), math.sin(phi)]]),
                                     variance, (la, lb), phi)[0]
    across = acvf.rotated_exponential(lb * np.array([[-math.sin(phi), math.cos(phi)]]),
                                      variance, (la, lb), phi)[0]
    holds = abs(slowest - 30.0) <= 0.1 and abs(along - math.exp(-1)) < 1e-12 \
        and abs(across - math.exp(-1)) < 1e-12
    return Check(f"slowest decay at {slowest:.2f} deg; r = {along:.4f}, {across:.4f} of "
                 f"sigma_k^2 at lambda_a along / lambda_b across (1/e = 0.3679)", holds)


# ------------------------------------------------------------------ section 2.3

def check_ma_finite(full):
    """MA(q) is a linear process (eq 13) with finitely many weights: ACVF zero beyond q."""
    from roughgp.models import arma
    ma = [0.5, -0.3, 0.2]
    weights = arma.linear_process_weights([], ma, 10)
    r = arma.arma_acvf([], ma, 1.0, 10)
    from_weights = arma.acvf_from_weights(weights, 1.0, 10)
    holds = (np.all(weights[4:] == 0) and np.all(r[4:] == 0)
             and np.abs(from_weights - r).max() < 1e-14)
    return Check(f"weights beyond b_3: {np.abs(weights[4:]).max():.0e}; ACVF beyond lag 3: "
                 f"{np.abs(r[4:]).max():.0e}", bool(holds))


def check_arma_linear(full):
    """A stationary ARMA is a causal linear process (eq 14): the truncated MA(K) ACVF
    converges to the ARMA's."""
    from roughgp.models import arma
    ar, ma = [1.2, -0.5], [0.4]
    exact = arma.arma_acvf(ar, ma, 1.0, 20)
    errors = []
    for k in (8, 16, 32, 64, 128):
        w = arma.linear_process_weights(ar, ma, k)
        errors.append(np.abs(arma.acvf_from_weights(w, 1.0, 20) - exact).max())
    holds = errors[-1] < 1e-12 and all(b < a for a, b in zip(errors, errors[1:]) if a > 1e-14)
    return Check("max ACVF error with K = 8, 16, ..., 128 weights: "
                 + ", ".join(f"{e:.0e}" for e in errors), bool(holds))


def check_gp_is_arma(full):
    """A sampled GP is an ARMA: exponential -> AR(1), Matern 3/2 -> ARMA(2, 1), exactly."""
    from roughgp.gp import kernels
    from roughgp.models import arma
    lags = np.arange(200.0)[:, None]
    ou = kernels.MaternKernel(nu=0.5, variance=2.0, lengthscale=500.0)
    ar, ma, s2 = arma.ou_to_ar1(2.0, 500.0, 1.0)
    gap_ou = np.abs(arma.arma_acvf(ar, ma, s2, 200) - ou.acvf(lags)).max() / 2.0
    m32 = kernels.MaternKernel(nu=1.5, variance=2.0, lengthscale=7.0)
    ar, ma, s2 = arma.matern32_to_arma21(2.0, 7.0, 1.0)
    gap_m32 = np.abs(arma.arma_acvf(ar, ma, s2, 200) - m32.acvf(lags)).max() / 2.0
    return Check(f"exponential (lambda = 500) as AR(1): {gap_ou:.0e}; Matern 3/2 as "
                 f"ARMA(2, 1): {gap_m32:.0e} of r(0)", gap_ou < 1e-13 and gap_m32 < 1e-12)


def check_ar_not_gp(full):
    """Not every AR process is a sampled GP of its kind: AR(1) with a < 0 alternates."""
    from roughgp.models import arma
    r = arma.arma_acvf([-0.6], [], 1.0, 8)
    try:
        arma.ar1_to_ou(-0.6, 1.0, 1.0)
        refused = False
    except ValueError:
        refused = True
    alternates = bool(np.all(np.sign(r) == (-1.0) ** np.arange(8)))
    return Check(f"AR(1), a = -0.6: ACVF signs {''.join('+' if v > 0 else '-' for v in r)}; "
                 f"no OU process maps to it: {refused}", alternates and refused)


def check_moving_average(full):
    """Eq 16-17: white noise smoothed by a feature map beta has the ACVF int beta beta."""
    from roughgp.models import moving_average
    gaussian = moving_average.gaussian_feature_map(variance=2.0, lengthscale=5.0)
    h = 0.25
    err = np.abs(moving_average.feature_map_acvf(gaussian, int(40 / h), h)
                 - gaussian.kernel(h * np.arange(int(40 / h)))).max()
    return Check(f"Gaussian feature map -> squared-exponential kernel: max error {err:.0e}",
                 err < 1e-12)
