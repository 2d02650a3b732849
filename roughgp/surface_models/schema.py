"""The model file's schema, validated once (beyond the paper).

Every command that reads a model file (``simulate --from``, ``check``, ``fill --model``)
reads it through :meth:`roughgp.surface_models.model.FittedModel.load`, which calls
:func:`validate_record` on the parsed JSON first; every FittedModel checks its fields with
:func:`check_fields`. A file is refused, with a message that names the field and the allowed
range, when it is larger than :data:`MAX_FILE_BYTES`, nested deeper than :data:`MAX_DEPTH`, of
another format or version, lacks a required field or has one this version does not know, or
holds a value of the wrong type (``true`` is not a number) or out of its range (:data:`RANGES`).
"""

from __future__ import annotations

from roughgp.surface_models import psd_core
from roughgp.surface_models.schema_numbers import (RANGES, ModelFileError, is_number, number,
                                                   numbers_list)

# ModelFileError and RANGES are imported from roughgp.surface_models.schema_numbers (and
# documented there); importing them from here works as before
__all__ = ["MODEL_FORMAT", "MODEL_VERSIONS", "STAGES", "EQUATIONS",
           "MAX_DEPTH", "MAX_FILE_BYTES", "MAX_MIXTURES", "MAX_SM2D_COMPONENTS",
           "SM2D_BANDWIDTHS", "FORMS", "AXES", "MAX_ANCHORS", "FIELD_NAMES", "FIT_INTEGERS",
           "FEED_DIRECTIONS", "MARK_SAMPLES", "FIT_LIKELIHOODS", "validate_record",
           "check_fields", "check_fit"]

MODEL_FORMAT = "roughgp-model"
#: versions read: 1 (no stage: its models describe the filtered heights) and 2
MODEL_VERSIONS = (1, 2)
#: the stages of the operator chain a model may describe
STAGES = ("form-removed", "filtered")
#: equation -> (kind, the hyperparameters it needs, with their units in the names)
EQUATIONS = {
    "eq18": ("surface", ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg",
                         "noise_variance_um2")),
    "eq18-matern": ("surface", ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg",
                                "noise_variance_um2", "nu")),
    "eq21": ("profile", ("weights_um2", "frequencies_per_um", "spectral_variances_per_um2",
                         "noise_variance_um2")),
    "measured-psd": ("surface", ("psd_um4", "frequency_min_per_um", "frequency_max_per_um",
                                 "noise_variance_um2")),
    "sm2d": ("surface", ("weights_um2", "frequencies_x_per_um", "frequencies_y_per_um",
                         "bandwidths_a_per_um", "bandwidths_b_per_um", "axes_deg",
                         "noise_variance_um2")),
    # eq 18 with parameter fields: their values at anchors (rows y, columns x), interpolated
    # between them (roughgp.surface_models.field_model)
    "eq18-field": ("surface", ("anchors_x_um", "anchors_y_um", "variance_um2", "lambda_a_um",
                               "lambda_b_um", "angle_deg", "noise_variance_um2")),
    # eq 18 over a population of regions: the typical region's parameters and the spread of a
    # new region about them (roughgp.surface_models.population_model)
    "eq18-population": ("surface", ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg",
                                    "noise_variance_um2", "log_variance_sd", "log_lambda_a_sd",
                                    "log_lambda_b_sd", "angle_sd_deg", "regions")),
    # a periodic machined surface: a deterministic feed mark, each mark's shift and depth as
    # Gaussian processes over the marks (and along the lay), eq 18 on top
    # (roughgp.surface_models.periodic_model)
    "periodic-mark": ("surface", ("feed_um", "feed_direction_deg", "origin_um", "mark_um",
                                  "shift_sd_um", "shift_rho", "depth_sd_um", "depth_rho",
                                  "lay_sd_um", "depth_length_um", "marks_fitted", "variance_um2", "lambda_a_um",
                                  "lambda_b_um", "angle_deg", "noise_variance_um2")),
    # the same for a profile, the roughness on top eq 18's exponential in one dimension
    "periodic-mark-profile": ("profile", ("feed_um", "origin_um", "mark_um", "shift_sd_um",
                                          "shift_rho", "depth_sd_um", "depth_rho",
                                          "marks_fitted", "variance_um2", "lambda_um",
                                          "noise_variance_um2")),
}
#: the periodic-mark model's directions of the feed (the marks repeat along x: 0, along y: 90)
FEED_DIRECTIONS = (0, 90)
#: the periodic-mark model's fewest and most samples of the mark
MARK_SAMPLES = (4, 8192)
#: the parameter fields' most anchors per axis
MAX_ANCHORS = 32
#: the fields of the eq18-field model, each a list of rows (anchors_y) of anchors_x values
FIELD_NAMES = ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg")
#: the 2-D spectral mixture's most components (its fit tries 4 by default)
MAX_SM2D_COMPONENTS = 8
#: its bandwidths' allowed range, in units of the Nyquist frequency 1 / (2 spacing): at least
#: 1e-4 (a correlation over some 10^4 points, what a circulant embedding can still hold)
SM2D_BANDWIDTHS = (1e-4, 4.0)
#: the IAAFT marginal's allowed number of quantiles and of iterations
QUANTILES = (3, 2001)
ITERATIONS = (1, 1000)
#: the log-polar PSD table's allowed size: radial bins, angular bins
PSD_RADII = (4, 128)
PSD_ANGLES = (1, 180)
OPTIONAL_HYPERPARAMETERS = ("mean_um",)
MAX_MIXTURES = 50
MAX_DEPTH = 8
MAX_FILE_BYTES = 1 << 20
MAX_OPERATORS = 16
#: the fields of the ``fit`` object that roughgp reads back (a calibrated check refits the
#: model the way it was fitted): integer name -> allowed range; ``likelihood`` one of
#: :data:`FIT_LIKELIHOODS`. The object's other fields (method, log likelihood, notes) are a
#: record, not read back.
FIT_INTEGERS = {"seed": (0, 2**32 - 1), "block": (4, 1024), "n_blocks": (1, 10000)}
FIT_LIKELIHOODS = ("blocks", "whittle")
FORMS = ("plane", "polynomial", "cylinder", None)
AXES = ("auto", "x", "y")
#: the population model's fewest and most regions
POPULATION_REGIONS = (2, 100000)
_TOP = {"format", "version", "equation", "kind", "stage", "description", "hyperparameters",
        "spacing_um", "marginal", "operators", "cutoffs", "data", "fit", "roughgp_version"}
