"""One file through a batch's steps (:func:`run_file`): the library calls of the single commands,
with their arguments, so that a file gives in a batch the numbers its single commands give
with ``--seed`` set to the file's seed (:func:`roughgp.batch.records.file_seed`):

* ``texture``: :func:`roughgp.texture` after the reader (``roughgp texture``);
* ``fit``: :func:`~roughgp.surface_models.fit.fit_surface_model` (eq 18, ``--model eq18``),
  :func:`~roughgp.surface_models.ladder.fit_rung` (``matern``, ``sm``, ``psd``),
  :func:`~roughgp.checking.auto_choice.choose_checked` (``auto``: the rung by held-out
  prediction, its heights by the out-of-sample check), the field and population
  models of :mod:`~roughgp.surface_models.field_model` and
  :mod:`~roughgp.surface_models.population_model` (``field``, ``population``: the map's
  ``anchors`` tiles), on the whole map or on the
  half ``part`` (``roughgp fit ground --part``), or for a profile
  :func:`~roughgp.surface_models.fit.fit_profile_model` on its mean profile (``roughgp fit``);
  the model file is written to the file's folder;
* ``check``: :func:`roughgp.check` of the model file read back, as ``roughgp check`` reads it;
  for a model fitted on a half (``part``), :func:`~roughgp.checking.held_out.held_out_check`
  on that half and the other (``roughgp check --held-out``);
* ``fill``: :func:`roughgp.fill` of a surface with unmeasured points (``roughgp fill``);
* ``simulate``: :func:`roughgp.simulate` of the model at the file's shape, put through the rest
  of its operator chain (``roughgp simulate --from``).

With ``--spurious`` (the read's option ``spurious``) the file's spurious points
(:func:`~roughgp.filling.spurious.detect_spurious`) are found once, on the whole map, and are
unmeasured for every step, as the single commands' ``--spurious`` finds them on the whole file
(``--part`` or not).

Every step runs inside :func:`roughgp.common.threads.one_blas_thread`, as the command does. A
step that fails ends the file: its record has the error (the exception's type and message) and
what the steps before it gave; the batch goes on.
"""

from __future__ import annotations

import time
from pathlib import Path

from roughgp.batch.records import RECORD_FORMAT, Plan, file_seed
from roughgp.common.version import VERSION

__all__ = ["run_file", "operators_of", "check_cutoffs", "ARTEFACTS"]

#: the artefacts a file's steps write into its folder, by step
ARTEFACTS = {"fit": "model.json", "fill": "filled.x3p", "simulate": "simulated.x3p",
             "check": "check.png"}


def operators_of(options: dict, *, s_default="auto", l_default="auto") -> dict:
    """``form``, ``s``, ``l``, ``degree``, ``axis`` for the library, from a step's options
    (``"none"`` is None; a filter not given is the step's default), as the commands'
    :func:`roughgp.cli.options.operator_settings` gives them."""
    def length(value, default):
        value = default if value is None else value
        return None if value == "none" else value

    form = options.get("form", "plane")
    return {"form": None if form == "none" else form,
            "s": length(options.get("s"), s_default), "l": length(options.get("l"), l_default),
            "degree": options.get("degree", 2), "axis": options.get("axis", "auto")}


def check_cutoffs(operators, shape, spacing) -> None:
    """The S- and L-filter nesting indices in ``operators`` at most the field's longer side (a
    longer Gaussian filter averages the whole field, and its kernel outgrows it); a ValueError
    naming the option and the field's length otherwise (the commands and the batch alike)."""
    extent = max(n * d for n, d in zip(shape, spacing))
    for option, key in (("--s-filter", "s"), ("--l-filter", "l")):
        value = operators.get(key)
        if isinstance(value, (int, float)) and value > extent:
            raise ValueError(f"{option} {value:g} um exceeds the field ({extent:.4g} um along "
                             f"its longer side): give at most {extent:.4g} um, or auto")


