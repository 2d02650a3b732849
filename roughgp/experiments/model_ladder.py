r"""Which model reproduces which measurement: a ladder of models on the real maps of ``data/``
(beyond the paper; the chapter "Which model reproduces which measurement").

Each *rung* of :data:`RUNGS` fits a model to a measured surface: the paper's eq 18 with
Gaussian heights (eq 8) or the measured skewness and kurtosis (Johnson,
:mod:`roughgp.non_gaussian`), eq 18's anisotropy with a Matérn profile (:math:`\nu` =
1.5, 2.5), a 2-D spectral mixture (eq 21/22's family,
:mod:`roughgp.surface_models.spectral_mixture`) and the map's own smoothed PSD
(:mod:`roughgp.surface_models.measured_psd`: what any stationary Gaussian model could do),
each with Gaussian heights or the measured ones matched exactly (IAAFT,
:mod:`roughgp.surface_models.iaaft`). :func:`run_rung` asks two questions of a rung:

* **Does it reproduce the measurement?** :func:`~roughgp.checking.model_check.check_model`
  places the map's 13 ISO 25178-2 parameters among those of 19 seeded simulations of the model
  (put through the map's holes and F-operator as the map was): a parameter is *outside* when
  the measured value lies beyond all 19. For a model that describes the measurement this
  happens to a parameter with probability 2/20, less for the parameters the fit pins
  (:mod:`roughgp.experiments.model_check` measured 9.9 % on average over 550 synthetic maps):
  about 1.3 of 13 outside, and 2 or fewer with probability 0.88 were the 13 independent.
* **Does it predict held-out points?** 2 % of the measured points (at most
  :data:`~roughgp.filling.self_check.CHECK_POINTS`, in small discs) are held out
  before the fit and kriged with its kernel
  (:func:`~roughgp.filling.self_check.self_check_fill`): the RMSE relative to linear
  interpolation's (below 1: the correlation helps) and the share inside :math:`\pm 2`
  predictive sd. Kriging uses the kernel alone: Johnson or IAAFT heights score as Gaussian.

:func:`model_ladder` runs every rung on every file (each map cropped to its central
:func:`crop_size` x :func:`crop_size` points, 128 quick, 256 at full size: the window is kept
in each result); :meth:`Ladder.best` names the best rung per file (fewest outside, then the
lower held-out RMSE, then the earlier rung) and :meth:`Ladder.share_reproduced` the share of
files on which it leaves at most :data:`MAX_OUTSIDE` of 13 outside, the issue's target of 80 %.
:func:`reasons` says, from which parameters stay outside, what of the surface the model misses.
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from roughgp.checking.model_check import SURFACE_PARAMETERS, check_model
from roughgp.common.settings import pick
from roughgp.experiments.real_maps import REAL_MAPS, central_crop, real_file
from roughgp.filling.self_check import held_out_points, self_check_fill
from roughgp.surface_models.chain import form_removed
from roughgp.surface_models.fit import fit_psd_model, fit_sm_model, fit_surface_model

__all__ = ["Rung", "RUNGS", "PSD_MARGINALS", "SM_MARGINALS", "QUICK_RUNGS", "QUICK_FILES", "FORMS",
           "MAX_OUTSIDE", "TARGET_SHARE", "crop_size", "RECORDED",
           "recorded_ladder", "RungResult", "run_rung", "ladder_case", "Ladder", "model_ladder",
           "reasons",
           "verdict_lines", "markdown_table", "plot_ladder", "TAILS", "AMPLITUDE", "SPATIAL"]

#: a best rung "reproduces" a map when at most this many of the 13 parameters are outside
MAX_OUTSIDE = 2
#: the issue's target: the best rung reproduces at least this share of the maps
TARGET_SHARE = 0.8
#: the quick run's maps: three kinds of instrument (white-light, AFM, confocal with holes)
QUICK_FILES = ("opd-1.opd", "di-3.di", "sample-land.x3p")
#: the F-operator per file (the land is a cylinder across its width); the others: a plane
FORMS = {"sample-land.x3p": "cylinder"}


@dataclasses.dataclass(frozen=True)
class Rung:
    """One model of the ladder: ``fit(z, spacing, *, form, seed, data)`` returns a fit result
    whose ``.model`` is a :class:`~roughgp.surface_models.model.FittedModel` of stage
    ``"form-removed"`` (and ``.range_notes``, where it has them, what the range check did)."""

    name: str
    label: str
    fit: object
    #: the label in a figure's column or a table's header, its heights only where not Gaussian
    short: str = ""


def _eq18(**options):
    def fit(z, spacing, *, form, seed, data):
        return fit_surface_model(z, spacing, form=form, seed=seed, data=data, **options)
    return fit


def _psd(marginal):
    def fit(z, spacing, *, form, seed, data):
        return fit_psd_model(z, spacing, form=form, seed=seed, data=data, marginal=marginal)
    return fit


def _sm(marginal):
    def fit(z, spacing, *, form, seed, data):
        return fit_sm_model(z, spacing, form=form, seed=seed, data=data, marginal=marginal)
    return fit


#: the height distributions' names in the rungs' labels
_HEIGHTS = {"gaussian": "Gaussian", "johnson": "Johnson heights", "iaaft": "IAAFT heights"}

#: the measured-PSD model's height distributions on the ladder: Gaussian, and the measured one
#: matched exactly (IAAFT); Johnson (skewness and kurtosis alone) left out, for the check's time
PSD_MARGINALS = ("gaussian", "iaaft")
#: the 2-D spectral mixture's height distributions on the ladder, as the PSD model's
SM_MARGINALS = PSD_MARGINALS

#: The ladder, simplest first. eq 18 is the paper's row; the measured-PSD model
#: (:mod:`roughgp.surface_models.measured_psd`) with :data:`PSD_MARGINALS`.
RUNGS = {rung.name: rung for rung in (
    Rung("eq18", "eq 18, Gaussian (the paper)", _eq18(), "eq 18\n(paper)"),
    Rung("eq18-johnson", "eq 18, Johnson heights", _eq18(non_gaussian=True), "eq 18\nJohnson"),
    Rung("matern-1.5", "Matérn ν = 1.5, Gaussian", _eq18(nu=1.5), "Matérn\nν = 1.5"),
    Rung("matern-2.5", "Matérn ν = 2.5, Gaussian", _eq18(nu=2.5), "Matérn\nν = 2.5"),
    *(Rung(f"sm-{m}", f"2-D spectral mixture, {_HEIGHTS.get(m, m)}", _sm(m),
           "spectral\nmixture" + ("" if m == "gaussian" else f"\n{m.upper()}"))
      for m in SM_MARGINALS),
    *(Rung(f"psd-{m}", f"measured PSD, {_HEIGHTS.get(m, m)}", _psd(m),
           "measured\nPSD" + ("" if m == "gaussian" else f"\n{m.upper()}"))
      for m in PSD_MARGINALS),
)}


def _short(rung) -> str:
    """A rung's short label (:attr:`Rung.short`), its own name for a rung not in :data:`RUNGS`."""
    return RUNGS[rung].short if rung in RUNGS else rung


