r"""The paper's loop on real measurements: fit, simulate, check, fill (beyond the paper).

The computations of the chapter "Measured surfaces", on the open files of ``data/``:

* :func:`bullet_land`: the striated bullet land (x3ptools' ``sample-land.x3p``, a confocal
  measurement with about 11 % of its points missing): its cylinder removed and its waviness cut
  by an L-filter, eq 18 fitted to the measured points (does the lay angle come out along the
  striations?), simulated, checked against the measurement, and its real holes filled;
* :func:`stylus_profile`: the Dektak stylus profile, eq 21 fitted (section 3.3's method),
  simulated and checked;
* :func:`cross_validated_fill`: measured points hidden in small discs (like an optical
  instrument's dropouts), filled by the GP (fitted without them; its smoothness and its band
  chosen by the fill's own self-check on other measured points,
  :mod:`roughgp.filling.self_check`) and by linear and cubic interpolation, scored
  against the hidden measured heights; the share inside the GP's Gaussian :math:`\pm 2` sd
  band of a new measurement, :math:`\sqrt{sd^2 + \sigma^2}`, and inside its calibrated band;
* :func:`increment_kurtosis`: how heavy-tailed the files' increments are (their defects).

The verdicts are the data's; where the model does not fit, the results say so.
"""

from __future__ import annotations

import dataclasses
import functools
import time

import numpy as np

from roughgp.filling.interpolants import interpolate_holes
from roughgp.checking.model_check import ModelCheck, check_model
from roughgp.filling.measured import MeasuredFill, fill_measured_surface
from roughgp.surface_models.fit import (
    ProfileModelFit,
    SurfaceModelFit,
    fit_profile_model,
    fit_surface_model,
)
from roughgp.filling.self_check import hide_discs, median_abs_of, rmse_of
from roughgp.experiments.real_maps import DATA
from roughgp.metrology.form import remove_form
from roughgp.io.measurement import Measurement, read_measurement

__all__ = ["DATA", "LAND_FILE", "PROFILE_FILE", "LAND_L_FILTER", "LandResult", "ProfileResult",
           "CrossValidation", "CV_FILES", "lay_deviation_deg", "land_fit", "land_check",
           "LAY_TOLERANCE_DEG", "WEAK_ANISOTROPY", "land_fit_verdicts", "land_check_verdicts",
           "bullet_land", "stylus_profile", "cross_validated_fill", "centre_crop", "hide_discs",
           "fill_verdicts", "TIE", "increment_kurtosis", "file_increment_kurtosis",
           "form_removed", "file_height_step", "display_unit", "cross_validation_rows",
           "self_check_rows"]

LAND_FILE = "sample-land.x3p"
PROFILE_FILE = "dektak-1.csv"
LAND_L_FILTER = 250.0  #: um: the land's waviness cut-off (a tenth of its width)
#: the chapter's cross-validated files and their F-operators
CV_FILES = {"sample-land.x3p": "cylinder", "sur-2.sur": "plane", "opd-1.opd": "plane",
            "di-1.di": "plane"}
TIE = 0.05  #: hidden-point RMSEs within 5 % of each other are a tie


@dataclasses.dataclass(frozen=True)
class LandResult:
    """:func:`bullet_land`: the measurement, the fit, a simulation, the check, the fill."""

    measurement: Measurement
    fit: SurfaceModelFit
    simulation: np.ndarray
    check: ModelCheck
    fill: MeasuredFill | None

    @property
    def lay_deviation_deg(self) -> float:
        """The fitted lay angle's distance from the striations' direction (y: 90 degrees)."""
        return lay_deviation_deg(self.fit)


@dataclasses.dataclass(frozen=True)
class ProfileResult:
    """:func:`stylus_profile`: the profile used, the fit, a simulation and the check."""

    z: np.ndarray
    spacing: float
    decimation: int
    fit: ProfileModelFit
    simulation: np.ndarray
    check: ModelCheck