_REQUIRED = ("format", "version", "equation", "hyperparameters", "spacing_um")


def _depth(value, level=1):
    if level > MAX_DEPTH:
        raise ModelFileError(f"the model file is nested deeper than {MAX_DEPTH} levels")
    if isinstance(value, (dict, list)):
        for v in (value.values() if isinstance(value, dict) else value):
            _depth(v, level + 1)


def check_fields(equation, hyperparameters, spacing, marginal, cutoffs, stage, operators=()):
    """The fields of a model (file or object): types, names and ranges (module docstring)."""
    if not isinstance(equation, str) or equation not in EQUATIONS:
        raise ModelFileError(f"equation must be one of {sorted(EQUATIONS)}, got {equation!r}")
    if not isinstance(stage, str) or stage not in STAGES:
        raise ModelFileError(f"stage must be one of {list(STAGES)}, got {stage!r}")
    kind, names = EQUATIONS[equation]
    if not isinstance(hyperparameters, dict):
        raise ModelFileError(f"hyperparameters must be an object, got {hyperparameters!r}")
    missing = [n for n in names if n not in hyperparameters]
    if missing:
        raise ModelFileError(f"the {equation} model lacks {', '.join(missing)}")
    extra = sorted(set(hyperparameters) - set(names) - set(OPTIONAL_HYPERPARAMETERS)
                   - set(psd_core.KEYS if equation == "measured-psd" else ())
                   - ({"steps"} if equation == "eq18-field" else set()))
    if extra:
        raise ModelFileError(f"the {equation} model has unknown hyperparameters "
                             f"{', '.join(map(str, extra))} (it takes {', '.join(names)})")
    hp = hyperparameters
    spacing = numbers_list("spacing_um", spacing, count=(2 if kind == "surface" else 1,))
    number("noise_variance_um2", hp["noise_variance_um2"])
    if "mean_um" in hp:
        number("mean_um", hp["mean_um"])
    if equation == "measured-psd":
        _check_psd(hp)
    elif equation == "sm2d":
        _check_sm2d(hp, spacing)
    elif equation == "eq18-field":
        _check_field(hp, spacing)
    elif equation == "eq18-population":
        for name in ("log_variance_sd", "log_lambda_a_sd", "log_lambda_b_sd", "angle_sd_deg"):
            number(name, hp[name])
        regions = hp["regions"]
        if not (is_number(regions) and float(regions).is_integer()
                and POPULATION_REGIONS[0] <= regions <= POPULATION_REGIONS[1]):
            raise ModelFileError(f"regions must be an integer in [{POPULATION_REGIONS[0]}, "
                                 f"{POPULATION_REGIONS[1]}] (the regions pooled), got "
                                 f"{regions!r}")
    elif equation in ("periodic-mark", "periodic-mark-profile"):
        _check_periodic(hp, spacing)
        if marginal is not None:
            raise ModelFileError(f"the {equation} model draws its roughness with Gaussian "
                                 f"heights: its marginal must be null")
    if equation in ("eq18-field", "eq18-population") and marginal is not None:
        raise ModelFileError(f"the {equation} model draws Gaussian heights: its marginal must "
                             f"be null")
    if kind == "surface" and equation not in ("measured-psd", "sm2d", "eq18-field"):
        for name in ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg"):
            number(name, hp[name])
        for name in ("lambda_a_um", "lambda_b_um"):
            if not 1e-3 * min(spacing) <= hp[name] <= 1e7 * max(spacing):
                raise ModelFileError(f"{name} must be within [1e-3, 1e7] spacings "
                                     f"([{1e-3 * min(spacing):g}, {1e7 * max(spacing):g}] um), "
                                     f"got {hp[name]!r}")
        if equation == "eq18-matern" and (not is_number(hp["nu"]) or hp["nu"] not in (1.5, 2.5)):
            raise ModelFileError(f"nu must be 1.5 or 2.5 (0.5 is eq 18), got {hp['nu']!r}")
    elif equation == "eq21":
        lists = [numbers_list(n, hp[n], count=range(1, MAX_MIXTURES + 1)) for n in names[:3]]
        if len({len(v) for v in lists}) != 1:
            raise ModelFileError("weights_um2, frequencies_per_um and "
                                 "spectral_variances_per_um2 must have the same length")
    if isinstance(marginal, dict) and marginal.get("method") == "iaaft":
        _check_iaaft(marginal)
    elif marginal is not None:
        if not isinstance(marginal, dict) or set(marginal) != {"skewness", "kurtosis"}:
            raise ModelFileError(f"marginal must be null, {{\"skewness\": s, \"kurtosis\": k}} "
                                 f"(Johnson) or {{\"method\": \"iaaft\", \"quantiles_um\": "
                                 f"[...], \"tail_probability\": p, \"iterations\": n}}, "
                                 f"got {marginal!r:.200}")
        s, k = number("skewness", marginal["skewness"]), number("kurtosis", marginal["kurtosis"])
        if not k > s * s + 1:
            raise ModelFileError(f"marginal kurtosis must be > skewness**2 + 1, got {marginal!r}")
    _check_cutoffs(cutoffs)
    if not isinstance(operators, (list, tuple)) or len(operators) > MAX_OPERATORS or \
            not all(isinstance(op, str) and len(op) <= 200 for op in operators):
        raise ModelFileError(f"operators must be a list of at most {MAX_OPERATORS} short "
                             f"strings, got {operators!r}")


