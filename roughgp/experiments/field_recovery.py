"""Does the ``eq18-field`` model recover parameter fields it was not told, and does it pass the
tile check where eq 18 fails? (issue 40, items 3 and 4.)

Synthetic maps of known non-stationary eq 18 surfaces (:data:`KINDS`), drawn by
:func:`roughgp.models.nonstationary.sample_nonstationary` (16 kernels) on 256 x 256 points,
spacing 1 um, lambda_a 8, lambda_b 3 um, lay 30 deg, variance 2 um^2, noise 0.05 um^2:

- ``stationary``: those values everywhere (the field model must come back stationary);
- ``gradient``: the variance rises from 1 to 3 um^2 left to right (log-linear);
- ``turning``: the lay turns from 0 to 60 deg left to right;
- ``zones``: the variance is 1 um^2 on the left half and 3 um^2 on the right;
- ``zones-off-grid``: the same with the boundary at 3/8 of the width, inside the second column
  of the fit's tiles (the fit's steps lie between tiles: the honest case of a part whose zones
  do not follow the tiles).

Per case (:func:`field_case`): the field model on 4 x 4 tiles
(:func:`~roughgp.surface_models.field_model.fit_field_model`), its fields at the anchors
against the truth (the share of anchors where the truth lies within 2 reported standard
errors, with :math:`\tau` integrated out and the forms averaged, and within 2 plug-in ones; the
truth of a tile is its mean over the tile, of the log for the variance and the lengths),
the pooling's tests, and the tile check (2 x 4 tiles, 19 simulations;
:func:`~roughgp.checking.tiles.tile_check`) of eq 18 (fitted by the Whittle likelihood) and of
the field model, with the share of outside tiles per parameter.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from roughgp.checking.ranks import share_interval
from roughgp.checking.tiles import TILE_PARAMETERS, tile_check
from roughgp.common.jsonl import read_records
from roughgp.inference.tile_fit import PARAMETERS
from roughgp.models.nonstationary import ParameterField, sample_nonstationary
from roughgp.surface_models.field_model import fit_field_model
from roughgp.surface_models.fit import fit_surface_model

__all__ = ["KINDS", "SHAPE", "TILES", "CHECK_TILES", "true_field", "field_case", "summary",
           "recovery_table", "load_records", "RECORDED"]

KINDS = ("stationary", "gradient", "turning", "zones", "zones-off-grid")
SHAPE = (256, 256)
TILES = (4, 4)
CHECK_TILES = (2, 4)
_BASE = {"variance": 2.0, "lambda_a": 8.0, "lambda_b": 3.0, "angle": math.radians(30.0),
         "noise_variance": 0.05}
#: the fields compared at the anchors, with their entry of the tiles' ``u``
_COMPARED = {"variance": 0, "lambda_a": 1, "lambda_b": 2, "angle": 3}
#: the recorded run (``benchmarks/field_recovery.py``: one :func:`field_case` a line)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "field_recovery.jsonl"


def true_field(kind, shape=SHAPE, spacing=1.0) -> dict:
    """The true parameters of ``kind`` (module docstring) on a grid of ``shape``: arrays."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    ny, nx = shape
    x = np.broadcast_to(np.arange(nx) * spacing, shape)
    fraction = x / ((nx - 1) * spacing)
    values = {name: np.full(shape, value) for name, value in _BASE.items()}
    if kind == "gradient":
        values["variance"] = 3.0 ** fraction
    elif kind == "turning":
        values["angle"] = math.radians(60.0) * fraction
    elif kind == "zones":
        values["variance"] = np.where(fraction < 0.5, 1.0, 3.0)
    elif kind == "zones-off-grid":
        values["variance"] = np.where(fraction < 0.375, 1.0, 3.0)
    return values


def _truth_at_anchors(values, fits):
    """Each tile's true value: the mean over the tile of the log variance and lengths, and of
    the angle (none of the kinds varies within a tile by more than a linear trend)."""
    from roughgp.common.tiling import tile_slices
    out = {}
    for name in _COMPARED:
        field = values[name] if name == "angle" else np.log(values[name])
        out[name] = np.array([field[s].mean() for s in tile_slices(field.shape, fits.tiles)]
                             ).reshape(fits.tiles)
    return out


def field_case(kind, index, *, shape=SHAPE, tiles=TILES, n_simulations=19, seed=0) -> dict:
    """One case (module docstring) as a JSON-ready dict."""
    began = time.perf_counter()
    rng = np.random.default_rng([seed, KINDS.index(kind), index])
    values = true_field(kind, shape)
    z = sample_nonstationary(shape, 1.0, ParameterField(**values), n_kernels=16, seed=rng)[0]
    fitted = fit_field_model(z, 1.0, l=None, tiles=tiles, seed=index)
    truth = _truth_at_anchors(values, fitted.tiles)
    covered, covered_plugin, widened, errors = {}, {}, {}, {}
    for name, k in _COMPARED.items():
        pooled = fitted.pooled[k]
        difference = pooled.shrunk - truth[name]
        if name == "angle":
            difference = (difference + math.pi / 2) % math.pi - math.pi / 2
        covered[name] = float(np.mean(np.abs(difference) <= 2 * pooled.shrunk_sd))
        covered_plugin[name] = float(np.mean(np.abs(difference) <= 2 * pooled.plugin_sd))
        widened[name] = float(np.mean(pooled.shrunk_sd / pooled.plugin_sd))
        errors[name] = float(np.sqrt(np.mean(difference**2)))
    eq18 = fit_surface_model(z, 1.0, l=None, likelihood="whittle").model
    shares = {}
    for label, model in (("eq18", eq18), ("field", fitted.model)):
        check = tile_check(model, z, tiles=CHECK_TILES, n_simulations=n_simulations,
                           seed=np.random.default_rng([seed, index]))
        shares[label] = {name: check.outside_share(name) for name in TILE_PARAMETERS}
    return {"kind": kind, "index": index, "seed": seed, "shape": list(shape),
            "tiles": list(tiles), "covered": covered, "covered_plugin": covered_plugin,
            "sd_widened": widened, "rms_error": errors,
            "tau": {n: p.tau for n, p in zip(PARAMETERS, fitted.pooled)},
            "p_homogeneity": {n: p.p_homogeneity for n, p in zip(PARAMETERS, fitted.pooled)},
            "trend_kept": {n: bool(p.slope != (0.0, 0.0))
                           for n, p in zip(PARAMETERS, fitted.pooled)},
            "step_kept": {n: bool(p.step) for n, p in zip(PARAMETERS, fitted.pooled)},
            "tile_outside": shares, "seconds": round(time.perf_counter() - began, 1)}