#: the quick run's rungs: all but the Matérn ones (the slowest fits, the best on none of the
#: quick maps) and the spectral mixture with Gaussian heights (its IAAFT rung keeps the heights)
QUICK_RUNGS = tuple(name for name in RUNGS
                    if not name.startswith("matern") and name != "sm-gaussian")


def crop_size(full=None) -> int:
    """The side of the central crop of each map: 128 quick, 256 at full size
    (:func:`roughgp.common.settings.pick`)."""
    return pick(128, 256, full=full)


@dataclasses.dataclass(frozen=True)
class RungResult:
    """One rung on one map.

    Attributes:
        file, rung: the map (its name in ``data/``) and the rung's name.
        window: the crop, ``(first row, first column, rows, columns)`` of the map.
        outside: the parameters outside the 19 simulations' range (None: the rung failed).
        check: the :class:`~roughgp.checking.model_check.ModelCheck` (None: failed).
        rmse_ratio: the GP's held-out RMSE over linear interpolation's (NaN: no score).
        coverage: the share of the held-out heights within 2 predictive sd (NaN: no score).
        fit_seconds, check_seconds: wall times.
        description: the fitted model in one line, or the error where the rung failed.
        notes: what the fit's range check did (a bound, a cap).
        recorded_reasons: :func:`reasons` as a recorded run kept them (no check kept).
    """

    file: str
    rung: str
    window: tuple
    outside: tuple | None
    check: object
    rmse_ratio: float
    coverage: float
    fit_seconds: float
    check_seconds: float
    description: str
    notes: tuple = ()
    recorded_reasons: tuple = ()

    @property
    def n_outside(self) -> int | None:
        return None if self.outside is None else len(self.outside)

    def to_record(self) -> dict:
        """A JSON-ready dict (the check left out, its :func:`reasons` kept as text)."""
        return {"file": self.file, "rung": self.rung, "window": list(self.window),
                "outside": None if self.outside is None else list(self.outside),
                "rmse_ratio": self.rmse_ratio, "coverage": self.coverage,
                "fit_seconds": self.fit_seconds, "check_seconds": self.check_seconds,
                "description": self.description, "notes": list(self.notes),
                "reasons": reasons(self)}

    @classmethod
    def from_record(cls, record) -> "RungResult":
        """The result of :meth:`to_record` (without its check)."""
        outside = record["outside"]
        return cls(record["file"], record["rung"], tuple(record["window"]),
                   None if outside is None else tuple(outside), None,
                   float(record["rmse_ratio"]), float(record["coverage"]),
                   float(record["fit_seconds"]), float(record["check_seconds"]),
                   record["description"], tuple(record["notes"]),
                   tuple(record.get("reasons", ())))