def _check_iaaft(marginal):
    """The IAAFT marginal: ``QUANTILES`` non-decreasing heights (um), not all equal, an
    iteration count in ``ITERATIONS``, and strictly increasing ``order_scores`` if any."""
    extra = sorted(set(marginal) - {"method", "quantiles_um", "tail_probability", "iterations",
                                    "above_l_um", "order_scores"})
    missing = sorted({"quantiles_um", "tail_probability", "iterations"} - set(marginal))
    if extra or missing:
        raise ModelFileError("the iaaft marginal takes method, quantiles_um, tail_probability "
                             "and iterations"
                             + (f"; unknown {', '.join(map(str, extra))}" if extra else "")
                             + (f"; lacks {', '.join(missing)}" if missing else ""))
    q = marginal["quantiles_um"]
    if not isinstance(q, (list, tuple)) or not QUANTILES[0] <= len(q) <= QUANTILES[1]:
        raise ModelFileError(f"quantiles_um must be a list of {QUANTILES[0]} to {QUANTILES[1]} "
                             f"heights (um), got {type(q).__name__}"
                             + (f" of {len(q)}" if isinstance(q, (list, tuple)) else ""))
    q = numbers_list("quantiles_um", q)
    if any(b < a for a, b in zip(q, q[1:])) or not q[-1] > q[0]:
        raise ModelFileError("quantiles_um must be non-decreasing and not all equal (the "
                             "quantile function of the heights)")
    number("tail_probability", marginal["tail_probability"], where="marginal tail_probability")
    if "order_scores" in marginal:   # roughgp.surface_models.order_scores
        keys = numbers_list("order_scores", marginal["order_scores"], count=(len(q),))
        if any(b <= a for a, b in zip(keys, keys[1:])):
            raise ModelFileError("order_scores must be strictly increasing (one normal score "
                                 "per quantile)")
    if "above_l_um" in marginal:
        number("l_um", marginal["above_l_um"], where="marginal above_l_um")
    n = marginal["iterations"]
    if not isinstance(n, int) or isinstance(n, bool) or not ITERATIONS[0] <= n <= ITERATIONS[1]:
        raise ModelFileError(f"marginal iterations must be an integer in [{ITERATIONS[0]}, "
                             f"{ITERATIONS[1]}], got {n!r}")