def run_file(path: str, sha256: str, plan: Plan, folder: str) -> dict:
    """Run ``plan``'s steps on the measurement file ``path`` (whose SHA-256 is ``sha256``),
    writing its artefacts into ``folder``; returns its record (JSON-ready values): ``status``
    ``"done"`` or ``"failed"`` with ``error``, the file's ``seed``, what it holds, and one entry
    per step run. Never raises for an error of the file or a step (KeyboardInterrupt aside)."""
    from roughgp.common.threads import one_blas_thread
    start = time.perf_counter()
    record = {"record_format": RECORD_FORMAT, "roughgp_version": VERSION,
              "plan_digest": plan.digest(), "path": str(path), "sha256": sha256,
              "seed": file_seed(plan.seed, sha256), "steps": list(plan.steps),
              "status": "failed", "error": None, "seconds": {}}
    step = "read"
    try:
        import warnings
        with one_blas_thread(), warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            heights = _read(path, plan, record)
            if plan.of("read").get("spurious"):
                heights = _without_spurious(heights, plan.of("read"), record)
            model_path = None
            for step in plan.steps:
                begin = time.perf_counter()
                if step == "texture":
                    record["texture"] = _texture(heights, plan.of("texture"))
                elif step == "fit":
                    record["fit"], model_path = _fit(path, heights, plan.of("fit"),
                                                     record["seed"], folder)
                elif step == "check":
                    record.update(_check(path, heights, model_path, plan.of("check"),
                                         record["seed"], folder))
                elif step == "fill":
                    record["fill"] = _fill(path, heights, plan.of("fill"), record["seed"],
                                           folder)
                elif step == "simulate":
                    record["simulate"] = _simulate(path, heights, model_path, record["seed"],
                                                   folder, plan.of("simulate"))
                record["seconds"][step] = time.perf_counter() - begin
        record["warnings"] = sorted({str(w.message) for w in caught})
        record["status"] = "done"
    except (KeyboardInterrupt, SystemExit):
        raise
    except MemoryError:
        record["error"] = f"{step}: out of memory"
    except Exception as exc:  # noqa: BLE001 - a file's error goes into its row
        record["error"] = f"{step}: {type(exc).__name__}: {exc}"
    record["seconds"]["total"] = time.perf_counter() - start
    return record


def _read(path, plan, record):
    from roughgp.api import read
    options = plan.of("read")
    begin = time.perf_counter()
    heights = read(path, kind=options.get("kind", "auto"), spacing=options.get("spacing"),
                   channel=options.get("channel", 0), unit=options.get("unit"))
    record["seconds"]["read"] = time.perf_counter() - begin
    import numpy as np
    record.update(reader=heights.reader, kind=heights.kind, shape=list(heights.z.shape),
                  spacing_um=list(heights.spacing), spacing_from=heights.spacing_source,
                  unit=heights.unit_source, missing=int(np.isnan(heights.z).sum()),
                  notes=list(heights.notes))
    return heights


def _without_spurious(heights, options, record):
    """``--spurious``: the file's spurious points found once, on the whole map, and treated as
    unmeasured by every step (as each single command's ``--spurious`` finds them on the whole
    file, with the file's seed and the F-operator ``form``); the detection's summary recorded.
    A profile is left as read, with a note (the detection works on surfaces)."""
    import dataclasses

    import numpy as np

    from roughgp.filling.spurious import detect_spurious
    if heights.kind != "surface":
        record["spurious"] = {"note": "a profile: --spurious works on surfaces"}
        return heights
    begin = time.perf_counter()
    form = options.get("form", "plane")
    found = detect_spurious(heights.z, spacing=heights.spacing,
                            form=None if form == "none" else form, seed=record["seed"])
    record["seconds"]["spurious"] = time.perf_counter() - begin
    record["spurious"] = {"flagged": int(found.count), "rounds": int(found.rounds),
                          "converged": bool(found.converged), "summary": found.summary()}
    return dataclasses.replace(heights, z=np.where(found.flagged, np.nan, heights.z))


def _texture(heights, options):
    """``roughgp texture FILE`` (:func:`roughgp.cli.texture.run`'s library calls)."""
    from roughgp.api import texture
    unfiltered = options.get("unfiltered", False)
    operators = operators_of(options)
    if not unfiltered:
        check_cutoffs(operators, heights.z.shape, heights.spacing)
    report = texture(heights.z, heights.spacing, **operators, filtered=not unfiltered,
                     l_kind=options.get("l_kind", "gaussian"))
    return {"standard": report.standard, "operators": list(report.operators),
            "notes": list(report.notes), "parameters": dict(report.parameters)}