def _held_out_score(model, z, spacing, held):
    """``(RMSE ratio GP / linear, coverage of +-2 sd)`` at the held-out points."""
    if held is None:
        return float("nan"), float("nan")
    residual = form_removed(z, spacing, model.cutoffs).sl
    score = self_check_fill(residual, model.kernel(), noise_variance=model.noise_variance,
                            spacing=spacing, held_out=held)
    rmse = score.rmse
    return float(rmse["GP"] / rmse["linear"]), float(score.coverage(2.0))


def run_rung(z, spacing, rung, *, file="", window=None, form="plane", seed=0,
             n_simulations=19) -> RungResult:
    """Fit ``rung`` (a :class:`Rung` or a name in :data:`RUNGS`) to the map ``z`` (um, NaN
    where unmeasured) without its held-out points, check the model against the whole map and
    score it at the held-out points (module docstring). A fit or check that fails (a model
    that cannot be simulated, say) is kept as a result with ``outside=None`` and the error."""
    rung = RUNGS[rung] if isinstance(rung, str) else rung
    z = np.asarray(z, dtype=np.float64)
    window = window or (0, 0, *z.shape)
    held = held_out_points(np.isfinite(z), seed)
    train = z if held is None else np.where(held, np.nan, z)
    start = time.perf_counter()
    try:
        fitted = rung.fit(train, spacing, form=form, seed=seed, data={"file": file})
    except (ValueError, RuntimeError, np.linalg.LinAlgError) as error:
        return RungResult(file, rung.name, window, None, None, float("nan"), float("nan"),
                          time.perf_counter() - start, 0.0, f"the fit failed: {error}")
    fit_seconds = time.perf_counter() - start
    model = fitted.model
    start = time.perf_counter()
    try:
        check = check_model(model, z, spacing, n_simulations=n_simulations, seed=seed)
    except (ValueError, RuntimeError, np.linalg.LinAlgError) as error:
        return RungResult(file, rung.name, window, None, None, float("nan"), float("nan"),
                          fit_seconds, time.perf_counter() - start,
                          f"{model.describe()}; the check failed: {error}")
    check_seconds = time.perf_counter() - start
    ratio, coverage = _held_out_score(model, z, spacing, held)
    return RungResult(file, rung.name, window, tuple(check.outside), check, ratio, coverage,
                      fit_seconds, check_seconds, model.describe(),
                      tuple(getattr(fitted, "range_notes", ())))


