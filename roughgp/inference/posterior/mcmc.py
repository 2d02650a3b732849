r"""The affine-invariant ensemble sampler of emcee over a :class:`PosteriorModel`.

:func:`sample_posterior` runs the chain and refuses to report a posterior from a chain shorter
than ``min_tau_multiple`` (50) autocorrelation times unless asked (:class:`ShortChainError`);
:func:`main_mode` keeps the walkers of the main mode.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Mapping

import numpy as np

from roughgp.common.checks import as_generator, check_integer, check_positive, check_size
from roughgp.common.numerics import perturbed_start
from roughgp.inference.posterior.priors import PosteriorModel, UniformAngle

# ------------------------------------------------------------------ sampling

class ShortChainError(ValueError):
    """The chain is too short, against its autocorrelation time, to report a posterior."""


@dataclasses.dataclass
class PosteriorSamples:
    """The result of :func:`sample_posterior`.

    ``samples``: dict name -> 1-D array of draws after burn-in (flattened over walkers,
    thinned), in natural units, angles wrapped into ``[-period/2, period/2)``;
    ``log_prob``: the log posterior (in u) of those draws; ``acceptance_fraction``: mean
    over walkers; ``autocorr_time``: dict name -> integrated autocorrelation time in steps
    (emcee, after burn-in); ``n_steps``; ``burn_in``; ``thin``; ``chain``: the whole chain
    (walkers, steps, parameters) in the unconstrained u, burn-in included;
    ``parameters``: the model's :class:`Parameter` tuple; ``walker_log_prob``: the log
    posterior of the whole chain (walkers, steps); ``walker_acceptance``: the acceptance
    fraction of each walker; ``walkers``: the indices (into the
    sampler's walkers) that ``samples`` were drawn from (all of them, unless
    :func:`main_mode` dropped some).
    """

    samples: dict
    log_prob: np.ndarray
    acceptance_fraction: float
    autocorr_time: dict
    n_steps: int
    burn_in: int
    thin: int
    chain: np.ndarray
    parameters: tuple
    walker_log_prob: np.ndarray
    walker_acceptance: np.ndarray
    walkers: tuple

    def _values(self, name):
        if name not in self.samples:
            raise ValueError(f"name must be one of {list(self.samples)}, got {name!r}")
        values = self.samples[name]
        prior = next(p.prior for p in self.parameters if p.name == name)
        if isinstance(prior, UniformAngle):  # re-centre on the circular mean: no split mode
            k = 2 * math.pi / prior.period
            centre = math.atan2(np.mean(np.sin(k * values)), np.mean(np.cos(k * values))) / k
            values = centre + prior.wrap(values - centre)
        return values

    def interval(self, name: str, level: float = 0.95) -> tuple[float, float]:
        """Central credible interval of probability ``level`` (equal tails). For an angle,
        computed in the window of one period centred on the samples' circular mean (so its
        ends may lie outside ``[-period/2, period/2)``)."""
        if not 0 < level < 1:
            raise ValueError(f"level must be in (0, 1), got {level!r}")
        lo, hi = np.quantile(self._values(name), [0.5 - level / 2, 0.5 + level / 2])
        return float(lo), float(hi)

    def summary(self) -> dict:
        """Dict name -> {median, lo68, hi68, lo95, hi95} (angles as in :meth:`interval`)."""
        out = {}
        for name in self.samples:
            v = self._values(name)
            q = np.quantile(v, [0.5, 0.16, 0.84, 0.025, 0.975])
            out[name] = dict(zip(("median", "lo68", "hi68", "lo95", "hi95"), map(float, q)))
        return out


def _initial_walkers(model, n_walkers, initial, rng, max_tries=100):
    ndim = len(model.parameters)
    if initial is not None:
        u0 = model.to_unconstrained(initial)
        if not math.isfinite(model.log_posterior(u0)):
            raise ValueError(f"initial has zero posterior density (outside a prior's support "
                             f"or a refused likelihood): {dict(initial)!r}")
        scale = 1e-3 * np.maximum(np.abs(u0), 1.0)
        draw = lambda k: u0 + scale * rng.standard_normal((k, ndim))  # noqa: E731
    else:
        draw = lambda k: np.column_stack([p.prior.sample(rng, k)  # noqa: E731
                                          for p in model.parameters])
    walkers = draw(n_walkers)
    for _ in range(max_tries):
        bad = [i for i in range(n_walkers) if not math.isfinite(model.log_posterior(walkers[i]))]
        if not bad:
            return walkers
        walkers[bad] = draw(len(bad))
    raise ValueError(f"could not start {n_walkers} walkers with finite posterior density in "
                     f"{max_tries} draws; pass initial= near a plausible value")


def sample_posterior(model: PosteriorModel, *, n_walkers=32, n_steps=2000, seed=None,
                     initial: Mapping | None = None, progress=False, burn_in=None, thin=1,
                     min_tau_multiple=50, allow_short=False) -> PosteriorSamples:
    r"""Draw from the posterior of ``model`` with emcee's ensemble sampler.

    Args:
        model: a :class:`PosteriorModel`.
        n_walkers: >= 2 x the number of parameters.
        n_steps: steps per walker (burn-in included).
        seed: int >= 0 (the same seed gives the same samples), None or a Generator.
        initial: dict name -> value (natural units): walkers start there with a relative
            scatter of 1e-3 in u; None: ``model.initial`` when set, else the prior.
        progress: emcee's progress bar.
        burn_in: steps discarded (default ``n_steps // 4``).
        thin: keep every ``thin``-th step after burn-in.
        min_tau_multiple: the chain must be at least this many times the longest
            autocorrelation time (emcee's estimate after burn-in, ``tol=0``)...
        allow_short: ...unless True (then the result is returned as is; check
            ``autocorr_time`` yourself).

    Returns:
        a :class:`PosteriorSamples`.

    Raises:
        ShortChainError: ``n_steps < min_tau_multiple * max(tau)`` and not ``allow_short``;
            the message gives n_steps, the longest tau and the length needed.
    """
    import emcee

    if not isinstance(model, PosteriorModel):
        raise ValueError(f"model must be a PosteriorModel, got {type(model).__name__}")
    ndim = len(model.parameters)
    for name, value, low in (("n_walkers", n_walkers, max(2 * ndim, 2)),
                             ("n_steps", n_steps, 2), ("thin", thin, 1)):
        check_integer(name, value, low)
    check_size(f"n_steps = {n_steps} steps of n_walkers = {n_walkers} walkers",
               n_steps * n_walkers * (ndim + 1), copies=2)  # emcee's chain and log_prob
    burn_in = n_steps // 4 if burn_in is None else burn_in
    if not (isinstance(burn_in, (int, np.integer)) and 0 <= burn_in < n_steps - 1):
        raise ValueError(f"burn_in must be an integer in [0, n_steps - 1) = [0, {n_steps - 1}),"
                         f" got {burn_in!r}")
    if not (isinstance(min_tau_multiple, (int, float)) and min_tau_multiple >= 0):
        raise ValueError(f"min_tau_multiple must be >= 0, got {min_tau_multiple!r}")
    rng = as_generator(seed)
    start = perturbed_start(_initial_walkers(model, n_walkers,
                                             model.initial if initial is None else initial, rng))

    sampler = emcee.EnsembleSampler(n_walkers, ndim, model.log_posterior)
    # emcee draws from its own RandomState (seeded from global entropy); seed it from ours.
    sampler.random_state = np.random.RandomState(rng.integers(2**32)).get_state()
    sampler.run_mcmc(start, n_steps, progress=progress)

    return _collect(model.parameters, np.swapaxes(sampler.get_chain(), 0, 1),
                    sampler.get_log_prob().T, sampler.acceptance_fraction,
                    tuple(range(n_walkers)), burn_in, thin, min_tau_multiple, allow_short)


def _collect(parameters, chain, walker_log_prob, acceptance, walkers, burn_in, thin,
             min_tau_multiple, allow_short) -> PosteriorSamples:
    """Autocorrelation check and natural-unit samples of ``chain`` (walkers, steps, ndim)."""
    import emcee

    names = [p.name for p in parameters]
    n_steps = chain.shape[1]
    kept = np.swapaxes(chain[:, burn_in:], 0, 1)                 # (steps, walkers, ndim)
    tau = np.atleast_1d(emcee.autocorr.integrated_time(kept, tol=0, quiet=True))
    autocorr = {n: float(t) for n, t in zip(names, tau)}
    tau_max = float(np.max(tau))
    if not allow_short and not n_steps >= min_tau_multiple * tau_max:
        raise ShortChainError(
            f"chain too short for a posterior: n_steps = {n_steps} but the longest "
            f"autocorrelation time is {tau_max:.1f} steps ({names[int(np.argmax(tau))]}); "
            f"{min_tau_multiple} x tau needs n_steps >= {math.ceil(min_tau_multiple * tau_max)}"
            f" (or pass allow_short=True)")
    flat = kept[thin - 1::thin].reshape(-1, len(names))          # emcee's thinning
    samples = {p.name: np.asarray(p.prior.to_natural(flat[:, j]), dtype=np.float64)
               for j, p in enumerate(parameters)}
    return PosteriorSamples(
        samples=samples, log_prob=walker_log_prob[:, burn_in:].T[thin - 1::thin].reshape(-1),
        acceptance_fraction=float(np.mean(acceptance)), autocorr_time=autocorr,
        n_steps=int(n_steps), burn_in=int(burn_in), thin=int(thin), chain=np.array(chain),
        parameters=tuple(parameters), walker_log_prob=np.array(walker_log_prob),
        walker_acceptance=np.array(acceptance, dtype=np.float64),
        walkers=tuple(int(w) for w in walkers))


def main_mode(result: PosteriorSamples, *, max_drop=10.0, min_tau_multiple=50,
              allow_short=False) -> PosteriorSamples:
    r"""``result`` from the walkers of its main mode only.

    An ensemble started at an optimum can lose a walker to a competing optimum of a
    multi-modal posterior (a spectral mixture's line moved to another frequency, say),
    where the stretch move cannot bring it back: its draws are not from the main mode and
    it inflates the autocorrelation times. This keeps the walkers whose median log
    posterior after burn-in is within ``max_drop`` of the best walker's median, and
    recomputes the samples, the autocorrelation times and the length check
    (:func:`sample_posterior`'s ``min_tau_multiple`` / ``allow_short``) from them. Say so
    when reporting: the result is the posterior *restricted to the main mode*.

    Raises:
        ValueError: ``max_drop`` not > 0, or fewer than two walkers would remain.
    """
    if not isinstance(result, PosteriorSamples):
        raise ValueError(f"result must be a PosteriorSamples, got {type(result).__name__}")
    check_positive("max_drop", max_drop)
    level = np.median(result.walker_log_prob[:, result.burn_in:], axis=1)
    keep = np.flatnonzero(level >= level.max() - max_drop)
    if keep.size < 2:
        raise ValueError(f"only {keep.size} walker within max_drop = {max_drop} of the best; "
                         f"raise max_drop")
    return _collect(result.parameters, result.chain[keep], result.walker_log_prob[keep],
                    result.walker_acceptance[keep], tuple(result.walkers[k] for k in keep),
                    result.burn_in, result.thin, min_tau_multiple, allow_short)
