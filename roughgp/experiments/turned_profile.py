r"""Figures 4 and 5 (section 3.3): the spectral mixture of eq 21 fitted to a turned profile, and
profiles simulated from the fit.

The paper's measured profile (a turned Rubert standard) is replaced by the synthetic stand-in
:func:`roughgp.models.turned.turned_profile`, tilted as a measurement arrives and levelled by
:func:`roughgp.metrology.levelling.level`. The computations, each returning a result object:

* :func:`figure5_fit` (cached): the profile, levelled, and the paper's fitting procedure
  (:func:`roughgp.inference.fitting.fit_spectral_mixture`, :math:`Q = 5`) on it, with every
  candidate's start and end (the multi-modality of section 3.3-3.4);
* :func:`figure5_simulations`: profiles drawn from the fitted GP (exactly, by circulant
  embedding) plus the fitted noise of eq 8 and the mean, and their ISO 4287 parameters against
  the data's (the claim "wide dales and narrow hills").

The chapter ``book/turned_profiles.ipynb`` draws and states its numbers from these results; the
ledger's claims ``fig5-periodicity``, ``fit-multimodal`` and ``fig5-dales-hills`` judge them.
"""

from __future__ import annotations

import dataclasses
import functools
import time

import numpy as np

from roughgp import sampling
from roughgp.gp.noise import GaussianNoise
from roughgp.inference import fitting
from roughgp.metrology import levelling, texture
from roughgp.models import turned

__all__ = ["SEED", "N_POINTS", "SPACING", "Q", "PARAMS", "PARAMETER_KEYS", "TurnedProfileFit",
           "TurnedProfileSimulations", "figure5_fit", "figure5_simulations", "dale_share",
           "profile_values"]

SEED = 7
N_POINTS = 8192               # an 8.2 mm profile at 1 um
SPACING = 1.0                 # um
Q = 5                         # components of eq 21, as in the paper
PARAMS = turned.TurnedParameters(tilt=0.002)   # RUBERT_LIKE (f = 250 um, r = 800 um) + a tilt
PARAMETER_KEYS = ("Ra", "Rq", "Rsk", "Rku", "RSm", "dale share")
"""The parameters compared between data and simulations (ISO 4287, and the share of the
profile below its mean line)."""


def dale_share(h) -> float:
    """The share of a profile below its mean line (more than one half: wide dales)."""
    h = np.asarray(h, dtype=float)
    return float(np.mean(h < h.mean()))


def profile_values(h, spacing) -> dict:
    """The parameters of :data:`PARAMETER_KEYS` of the profile ``h`` (NaN where undefined)."""
    values = texture.profile_parameters(h, spacing, undefined="nan")
    return {key: float(values[key]) if key != "dale share" else dale_share(h)
            for key in PARAMETER_KEYS}


@dataclasses.dataclass(frozen=True)
class TurnedProfileFit:
    """A turned profile, levelled, and eq 21 fitted to it by the paper's procedure.

    ``x``, ``raw`` (as measured, tilted) and ``z`` (levelled) are read-only arrays in um;
    ``fit`` is the :class:`~roughgp.inference.fitting.SpectralMixtureFit` (its ``candidates``
    hold every start); ``measured``: the levelled profile's :data:`PARAMETER_KEYS`;
    ``seconds``: the time the fit took.
    """

    n_points: int
    spacing: float
    parameters: turned.TurnedParameters
    n_components: int
    seed: int
    x: np.ndarray
    raw: np.ndarray
    z: np.ndarray
    fit: fitting.SpectralMixtureFit
    measured: dict
    seconds: float

    @property
    def feed(self) -> float:
        """The true period of the profile (um)."""
        return float(self.parameters.feed)

    @property
    def period_error(self) -> float:
        """The dominant fitted period relative to the feed, less one."""
        return float(self.fit.dominant_period / self.feed - 1)

    @property
    def initial_log_likelihoods(self) -> np.ndarray:
        """Every candidate's log marginal likelihood at its start."""
        return np.array([c.initial_log_likelihood for c in self.fit.candidates])

    @property
    def optimised_log_likelihoods(self) -> np.ndarray:
        """The optimised candidates' final log marginal likelihoods, ascending."""
        return np.sort([c.final_log_likelihood for c in self.fit.candidates if c.optimised])

    @property
    def n_feeds(self) -> float:
        """The profile's length in feeds."""
        return self.n_points * self.spacing / self.feed

    @property
    def n_distinct_optima(self) -> int:
        """How many different optima (to one log-likelihood unit) the optimised starts reach."""
        return len({round(float(v), 0) for v in self.optimised_log_likelihoods})