@dataclasses.dataclass(frozen=True)
class Ladder:
    """What :func:`model_ladder` returns: every rung on every file.

    Attributes:
        results: the :class:`RungResult` list, file by file, rung by rung.
        files, rungs: in the order run.
        size: the crop's side; seconds: wall time of the whole run.
    """

    results: tuple
    files: tuple
    rungs: tuple
    size: int
    seconds: float

    @classmethod
    def from_records(cls, records, size, seconds=float("nan")) -> "Ladder":
        """A ladder of :meth:`RungResult.to_record` records (a recorded run, perhaps of
        several passes): the rungs in the order of :data:`RUNGS`, the files in the order they
        come, and of those only the files with a record of every rung (a run stopped part-way
        leaves its last file out)."""
        results = tuple(RungResult.from_record(r) for r in records)
        present = set(r.rung for r in results)
        rungs = tuple(g for g in RUNGS if g in present) + \
            tuple(sorted(present.difference(RUNGS)))
        done = {(r.file, r.rung) for r in results}
        files = tuple(f for f in dict.fromkeys(r.file for r in results)
                      if all((f, g) in done for g in rungs))
        return cls(tuple(r for r in results if r.file in files), files, rungs, int(size),
                   float(seconds))

    def result(self, file, rung) -> RungResult:
        for r in self.results:
            if r.file == file and r.rung == rung:
                return r
        raise ValueError(f"no result for file {file!r} and rung {rung!r}")

    def best(self, file) -> RungResult:
        """The best rung on ``file``: the fewest parameters outside, then the lower held-out
        RMSE ratio, then the earlier (simpler) rung. Failed rungs are never best unless all
        failed."""
        ranked = [(r.n_outside if r.outside is not None else 99,
                   r.rmse_ratio if np.isfinite(r.rmse_ratio) else np.inf, self.rungs.index(r.rung),
                   r) for r in self.results if r.file == file]
        return min(ranked, key=lambda t: t[:3])[-1]

    def reproduced(self, max_outside=MAX_OUTSIDE) -> list:
        """The files whose best rung leaves at most ``max_outside`` parameters outside."""
        return [f for f in self.files
                if self.best(f).outside is not None and self.best(f).n_outside <= max_outside]

    def share_reproduced(self, max_outside=MAX_OUTSIDE) -> float:
        """The share of the files :meth:`reproduced`: the issue asks for >= 80 %."""
        return len(self.reproduced(max_outside)) / len(self.files)

    def files_outside(self, rung=None) -> dict:
        """``{parameter: number of files with it outside}`` under ``rung`` (a name; None: each
        file's best rung), over the files where that rung ran."""
        chosen = [self.best(f) if rung is None else self.result(f, rung) for f in self.files]
        return {name: sum(name in r.outside for r in chosen if r.outside is not None)
                for name in SURFACE_PARAMETERS}

    def counts(self):
        """A pandas DataFrame, files x rungs: the number of parameters outside (NaN: failed)."""
        import pandas as pd
        return pd.DataFrame([[np.nan if self.result(f, g).outside is None
                              else self.result(f, g).n_outside for g in self.rungs]
                             for f in self.files], index=list(self.files),
                            columns=list(self.rungs))

    def table(self):
        """A pandas DataFrame, one row per file and rung: the crop, the count outside and
        which, the held-out score, the fit seconds, and whether it is the file's best rung."""
        import pandas as pd
        rows = []
        for r in self.results:
            best = self.best(r.file) is r
            rows.append({"file": r.file, "crop (rows x cols at row, col)":
                         f"{r.window[2]} x {r.window[3]} at {r.window[0]}, {r.window[1]}",
                         "model": RUNGS[r.rung].label if r.rung in RUNGS else r.rung,
                         "outside (of 13)": r.n_outside,
                         "which": "failed: " + r.description if r.outside is None
                         else ", ".join(r.outside) or "none",
                         "held-out RMSE / linear": r.rmse_ratio,
                         "in ±2 sd": r.coverage, "fit (s)": r.fit_seconds, "best": best})
        return pd.DataFrame(rows)


#: the records of a run on every map (``benchmarks/model_ladder_full.py --size 128``)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "model_ladder_full_128.jsonl"