def load_records(path=RECORDED) -> list:
    """The recorded cases (empty when none are)."""
    return read_records(path)


def summary(records) -> dict:
    """Per kind recorded: ``cases``; ``covered`` (the share of anchors covered, per field) and
    ``covered_min`` (the least of them), ``covered_plugin_min`` (the least share within the
    plug-in standard errors; NaN for records without it); ``constant``, the share of cases
    whose four fields came back constant (no spread, no trend, no step), ``variance_step``
    the share whose variance came back as two zones; ``field_sq_interval``, the field model's
    share of tiles with Sq outside, ``(mean, low, high)`` over the cases (95 %,
    :func:`~roughgp.checking.ranks.share_interval`); the tile check's mean outside share per
    parameter, ``eq18`` and ``field``, and over the four, ``eq18_mean`` and ``field_mean``."""
    out = {}
    for kind in KINDS:
        rows = [r for r in records if r["kind"] == kind]
        if not rows:
            continue
        covered = {n: float(np.mean([r["covered"][n] for r in rows])) for n in _COMPARED}
        plugin = [min(np.mean([r["covered_plugin"][n] for r in rows]) for n in _COMPARED)
                  ] if all("covered_plugin" in r for r in rows) else []
        shares = {label: {n: float(np.mean([r["tile_outside"][label][n] for r in rows]))
                          for n in TILE_PARAMETERS} for label in ("eq18", "field")}
        fields = [name for name in PARAMETERS if name != "log noise"]
        out[kind] = {"cases": len(rows), "covered": covered,
                     "covered_min": min(covered.values()),
                     "covered_plugin_min": plugin[0] if plugin else math.nan,
                     "constant": float(np.mean([all(_constant(r, n) for n in fields)
                                                for r in rows])),
                     "variance_step": float(np.mean([_kept(r, "step_kept", "log variance")
                                                     for r in rows])),
                     **shares,
                     "field_sq_interval": share_interval(
                         [r["tile_outside"]["field"]["Sq"] for r in rows]) if len(rows) > 1
                     else (math.nan,) * 3,
                     "eq18_mean": float(np.mean(list(shares["eq18"].values()))),
                     "field_mean": float(np.mean(list(shares["field"].values())))}
    return out


def _kept(record, key, name) -> bool:
    """Whether ``record`` kept a trend (``key`` ``"trend_kept"``) or a step (``"step_kept"``,
    False in records made before steps) of the parameter ``name``."""
    return bool(record.get(key, {}).get(name, False))


def _constant(record, name) -> bool:
    """Whether ``name`` came back constant: no spread, no trend, no step."""
    return (record["tau"][name] == 0 and not _kept(record, "trend_kept", name)
            and not _kept(record, "step_kept", name))


def _covered_cell(rows, name) -> str:
    """The share of anchors covered, then (where recorded) within the plug-in errors."""
    cell = f"{np.mean([r['covered'][name] for r in rows]):.0%}"
    if all("covered_plugin" in r for r in rows):
        cell += f" ({np.mean([r['covered_plugin'][name] for r in rows]):.0%})"
    return cell


def recovery_table(records) -> str:
    """Markdown: per kind, the cases, the share of anchors covered per field (with the
    plug-in standard errors in brackets, where recorded), how often the variance came back
    constant (no spread, no trend, no step), with a gradient or with two zones, how often the
    lay came back constant, and the tile check's mean outside share of eq 18 and the field
    model."""
    head = ("| kind | cases | anchors covered, tau integrated out (plug-in tau): variance, "
            "lambda_a, lambda_b, angle | variance: constant, a gradient, two zones | lay "
            "constant | tile check outside, eq 18: Sq, Sal, Str, Std | field model: Sq, Sal, "
            "Str, Std |")
    lines = [head, "|" + "---|" * 7]
    for kind in KINDS:
        rows = [r for r in records if r["kind"] == kind]
        if not rows:
            continue
        cover = ", ".join(_covered_cell(rows, n) for n in _COMPARED)
        variance = ", ".join(f"{np.mean(values):.0%}" for values in (
            [_constant(r, "log variance") for r in rows],
            [_kept(r, "trend_kept", "log variance") for r in rows],
            [_kept(r, "step_kept", "log variance") for r in rows]))

        def outside(label):
            return ", ".join(f"{np.mean([r['tile_outside'][label][n] for r in rows]):.0%}"
                             for n in TILE_PARAMETERS)
        lay = np.mean([_constant(r, "angle") for r in rows])
        lines.append(f"| {kind} | {len(rows)} | {cover} | {variance} | {lay:.0%} | "
                     f"{outside('eq18')} | {outside('field')} |")
    return "\n".join(lines)
