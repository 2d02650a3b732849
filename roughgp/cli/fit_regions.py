"""``roughgp fit ground --model field`` and ``--model population``: eq 18 over regions, the
tiles of one map or several measurements of one part, pooled by random effects
(:mod:`roughgp.surface_models.field_model`, :mod:`roughgp.surface_models.population_model`;
argument handling and printing only)."""

from __future__ import annotations

import math

import numpy as np

from roughgp.cli.options import check_cutoffs
from roughgp.cli.output import UsageError, err, print_operators, print_wrapped, refused_by

__all__ = ["fit_field_command", "fit_population_command", "fit_population_files_command"]


def fit_field_command(args, heights, operators, data, z):
    """``fit ground --model field``: eq 18 per tile, pooled (roughgp.surface_models.field_model)."""
    from roughgp.inference.tile_fit import PARAMETERS
    from roughgp.surface_models.field_model import fit_field_model
    tiles = tuple(args.anchors or (4, 4))
    with refused_by(args.file):
        fitted = fit_field_model(z, heights.spacing, **operators, tiles=tiles, seed=args.seed,
                                 data=data, device=args.device)
    model = fitted.model
    print(f"fitted to {args.file}: {model.describe()}")
    print_operators(model)
    print(f"  {'parameter':<13} {'population':>11} {'spread tau':>11} {'p same':>8} "
          f"{'p gradient':>11} {'se anchor':>10}  kept")
    for name in PARAMETERS:
        p = fitted.pooled_of(name)
        kept = ("the tiles' median" if name == "log noise" else
                f"two zones, {p.step[0]} = {p.step[1]:.4g} um (p {p.p_step:.2g})" if p.step else
                "a gradient" if p.slope != (0.0, 0.0) else
                "tile values" if p.tau > 0 else "one value")
        trend = "-" if math.isnan(p.p_trend) else f"{p.p_trend:.3g}"
        se = "-" if name == "log noise" else f"{float(np.median(p.shrunk_sd)):.3g}"
        print(f"  {name:<13} {p.mean:>11.4g} {p.tau:>11.3g} {p.p_homogeneity:>8.3g} "
              f"{trend:>11} {se:>10}  {kept}")
    print_wrapped("(log scale but for the angle, in radians; p same: the test that all tiles "
                  "share one value; p gradient: that a plane in position does better, kept "
                  "below 0.01, as is a step between two zones at its own test; se anchor: "
                  "the median standard error of the field at the anchors, the spread's and "
                  "the form's own uncertainty included, each anchor's in the model file's "
                  "fit.anchor_sd)")
    return model


def fit_population_files_command(args, heights, operators, data, more):
    """``fit ground A B ... --model population``: each file one region, all of one spacing."""
    from roughgp.api import read
    from roughgp.io.provenance import of_file
    if heights.kind != "surface":
        raise UsageError(f"{args.file} holds a profile; the population model needs surfaces")
    maps, names, sources = [heights.z], [args.file], [data]
    for path in more:
        other = read(path, kind="surface", spacing=args.spacing, channel=args.channel,
                     unit=args.unit)
        if other.kind != "surface":
            raise UsageError(f"FILE2 {path} holds a profile; the population model needs "
                             f"surfaces")
        if not np.allclose(other.spacing, heights.spacing, rtol=1e-6, atol=0):
            raise UsageError(f"FILE2 {path} has the spacing {other.spacing[0]:g} x "
                             f"{other.spacing[1]:g} um, {args.file} {heights.spacing[0]:g} x "
                             f"{heights.spacing[1]:g} um: the measurements of one part must "
                             f"share one spacing (resample them, or give --spacing when the "
                             f"files' own is wrong)")
        for note in other.notes:
            err(f"note: {path}: {note}")
        maps.append(other.z)
        names.append(path)
        sources.append(of_file(path, other))
    for name, z in zip(names, maps):
        check_cutoffs(operators, z.shape, heights.spacing)
    described = {**data, "files": sources}
    return fit_population_command(args, maps, heights.spacing, operators, described, names)


def fit_population_command(args, maps, spacing, operators, data, names):
    """The population model of ``maps`` (one: its tiles are the regions; several: each one)."""
    from roughgp.inference.tile_fit import PARAMETERS
    from roughgp.surface_models.population_draw import SPREAD_NAMES
    from roughgp.surface_models.population_model import fit_population_model
    several = len(maps) > 1
    tiles = tuple(args.anchors or (2, 2))
    err(f"fitting eq 18 on each of {len(maps)} maps" if several else
        f"fitting eq 18 on each of {tiles[0]} x {tiles[1]} tiles of {names[0]}")
    with refused_by(", ".join(map(str, names))):
        fitted = fit_population_model(maps if several else maps[0], spacing, **operators,
                                      tiles=tiles, seed=args.seed, data=data,
                                      device=args.device)
    model = fitted.model
    print(f"fitted to {', '.join(map(str, names))}: {model.describe()}")
    print_operators(model)
    print(f"  {'parameter':<13} {'population':>11} {'spread tau':>11} {'se mean':>9} "
          f"{'p same':>8}  {'a new region':>13}")
    for label, pooled, spread in zip(PARAMETERS, fitted.pooled, SPREAD_NAMES):
        value = model.hyperparameters[spread]
        shown = f"+- {value:.3g} deg" if spread == "angle_sd_deg" else f"x/ {math.exp(value):.3g}"
        print(f"  {label:<13} {pooled.mean:>11.4g} {pooled.tau:>11.3g} {pooled.mean_sd:>9.3g} "
              f"{pooled.p_homogeneity:>8.3g}  {shown:>13}")
    print_wrapped("(log scale but for the angle, in radians; tau: the spread between regions; "
                  "p same: the test that all regions share one value; a new region's spread "
                  "adds the mean's standard error, drawn from Student's t with regions - 2 "
                  "degrees of freedom; the noise is the regions' median)")
    return model