def recorded_ladder(path=RECORDED, size=128) -> Ladder:
    """The :class:`Ladder` of a recorded run (JSON lines of :meth:`RungResult.to_record`), or
    None where there is no such file."""
    path = Path(path)
    if not path.is_file():
        return None
    records = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return Ladder.from_records(records, size)


def model_ladder(files=None, rungs=None, *, size=None, seed=0, n_simulations=19,
                 full=None, progress=None) -> Ladder:
    """Every rung of ``rungs`` (names; default :data:`QUICK_RUNGS` quick, all of
    :data:`RUNGS` at full size) on every map of ``files``
    (names in ``data/``; default :data:`QUICK_FILES` quick, all of
    :data:`~roughgp.experiments.real_maps.REAL_MAPS` at full size), each cropped to its central
    ``size`` points (default :func:`crop_size`). ``progress``: a callable given each
    :class:`RungResult` as it comes (a log for long runs)."""
    files = tuple(files or pick(QUICK_FILES, tuple(e.name for e in REAL_MAPS), full=full))
    rungs = tuple(rungs or pick(QUICK_RUNGS, tuple(RUNGS), full=full))
    unknown = [g for g in rungs if g not in RUNGS]
    if unknown:
        raise ValueError(f"rungs must be among {list(RUNGS)}, got {unknown}")
    size = crop_size(full) if size is None else int(size)
    start = time.perf_counter()
    results = []
    for name in files:
        for rung in rungs:
            result = ladder_case(name, rung, size, seed=seed, n_simulations=n_simulations)
            results.append(result)
            if progress is not None:
                progress(result)
    return Ladder(tuple(results), files, rungs, size, time.perf_counter() - start)


def ladder_case(name, rung, size, *, seed=0, n_simulations=19) -> RungResult:
    """One case of the ladder: the rung ``rung`` on the central ``size`` points of the map
    ``name`` of data/ (its form from :data:`FORMS`), as :func:`model_ladder` runs it. Depends on
    its arguments only: the benchmark runs the cases on the project's engine
    (:func:`roughgp.batch.engine.run_cases`) with the same records in any order."""
    z, spacing, window = central_crop(name, size)
    return run_rung(z, spacing, rung, file=name, window=window, form=FORMS.get(name, "plane"),
                    seed=seed, n_simulations=n_simulations)


#: the parameters of the height distribution's tails (spikes, pits, steps)
TAILS = ("Ssk", "Sku", "Sp", "Sv", "Sz", "Spk", "Svk")
#: the amplitude (variance) parameters
AMPLITUDE = ("Sq", "Sa", "Sk")
#: the spatial parameters (lay, correlation length)
SPATIAL = ("Sal", "Str", "Std")


def _span(p, unit=True):
    u = f" {p.unit.replace('um', 'µm')}" if unit and p.unit else ""
    return f"{p.name} {p.measured:.3g}{u} against {p.low:.3g} to {p.high:.3g}"


def reasons(result: RungResult) -> list:
    """What the model of ``result`` misses, from which parameters stay outside, with the
    measured value against the simulations' range of one parameter of each group: the height
    distribution (:data:`TAILS`: spikes, pits, steps, plateaus), the amplitude
    (:data:`AMPLITUDE`: a variance the model's simulations do not match, long wavelengths or a
    field that is not stationary), the spatial structure (:data:`SPATIAL`: a lay, periodic or structured texture, or a
    correlation the model's lengths do not describe). Empty when none is outside."""
    if result.outside is None:
        return [result.description]
    if result.check is None and result.recorded_reasons:
        return list(result.recorded_reasons)
    by_name = {} if result.check is None else {p.name: p for p in result.check.parameters}
    said = []
    for group, lead, what in (
            (TAILS, "Sku", "the height distribution (its tails and asymmetry: spikes, "
                           "pits, steps, plateaus)"),
            (AMPLITUDE, "Sq", "the amplitude (wavelengths longer than the fit sees, or a "
                              "field that is not stationary)"),
            (SPATIAL, "Sal", "the spatial structure (lay, periodic or structured texture, "
                             "correlation lengths)")):
        out = [n for n in group if n in result.outside]
        if out:
            shown = by_name.get(lead if lead in out else out[0])
            said.append(f"{what}: {', '.join(out)}" + (f" ({_span(shown)})" if shown else ""))
    return said