def _check_psd(hp):
    """The measured-psd model's table: a list of ``PSD_RADII`` rows of ``PSD_ANGLES`` numbers
    >= 0, not all 0, over frequencies ``frequency_min_per_um`` < ``frequency_max_per_um``."""
    rows = hp["psd_um4"]
    if not isinstance(rows, list) or not PSD_RADII[0] <= len(rows) <= PSD_RADII[1]:
        raise ModelFileError(f"psd_um4 must be a list of {PSD_RADII[0]} to {PSD_RADII[1]} rows "
                             f"(radial bins), got {type(rows).__name__}"
                             + (f" of {len(rows)}" if isinstance(rows, list) else ""))
    width = len(rows[0]) if isinstance(rows[0], list) else None
    if width is None or not PSD_ANGLES[0] <= width <= PSD_ANGLES[1]:
        raise ModelFileError(f"psd_um4 rows must be lists of {PSD_ANGLES[0]} to {PSD_ANGLES[1]} "
                             f"numbers (angular bins), got {rows[0]!r:.60}")
    total = 0.0
    for i, row in enumerate(rows):
        if not isinstance(row, list) or len(row) != width:
            raise ModelFileError(f"psd_um4[{i}] must be a list of {width} numbers like row 0")
        total += sum(number("psd_um4", v, where=f"psd_um4[{i}][{j}]") for j, v in enumerate(row))
    if not total > 0:
        raise ModelFileError("psd_um4 must hold at least one value > 0")
    if hp["noise_variance_um2"] != 0:
        raise ModelFileError(f"noise_variance_um2 of a measured-psd model must be 0 (its white "
                             f"noise is part of psd_um4, the table's flat high-frequency "
                             f"floor, and no command adds another), got "
                             f"{hp['noise_variance_um2']!r}")
    low = number("frequency_min_per_um", hp["frequency_min_per_um"])
    high = number("frequency_max_per_um", hp["frequency_max_per_um"])
    if not low < high:
        raise ModelFileError(f"frequency_min_per_um must be smaller than frequency_max_per_um, "
                             f"got {low:g} and {high:g}")
    psd_core.check_core(hp, ModelFileError)


