r"""Figure 3 (section 3.2, eq 19 and 20): the two-step honed surface, its cross-hatch and plateau.

One computation, shared by the chapter ``book/honed.ipynb`` (which draws its figures and
states its numbers from the results) and the ledger's checks ``fig3-crosshatch`` and
``fig3-plateau`` (which judge them):

* :func:`figure3` draws figure 3 (the preset :data:`roughgp.models.surfaces.FIGURE_3` on
  :data:`~roughgp.models.surfaces.FIGURE_3_SHAPE`, exactly, by circulant embedding), keeps the
  four ground surfaces of eq 19 and 20 and their minimum, and measures it: the cross-hatch
  (:func:`crosshatch_lobes`) and the plateau (:func:`plateau`). The draw is cached per seed.
* :func:`crosshatch_lobes`: the two lobes of the angular spectrum
  (:func:`roughgp.metrology.texture.angular_spectrum`) near the groove directions
  :math:`\pm\phi` of eq 19, and how far they stand above the power at 0 and 90 degrees.
* :func:`plateau`: ISO 25178-2 and 13565-2 parameters; a plateau-honed surface has
  :math:`Ssk < 0` and :math:`Spk < Svk`.
* :func:`finishing_sweep`: the finishing step's latent variance :math:`\sigma_{k,2}^2` swept
  (eq 20 with step 1 held fixed per seed, a paired comparison) and its effect on Sk, Spk,
  Svk and Ssk.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from roughgp.metrology import texture
from roughgp.models import surfaces

__all__ = ["SEED", "NOISE_VARIANCE", "LOBE_HALF_WIDTH", "QUIET_WIDTH", "Crosshatch", "Plateau",
           "Figure3", "FinishingSweep", "figure3_stack", "crosshatch_lobes", "plateau",
           "figure3", "CrosshatchSeeds", "crosshatch_over_seeds", "finishing_sweep"]

#: The seed of figure 3's draw (the chapter's and the ledger's).
SEED = 3
#: sigma^2 of eq 8, on every ground surface (the paper: 1 "in all cases").
NOISE_VARIANCE = 1.0
#: A lobe is the angular spectrum's maximum within this many degrees of +-phi.
LOBE_HALF_WIDTH = 20.0
#: The power between the lobes: the mean within this many degrees of 0 and of 90 degrees.
QUIET_WIDTH = 5.0


@dataclasses.dataclass(frozen=True)
class Crosshatch:
    """The cross-hatch in the angular spectrum (eq 19: groove families at +phi and -phi).

    Attributes:
        angles, power: the angular spectrum (lay direction in degrees, power per sector).
        expected: the groove directions ``(-phi, +phi)`` in degrees.
        lobe_angles: the direction of the maximum near each expected direction (degrees).
        lobe_powers: the power at those maxima.
        quiet_power: the mean power within :data:`QUIET_WIDTH` degrees of 0 and 90 degrees.
    """

    angles: np.ndarray
    power: np.ndarray
    expected: tuple
    lobe_angles: tuple
    lobe_powers: tuple
    quiet_power: float

    @property
    def offsets(self) -> tuple:
        """Each lobe's angle less its expected direction (degrees)."""
        return tuple(a - e for a, e in zip(self.lobe_angles, self.expected))

    @property
    def ratios(self) -> tuple:
        """Each lobe's power over the power at 0 and 90 degrees."""
        return tuple(p / self.quiet_power for p in self.lobe_powers)


@dataclasses.dataclass(frozen=True)
class Plateau:
    """The height parameters of a surface (ISO 25178-2, 13565-2), keyed by their names."""

    parameters: dict

    @property
    def ssk(self) -> float:
        """Skewness Ssk (< 0 for a plateau)."""
        return float(self.parameters["Ssk"])

    @property
    def spk(self) -> float:
        """Reduced peak height Spk."""
        return float(self.parameters["Spk"])

    @property
    def svk(self) -> float:
        """Reduced valley depth Svk (> Spk for a plateau)."""
        return float(self.parameters["Svk"])