@dataclasses.dataclass(frozen=True)
class TurnedProfileSimulations:
    """Profiles simulated from a :class:`TurnedProfileFit` and their parameters.

    ``profiles``: shape (n_simulations, n_points), the fitted mean plus the latent draw plus
    eq 8's noise; ``values``: per key of :data:`PARAMETER_KEYS`, one value per profile
    (NaN where undefined); ``measured``: the data's; ``ranges``: each key's 2.5-97.5 %
    range over the simulations; ``inside``: whether the data's value lies in it.
    """

    seed: int
    profiles: np.ndarray
    values: dict
    measured: dict
    ranges: dict
    inside: dict

    @property
    def n_simulations(self) -> int:
        return int(self.profiles.shape[0])


def _read_only(array):
    array = np.asarray(array)
    array.setflags(write=False)
    return array


def figure5_fit(n_points: int = N_POINTS, *, spacing: float = SPACING,
                parameters: turned.TurnedParameters = PARAMS, n_components: int = Q,
                seed: int = SEED) -> TurnedProfileFit:
    """The turned profile of figure 4's stand-in, levelled, with eq 21 fitted to it.

    The profile is ``turned.turned_profile(n_points, spacing, parameters, seed=seed)``; the
    fit is ``fitting.fit_spectral_mixture(x, z, n_components, seed=seed)``. The last call is
    cached (the arrays are read-only), so the chapter's and the ledger's several uses fit once.
    """
    return _cached_fit(int(n_points), float(spacing), parameters, int(n_components), int(seed))


@functools.lru_cache(maxsize=1)
def _cached_fit(n_points, spacing, parameters, n_components, seed):
    x, raw = turned.turned_profile(n_points, spacing, parameters, seed=seed)
    z = levelling.level(raw, spacing=spacing)
    start = time.perf_counter()
    fit = fitting.fit_spectral_mixture(x, z, n_components, seed=seed)
    seconds = time.perf_counter() - start
    return TurnedProfileFit(n_points, spacing, parameters, n_components, seed, _read_only(x),
                            _read_only(raw), _read_only(z), fit, profile_values(z, spacing),
                            seconds)


def figure5_simulations(result: TurnedProfileFit, n_simulations: int, *,
                        seed: int | None = None) -> TurnedProfileSimulations:
    """``n_simulations`` profiles from the fitted GP on the data's grid, and their parameters.

    The latent draws come from ``seed`` (default: the fit's seed + 1), eq 8's noise from
    ``seed + 1``.
    """
    seed = result.seed + 1 if seed is None else int(seed)
    fit = result.fit
    latent = sampling.sample_grid(fit.kernel(), (result.n_points,), spacing=result.spacing,
                                  n_samples=n_simulations, seed=seed)
    profiles = fit.mean + GaussianNoise(fit.noise_variance).sample(latent, seed=seed + 1)
    each = [profile_values(p, result.spacing) for p in profiles]
    values = {key: np.array([v[key] for v in each]) for key in PARAMETER_KEYS}
    ranges = {key: tuple(float(b) for b in np.nanpercentile(v, [2.5, 97.5]))
              for key, v in values.items()}
    inside = {key: bool(lo <= result.measured[key] <= hi) for key, (lo, hi) in ranges.items()}
    return TurnedProfileSimulations(seed, _read_only(profiles), values, dict(result.measured),
                                    ranges, inside)