def _check_field(hp, spacing):
    """The eq18-field model: 1 to :data:`MAX_ANCHORS` strictly increasing anchors per axis,
    and each field of :data:`FIELD_NAMES` a list of ``len(anchors_y_um)`` rows of
    ``len(anchors_x_um)`` numbers in the range of the stationary eq 18's; optionally
    ``steps``, per field the boundary of two zones (:func:`_check_steps`)."""
    axes = {}
    for name in ("anchors_x_um", "anchors_y_um"):
        values = numbers_list(name, hp[name], count=range(1, MAX_ANCHORS + 1))
        if any(b <= a for a, b in zip(values, values[1:])):
            raise ModelFileError(f"{name} must be strictly increasing, got {values!r:.200}")
        axes[name] = values
    rows, cols = len(axes["anchors_y_um"]), len(axes["anchors_x_um"])
    for name in FIELD_NAMES:
        grid = hp[name]
        if not isinstance(grid, list) or len(grid) != rows or not all(
                isinstance(row, list) and len(row) == cols for row in grid):
            raise ModelFileError(f"{name} must be a list of {rows} rows (anchors_y_um) of {cols} "
                                 f"numbers (anchors_x_um), got {grid!r:.120}")
        for i, row in enumerate(grid):
            for j, value in enumerate(row):
                value = number(name, value, where=f"{name}[{i}][{j}]")
                if name.startswith("lambda") and not \
                        1e-3 * min(spacing) <= value <= 1e7 * max(spacing):
                    raise ModelFileError(f"{name}[{i}][{j}] must be within [1e-3, 1e7] spacings "
                                         f"([{1e-3 * min(spacing):g}, {1e7 * max(spacing):g}] "
                                         f"um), got {value!r}")
    if "steps" in hp:
        _check_steps(hp["steps"], axes)


def _check_steps(steps, axes):
    """``steps``: an object whose keys are fields of :data:`FIELD_NAMES` and whose values are
    ``{"axis": "x" or "y", "at_um": b}``, ``b`` strictly between two neighbouring anchors of
    that axis (the field steps there between two zones)."""
    if not isinstance(steps, dict):
        raise ModelFileError(f"steps must be an object (field -> its step), got {steps!r:.120}")
    for name, step in steps.items():
        if name not in FIELD_NAMES:
            raise ModelFileError(f"steps has an unknown field {name!r:.60} (it takes "
                                 f"{', '.join(FIELD_NAMES)})")
        if not isinstance(step, dict) or set(step) != {"axis", "at_um"} or \
                step["axis"] not in ("x", "y"):
            raise ModelFileError(f"steps.{name} must be {{\"axis\": \"x\" or \"y\", "
                                 f"\"at_um\": a position}}, got {step!r:.120}")
        anchors = axes[f"anchors_{step['axis']}_um"]
        at = number(f"anchors_{step['axis']}_um", step["at_um"], where=f"steps.{name}.at_um")
        if not any(a < at < b for a, b in zip(anchors, anchors[1:])):
            raise ModelFileError(f"steps.{name}.at_um must lie strictly between two "
                                 f"neighbouring anchors_{step['axis']}_um, got {at!r}")