@dataclasses.dataclass(frozen=True)
class Figure3:
    """Figure 3 and what it shows.

    Attributes:
        seed, noise_variance: the draw's.
        stack: the ground surfaces, shape ``(P, 2, ny, nx)`` (:func:`surfaces.honing_stack`).
        surface: their minimum, the honed surface (eq 19, 20).
        crosshatch: :func:`crosshatch_lobes` of ``surface``.
        plateau: :func:`plateau` of ``surface``.
    """

    seed: int
    noise_variance: float
    stack: np.ndarray
    surface: np.ndarray
    crosshatch: Crosshatch
    plateau: Plateau

    @property
    def source(self) -> np.ndarray:
        """For each point, the index (step * 2 + mirrored) of the ground surface that is lowest."""
        return self.stack.reshape(-1, *self.surface.shape).argmin(axis=0)

    @property
    def share(self) -> np.ndarray:
        """The fraction of the points each ground surface supplies (same order as ``source``)."""
        return np.bincount(self.source.ravel(), minlength=self.stack.shape[0] * 2) / self.surface.size


@functools.lru_cache(maxsize=1)
def _cached_stack(shape, steps, noise_variance, seed):
    stack = surfaces.honing_stack(shape, steps, noise_variance=noise_variance, seed=seed)
    stack.setflags(write=False)
    return stack


def figure3_stack(seed=SEED, *, noise_variance=NOISE_VARIANCE, shape=surfaces.FIGURE_3_SHAPE,
                  steps=surfaces.FIGURE_3) -> np.ndarray:
    """The ground surfaces of figure 3 (eq 19, 20), drawn exactly from ``seed``; cached, read-only.

    ``shape`` and ``steps`` default to the paper's (512 x 512, two steps at phi = pi/4).
    """
    return _cached_stack(tuple(shape), tuple(steps), float(noise_variance), int(seed))


def _lobe(angles, power, centre, half_width):
    """Direction and power of the maximum within ``half_width`` degrees of ``centre``."""
    near = np.abs(angles - centre) <= half_width
    k = np.argmax(power[near])
    return float(angles[near][k]), float(power[near][k])


def _quiet_power(angles, power, width):
    """The mean power within ``width`` degrees of 0 and of 90 degrees (between +-45 deg lobes)."""
    return float(power[(np.abs(angles) <= width) | (np.abs(angles) >= 90 - width)].mean())


def crosshatch_lobes(z, *, phi=surfaces.FIGURE_3[0].angle, half_width=LOBE_HALF_WIDTH,
                     quiet_width=QUIET_WIDTH) -> Crosshatch:
    """The two lobes of the angular spectrum of ``z`` near the groove directions -phi and +phi.

    Args:
        z: heights ``z[iy, ix]``.
        phi: the groove angle of eq 19 in radians (figure 3: pi/4).
        half_width: a lobe is the maximum within this many degrees of -+phi.
        quiet_width: the reference power is the mean within this many degrees of 0 and 90.
    """
    angles, power = texture.angular_spectrum(z)
    expected = (-math.degrees(phi), math.degrees(phi))
    lobes = [_lobe(angles, power, centre, half_width) for centre in expected]
    return Crosshatch(angles, power, expected, tuple(a for a, _ in lobes),
                      tuple(p for _, p in lobes), _quiet_power(angles, power, quiet_width))


def plateau(z) -> Plateau:
    """ISO 25178-2 and 13565-2 parameters of ``z`` (Ssk, Spk, Svk, Sk, ...), Str NaN if undefined."""
    return Plateau(dict(texture.areal_parameters(z, undefined="nan")))


def figure3(seed=SEED, *, noise_variance=NOISE_VARIANCE, shape=surfaces.FIGURE_3_SHAPE,
            steps=surfaces.FIGURE_3) -> Figure3:
    """Figure 3 (eq 19, 20) drawn from ``seed``, with its cross-hatch and plateau measured."""
    stack = figure3_stack(seed, noise_variance=noise_variance, shape=shape, steps=steps)
    z = stack.min(axis=(0, 1))
    return Figure3(int(seed), float(noise_variance), stack, z,
                   crosshatch_lobes(z, phi=steps[0].angle), plateau(z))