def _relative(path) -> str:
    """An artefact's path as the record keeps it: relative to the batch's output folder
    (``files/NAME/ARTEFACT``), so that two output folders hold the same records."""
    path = Path(path)
    return f"files/{path.parent.name}/{path.name}"


def _save(model, folder):
    from roughgp.common.atomic import atomic_output
    path = Path(folder) / ARTEFACTS["fit"]
    with atomic_output(path) as partial:
        model.save(partial)
    return path


def _fit(path, heights, options, seed, folder):
    """``roughgp fit ground|profile FILE --seed SEED --out MODEL.json``."""
    from roughgp.io.provenance import of_file
    data = of_file(path, heights)
    if heights.kind == "profile" or options.get("profile"):
        return _fit_profile(heights, options, seed, data, folder)
    if options.get("part"):  # fit ground --part HALF: the part is recorded in the model file
        import dataclasses

        from roughgp.checking.held_out import part_of
        part = part_of(heights.z.shape, options["part"])
        data["part"] = part.to_dict()
        heights = dataclasses.replace(heights, z=part.cut(heights.z))
    from roughgp.surface_models.fit import fit_surface_model
    from roughgp.surface_models.ladder import fit_rung
    operators = operators_of(options, s_default="none", l_default="auto")
    check_cutoffs(operators, heights.z.shape, heights.spacing)
    z, block, n_blocks = heights.z, options.get("block", 24), options.get("blocks", 12)
    side = min(z.shape)
    if side < 4 or block > side:
        raise ValueError(f"--block {block} does not fit in the map's shorter side ({side} "
                         f"points): the eq 18 fit needs blocks of 4 to {min(side, 32)} points")
    rung, marginal = options.get("model", "eq18"), options.get("marginal") or "gaussian"
    nu, likelihood = options.get("nu", 0.5), options.get("likelihood", "blocks")
    entry = {"rung": rung}
    if rung in ("field", "population"):   # fit ground --model field|population --anchors M N
        if marginal != "gaussian" or nu != 0.5:
            raise ValueError(f"--model {rung} draws Gaussian heights with eq 18's profile: "
                             f"leave out --marginal {marginal} and --nu {nu:g}")
        tiles = tuple(options.get("anchors") or ((4, 4) if rung == "field" else (2, 2)))
        if rung == "field":
            from roughgp.surface_models.field_model import fit_field_model
            model = fit_field_model(z, heights.spacing, **operators, tiles=tiles, seed=seed,
                                    data=data).model
        else:
            from roughgp.surface_models.population_model import fit_population_model
            model = fit_population_model(z, heights.spacing, **operators, tiles=tiles,
                                         seed=seed, data=data).model
        notes = ()
    elif rung == "eq18":
        result = fit_surface_model(z, heights.spacing, **operators, block=block,
                                   n_blocks=n_blocks, seed=seed, nu=nu, marginal=marginal,
                                   data=data, likelihood=likelihood)
        model, notes = result.model, result.range_notes
        entry["log_likelihood"] = result.block_fit.log_likelihood
    else:
        settings = dict(**operators, marginal=marginal, seed=seed, block=block,
                        n_blocks=n_blocks, nu=nu if nu in (1.5, 2.5) else 1.5, data=data,
                        likelihood=likelihood)
        if rung == "auto":
            from roughgp.checking.auto_choice import choose_checked
            settings.pop("marginal")
            choice = choose_checked(z, heights.spacing, marginal=options.get("marginal"),
                                    **settings)
            model, notes = choice.model, choice.range_notes
            entry.update(chosen=choice.chosen, reason=choice.ladder.reason,
                         held_out_rmse_um=model.fit["held_out_rmse_um"],
                         refused_rungs=model.fit.get("refused_rungs", {}),
                         heights=choice.marginal, heights_reason=choice.reason,
                         out_of_sample_outside=model.fit["out_of_sample_outside"])
        else:
            model, notes = fit_rung(rung, z, heights.spacing, **settings)
    model_path = _save(model, folder)
    if "part" in data:
        entry["part"] = data["part"]
    entry.update(equation=model.equation, describe=model.describe(),
                 marginal=model.marginal_method, operators=list(model.operators),
                 hyperparameters=dict(model.hyperparameters), notes=list(notes),
                 model_file=_relative(model_path))
    return entry, model_path


