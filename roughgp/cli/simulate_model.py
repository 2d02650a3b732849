"""``roughgp simulate --from MODEL.json``: draw from a fitted model and write it, plug-in or
with the fit's uncertainty carried (``--predictive-from``). Argument handling and messages
only: the draws are :func:`roughgp.simulate` and
:func:`roughgp.checking.predictive.predictive_draws`.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from roughgp.cli.options import PREDICTIVE_SOURCES
from roughgp.cli.output import UsageError, check_outputs, err
from roughgp.io.writers import WRITE_FORMATS, write_heights

__all__ = ["add_predictive_options", "fitted_map", "run_model"]


_ABOUT = {"refits": "one bootstrap refit of the model (a measurement of the fitted size drawn "
                    "from the model and refitted the way the model was fitted)",
          "sandwich": "one parameter set from the fit's Whittle sandwich covariance",
          "tiles": "the model given the variance and the heights of the fitted part's 4 x 4 "
                   "tiles drawn with replacement (the variance's spread widened to a crop's; "
                   "a measured PSD their spectrum's shape too)"}


def add_predictive_options(parser) -> None:
    """``--predictive-from SOURCE`` and ``--fitted FILE`` of ``simulate --from``."""
    parser.add_argument("--predictive-from", choices=PREDICTIVE_SOURCES, metavar="SOURCE",
                        help="with --from: draw the surface's model first, the fit's "
                             "uncertainty carried (a new surface of the part, not of the "
                             "fitted crop): 'refits' (one bootstrap refit), 'sandwich' (eq 18: "
                             "one parameter set of the fit's sandwich covariance) or 'tiles' "
                             "(measured PSD or eq 18: the fitted map's 4 x 4 tiles drawn with "
                             "replacement; give --fitted)")
    parser.add_argument("--fitted", metavar="FILE",
                        help="with --predictive-from tiles: the measurement the model was "
                             "fitted on (checked against the SHA-256 the model file records; "
                             "the model's part of it is used)")
    parser.add_argument("--spurious", action="store_true",
                        help="with --fitted: leave out the spurious points of FILE as a fit "
                             "with --spurious did (found by the GP on the whole file, with the "
                             "model's F-operator and the fit's seed), so that the tiles hold "
                             "the points the model was fitted on")


def fitted_map(model, path, option="--fitted", args=None) -> tuple:
    """``(z, spacing)`` of the map (the model's part of it) that ``model`` was fitted on, read
    from ``path``; a :class:`UsageError` where ``path`` is not that file. With ``args`` whose
    ``spurious`` is set (``simulate --spurious``): its spurious points left out first, as ``fit
    --spurious`` found them (:func:`_without_spurious`)."""
    spurious = bool(getattr(args, "spurious", False))
    from roughgp.api import read
    from roughgp.checking.held_out import Part
    from roughgp.common.digests import file_sha256
    data = model.data if isinstance(model.data, dict) else {}
    recorded = data.get("sha256")
    if recorded and file_sha256(path) != recorded:
        raise UsageError(f"{option} {path} is not the file the model was fitted on: its SHA-256 "
                         f"differs from the one the model file records for "
                         f"{data.get('file', 'its data')}")
    heights = read(path)
    if heights.kind != "surface" or model.kind != "surface":
        raise UsageError(f"{option}: the tile bootstrap cuts a surface into tiles; {path} holds "
                         f"a {heights.kind} and the model is a {model.kind} model")
    z = _without_spurious(model, heights, path, args) if spurious else heights.z
    record = data.get("part")
    if record is not None:
        try:
            part = Part.from_dict(record)
        except ValueError as error:
            raise UsageError(f"{option}: the model file's data.part: {error}") from None
        if tuple(part.of_shape) != z.shape:
            raise UsageError(f"{option}: the model was fitted on part {part.name} of a "
                             f"{part.of_shape[0]} x {part.of_shape[1]} map; {path} is "
                             f"{z.shape[0]} x {z.shape[1]}")
        z = part.cut(z)
    shape = model.recorded_shape
    if shape is not None and tuple(shape) != z.shape:
        raise UsageError(f"{option}: the model was fitted on {shape[0]} x {shape[1]} points; "
                         f"{path} {'(its part) ' if record else ''}holds {z.shape[0]} x "
                         f"{z.shape[1]}")
    used = data.get("points_used")
    if used is not None and int(used) != int(np.isfinite(z).sum()):
        raise UsageError(f"{option}: the model was fitted on {int(used)} points of "
                         f"{'its part of ' if record else ''}the map, and {path} holds "
                         f"{int(np.isfinite(z).sum())} there: the fit left points out"
                         + (" (fit --spurious: give --spurious too)" if not spurious else "")
                         + ", and the tiles would hold them")
    assumed = "assumed" in str(heights.spacing_source)
    spacing = tuple(model.spacing) if assumed else tuple(heights.spacing)
    if not np.allclose(spacing, model.spacing, rtol=1e-6):
        raise UsageError(f"{option}: {path} has a spacing of "
                         f"{', '.join(f'{d:g}' for d in spacing)} um; the model was fitted at "
                         f"{', '.join(f'{d:g}' for d in model.spacing)} um")
    return z, spacing


def _without_spurious(model, heights, path, args):
    """The heights of the whole ``heights`` (read from ``path``) with their spurious points
    unmeasured, found as ``fit ground --spurious`` found them: on the whole file, with the
    model's F-operator and the seed the model file records for its fit
    (:func:`roughgp.cli.options.remove_spurious`)."""
    from roughgp.cli.options import remove_spurious
    fit = model.fit if isinstance(model.fit, dict) else {}
    return remove_spurious(args, heights, model.cutoffs.get("form", "plane"), file=path,
                           seed=fit.get("seed", 0))[0]


def _refuse_predictive(args) -> None:
    if args.spurious and args.fitted is None:
        raise UsageError("--spurious leaves out the spurious points of the --fitted map, as the "
                         "fit with --spurious did: give it with --predictive-from tiles "
                         "--fitted FILE")
    if args.predictive_from is None and args.fitted is not None:
        raise UsageError("--fitted is the map the tile bootstrap draws from: give it with "
                         "--predictive-from tiles")
    if args.predictive_from == "tiles" and args.fitted is None:
        raise UsageError("--predictive-from tiles draws the tiles of the map the model was "
                         "fitted on: give it as --fitted FILE")
    if args.predictive_from not in (None, "tiles") and args.fitted is not None:
        raise UsageError(f"--fitted is for --predictive-from tiles; --predictive-from "
                         f"{args.predictive_from} draws from the model file alone")


def _draw(model, shape, spacing, seed, args, fitted):
    """The drawn surface (before the rest of the chain), plug-in or predictive (``fitted``:
    :func:`fitted_map` for the tiles, else None)."""
    from roughgp.api import simulate
    if args.predictive_from is None:
        return simulate(model, shape, seed=seed, spacing=spacing)
    from roughgp.checking.predictive import predictive_draws
    err(f"the model of the surface drawn first (--predictive-from {args.predictive_from}): "
        f"{_ABOUT[args.predictive_from]} ...")
    try:
        z, models, held = predictive_draws(model, shape, source=args.predictive_from,
                                           seed=seed, spacing=spacing, fitted=fitted)
    except ValueError as error:
        raise UsageError(f"--predictive-from {args.predictive_from}: {args.model}: "
                         f"{error}") from None
    err(f"  drawn model: {models[0].describe()}")
    if held:
        err(f"  held at the fit (the fitted grid does not determine them): {', '.join(held)}")
    return z


def _size(args, model, max_points) -> None:
    """``--shape`` not given: set to the size the model was fitted on, where its file records
    one (a profile model that records none is a usage error)."""
    from roughgp.cli.options import fitted_size
    if args.shape is None:
        args.shape = fitted_size(model, max_points)
        if args.shape is None and model.kind == "profile":
            raise UsageError(f"the size is missing: --from {args.model} is a profile model "
                             f"that does not record its profile's length: give --shape 1 N "
                             f"(a profile of N points)")
        if args.shape is not None:
            err(f"--shape not given: {' x '.join(map(str, args.shape))} points, the size of "
                f"the {model.kind} the model was fitted on")


def run_model(args, check_shape, check_drawn, max_points) -> int:
    """``roughgp simulate --from MODEL.json``: draw from a fitted model (``check_shape``,
    ``check_drawn``: ``simulate``'s checks of ``--shape`` and of the drawn heights)."""
    from roughgp.api import simulate
    from roughgp.cli.options import load_model, seed_or_fresh
    if args.out is None:
        raise UsageError("--out FILE is required (the simulated surface: "
                         + ", ".join(WRITE_FORMATS) + ")")
    _refuse_predictive(args)
    inputs = (("--from", args.model),) + ((("--fitted", args.fitted),) if args.fitted else ())
    out, = check_outputs(("--out", args.out, "heights"), inputs=inputs, force=args.force)
    model = load_model(args.model, "--from")
    _size(args, model, max_points)
    shape = check_shape(args)
    if model.kind == "profile":
        if shape[0] != 1:
            raise UsageError(f"--from {args.model} is a profile model: give --shape 1 N")
        shape = (shape[1],)
    elif min(shape) < 2:
        raise UsageError(f"--from {args.model} is a surface model: give --shape NY NX with "
                         f"NY, NX >= 2")
    spacing = model.spacing if args.spacing is None else (args.spacing,) * len(model.spacing)
    if len(spacing) == 2 and spacing[0] != spacing[1] and out.suffix.lower() == ".csv":
        raise UsageError("the model's spacing differs along y and x: a .csv stores one "
                         "spacing; write .x3p or .npy")
    fitted = fitted_map(model, args.fitted, args=args) if args.predictive_from == "tiles" \
        else None
    seed = seed_or_fresh(args.seed)
    err(f"drawing {' x '.join(map(str, shape))} points from {args.model}: {model.describe()}")
    from roughgp.cli.pace import announce_long_draw
    announce_long_draw(lambda pilot: simulate(model, pilot, seed=seed, spacing=spacing), shape)
    start = time.perf_counter()
    z = _draw(model, shape, spacing, seed, args, fitted)
    check_drawn(z)
    if not args.model_stage:
        from roughgp.surface_models.chain import rest_of_chain
        chain = rest_of_chain(model, z, spacing)
        z = chain.sl
        err(f"through the rest of the chain ({model.stage} model): "
            f"{'; '.join(chain.operators)} (--model-stage: the draw before it)")
    err(f"drawn in {time.perf_counter() - start:.2f} s; {'Rq' if z.ndim == 1 else 'Sq'} = "
        f"{np.std(z):.4g} um")
    how = "" if args.predictive_from is None else f" --predictive-from {args.predictive_from}"
    comment = (f"roughgp simulate --from {Path(args.model).name}{how} --seed {seed}: "
               f"{model.describe()}")
    write_heights(out, z, spacing[-1] if len(set(spacing)) == 1 else tuple(spacing), comment)
    err(f"wrote {out} ({model.kind} of shape {z.shape}, heights in um)")
    return 0