@dataclasses.dataclass(frozen=True)
class CrosshatchSeeds:
    """The cross-hatch of figure 3's model over several draws.

    One 512 x 512 draw holds few of step 1's grooves (lambda_a = 500): its lobe for one family
    can come out faint, so the claim "two lobes at +-phi" is judged over draws, not on one.

    Attributes:
        seeds: the seeds drawn (figure 3's own first).
        offsets: ``(len(seeds), 2)`` lobe direction minus -phi, +phi, in degrees.
        ratios: ``(len(seeds), 2)`` each lobe's power over the power at 0 and 90 degrees.
    """

    seeds: tuple
    offsets: np.ndarray
    ratios: np.ndarray

    @property
    def median_ratios(self) -> tuple:
        """The median ratio of the lobe at -phi and of the lobe at +phi."""
        return tuple(float(r) for r in np.median(self.ratios, axis=0))


def crosshatch_over_seeds(n_seeds, *, seed=SEED, noise_variance=NOISE_VARIANCE,
                          shape=surfaces.FIGURE_3_SHAPE,
                          steps=surfaces.FIGURE_3) -> CrosshatchSeeds:
    """:func:`crosshatch_lobes` of figure 3's surface (eq 19, 20) drawn from seeds
    ``seed, seed + 1, ..., seed + n_seeds - 1``."""
    seeds = tuple(range(int(seed), int(seed) + int(n_seeds)))
    lobes = [figure3(s, noise_variance=noise_variance, shape=shape, steps=steps).crosshatch
             for s in seeds]
    return CrosshatchSeeds(seeds, np.array([c.offsets for c in lobes]),
                           np.array([c.ratios for c in lobes]))


@dataclasses.dataclass(frozen=True)
class FinishingSweep:
    """Height parameters against the finishing step's latent variance (eq 20).

    Attributes:
        variances: the values of sigma_{k,2}^2.
        seeds: the seed of each surface's step 1 (step 2 uses seed + 1).
        values: for each key, an array ``(len(variances), len(seeds))``.
    """

    variances: tuple
    seeds: tuple
    values: dict

    def change(self, key) -> np.ndarray:
        """Per seed, ``key`` at the largest variance less at the smallest (paired)."""
        return self.values[key][-1] - self.values[key][0]


def _sweep_seed(shape, steps, variances, seed, keys):
    """One seed of the sweep: ``{key: values over variances}``; step 1 drawn once (eq 19, 20)."""
    step_1 = surfaces.honed(shape, steps[:1], seed=seed)                       # eq 19, step 1
    values = {k: np.empty(len(variances)) for k in keys}
    for i, variance in enumerate(variances):
        step_2 = surfaces.honed(shape, [dataclasses.replace(steps[1], variance=variance)],
                                seed=seed + 1)
        p = texture.areal_parameters(np.minimum(step_1, step_2), undefined="nan")    # eq 20
        for k in keys:
            values[k][i] = p[k]
    return values


def finishing_sweep(variances, n_seeds, *, seed=SEED, shape=surfaces.FIGURE_3_SHAPE,
                    steps=surfaces.FIGURE_3, keys=("Sk", "Spk", "Svk", "Ssk")) -> FinishingSweep:
    """Sweep sigma_{k,2}^2 of figure 3's finishing step; step 1 is drawn once per seed.

    Surface ``j`` uses the seed ``seed + 100 (j + 1)`` for step 1 and that plus 1 for step 2,
    so for each seed the same step-1 surfaces serve every variance (a paired comparison).
    """
    variances, seeds = tuple(variances), tuple(seed + 100 * (j + 1) for j in range(n_seeds))
    per_seed = [_sweep_seed(shape, steps, variances, s, keys) for s in seeds]
    values = {k: np.stack([v[k] for v in per_seed], axis=1) for k in keys}
    return FinishingSweep(variances, seeds, values)