def _check_periodic(hp, spacing):
    """The periodic-mark model: the feed along x or y (:data:`FEED_DIRECTIONS`), at least
    ``MARK_SAMPLES[0]`` spacings of that axis; the mark ``MARK_SAMPLES`` heights; the origin
    within one feed; shifts of at most a quarter feed; correlations in [0, 0.99]."""
    direction = hp.get("feed_direction_deg", 0)     # a profile's marks repeat along it
    if not is_number(direction) or direction not in FEED_DIRECTIONS:
        raise ModelFileError(f"feed_direction_deg must be 0 (the marks repeat along x) or 90 "
                             f"(along y), got {direction!r}")
    step = spacing[-1] if direction == 0 else spacing[0]
    feed = number("feed_um", hp["feed_um"])
    if not feed >= MARK_SAMPLES[0] * step:
        raise ModelFileError(f"feed_um must be at least {MARK_SAMPLES[0]} spacings "
                             f"({MARK_SAMPLES[0] * step:g} um) along the feed, got {feed!r}")
    mark = hp["mark_um"]
    if not isinstance(mark, list) or not MARK_SAMPLES[0] <= len(mark) <= MARK_SAMPLES[1]:
        raise ModelFileError(f"mark_um must be a list of {MARK_SAMPLES[0]} to {MARK_SAMPLES[1]} "
                             f"heights (um), got {type(mark).__name__}"
                             + (f" of {len(mark)}" if isinstance(mark, list) else ""))
    numbers_list("mark_um", mark)
    if not number("origin_um", hp["origin_um"]) < feed:
        raise ModelFileError(f"origin_um must be in [0, feed_um = {feed:g}), got "
                             f"{hp['origin_um']!r}")
    if not number("shift_sd_um", hp["shift_sd_um"]) <= feed / 4:
        raise ModelFileError(f"shift_sd_um must be in [0, feed_um / 4 = {feed / 4:g}], got "
                             f"{hp['shift_sd_um']!r}")
    for name in ("shift_rho", "depth_sd_um", "depth_rho", "lay_sd_um", "depth_length_um",
                 "variance_um2", "lambda_um"):
        if name in hp:
            number(name, hp[name])
    count = hp["marks_fitted"]
    if not isinstance(count, int) or isinstance(count, bool) or not 2 <= count <= 10 ** 6:
        raise ModelFileError(f"marks_fitted must be an integer in [2, 1000000] (the whole marks "
                             f"the spreads were estimated from), got {count!r:.60}")


def _check_sm2d(hp, spacing):
    """The 2-D spectral mixture: lists of 1 to :data:`MAX_SM2D_COMPONENTS` numbers of one
    length, each frequency within the Nyquist frequency of its axis at ``spacing`` (dy, dx), each
    bandwidth within :data:`SM2D_BANDWIDTHS` times the Nyquist frequency."""
    names = EQUATIONS["sm2d"][1][:6]
    lists = {n: numbers_list(n, hp[n], count=range(1, MAX_SM2D_COMPONENTS + 1)) for n in names}
    if len({len(v) for v in lists.values()}) != 1:
        raise ModelFileError(f"{', '.join(names)} must have the same length")
    nyquist = {"frequencies_y_per_um": 0.5 / spacing[0], "frequencies_x_per_um": 0.5 / spacing[1]}
    for name, limit in nyquist.items():
        for i, f in enumerate(lists[name]):
            if abs(f) > limit * (1 + 1e-9):
                raise ModelFileError(f"{name}[{i}] must be within the Nyquist frequency "
                                     f"[-{limit:g}, {limit:g}] 1/um of the spacing, got {f!r}")
    top = 0.5 / min(spacing)
    low, high = SM2D_BANDWIDTHS[0] * 0.5 / max(spacing), SM2D_BANDWIDTHS[1] * top
    for name in ("bandwidths_a_per_um", "bandwidths_b_per_um"):
        for i, b in enumerate(lists[name]):
            if not low <= b <= high:
                raise ModelFileError(f"{name}[{i}] must be within [{low:g}, {high:g}] 1/um "
                                     f"({SM2D_BANDWIDTHS[0]:g} to {SM2D_BANDWIDTHS[1]:g} times "
                                     f"the Nyquist frequency), got {b!r}")


def check_fit(fit) -> None:
    """The ``fit`` object's fields that are read back (:data:`FIT_INTEGERS`, ``likelihood``):
    integers (not ``true``, not ``"24"``, not ``[1]``) in their ranges, a known likelihood."""
    for name, (low, high) in FIT_INTEGERS.items():
        if name in fit:
            value = fit[name]
            if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
                raise ModelFileError(f"fit.{name} must be an integer in [{low}, {high}], got "
                                     f"{value!r:.60}")
    if "likelihood" in fit and fit["likelihood"] not in FIT_LIKELIHOODS:
        raise ModelFileError(f"fit.likelihood must be one of {list(FIT_LIKELIHOODS)}, got "
                             f"{fit['likelihood']!r:.60}")