def _fit_profile(heights, options, seed, data, folder):
    """``roughgp fit profile FILE``: eq 21 on the (mean) profile."""
    import numpy as np

    from roughgp.io.measurement import mean_profile
    from roughgp.surface_models.fit import fit_profile_model
    operators = operators_of(options, s_default="none", l_default="none")
    check_cutoffs(operators, heights.z.shape, heights.spacing)
    z, spacing, how = mean_profile(heights, options.get("profile_axis", "x"))
    if np.isnan(z).any():
        raise ValueError(f"{how}: unmeasured points; the eq 21 fit needs a complete profile")
    if z.size > options.get("max_profile_points", 65536):
        raise ValueError(f"the profile has {z.size} points; the exact eq 21 fit takes at most "
                         f"{options.get('max_profile_points', 65536)}")
    result = fit_profile_model(z, spacing, form=operators["form"], s=operators["s"],
                               l=operators["l"], num_mixtures=options.get("mixtures", 5),
                               seed=seed, n_candidates=options.get("candidates", 10),
                               non_gaussian=options.get("marginal") == "johnson",
                               data={**data, "profile": how})
    model = result.model
    model_path = _save(model, folder)
    return ({"rung": "eq21", "equation": model.equation, "describe": model.describe(),
             "marginal": model.marginal_method, "operators": list(model.operators),
             "hyperparameters": dict(model.hyperparameters),
             "log_likelihood": result.mixture.log_marginal_likelihood,
             "model_file": _relative(model_path)}, model_path)


def _check(path, heights, model_path, options, seed, folder):
    """``roughgp check MODEL.json FILE --seed SEED`` (the model file read back, as there); for
    a model fitted on a part (``--part``), ``check --held-out``: the fitted part and the other
    half, the latter recorded as ``held_out``; with ``predictive`` (B) the simulations drawn
    from B models of :func:`~roughgp.checking.predictive.predictive_models` (``predictive_from``:
    refits, sandwich, or tiles of the fitted part), recorded in the check's entry."""
    from roughgp.api import check
    from roughgp.surface_models.model import FittedModel
    model = FittedModel.load(model_path)
    spacing = heights.spacing if model.kind == "surface" else (heights.spacing[-1],)
    n = options.get("simulations", 19)
    models, held = None, ()
    part = model.data.get("part") if isinstance(model.data, dict) else None
    if options.get("predictive"):
        from roughgp.checking.predictive import predictive_models
        models, held = predictive_models(model, options["predictive"],
                                         source=options.get("predictive_from", "refits"),
                                         seed=seed, fitted=_fitted_part(model, heights, spacing))
    if part is not None and model.kind == "surface":
        from roughgp.checking.held_out import Part, held_out_check
        both = held_out_check(model, heights.z, spacing, fitted_part=Part.from_dict(part),
                              n_simulations=n, seed=seed, models=models)
        result = both.fitted
        entries = {"check": _check_entry(both.fitted, n, both.fitted_part),
                   "held_out": _check_entry(both.held_out, n, both.held_out_part)}
    else:
        result = check(model, heights.z, spacing, n_simulations=n, seed=seed, models=models)
        entries = {"check": _check_entry(result, n)}
    if models is not None:
        entries["check"]["predictive"] = {"models": len(models),
                                          "from": options.get("predictive_from", "refits"),
                                          "held": list(held)}
    if options.get("plot"):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from roughgp.checking.model_check import plot_model_check
        from roughgp.common.atomic import atomic_output
        out = Path(folder) / ARTEFACTS["check"]
        shown = both.held_out if "held_out" in entries else result
        where = " (the held-out half)" if "held_out" in entries else ""
        with atomic_output(out) as partial:
            title = (f"{Path(path).name}{where}: the measurement (line) among {n} "
                     f"simulations")
            figure = plot_model_check(shown, partial, title=title)
        plt.close(figure)
        entries["check"]["plot"] = _relative(out)
    return entries


