"""Input checks shared by the library: each raises a ``ValueError`` that names the
parameter and the allowed range, so bad input never turns into a silent NaN."""

from __future__ import annotations

import sys

import numpy as np


def is_tensor(value) -> bool:
    """Whether ``value`` is a torch tensor, without importing torch: a tensor exists only once
    torch is imported, so the numpy paths never load it."""
    torch = sys.modules.get("torch")
    return torch is not None and isinstance(value, torch.Tensor)


def as_numpy(value) -> np.ndarray:
    """``value`` as a numpy array (a torch tensor detached and copied to the CPU), without
    importing torch."""
    if is_tensor(value):
        return value.detach().cpu().numpy()
    return np.asarray(value)


def check_finite(name: str, value) -> None:
    """Raise if any element of ``value`` is NaN or infinite."""
    arr = as_numpy(value)
    if not np.issubdtype(arr.dtype, np.number):
        raise ValueError(f"{name} must be numeric, got dtype {arr.dtype}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {arr.tolist()!r}"
                         if arr.size <= 8 else f"{name} must be finite (no NaN or inf)")


def check_positive(name: str, value) -> None:
    """Raise unless every element of ``value`` is finite and > 0."""
    check_finite(name, value)
    arr = as_numpy(value)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be > 0 (allowed range: (0, inf)), got {arr.tolist()!r}")


def check_nonnegative(name: str, value) -> None:
    """Raise unless every element of ``value`` is finite and >= 0."""
    check_finite(name, value)
    arr = as_numpy(value)
    if np.any(arr < 0):
        raise ValueError(f"{name} must be >= 0 (allowed range: [0, inf)), got {arr.tolist()!r}")


def check_shape(name: str, value, shape: tuple) -> None:
    """Raise unless ``value`` has exactly ``shape`` (``None`` in ``shape`` matches any size)."""
    got = tuple(as_numpy(value).shape)
    ok = len(got) == len(shape) and all(s is None or s == g for s, g in zip(shape, got))
    if not ok:
        parts = ["any" if s is None else str(s) for s in shape]
        want = "(" + ", ".join(parts) + ("," if len(parts) == 1 else "") + ")"
        raise ValueError(f"{name} must have shape {want}, got {got}")


#: Most values an array that the library allocates for a result may hold: 2**28 (2 GiB of float64).
MAX_ARRAY_VALUES = 2 ** 28


def check_size(what: str, count: int, *, copies: int = 1, limit: int = MAX_ARRAY_VALUES) -> None:
    """Raise a ``ValueError`` before allocating when ``count`` float64 values, held in
    ``copies`` working copies, exceed ``limit`` values (:data:`MAX_ARRAY_VALUES`, 2 GiB);
    ``what`` names the parameters that set ``count`` (``"n_samples = 10**9 draws of (8, 8)"``)."""
    count = int(count)
    if count * copies > limit:
        held = f" in {copies} working copies" if copies > 1 else ""
        raise ValueError(f"{what} would need about {count * copies * 8 / 2**30:.3g} GiB "
                         f"({count:.3g} values{held}); at most {limit * 8 / 2**30:.3g} GiB "
                         f"({limit} float64 values) are allowed: ask for fewer or smaller")


def check_lags(name: str, lags, dim: int) -> None:
    """Raise unless ``lags`` is finite with a last axis of length ``dim``."""
    arr = as_numpy(lags)
    if arr.ndim == 0 or arr.shape[-1] != dim:
        raise ValueError(f"{name} must have shape (..., {dim}) (last axis: the {dim} lag "
                         f"components), got {tuple(arr.shape)}")
    check_finite(name, arr)


#: The magnitudes a scale (a height, variance, length or spacing) may take: beyond them the
#: squares, fourth powers and ratios that the library forms overflow or underflow float64.
SCALE_RANGE = (1e-60, 1e60)


def check_scale(name: str, value, *, zero: bool = False) -> float:
    """``value`` as a float; raise unless it is finite and in :data:`SCALE_RANGE` (or 0 when
    ``zero``), naming ``name`` and the allowed range."""
    low, high = SCALE_RANGE
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not (number == 0 and zero) and not low <= number <= high:
        sign = ">= 0: 0 or" if zero else "> 0 and"
        raise ValueError(f"{name} must be {sign} within [{low:g}, {high:g}] (allowed range; "
                         f"larger or smaller magnitudes overflow float64), got {number:g}")
    return number