def _check_cutoffs(cutoffs):
    if not isinstance(cutoffs, dict):
        raise ModelFileError(f"cutoffs must be an object, got {cutoffs!r}")
    extra = sorted(set(cutoffs) - {"form", "s_um", "l_um", "degree", "axis"})
    if extra:
        raise ModelFileError(f"cutoffs has unknown fields {', '.join(map(str, extra))} (it takes "
                             f"form, s_um, l_um, degree, axis)")
    form = cutoffs.get("form", "plane")
    if form not in FORMS:
        raise ModelFileError(f"cutoffs.form must be one of {list(FORMS)}, got {form!r}")
    s, l = (None if cutoffs.get(n) is None else number(n, cutoffs[n], where=f"cutoffs.{n}")
            for n in ("s_um", "l_um"))
    if s is not None and l is not None and not s < l:
        raise ModelFileError(f"cutoffs.s_um must be smaller than cutoffs.l_um, got {s:g} and "
                             f"{l:g}")
    if "degree" in cutoffs:
        degree = cutoffs["degree"]
        if not isinstance(degree, int) or isinstance(degree, bool) or not 0 <= degree <= 10:
            raise ModelFileError(f"cutoffs.degree must be an integer in [0, 10], got {degree!r}")
    if cutoffs.get("axis", "auto") not in AXES:
        raise ModelFileError(f"cutoffs.axis must be one of {list(AXES)}, got "
                             f"{cutoffs.get('axis')!r}")


def validate_record(values, source="the model") -> dict:
    """The parsed JSON of a model file, checked (module docstring); returns the fields for
    :class:`~roughgp.surface_models.model.FittedModel` (``stage`` of a version-1 file:
    ``"filtered"``)."""
    if not isinstance(values, dict) or values.get("format") != MODEL_FORMAT:
        raise ModelFileError(f"{source} is not a roughgp model file (no \"format\": "
                             f"\"{MODEL_FORMAT}\"; write one with roughgp fit ... --out)")
    version = values.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or version not in MODEL_VERSIONS:
        raise ModelFileError(f"{source} is a model file of version {version!r}; this roughgp "
                             f"reads versions {', '.join(map(str, MODEL_VERSIONS))}")
    _depth(values)
    missing = [n for n in _REQUIRED + (("stage",) if version > 1 else ()) if n not in values]
    if missing:
        raise ModelFileError(f"{source} lacks the field(s) {', '.join(missing)}")
    extra = sorted(set(values) - _TOP)
    if extra:
        raise ModelFileError(f"{source} has unknown field(s) {', '.join(map(str, extra))}")
    if version == 1 and values.get("stage", "filtered") != "filtered":
        raise ModelFileError(f"{source} is a model file of version 1, whose models describe the "
                             f"filtered heights, but states \"stage\": {values['stage']!r:.60}: "
                             f"give \"version\": 2 to keep that stage, or drop the stage")
    for name in ("data", "fit", "cutoffs"):
        if not isinstance(values.get(name, {}), dict):
            raise ModelFileError(f"{source}: {name} must be an object, got {values[name]!r}")
    for name in ("description", "roughgp_version", "kind"):
        if name in values and not isinstance(values[name], str):
            raise ModelFileError(f"{source}: {name} must be a string, got {values[name]!r}")
    fields = {"equation": values["equation"], "hyperparameters": values["hyperparameters"],
              "spacing": values["spacing_um"], "marginal": values.get("marginal"),
              "cutoffs": values.get("cutoffs", {}), "operators": values.get("operators", []),
              "stage": values["stage"] if version > 1 else "filtered"}
    try:
        check_fields(**fields)
        check_fit(values.get("fit", {}))
    except ModelFileError as exc:
        raise ModelFileError(f"{source}: {exc}") from None
    if "kind" in values and values["kind"] != EQUATIONS[values["equation"]][0]:
        raise ModelFileError(f"{source}: kind {values['kind']!r} does not match the equation "
                             f"{values['equation']} ({EQUATIONS[values['equation']][0]})")
    return {**fields, "spacing": tuple(float(v) for v in values["spacing_um"]),
            "operators": tuple(fields["operators"]), "hyperparameters": dict(fields[
                "hyperparameters"]), "cutoffs": dict(fields["cutoffs"]),
            "data": dict(values.get("data", {})), "fit": dict(values.get("fit", {}))}