@dataclasses.dataclass(frozen=True)
class CrossValidation:
    """:func:`cross_validated_fill`: hidden measured points and their estimates.

    Attributes:
        file: the measurement; hidden: boolean map of the hidden points.
        truth: their measured heights; estimates: ``{"GP", "linear", "cubic": heights}``.
        sd: the GP's predictive sd of a new measurement there, ``sqrt(sd^2 + sigma^2)``.
        rmse: per method; coverage: share of the hidden points within ``2 sd`` of the GP mean.
        seconds: ``{"GP": fits, self-check and fill, "linear and cubic": both}``.
        log_likelihood: the block composite log-likelihood of the GP's fit (eq 18 or its
            Matérn variant; comparable between the two on one file and seed: the same blocks).
        nu: the smoothness used; band_factor: the self-check's 95 % factor k (of its small
            discs); calibrated_coverage: share of the hidden points within the band the fill
            writes (``roughgp fill --band``: a factor per size of hole and depth,
            :mod:`roughgp.filling.hole_band`).
        self_checks: ``{nu: FillSelfCheck}`` on other measured points (the fill's choice).
        fit: the GP's fit (:class:`~roughgp.inference.block_fit.BlockFit`).
    """

    file: str
    hidden: np.ndarray
    truth: np.ndarray
    estimates: dict
    sd: np.ndarray
    rmse: dict
    coverage: float
    seconds: dict
    log_likelihood: float
    nu: float
    band_factor: float
    calibrated_coverage: float
    self_checks: dict
    fit: object = None

    @property
    def median_abs(self) -> dict:
        """``{method: median absolute error at the hidden points}``."""
        return median_abs_of(self.estimates, self.truth)

    def worse_tail(self, method="GP", than="linear") -> float:
        """The share of the hidden points, counted from the largest errors down, over which
        ``method``'s sorted absolute errors exceed ``than``'s (0: never at the top)."""
        a = np.sort(np.abs(self.estimates[method] - self.truth))[::-1]
        b = np.sort(np.abs(self.estimates[than] - self.truth))[::-1]
        better = np.flatnonzero(a <= b)
        return float((better[0] if better.size else a.size) / a.size)

    def largest_errors_share(self, method="GP", top=0.01) -> float:
        """The share of ``method``'s squared error carried by its largest ``top`` of errors."""
        squared = np.sort((self.estimates[method] - self.truth) ** 2)[::-1]
        return float(squared[:max(1, int(round(top * squared.size)))].sum() / squared.sum())


def _read(name):
    return read_measurement(DATA / name)


def lay_deviation_deg(fit: SurfaceModelFit) -> float:
    """The fitted lay angle (phi of eq 18) from the land's striations (along y: 90 degrees
    from x), in degrees, 0 to 90."""
    angle = fit.model.hyperparameters["angle_deg"]
    return float(abs(angle % 180.0 - 90.0))


def land_fit(*, seed=0, l_filter=LAND_L_FILTER) -> tuple[Measurement, SurfaceModelFit]:
    """The bullet land and eq 18 plus noise fitted to its measured points (cylinder removed,
    L-filter ``l_filter``): ``(measurement, fit)``."""
    land = _read(LAND_FILE)
    fit = fit_surface_model(land.z, land.spacing, form="cylinder", l=l_filter, seed=seed,
                            data={"file": LAND_FILE})
    return land, fit


#: the land's lay: phi within this many degrees of the striations (y) ...
LAY_TOLERANCE_DEG = 20.0
#: ... and a weak anisotropy, lambda_a / lambda_b below this (figure 2: 100)
WEAK_ANISOTROPY = 5.0


def land_fit_verdicts(fit: SurfaceModelFit) -> dict:
    """The data's verdicts on the land's eq-18 fit, as the chapter asserts them and the
    ledger's ``land-lay`` row judges them: statement -> bool."""
    hp = fit.model.hyperparameters
    return {
        f"the lay lies along the striations (within {LAY_TOLERANCE_DEG:g} deg)":
            lay_deviation_deg(fit) < LAY_TOLERANCE_DEG,
        f"the anisotropy is weak (lambda_a / lambda_b < {WEAK_ANISOTROPY:g})":
            hp["lambda_a_um"] / hp["lambda_b_um"] < WEAK_ANISOTROPY,
    }


def land_check_verdicts(check: ModelCheck) -> dict:
    """The data's verdicts on the land among its model's simulations, as the chapter asserts
    them and the ledger's ``land-model`` row judges them: statement -> bool."""
    by_name = {p.name: p for p in check.parameters}
    sku, std, str_, sq = by_name["Sku"], by_name["Std"], by_name["Str"], by_name["Sq"]
    return {
        "Sku lies outside, above twice the simulations' largest (heavy-tailed heights)":
            bool(sku.outside and sku.measured > 2 * sku.high),
        "Sq lies outside, above twice the simulations' median (the fit describes the "
        "waviness, which the L-filter takes out of the simulations)":
            bool(sq.outside and sq.measured > 2 * sq.median),
        "Std lies inside the simulations' range": not std.outside,
        "Str lies outside, below the simulations' smallest (a stronger anisotropy)":
            bool(str_.outside and str_.measured < str_.low),
    }


def land_check(land: Measurement, fit: SurfaceModelFit, *, seed=0,
               n_simulations=19) -> ModelCheck:
    """The land's texture parameters among ``n_simulations`` simulations of ``fit``'s model."""
    return check_model(fit.model, land.z, n_simulations=n_simulations, seed=seed)