#: heights whose variance is at most this share of the raw heights' mean square are constant:
#: what is left is the rounding of the operators (a constant map's plane removal leaves 1e-34)
CONSTANT_SHARE = 1e-24


def constant_variance(heights, raw=None) -> float | None:
    """The variance of the finite ``heights`` when they are constant: at most
    :data:`CONSTANT_SHARE` times the mean square of ``raw`` (the heights before the operators;
    default ``heights``), what the operators' rounding leaves of a constant (or, after a form
    removal, planar) map; None when they vary."""
    values = np.asarray(heights, dtype=np.float64)
    values = values[np.isfinite(values)]
    reference = values if raw is None else np.asarray(raw, dtype=np.float64)
    scale = float(np.mean(np.square(reference[np.isfinite(reference)]))) \
        if np.isfinite(reference).any() else 0.0
    variance = float(np.var(values)) if values.size else 0.0
    return variance if not variance > CONSTANT_SHARE * scale or not variance > 0 else None


def check_varies(what: str, heights, raw=None) -> None:
    """Raise unless the finite ``heights`` vary (:func:`constant_variance`), so a constant map
    is refused by name rather than give a model of variance 1e-34."""
    variance = constant_variance(heights, raw)
    if variance is not None:
        raise ValueError(f"{what} are constant (variance {variance:.3g} um^2, no more than "
                         f"the rounding of the operators): a flat map has no texture to "
                         f"measure or model; give a map whose heights vary")


def check_integer(name: str, value, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int; raise unless it is an integer (not a bool) >= ``minimum`` (and
    <= ``maximum`` when given: the message then states the allowed range)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum \
            or (maximum is not None and value > maximum):
        wanted = f">= {minimum}" + ("" if maximum is None else f" and <= {maximum}")
        raise ValueError(f"{name} must be an integer {wanted} (allowed range), got {value!r}")
    return int(value)


def as_generator(seed) -> np.random.Generator:
    """The numpy Generator of a ``seed``: an int >= 0 (the same int gives the same draws),
    None (fresh entropy) or a Generator (used as is, so calls can share one stream)."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool)
                        and seed >= 0):
        return np.random.default_rng(seed)
    raise ValueError(f"seed must be an integer >= 0, None or a numpy.random.Generator, "
                     f"got {seed!r}")


def profile_or_surface(z, name: str = "z") -> np.ndarray:
    """``z`` as a new float64 profile ``z[ix]`` or surface ``z[iy, ix]``: non-empty, no infinite
    value (NaN marks an unmeasured point); a ValueError otherwise."""
    arr = np.array(z, dtype=np.float64)
    if arr.ndim not in (1, 2) or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty profile z[ix] (1-D) or surface z[iy, ix] "
                         f"(2-D), got shape {arr.shape}")
    if np.any(np.isinf(arr)):
        raise ValueError(f"{name} must not hold infinite values (NaN marks a missing point)")
    return arr


def height_map(z, name: str = "z") -> np.ndarray:
    """``z`` as a new float64 profile ``z[ix]`` or surface ``z[iy, ix]``: non-empty, no infinite
    value, at least one measured point (NaN marks an unmeasured one); a ValueError otherwise."""
    arr = profile_or_surface(z, name)
    if not np.any(np.isfinite(arr)):
        raise ValueError(f"{name} must hold at least one measured (finite) point, got all NaN")
    return arr


def surface_array(z, name: str = "z") -> np.ndarray:
    """``z`` as a float64 surface ``z[iy, ix]`` (NaN marks an unmeasured point); a ValueError
    naming ``name`` and the shape otherwise."""
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a surface z[iy, ix], got shape {arr.shape}")
    return arr


def boolean_map(value, shape, name: str = "mask") -> np.ndarray:
    """``value`` as a boolean map of the surface's ``shape`` (points to treat as missing, to
    predict, ...); a ValueError naming ``name`` otherwise."""
    arr = np.asarray(value)
    if arr.dtype != bool or arr.shape != tuple(shape):
        raise ValueError(f"{name} must be a boolean array of the shape of z {tuple(shape)}, got "
                         f"{arr.dtype} of shape {arr.shape}")
    return arr
