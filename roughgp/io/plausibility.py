"""What a reading may claim: one bounds table, checked on every file read.

A damaged or misread file can give numbers that no surface has: one changed byte of a Wyko
``.opd`` gives heights of 1e30 µm, a ``.sur`` whose z-scale reads 1e30 gives 1e34, a spacing
read in the wrong unit puts a 512² field 160 m wide. :func:`check_reading` refuses such a
reading with the implausible value named, rather than computing texture parameters from it.
The bounds (:data:`BOUNDS`, in µm) are wide: a metre for heights and fields, a picometre to a
metre for a step. Real instruments sit far inside them (the 22 files of
:mod:`roughgp.experiments.real_maps`: heights up to 0.107 m, a stage's level; steps from 1e-4
to 200 µm; fields up to 60 mm).
"""

from __future__ import annotations

import math

import numpy as np

from roughgp.io.readers import MalformedFileError

__all__ = ["BOUNDS", "check_reading"]

#: What a reading may claim, in µm: ``"height"``: the largest ``|z|``; ``"step"``: the smallest
#: and largest lateral step; ``"field"``: the largest extent of the map along an axis.
BOUNDS = {"height": 1e6, "step": (1e-6, 1e6), "field": 1e6}


def _um(value: float) -> str:
    return f"{value:.4g} um" + (f" ({value / 1e6:.3g} m)" if abs(value) >= 1e5 else "")


def check_reading(z, spacing, path) -> None:
    """Refuse a reading that no surface measurement can be (:data:`BOUNDS`).

    Args:
        z: heights in µm, ``z[ix]`` or ``z[iy, ix]``, NaN where unmeasured.
        spacing: the steps in µm in array order.
        path: the file, named in the message.

    Raises:
        MalformedFileError: naming the file and the implausible value: a step that is not
            finite or outside ``BOUNDS["step"]``, a field wider than ``BOUNDS["field"]``, a
            height beyond ``BOUNDS["height"]`` (with its index), or no measured point.
    """
    z = np.asarray(z)
    low, high = BOUNDS["step"]
    axes = ("x",) if z.ndim == 1 else ("y", "x")
    for axis, step, n in zip(axes, spacing, z.shape):
        step = float(step)
        an = "an" if axis == "x" else "a"
        if not (math.isfinite(step) and low <= step <= high):
            raise MalformedFileError(
                f"{path}: implausible reading: {an} {axis} step of {step!r} um, outside the "
                f"{low:g} to {high:g} um (1 pm to 1 m) a measurement's step can be (a damaged "
                "file, or a spacing read in the wrong unit)")
        if step * n > BOUNDS["field"]:
            raise MalformedFileError(
                f"{path}: implausible reading: {n} points at {an} {axis} step of {_um(step)} "
                f"make a field {_um(step * n)} wide, more than the {BOUNDS['field'] / 1e6:g} m "
                "a measurement can be (a spacing in the wrong unit?)")
    measured = np.isfinite(z)
    if not np.any(measured):
        raise MalformedFileError(f"{path}: holds no measured point: all {z.size} heights are "
                                 "marked unmeasured (NaN)")
    size = np.abs(np.where(measured, z, 0.0))
    worst = np.unravel_index(int(np.argmax(size)), z.shape)
    if size[worst] > BOUNDS["height"]:
        where = ", ".join(str(int(i)) for i in worst)
        beyond = int(np.count_nonzero(size > BOUNDS["height"]))
        raise MalformedFileError(
            f"{path}: implausible reading: the height z[{where}] = {_um(float(z[worst]))}, "
            f"beyond the {BOUNDS['height'] / 1e6:g} m a surface's height can be ({beyond} of "
            f"{z.size} points are; a damaged file, or a height scale read wrong)")
