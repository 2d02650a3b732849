r"""The errors of the pooled regional values (:mod:`roughgp.inference.random_effects`): the
spread between regions :math:`\tau` integrated out, and the population's form averaged over
(beyond the paper; issue 40, items 3 and 4).

For one form of the population's value (a constant, a plane, a step between two zones: the
columns of ``design``, :math:`X`) the normal random-effects model
:math:`\hat\theta_i \mid \theta_i \sim N(\theta_i, v_i)`, :math:`\theta \sim N(X\beta, \tau^2
I)` with a uniform prior on :math:`\tau` and a flat one on :math:`\beta` has the posterior
(Gelman et al., *Bayesian Data Analysis*, 3rd ed., section 5.4)

.. math::
    p(\tau \mid \hat\theta) \propto |X^T W_\tau X|^{-1/2} \prod_i (v_i + \tau^2)^{-1/2}
    \exp\Big(-\tfrac12 \sum_i \frac{(\hat\theta_i - x_i^T\hat\beta_\tau)^2}{v_i + \tau^2}\Big),
    \qquad W_\tau = \operatorname{diag}(1 / (v_i + \tau^2)),

and given :math:`\tau` each region's value is normal about the shrunk value, with the variance
of :mod:`~roughgp.inference.random_effects`; :func:`tau_posterior_moments` mixes those
moments over a grid of :math:`\tau`. The form itself is chosen by tests on the same regions;
where the data leave it open (a roughness gradient over four columns of noisy tiles looks much
like a step), the chosen form's errors are too small. :func:`averaged_moments` mixes the
forms' posterior moments with Akaike weights (Burnham and Anderson, *Model Selection and
Multimodel Inference*, 2002, section 4.3: the unconditional variance), each form's AIC from its
maximum likelihood over :math:`\tau` and :math:`\beta`,
:math:`-2\log L + 2(p + 1)`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["TAU_GRID_POINTS", "tau_posterior_moments", "averaged_moments"]

#: points of the grid over tau in :func:`tau_posterior_moments`
TAU_GRID_POINTS = 400


def _on_tau_grid(theta, v, x):
    """Posterior mean, posterior variance and the maximum log likelihood (over tau and beta,
    up to a constant) of one form, or None where the posterior is improper."""
    known = np.isfinite(theta) & np.isfinite(v) & (v > 0)
    t, vk, xk = theta[known], v[known], x[known]
    if t.size < x.shape[-1] + 2:
        return None
    scale = math.sqrt(max(float(np.var(t)), float(np.median(vk))))
    taus = 30.0 * scale * np.linspace(0.0, 1.0, TAU_GRID_POINTS + 1) ** 2
    tau2 = (taus * taus)[:, None]
    w = 1.0 / (vk + tau2)
    information = np.einsum("ki,nk,kj->nij", xk, w, xk)
    inverse = np.linalg.inv(information)
    beta = np.einsum("nij,kj,nk,k->ni", inverse, xk, w, t)
    residual = t - beta @ xk.T
    log_likelihood = -0.5 * (np.sum(np.log(vk + tau2), axis=1) + np.sum(w * residual**2,
                                                                         axis=1))
    log_density = log_likelihood - 0.5 * np.linalg.slogdet(information)[1]
    fitted = np.einsum("...j,nj->n...", x, beta)
    fitted_var = np.einsum("...i,nij,...j->n...", x, inverse, x)
    tau2 = tau2.reshape((taus.size,) + (1,) * theta.ndim)
    vv = np.where(known, v, 1.0)
    shrink = np.where(known, tau2 / (tau2 + vv), 0.0)
    means = fitted + shrink * (np.where(known, theta, fitted) - fitted)
    rest = np.where(known, vv / (tau2 + vv), 1.0)
    variances_given = np.where(known, shrink * vv, tau2) + rest**2 * fitted_var
    weights = np.exp(log_density - log_density.max()) * np.gradient(taus)
    weights /= weights.sum()
    mean = np.tensordot(weights, means, axes=1)
    second = np.tensordot(weights, variances_given + means**2, axes=1)
    return mean, np.maximum(second - mean**2, 0.0), float(log_likelihood.max())


def tau_posterior_moments(estimates, variances, design):
    """Each region's posterior mean and variance with :math:`\\tau` integrated out (module
    docstring) for one form, ``design`` (``(..., p)``, the regions' shape then the
    coefficients); NaN estimates mark regions without one, which get the population's
    predictive moments. None where the posterior is improper (fewer than ``p + 2`` regions
    with an estimate).

    The posterior of :math:`\\tau` is taken on :data:`TAU_GRID_POINTS` points from 0 to 30
    times the estimates' own scale (quadratically spaced, denser near 0; its tail falls as
    :math:`\\tau^{-(k-p)}`), and the conditional moments mixed by its weights.
    """
    result = _on_tau_grid(np.asarray(estimates, dtype=np.float64),
                          np.asarray(variances, dtype=np.float64),
                          np.asarray(design, dtype=np.float64))
    return None if result is None else result[:2]


def averaged_moments(estimates, variances, designs):
    """Each region's posterior mean and variance averaged over the forms ``designs`` (a list
    of ``design`` arrays, :func:`tau_posterior_moments`) with Akaike weights (module
    docstring): the mean of the forms' means, and the mean of their variances plus the spread
    of their means. Forms whose posterior is improper are left out; None when all are."""
    theta = np.asarray(estimates, dtype=np.float64)
    v = np.asarray(variances, dtype=np.float64)
    results = [(r, x.shape[-1]) for x in designs
               if (r := _on_tau_grid(theta, v, np.asarray(x, dtype=np.float64))) is not None]
    if not results:
        return None
    aic = np.array([-2.0 * r[2] + 2.0 * (p + 1) for r, p in results])
    weights = np.exp(-0.5 * (aic - aic.min()))
    weights /= weights.sum()
    mean = sum(w * r[0] for w, (r, _) in zip(weights, results))
    variance = sum(w * (r[1] + (r[0] - mean) ** 2) for w, (r, _) in zip(weights, results))
    return mean, variance