def _fitted_part(model, heights, spacing):
    """``(z, spacing)`` of the part of the file's heights the model was fitted on (its
    ``data.part``: ``batch --part``), what the tile bootstrap draws from; None where the model
    records no part (the batch refuses tiles without ``--part``)."""
    part = model.data.get("part") if isinstance(model.data, dict) else None
    if part is None:
        return None
    from roughgp.checking.held_out import Part
    return Part.from_dict(part).cut(heights.z), spacing


def _check_entry(result, n, part=None) -> dict:
    """A check's record: the simulations, the parameters outside, and per parameter the
    measured value, its rank and the simulated range (and the part checked, if any)."""
    entry = {"simulations": n, "outside": list(result.outside),
             "parameters": {p.name: {"measured": p.measured, "rank": int(p.rank),
                                     "outside": bool(p.outside), "low": p.low,
                                     "median": p.median, "high": p.high}
                            for p in result.parameters}}
    if part is not None:
        entry["part"] = part.to_dict()
    return entry


def _fill(path, heights, options, seed, folder):
    """``roughgp fill FILE --seed SEED --out filled.x3p`` on a surface with unmeasured points
    (a file without any is recorded as such, not as an error)."""
    import numpy as np

    from roughgp.api import fill
    from roughgp.io.writers import write_heights
    if heights.kind != "surface":
        return {"filled": 0, "note": "a profile: fill works on surfaces"}
    z = heights.z
    missing = np.isnan(z)
    if not missing.any():
        return {"filled": 0, "note": "no unmeasured point: nothing to fill"}
    form = options.get("form", "plane")
    nu = options.get("nu", 0.5)
    result = fill(z, heights.spacing, model=None, n_samples=0, seed=seed,
                  block=options.get("block", 24), n_blocks=options.get("blocks", 12),
                  form=None if form == "none" else form, degree=options.get("degree", 2),
                  axis=options.get("axis", "auto"), method=options.get("method", "local"),
                  nu=nu, self_check=options.get("self_check", True))
    dy, dx = heights.spacing
    out = Path(folder) / ARTEFACTS["fill"]
    from roughgp.common.atomic import atomic_output
    with atomic_output(out) as partial:
        write_heights(partial, result.filled, dx if dy == dx else (dy, dx),
                      f"roughgp batch fill {Path(path).name} --seed {seed}: the "
                      f"{int(missing.sum())} missing points filled by the GP posterior mean",
                      source=heights.meta)
    entry = {"filled": int(missing.sum()), "nu": result.nu, "file": _relative(out)}
    if result.self_check is not None:
        entry["self_check"] = result.self_check.summary()
    return entry


def _simulate(path, heights, model_path, seed, folder, options=None):
    """``roughgp simulate --from MODEL.json --shape (the file's) --seed SEED``, through the
    rest of the chain; with ``predictive_from`` (``batch --predictive B --predictive-from
    SOURCE``) the surface's model drawn first, as ``simulate --predictive-from SOURCE`` (tiles:
    of the part the model was fitted on, the file's points as the fit saw them)."""
    from roughgp.api import simulate
    from roughgp.common.atomic import atomic_output
    from roughgp.io.writers import write_heights
    from roughgp.surface_models.chain import rest_of_chain
    from roughgp.surface_models.model import FittedModel
    model = FittedModel.load(model_path)
    shape = heights.z.shape if model.kind == "surface" else (heights.z.shape[-1],)
    spacing = model.spacing
    source = (options or {}).get("predictive_from")
    fitted = _fitted_part(model, heights, tuple(heights.spacing)) if source == "tiles" else None
    z = simulate(model, shape, seed=seed, spacing=spacing, predictive=source, fitted=fitted)
    z = rest_of_chain(model, z, spacing).sl
    out = Path(folder) / ARTEFACTS["simulate"]
    how = "" if source is None else f" --predictive-from {source}"
    with atomic_output(out) as partial:
        write_heights(partial, z, spacing[-1] if len(set(spacing)) == 1 else tuple(spacing),
                      f"roughgp batch simulate --from {Path(model_path).name}{how} --seed "
                      f"{seed}: {model.describe()}")
    entry = {"file": _relative(out), "shape": list(z.shape)}
    if source is not None:
        entry["predictive_from"] = source
    return entry