def verdict_lines(ladder: Ladder) -> list:
    """One sentence per file: its instrument, its best rung and what stays outside and why
    (:func:`reasons`), and what the paper's eq 18 leaves outside."""
    lines = []
    for name in ladder.files:
        best = ladder.best(name)
        entry = real_file(name)
        label = RUNGS[best.rung].label if best.rung in RUNGS else best.rung
        text = f"`{name}` ({entry.technique}): "
        if best.outside is None:
            text += f"every model failed ({best.description})."
        else:
            why = reasons(best)
            text += (f"best {label}, {best.n_outside} of 13 outside"
                     + (f": {'; '.join(why)}." if why else "."))
        if "eq18" in ladder.rungs and best.rung != "eq18":
            paper = ladder.result(name, "eq18")
            text += (" The paper's eq 18: " + ("failed." if paper.outside is None else
                     f"{paper.n_outside} outside ({', '.join(paper.outside) or 'none'})."))
        lines.append(text)
    return lines


def markdown_table(ladder: Ladder, *, per_rung: bool = True) -> str:
    """The ladder as a Markdown table: per file, the count outside under each rung (the best
    in bold), the parameters outside under the best and its held-out RMSE ratio. With
    ``per_rung=False`` the counts per rung give way to the best rung's name (a table that fits
    the book's column, beside :func:`plot_ladder`'s map of the counts)."""
    head = ["file", "instrument"]
    head += ([_short(g).replace("\n", " ") for g in ladder.rungs] if per_rung
             else ["best model"])
    head += ["outside (best)", "held-out RMSE / linear (best)"]
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name in ladder.files:
        best = ladder.best(name)
        cells = [f"`{name}`", real_file(name).technique]
        if per_rung:
            for rung in ladder.rungs:
                r = ladder.result(name, rung)
                cell = "failed" if r.outside is None else str(r.n_outside)
                cells.append(f"**{cell}**" if r is best else cell)
        else:
            cells.append(_short(best.rung).replace("\n", " "))
        cells.append("failed" if best.outside is None else ", ".join(best.outside) or "none")
        cells.append(f"{best.rmse_ratio:.2f}")
        rows.append("| " + " | ".join(cells) + " |")
    return "\n".join(rows)


def plot_ladder(ladder: Ladder, *, title=None):
    """The heat map files x rungs of the parameters outside (of 13), each cell labelled with
    its count, the best rung of each file framed. Returns the figure (7.6 in wide, its text at
    least 9 pt on the book's page: :func:`roughgp.common.plotting.font_sizes_on_page`)."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from roughgp.common.plotting import use_style

    use_style()
    counts = ladder.counts().to_numpy(dtype=float)
    n_files, n_rungs = counts.shape
    fig, ax = plt.subplots(figsize=(7.6, 1.6 + 0.42 * n_files))
    shown = np.ma.masked_invalid(counts)
    image = ax.imshow(shown, cmap="Reds", vmin=0, vmax=13, aspect="auto")
    for i in range(n_files):
        for j in range(n_rungs):
            text = "failed" if np.isnan(counts[i, j]) else f"{counts[i, j]:.0f}"
            ax.text(j, i, text, ha="center", va="center", fontsize=11,
                    color="white" if counts[i, j] > 8 else "black")
        j = ladder.rungs.index(ladder.best(ladder.files[i]).rung)
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, lw=2.5, color="tab:blue"))
    ax.set_xticks(range(n_rungs), [_short(g) for g in ladder.rungs], fontsize=11)
    ax.set_xlabel("model (Gaussian heights unless named)", fontsize=11)
    ax.set_yticks(range(n_files), list(ladder.files), fontsize=11)
    ax.tick_params(length=0)
    ax.grid(False)
    bar = fig.colorbar(image, ax=ax, pad=0.02)
    bar.set_label("parameters outside (of 13)", fontsize=11)
    bar.ax.tick_params(labelsize=11)
    ax.set_title(title or f"parameters outside 19 simulations; central {ladder.size} x "
                 f"{ladder.size} points; the best model framed", fontsize=11)
    return fig
