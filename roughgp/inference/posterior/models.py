r"""Ready-made posterior models: eq 21 plus noise on a profile, eq 18 plus noise on a patch.

Also the helpers that read a posterior of them: :func:`order_lengthscales` (the two
lengthscales of eq 18 are exchangeable with the angle turned by 90 degrees) and
:func:`maximum_a_posteriori`.
"""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from roughgp.common.checks import check_positive
from roughgp.common.device import resolve as resolve_device
from roughgp.common.grid import normalize
from roughgp.common.numerics import perturbed_start
from roughgp.inference.posterior.likelihoods import (
    check_patch,
    grid_likelihood,
    profile_likelihood,
)
from roughgp.inference.posterior.priors import (
    LogNormal,
    LogUniform,
    Parameter,
    PosteriorModel,
    Uniform,
    UniformAngle,
)

# ------------------------------------------------------------------ ready-made models

def spectral_mixture_profile_model(x, z, q, *, fit=None, width=1.0) -> PosteriorModel:
    r"""Eq 21 with Q components plus white noise, for a profile ``(x, z)``.

    Parameters ``w_i``, ``mu_i``, ``v_i`` (i = 1..Q; weights, mean frequencies in cycles per
    unit of x, variances in cycles² per unit²) and ``noise_variance``. The mean of z is
    removed (as :func:`roughgp.inference.fitting.fit_spectral_mixture` does).

    Priors: ``mu_i`` uniform on ``[0, 1/(2 dx)]`` (up to the Nyquist frequency). With a
    :class:`roughgp.inference.fitting.SpectralMixtureFit` ``fit`` (of Q components): the scales
    log-normal around the fitted values with log-standard deviation ``width``, and the
    walkers start at the fit (``model.initial``). Without: log-uniform over wide ranges set
    by the data (weights and noise in ``[1e-6, 10] var(z)``, line widths from
    ``(0.05 / L)^2``, :data:`roughgp.inference.fitting.MIN_LINE_WIDTH`, to ``(1 / (2 dx))^2``), walkers
    from the prior. The components are exchangeable (label switching): chains started at a
    fit keep its labels in practice; chains from the prior may not, so summarise per label
    with care.
    """
    from roughgp.inference.fitting import MIN_LINE_WIDTH, check_profile

    x, z, dx = check_profile(x, z)
    if not (isinstance(q, (int, np.integer)) and q >= 1):
        raise ValueError(f"q must be an integer >= 1, got {q!r}")
    q = int(q)
    check_positive("width", width)
    z = z - z.mean()
    var = float(np.var(z))
    if not var > 0:
        raise ValueError("z must not be constant")
    nyquist = 0.5 / dx
    length = z.size * dx
    mu_prior = Uniform(0.0, nyquist)
    initial = None
    if fit is not None:
        if len(fit.weights) != q:
            raise ValueError(f"fit must have q = {q} components, got {len(fit.weights)}")
        noise = max(float(fit.noise_variance), 1e-8 * var)
        initial = {"noise_variance": noise}
        params = []
        for i in range(q):
            w, mu, v = float(fit.weights[i]), float(fit.means[i]), float(fit.variances[i])
            params += [Parameter(f"w_{i + 1}", LogNormal(math.log(w), width)),
                       Parameter(f"mu_{i + 1}", mu_prior),
                       Parameter(f"v_{i + 1}", LogNormal(math.log(v), width))]
            initial.update({f"w_{i + 1}": w, f"mu_{i + 1}": min(max(mu, 1e-9 * nyquist),
                                                                 nyquist * (1 - 1e-9)),
                            f"v_{i + 1}": v})
        params.append(Parameter("noise_variance", LogNormal(math.log(noise), width)))
    else:
        w_prior = LogUniform(1e-6 * var, 10.0 * var)
        v_prior = LogUniform((MIN_LINE_WIDTH / length) ** 2, nyquist ** 2)
        params = []
        for i in range(q):
            params += [Parameter(f"w_{i + 1}", w_prior), Parameter(f"mu_{i + 1}", mu_prior),
                       Parameter(f"v_{i + 1}", v_prior)]
        params.append(Parameter("noise_variance", LogUniform(1e-6 * var, 10.0 * var)))

    def acvf_fn(p, lags):
        out = np.zeros_like(lags)
        lag2 = lags * lags
        for i in range(1, q + 1):
            out += (p[f"w_{i}"] * np.cos(2 * math.pi * p[f"mu_{i}"] * lags)
                    * np.exp(-2 * math.pi ** 2 * p[f"v_{i}"] * lag2))
        return out

    return PosteriorModel(tuple(params), profile_likelihood(z, dx, acvf_fn), initial)