def bullet_land(*, seed=0, n_simulations=19, l_filter=LAND_L_FILTER, fill=True) -> LandResult:
    """Fit (eq 18, :func:`land_fit`), simulate, check (:func:`land_check`) and fill the bullet
    land (module docstring; the fill with its self-check); ``fill=False`` leaves out the fill of
    its real holes (``LandResult.fill`` is then None)."""
    land, fit = land_fit(seed=seed, l_filter=l_filter)
    simulation = fit.model.simulate(land.z.shape, seed=seed + 1)
    check = land_check(land, fit, seed=seed, n_simulations=n_simulations)
    filled = (fill_measured_surface(land.z, spacing=land.spacing, form="cylinder", seed=seed,
                                    self_check=True) if fill else None)
    return LandResult(land, fit, simulation, check, filled)


def centre_crop(name, size) -> tuple:
    """The slices of the central ``size`` x ``size`` points of ``data/name`` (the whole of an
    axis shorter than ``size``), for :func:`cross_validated_fill`'s ``crop``."""
    return tuple(slice(max((n - size) // 2, 0), max((n - size) // 2, 0) + min(n, size))
                 for n in _read(name).z.shape)


def stylus_profile(*, seed=0, num_mixtures=3, decimation=4, n_simulations=19) -> ProfileResult:
    """Fit eq 21 to the Dektak profile (every ``decimation``-th point: the exact likelihood
    costs O(n^2)), simulate it and check it."""
    profile = _read(PROFILE_FILE)
    z = profile.z[::decimation]
    spacing = float(profile.spacing[-1]) * decimation
    fit = fit_profile_model(z, spacing, num_mixtures=num_mixtures, seed=seed, n_candidates=6,
                            data={"file": PROFILE_FILE, "decimation": decimation})
    simulation = fit.model.simulate(z.size, seed=seed + 1)
    check = check_model(fit.model, z, spacing=(spacing,), n_simulations=n_simulations,
                        seed=seed)
    return ProfileResult(z, spacing, decimation, fit, simulation, check)


@functools.lru_cache(maxsize=4)
def _hidden_and_baseline(name, share, seed, crop_key):
    """The measurement, its (cropped) heights, the hidden points and the linear and cubic
    interpolation of them: the same for every kernel tried on one file (cached)."""
    m = _read(name)
    z = m.z if crop_key is None else m.z[tuple(slice(a, b) for a, b in crop_key)]
    valid = np.isfinite(z)
    hidden = hide_discs(valid, share, seed=seed)
    start = time.perf_counter()
    baseline = interpolate_holes(z, hidden, methods=("linear", "cubic"))
    seconds = time.perf_counter() - start
    for array in (z, hidden, *baseline.values()):
        array.setflags(write=False)
    return m, z, hidden, baseline, seconds


def cross_validated_fill(name=LAND_FILE, *, share=0.02, seed=0, form="cylinder",
                         crop=None, nu="auto") -> CrossValidation:
    """Hide ``share`` of the measured points of ``data/name`` in small discs, fill them with
    the GP (fitted without them, moving-window kriging, with the fill's self-check on other
    measured points: :mod:`roughgp.filling.self_check`) and with linear and cubic
    interpolation (Delaunay, Clough-Tocher, per hole), and score all against the hidden
    heights. ``crop``: a pair of slices to work on a part of the file; ``nu``: the smoothness
    of the fitted kernel (0.5: eq 18; 1.5, 2.5: its Matérn variant; ``"auto"``: the fill's
    choice by its self-check)."""
    crop_key = None if crop is None else tuple((c.start, c.stop) for c in crop)
    m, z, hidden, baseline, baseline_seconds = _hidden_and_baseline(name, share, seed, crop_key)
    start = time.perf_counter()
    gp = fill_measured_surface(z, spacing=m.spacing, form=form, seed=seed, mask=hidden, nu=nu,
                               self_check=True)
    seconds = {"GP": time.perf_counter() - start, "linear and cubic": baseline_seconds}
    truth = z[hidden]
    estimates = {"GP": gp.filled[hidden], **baseline}
    sd = gp.predictive_sd[hidden]
    rmse = rmse_of(estimates, truth)
    inside = np.abs(estimates["GP"] - truth) / sd
    return CrossValidation(name, hidden, truth, estimates, sd, rmse, float(np.mean(inside <= 2)),
                           seconds, float(gp.fit.log_likelihood), gp.nu, gp.band_factor,
                           float(np.mean(np.abs(estimates["GP"] - truth) <= gp.band[hidden])),
                           gp.self_checks, gp.fit)


def fill_verdicts(cvs) -> dict:
    """The data's verdicts on the cross-validation of :data:`CV_FILES` (``cvs``: file name ->
    :class:`CrossValidation`, ``nu="auto"``), as the chapter states them and the ledger's
    ``measured-fill`` row judges them: statement -> bool."""
    land, sur = cvs[LAND_FILE], cvs["sur-2.sur"]
    clean = [cvs[name] for name in ("opd-1.opd", "di-1.di")]
    heavy = (land, sur)
    return {
        "the GP beats cubic interpolation on every file":
            all(cv.rmse["GP"] < cv.rmse["cubic"] for cv in cvs.values()),
        "the GP beats linear interpolation by more than a tie on opd-1 and di-1":
            all(cv.rmse["GP"] < (1 - TIE) * cv.rmse["linear"] for cv in clean),
        "the GP ties with linear interpolation on the land":
            abs(land.rmse["GP"] / land.rmse["linear"] - 1) < TIE,
        "linear interpolation beats the GP on sur-2":
            sur.rmse["linear"] < (1 - TIE) * sur.rmse["GP"],
        "in median absolute error the GP is no worse than linear (a tie at most) on every file":
            all(cv.median_abs["GP"] < (1 + TIE) * cv.median_abs["linear"]
                for cv in cvs.values()),
        "on the land and sur-2 the largest 1 % of the GP's errors carry over half its squared "
        "error (under a quarter on opd-1 and di-1)":
            all(cv.largest_errors_share() > 0.5 for cv in heavy)
            and all(cv.largest_errors_share() < 0.25 for cv in clean),
        "the Gaussian +-2 sd band is too narrow on the land and sur-2 (< 93 %)":
            all(cv.coverage < 0.93 for cv in heavy),
        "the fill's calibrated band holds 95 +- 3 % of the hidden points on every file":
            all(abs(cv.calibrated_coverage - 0.95) < 0.03 for cv in cvs.values()),
    }


def display_unit(name) -> tuple[str, float]:
    """The unit the chapter shows a file's heights and errors in, and the factor from µm: the
    land in µm, the nanometre-scale files of :data:`CV_FILES` in nm."""
    return ("µm", 1.0) if name == LAND_FILE else ("nm", 1000.0)


def cross_validation_rows(cvs) -> list[dict]:
    """One row per file of the cross-validation ``cvs`` (file name -> :class:`CrossValidation`)
    for the chapter's table: the smoothness chosen, the RMSE at the hidden points of the GP,
    linear and cubic interpolation and the median absolute errors (in :func:`display_unit`),
    the share inside the Gaussian ±2 sd band, the self-check's factor k and the share inside
    the band the fill writes."""
    rows = []
    for name, cv in cvs.items():
        unit, factor = display_unit(name)
        rows.append({"file": name, "unit": unit, "ν": cv.nu,
                     **{f"RMSE {m}": factor * cv.rmse[m] for m in ("GP", "linear", "cubic")},
                     **{f"median |error| {m}": factor * cv.median_abs[m]
                        for m in ("GP", "linear")},
                     "in ±2 sd": cv.coverage, "k": cv.band_factor,
                     "in the band": cv.calibrated_coverage})
    return rows


def self_check_rows(cvs) -> list[dict]:
    """One row per file: the fill's self-check on other measured points, the held-out RMSE of
    the GP for each smoothness ν tried and of linear interpolation (in :func:`display_unit`)."""
    rows = []
    for name, cv in cvs.items():
        unit, factor = display_unit(name)
        checks = cv.self_checks
        rows.append({"file": name, "unit": unit,
                     **{f"GP, ν = {nu:g}": factor * c.rmse["GP"] for nu, c in checks.items()},
                     "linear": factor * next(iter(checks.values())).rmse["linear"]})
    return rows


def increment_kurtosis(heights) -> float:
    """The kurtosis of a height map's first differences along y and x (the mean of the two;
    NaN ignored): 3 for a Gaussian surface, whatever its ACVF; far more where a few spikes,
    pits or steps make the increments heavy-tailed."""
    heights = np.asarray(heights, dtype=np.float64)
    values = []
    for axis in (0, 1):
        d = np.diff(heights, axis=axis)
        d = d[np.isfinite(d)] - np.mean(d[np.isfinite(d)])
        values.append(np.mean(d ** 4) / np.mean(d ** 2) ** 2)
    return float(np.mean(values))


def file_height_step(name) -> float:
    """The smallest difference between distinct heights of ``data/name``: the resolution its
    heights are stored to (um)."""
    z = _read(name).z
    return float(np.min(np.diff(np.unique(z[np.isfinite(z)]))))


def form_removed(name, form) -> np.ndarray:
    """The heights of ``data/name`` with its form (``form``, the F-operator) removed."""
    m = _read(name)
    return remove_form(m.z, m.spacing, form)[0]


def file_increment_kurtosis(name, form) -> float:
    """:func:`increment_kurtosis` of ``data/name`` with its form (``form``) removed."""
    return increment_kurtosis(form_removed(name, form))
