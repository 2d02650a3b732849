r"""Fits that stay in range: a fitted eq 18 model that ends on a bound of the fit, or with a
correlation length far beyond the field, says so, and a model that cannot be simulated is
replaced by one that can, or refused with the reason (beyond the paper).

One field does not identify a correlation length much longer than itself: over the field, eq 18
with :math:`\lambda \gg` the field is :math:`\sigma_k^2 (1 - r + \dots)`, a random walk's
variogram :math:`\sigma_k^2 r` whose slope :math:`\sigma_k^2 / \lambda_a` is all the data pin.
The block fit (:mod:`roughgp.inference.block_fit`) then runs to its upper bound of fifty blocks,
and a circulant embedding of such an ACVF on the field's grid can stay indefinite (the issue's
FRT file: :math:`\lambda_a = 2.4 \cdot 10^5` um, "keeps negative eigenvalues").
:func:`keep_in_range`:

1. names what is out of range (:func:`range_findings`): a length on the fit's upper bound, a
   length more than :data:`FAR_BEYOND` times the field's longer side;
2. if any, caps both lengths at the field's longer side and scales the variance by
   :math:`\lambda_a' / \lambda_a`, which keeps the variogram's slope along the lay (what the
   field pins; across the lay it is then steeper by the same factor), and keeps the findings,
   what was done and the fitted values in the model's ``fit``. Trying the fitted model first is
   no option: on the FRT file its embedding search took 150 s before it failed;
3. draws once from the model to be written on the measurement's grid; if that fails the fit is
   refused (``ValueError`` with the reason), so ``simulate --from`` at the measurement's size
   does not fail on a model that ``fit`` wrote.
"""

from __future__ import annotations

import dataclasses

from roughgp.inference.whittle_fit import FAR_BEYOND
from roughgp.surface_models.model import FittedModel

__all__ = ["FAR_BEYOND", "range_findings", "keep_in_range"]

#: the block fit's upper bound on the lengths, in blocks (roughgp.inference.block_fit)
_BOUND_BLOCKS = 50.0


def _field(shape, spacing) -> float:
    return float(max(n * d for n, d in zip(shape, spacing)))


def range_findings(model: FittedModel, shape, block) -> list:
    """What is out of range in a fitted surface model on a field of ``shape`` (points), fitted
    with blocks of ``block`` points (None: a fit of the whole field, whose bound lies far beyond
    it): one sentence per finding (empty: none)."""
    if model.kind != "surface":
        return []
    hp = model.hyperparameters
    field = _field(shape, model.spacing)
    bound = None if block is None else _BOUND_BLOCKS * block * max(model.spacing)
    found = []
    for name in ("lambda_a_um", "lambda_b_um"):
        if bound is not None and hp[name] >= 0.98 * bound:
            found.append(f"{name} = {hp[name]:.4g} um lies on the fit's upper bound "
                         f"({bound:.4g} um, {_BOUND_BLOCKS:g} blocks)")
        elif hp[name] > FAR_BEYOND * field:
            found.append(f"{name} = {hp[name]:.4g} um is {hp[name] / field:.3g} times the "
                         f"field's longer side ({field:.4g} um): the field does not pin it")
    return found


def _draw_fails(model, shape):
    """None if ``model`` draws on ``shape``, else the sampler's reason."""
    try:
        model.simulate(shape, seed=0)
    except (ValueError, MemoryError) as exc:
        return str(exc)
    return None


def keep_in_range(model: FittedModel, shape, block) -> tuple:
    """``(model, notes)``: the fitted ``model`` kept, or replaced when out of range (module
    docstring). Raises ``ValueError`` with the reason when the model to be written does not
    draw on the measurement's grid."""
    findings = range_findings(model, shape, block)
    notes = list(findings)
    if findings:
        hp = model.hyperparameters
        field = _field(shape, model.spacing)
        scale = min(1.0, field / hp["lambda_a_um"])
        capped = {**hp, "lambda_a_um": min(hp["lambda_a_um"], field),
                  "lambda_b_um": min(hp["lambda_b_um"], field),
                  "variance_um2": hp["variance_um2"] * scale}
        notes.append(f"replaced by lengths capped at the field's longer side ({field:.4g} um) "
                     f"and the variance scaled by {scale:.3g} (the variogram's slope along the "
                     f"lay kept): lambda_a {capped['lambda_a_um']:.4g} um, lambda_b "
                     f"{capped['lambda_b_um']:.4g} um, variance {capped['variance_um2']:.4g} "
                     f"um^2")
        model = dataclasses.replace(model, hyperparameters=capped,
                                    fit={**model.fit, "range": notes,
                                         "fitted_hyperparameters": dict(hp)})
    failure = _draw_fails(model, shape)
    if failure is not None:
        raise ValueError("the fit gives no model that can be simulated on the measurement's "
                         "grid: " + "; ".join(notes + [failure.splitlines()[0]]))
    return model, notes