def ground_patch_model(z, spacing=1.0, *, priors: Mapping | None = None,
                       device=None) -> PosteriorModel:
    r"""Eq 18 plus white noise (eq 8) for a small ground patch ``z`` (ny, nx).

    Parameters: ``variance`` (:math:`\sigma_k^2`), ``lambda_a``, ``lambda_b``, ``angle``
    (:math:`\phi`, period :math:`\pi`) and ``noise_variance``. The mean of z is removed.
    Default priors, from the data (``var = var(z)``, ``L`` the longer side, ``d`` the finer
    spacing): ``variance`` and ``noise_variance`` log-uniform on ``[1e-6, 10] var``, the
    lengthscales log-uniform on ``[d/10, 10 L]``, the angle :class:`UniformAngle`; ``priors``
    (dict name -> prior) replaces any of them. Note :math:`(\lambda_a, \lambda_b, \phi)` and
    :math:`(\lambda_b, \lambda_a, \phi + \pi/2)` give the same ACVF, so the posterior has two
    mirrored modes unless a prior orders the lengthscales. ``device``: where the dense
    likelihood runs (:func:`grid_likelihood`); a GPU lifts the CPU's patch limit.
    """
    from roughgp.gp import acvf as _acvf

    device = resolve_device(device)
    z = check_patch(z, device)
    shape, sp = normalize(z.shape, spacing)
    z = z - z.mean()
    var = float(np.var(z))
    if not var > 0:
        raise ValueError("z must not be constant")
    extent = float(max(n * d for n, d in zip(shape, sp)))
    scale = LogUniform(float(sp.min()) / 10.0, 10.0 * extent)
    chosen = {"variance": LogUniform(1e-6 * var, 10.0 * var), "lambda_a": scale,
              "lambda_b": scale, "angle": UniformAngle(math.pi),
              "noise_variance": LogUniform(1e-6 * var, 10.0 * var)}
    unknown = set(priors or {}) - set(chosen)
    if unknown:
        raise ValueError(f"priors has unknown names {sorted(unknown)}; allowed: "
                         f"{list(chosen)}")
    chosen.update(priors or {})

    def kernel_factory(p):
        lengthscales = np.array([p["lambda_a"], p["lambda_b"]])
        return lambda lags: _acvf.rotated_exponential(lags, p["variance"], lengthscales,
                                                      p["angle"])

    params = tuple(Parameter(n, prior) for n, prior in chosen.items())
    return PosteriorModel(params, grid_likelihood(z, sp, kernel_factory, device=device))


def order_lengthscales(samples: Mapping, period: float = math.pi) -> dict:
    r"""Samples of eq 18 with :math:`\lambda_a \ge \lambda_b`: where a draw has
    :math:`\lambda_a < \lambda_b`, swap the two and turn the angle by a quarter turn,
    :math:`(\lambda_a, \lambda_b, \phi) \to (\lambda_b, \lambda_a, \phi + \pi/2)`, which
    is the same ACVF. Removes the mirrored mode of :func:`ground_patch_model`'s posterior.

    Args:
        samples: dict with ``"lambda_a"``, ``"lambda_b"`` and ``"angle"`` arrays (others are
            copied unchanged), e.g. :attr:`PosteriorSamples.samples`.
        period: of the angle (pi for eq 18); angles are wrapped into ``[-period/2, period/2)``.

    Returns:
        a new dict.
    """
    for name in ("lambda_a", "lambda_b", "angle"):
        if name not in samples:
            raise ValueError(f"samples must hold {name!r}, got {sorted(samples)}")
    out = {k: np.array(v, dtype=np.float64, copy=True) for k, v in samples.items()}
    swap = out["lambda_a"] < out["lambda_b"]
    out["lambda_a"][swap], out["lambda_b"][swap] = (out["lambda_b"][swap],
                                                    np.asarray(samples["lambda_a"])[swap])
    angle = out["angle"] + np.where(swap, period / 2, 0.0)
    out["angle"] = (angle + period / 2) % period - period / 2
    return out


OPTIMISERS = ("Nelder-Mead", "L-BFGS-B")


def maximum_a_posteriori(model: "PosteriorModel", initial: Mapping, *, maxiter=5000,
                         method="Nelder-Mead") -> dict:
    """The posterior mode of ``model`` near ``initial`` (natural units), in the unconstrained
    u: the optimum around which :func:`sample_posterior` starts its walkers (section 2.2's
    "optimized by maximizing", with the priors included).

    Args:
        method: ``"Nelder-Mead"`` (default; no gradient) or ``"L-BFGS-B"`` (finite-difference
            gradients: far fewer evaluations for a smooth log posterior of a few parameters;
            on the eq 18 block likelihood about a quarter of Nelder-Mead's, same optimum).

    Returns:
        dict name -> value (natural units).
    """
    from scipy import optimize

    if method not in OPTIMISERS:
        raise ValueError(f"method must be one of {OPTIMISERS}, got {method!r}")
    u0 = perturbed_start(model.to_unconstrained(initial))
    if not math.isfinite(model.log_posterior(u0)):
        raise ValueError(f"initial has zero posterior density: {dict(initial)!r}")
    if method == "Nelder-Mead":
        result = optimize.minimize(lambda u: -model.log_posterior(u), u0, method="Nelder-Mead",
                                   options={"maxiter": int(maxiter), "xatol": 1e-6,
                                            "fatol": 1e-8})
    else:
        def objective(u):  # a zero density (outside a prior's support) as a large finite value
            value = -model.log_posterior(u)
            return value if math.isfinite(value) else 1e300

        result = optimize.minimize(objective, u0, method="L-BFGS-B",
                                   options={"maxiter": int(maxiter)})
    return model.to_natural(result.x)
