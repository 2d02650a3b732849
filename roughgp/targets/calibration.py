r"""Ground surfaces drawn with prescribed ISO 25178-2 Sq, Sal, Str and Std (beyond the paper).

:func:`simulate_with_targets` draws a ground surface (eq 18 plus the noise of eq 8) whose
parameters are the targets: with the closed-form hyperparameters of
:func:`roughgp.targets.closed_form.hyperparameters_for` (exact for an infinite field), or with those
of a :class:`Calibration`. :func:`calibrate` corrects the closed form for the biases of a
finite field and grid by simulation (a few multiplicative fixed-point corrections of the
targets, on the mean over a set of seeds; the reasons are in :mod:`roughgp.targets.closed_form`).

Units as in :mod:`roughgp.targets.closed_form`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from roughgp.models import surfaces
from roughgp.targets.closed_form import (
    TARGET_NAMES,
    GroundHyperparameters,
    RoughnessTargets,
    achieved_parameters,
    as_targets,
    check_spacing,
    direction_difference,
    field_warning,
    finite_number,
    fold_direction,
    hyperparameters_for,
    summarize,
    surface_shape,
)

__all__ = ["Calibration", "calibrate", "simulate_with_targets"]


@dataclass(frozen=True)
class Calibration:
    """The result of :func:`calibrate`.

    Attributes:
        targets: the prescribed :class:`RoughnessTargets`.
        shape, spacing, noise_variance: the field and noise it was calibrated for.
        hyperparameters: the calibrated :class:`GroundHyperparameters`.
        closed_form: those of :func:`hyperparameters_for` for the targets themselves.
        history: per round, ``(inputs, means)``: the targets fed to the closed form and the
            mean measured parameters over ``seeds`` (dicts by name); the last entry's inputs
            gave ``hyperparameters``, its means are those the round measured (NaN when the
            last correction was not measured again).
        seeds: the seeds of the surfaces simulated in every round.
    """

    targets: RoughnessTargets
    shape: tuple
    spacing: object
    noise_variance: float
    hyperparameters: GroundHyperparameters
    closed_form: GroundHyperparameters
    history: tuple
    seeds: tuple


def calibrate(targets, shape, *, seeds=range(8), iterations=3, noise_variance=1.0,
              spacing=1.0, method="auto", correct=("Sq", "Sal", "Str")) -> Calibration:
    r"""Hyperparameters whose surfaces of ``shape`` hit the targets ON AVERAGE.

    The closed form (:func:`hyperparameters_for`) is exact for an infinite field. On a
    finite one the estimators are biased (module docstring). Starting from the targets
    themselves, each round draws one surface per seed with the hyperparameters of the
    current inputs (eq 18 plus eq 8), measures the mean of each parameter over the seeds,
    and corrects the inputs: multiplicatively for Sq, Sal and Str
    (:math:`T_{in} \leftarrow T_{in}\,T/\bar M`, which scales :math:`\sigma_k^2` and the
    lengthscales :math:`\lambda_b \propto S_{al}`, :math:`\lambda_a \propto S_{al}/S_{tr}`),
    additively for Std (only when named in ``correct``; for a strong lay its mean was found
    within about a degree of the target, pulled slightly toward the grid's axes). Str is
    capped at 1 and Sq kept above the limit :math:`\sqrt{5\sigma^2/4}`.
    The same seeds are used in every round; they give the same white noise only while the
    sampler keeps its circulant torus, so the rounds also differ by the luck of the draw.

    Cost: ``iterations`` rounds of ``len(seeds)`` surfaces. The result hits the targets on
    the mean over THESE seeds, so it is only as precise as that mean: a bias smaller than
    one surface's sd / sqrt(len(seeds)) cannot be corrected. Judge it on other seeds.

    Args:
        targets: :class:`RoughnessTargets` or a mapping with the keys Sq, Sal, Str, Std.
        shape: ``(ny, nx)`` of the surfaces to be drawn.
        seeds: the seeds of each round's surfaces (at least 2).
        iterations: number of corrections (rounds), >= 1.
        noise_variance, spacing: as in :func:`hyperparameters_for`.
        method: the sampler of :func:`roughgp.models.surfaces.ground`.
        correct: which parameters to correct (a subset of Sq, Sal, Str, Std).

    Raises:
        ValueError: bad arguments, or Sal / Str undefined on a surface (the field is too
            short for the grooves: the message says so).
    """
    t = as_targets(targets)
    shape = surface_shape(shape)
    seeds = tuple(seeds)
    if len(seeds) < 2:
        raise ValueError(f"seeds must name at least 2 seeds, got {seeds!r}")
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) \
            or iterations < 1:
        raise ValueError(f"iterations must be an integer >= 1, got {iterations!r}")
    unknown = [c for c in correct if c not in TARGET_NAMES]
    if unknown:
        raise ValueError(f"correct must name parameters among {', '.join(TARGET_NAMES)}, "
                         f"got {', '.join(map(repr, unknown))}")
    noise_variance = finite_number("noise_variance", noise_variance)
    closed_form = hyperparameters_for(**t.as_dict(), noise_variance=noise_variance,
                                      spacing=spacing)
    inputs = t.as_dict()
    lowest = math.sqrt(5.0 * noise_variance / 4.0)
    history = []
    for _ in range(int(iterations)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the resolution warning was given once above
            hyper = hyperparameters_for(**inputs, noise_variance=noise_variance,
                                        spacing=spacing)
        values = achieved_parameters(hyper, shape, seeds=seeds, spacing=spacing,
                                     method=method)
        for name in correct:
            bad = int(np.count_nonzero(np.isnan(values[name])))
            if bad:
                raise ValueError(
                    f"{name} is undefined on {bad} of {len(seeds)} surfaces of shape "
                    f"{shape}: the ACF does not decay to 0.2 within the field (the decay "
                    f"length along the grooves is about Sal/Str = {t.Sal / t.Str:.4g}); "
                    f"use a larger shape, or leave {name} out of correct")
        means = {name: m for name, (m, _) in summarize(values).items()}
        history.append((dict(inputs), means))
        new = dict(inputs)
        if "Sq" in correct:
            new["Sq"] = max(inputs["Sq"] * t.Sq / means["Sq"], lowest * (1 + 1e-9))
        if "Sal" in correct:
            new["Sal"] = inputs["Sal"] * t.Sal / means["Sal"]
        if "Str" in correct:
            new["Str"] = min(1.0, inputs["Str"] * t.Str / means["Str"])
        if "Std" in correct:
            new["Std"] = fold_direction(inputs["Std"]
                                        + float(direction_difference(t.Std, means["Std"])))
        inputs = new
    history.append((dict(inputs), dict.fromkeys(TARGET_NAMES, math.nan)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        final = hyperparameters_for(**inputs, noise_variance=noise_variance, spacing=spacing)
    return Calibration(targets=t, shape=shape, spacing=spacing, noise_variance=noise_variance,
                       hyperparameters=final, closed_form=closed_form, history=tuple(history),
                       seeds=seeds)


# --------------------------------------------------------------------------- simulating

def simulate_with_targets(targets, shape, *, seed, spacing=1.0, noise_variance=1.0,
                          calibration: Calibration | None = None, method="auto"):
    r"""A ground surface (eq 18 plus the noise of eq 8, :func:`roughgp.models.surfaces.ground`)
    whose ISO 25178-2 parameters are ``targets`` (Sq 4.1, Sal 4.2.1, Str 4.2.2, Std 4.5.1).

    Args:
        targets: :class:`RoughnessTargets` or a mapping with the keys Sq, Sal, Str, Std.
        shape: ``(ny, nx)``.
        seed: int, None or ``numpy.random.Generator``; the same seed gives the same surface.
        spacing: grid spacing, scalar or ``(dy, dx)``, in the unit of Sal.
        noise_variance: :math:`\\sigma^2` of eq 8 (default 1, the paper's).
        calibration: a :func:`calibrate` result for the same targets, shape, spacing and
            noise variance, whose hyperparameters are used; None: the closed form of
            :func:`hyperparameters_for`, with a ``UserWarning`` when the field spans fewer
            than :data:`MIN_GROOVE_LENGTHS` correlation lengths :math:`\lambda_a`.
        method: the sampler of :func:`roughgp.models.surfaces.ground`.

    Returns:
        ``(z, hyperparameters)``: the surface ``z[iy, ix]`` and the
        :class:`GroundHyperparameters` it was drawn with.
    """
    t = as_targets(targets)
    shape = surface_shape(shape)
    noise_variance = finite_number("noise_variance", noise_variance)
    if calibration is None:
        hyper = hyperparameters_for(**t.as_dict(), noise_variance=noise_variance,
                                    spacing=spacing)
    else:
        if not isinstance(calibration, Calibration):
            raise ValueError(f"calibration must be a Calibration from calibrate(), got "
                             f"{type(calibration).__name__}")
        mismatch = [name for name, mine, theirs in (
            ("targets", t, calibration.targets), ("shape", shape, calibration.shape),
            ("noise_variance", noise_variance, calibration.noise_variance),
            ("spacing", tuple(check_spacing(spacing)),
             tuple(check_spacing(calibration.spacing)))) if mine != theirs]
        if mismatch:
            raise ValueError(f"calibration was made for other {', '.join(mismatch)}: "
                             f"calibrate for these targets, shape, spacing and noise_variance")
        hyper = calibration.hyperparameters
    if calibration is None:
        message = field_warning(hyper, shape, spacing)
        if message:
            warnings.warn(message, stacklevel=2)
    z = surfaces.ground(shape, **hyper.ground_kwargs(), spacing=spacing, seed=seed,
                        method=method)
    return z, hyper
