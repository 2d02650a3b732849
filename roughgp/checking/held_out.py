r"""The check out of sample: a model fitted on one part of a map, checked on the part it did
not see (beyond the paper; issue 40).

A model that describes *the surface*, not only the crop it was fitted on, reproduces every
other crop of the same surface: the texture parameters of a held-out part fall among those of
the model's simulations of that part as often as the check's nominal level says
(:mod:`roughgp.checking.model_check`: outside with probability :math:`2 / (n + 1)`). The
in-sample check (the part the model saw) cannot show that: a fit follows its own data.

A :class:`Part` is a rectangle of the map, by name (:data:`HALVES`: ``"left"`` and
``"right"`` halves of the columns, ``"top"`` and ``"bottom"`` halves of the rows, row 0 at
the top as an image shows it) or by indices ``"R0:R1,C0:C1"`` (rows and columns, Python's
half-open ranges); a half's held-out part is the other half (:func:`held_out_of`).
:func:`held_out_check` checks the model on both parts side by side: each part is a
measurement of its own (its F-operator and filters applied to it alone, its simulations drawn
on its grid).

Two things make the out-of-sample check say "outside" more often than 10 % even for the
right family of models: the fitted parameters are uncertain (the plug-in simulations are too
alike; :mod:`roughgp.checking.predictive` draws them from the fit's bootstrap), and the
surface may vary across the part (then no stationary model describes it; the tile check,
:mod:`roughgp.checking.tiles`, shows where). How often it says so on synthetic surfaces of
known models is measured by ``benchmarks/held_out_calibration.py``.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from roughgp.checking.model_check import ModelCheck, check_model
from roughgp.surface_models.model import FittedModel

__all__ = ["HALVES", "MIN_PART", "Part", "part_of", "held_out_of", "HeldOutCheck",
           "held_out_check"]

HALVES = ("left", "right", "top", "bottom")
_OTHER_HALF = {"left": "right", "right": "left", "top": "bottom", "bottom": "top"}
MIN_PART = 16  #: the fewest rows and columns of a part (the spatial parameters need lags)
_RANGES = re.compile(r"^\s*(\d+)\s*:\s*(\d+)\s*,\s*(\d+)\s*:\s*(\d+)\s*$")


@dataclasses.dataclass(frozen=True)
class Part:
    """A rectangle ``rows`` x ``cols`` (half-open index ranges) of a map of ``of_shape``."""

    name: str
    rows: tuple
    cols: tuple
    of_shape: tuple

    @property
    def shape(self) -> tuple:
        return (self.rows[1] - self.rows[0], self.cols[1] - self.cols[0])

    def cut(self, z) -> np.ndarray:
        """The part of the map ``z`` (a copy); ``z`` must have the shape the part was cut
        from."""
        z = np.asarray(z)
        if z.shape != tuple(self.of_shape):
            raise ValueError(f"the part {self.name!r} is of a {self.of_shape[0]} x "
                             f"{self.of_shape[1]} map, got one of shape {z.shape}")
        return z[self.rows[0]:self.rows[1], self.cols[0]:self.cols[1]].copy()

    def overlaps(self, other: "Part") -> bool:
        return (self.rows[0] < other.rows[1] and other.rows[0] < self.rows[1]
                and self.cols[0] < other.cols[1] and other.cols[0] < self.cols[1])

    def to_dict(self) -> dict:
        return {"name": self.name, "rows": list(self.rows), "cols": list(self.cols),
                "of_shape": list(self.of_shape)}

    @classmethod
    def from_dict(cls, record) -> "Part":
        try:
            part = part_of(record["of_shape"], record["name"])
        except (KeyError, TypeError) as error:
            raise ValueError(f"a part record needs name and of_shape, got {record!r}") from error
        if list(part.rows) != list(record.get("rows", part.rows)) or \
                list(part.cols) != list(record.get("cols", part.cols)):
            raise ValueError(f"the part record {record!r} does not match its name")
        return part


def part_of(shape, spec: str) -> Part:
    """The part ``spec`` of a map of ``shape = (ny, nx)``: a half's name (:data:`HALVES`) or
    ``"R0:R1,C0:C1"``. Raises ValueError naming the allowed forms and ranges."""
    ny, nx = (int(n) for n in shape)
    spec = str(spec).strip()
    if spec in HALVES:
        rows, cols = (0, ny), (0, nx)
        if spec in ("left", "right"):
            cols = (0, nx // 2) if spec == "left" else (nx // 2, nx)
        else:
            rows = (0, ny // 2) if spec == "top" else (ny // 2, ny)
    else:
        match = _RANGES.match(spec)
        if match is None:
            raise ValueError(f"part must be one of {', '.join(HALVES)} or 'R0:R1,C0:C1' "
                             f"(row and column ranges), got {spec!r}")
        r0, r1, c0, c1 = (int(g) for g in match.groups())
        if not (0 <= r0 < r1 <= ny and 0 <= c0 < c1 <= nx):
            raise ValueError(f"part {spec!r}: rows must lie in 0:{ny} and columns in 0:{nx} "
                             f"(start < stop) on this {ny} x {nx} map")
        rows, cols = (r0, r1), (c0, c1)
    part = Part(spec, rows, cols, (ny, nx))
    if min(part.shape) < MIN_PART:
        raise ValueError(f"part {spec!r} of the {ny} x {nx} map is {part.shape[0]} x "
                         f"{part.shape[1]} points: a part needs at least {MIN_PART} rows and "
                         f"columns")
    return part


def held_out_of(part: Part) -> Part:
    """The other half of a half (:data:`HALVES`); a part given by indices has no single
    complement (raises ValueError: name the held-out part)."""
    if part.name not in _OTHER_HALF:
        raise ValueError(f"the part {part.name!r} is given by indices: name the held-out part "
                         f"too (a half, {', '.join(HALVES)}, has the other half)")
    return part_of(part.of_shape, _OTHER_HALF[part.name])


@dataclasses.dataclass(frozen=True)
class HeldOutCheck:
    """The model on the part it was fitted on and on a part it did not see."""

    fitted_part: Part
    held_out_part: Part
    fitted: ModelCheck
    held_out: ModelCheck

    def to_dict(self) -> dict:
        return {"fitted_part": self.fitted_part.to_dict(),
                "held_out_part": self.held_out_part.to_dict(),
                "fitted": self.fitted.to_dict(), "held_out": self.held_out.to_dict()}


def held_out_check(model: FittedModel, z, spacing=None, *, fitted_part: Part,
                   held_out_part: Part | None = None, n_simulations=19, seed=0, names=None,
                   models=None) -> HeldOutCheck:
    """Check ``model`` (fitted on ``fitted_part`` of the map ``z``) on that part and on
    ``held_out_part`` (default: the other half), each a measurement of its own
    (:func:`~roughgp.checking.model_check.check_model` with the same seed, ``names`` and
    ``models``: the predictive draws, :func:`roughgp.checking.predictive.bootstrap_models`).
    Raises ValueError when the parts overlap: a held-out part must be unseen."""
    held_out_part = held_out_of(fitted_part) if held_out_part is None else held_out_part
    if fitted_part.overlaps(held_out_part):
        raise ValueError(f"the held-out part {held_out_part.name!r} overlaps the fitted part "
                         f"{fitted_part.name!r}: the model has seen some of it")
    options = dict(n_simulations=n_simulations, seed=seed, names=names, models=models)
    return HeldOutCheck(fitted_part, held_out_part,
                        check_model(model, fitted_part.cut(z), spacing, **options),
                        check_model(model, held_out_part.cut(z), spacing, **options))
