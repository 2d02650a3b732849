r"""Spurious points: the chapter's computations (beyond the paper).

* :func:`feature_profiles`, :func:`stratified_comparison`: the robust filters on the cases of
  their standards (a spike, a deep valley, a step; a plateau-honed profile with waviness).
* :func:`benchmark`: eq 18 and plateau-honed surfaces (eq 19-20) with spikes and pits of
  3-20 sd injected at known points (a share :data:`SHARES` of the points, sign at random):
  each method of :data:`roughgp.filling.spurious.METHODS` (and the GP detector
  without its robust rounds) flags points; its detection rate (injected points flagged) and
  false-alarm rate (other points flagged), and on the surfaces without injections the share
  it flags. :func:`detection_targets` judges the issue's targets (GP >= 95 % detection,
  < 0.1 % false alarms).
* :func:`real_file_study`: on a real file (:data:`REAL_FILES`) the points the GP flags; a
  cross-validation of the fill with and without them (measured points that are not flagged
  hidden in discs, filled by the GP and by linear interpolation, scored there), the
  self-check's verdict beside it, and the texture parameters before and after.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from pathlib import Path

import numpy as np
import scipy.ndimage

from roughgp.experiments import honed
from roughgp.experiments.measured_surfaces import CV_FILES, DATA, centre_crop
from roughgp.filling.interpolants import interpolate_holes
from roughgp.filling.measured import fill_measured_surface
from roughgp.filling.self_check import (
    disc_mean_difference,
    hide_discs,
    method_difference,
    rmse_of,
    verdict_of,
)
from roughgp.filling.spurious import METHODS, detect_spurious, flag_by, noise_floor
from roughgp.io.measurement import read_measurement
from roughgp.metrology.filters import gaussian_filter
from roughgp.metrology.form import remove_form
from roughgp.metrology.robust_filters import robust_gaussian_filter, robust_l_filter
from roughgp.metrology.stratified import stratified_l_filter
from roughgp.metrology.texture_heights import material_ratio_parameters
from roughgp.metrology.texture_report import L_FILTERS, filtered_parameters
from roughgp.models import surfaces

__all__ = ["SHARES", "AMPLITUDES", "GROUND", "HONED_STEPS", "KINDS", "REAL_FILES",
           "TEXTURE_KEYS", "Injected", "inject", "draw_surface", "BenchmarkRow", "benchmark",
           "detection_targets", "RealFileStudy", "real_file_study", "study_record", "RECORDED",
           "recorded_studies", "NOISE_TILE", "TileNoise", "tile_noise", "plateau_honed_profile",
           "feature_profiles", "stratified_comparison", "STRATIFIED_KEYS", "STRATIFIED_FILE",
           "figure3_surface", "stratified_texture", "stratified_cases"]

SHARES = (0.0, 0.001, 0.01)  #: shares of the points injected (0: the clean surface)
AMPLITUDES = (3.0, 20.0)  #: spikes and pits of this many sd (uniform), sign at random
#: eq 18 (the gap-filling chapter's surface: grooves at 30 degrees) with noise 0.1
GROUND = surfaces.GrooveParameters(variance=10.0, lengthscales=(40.0, 5.0), angle=math.pi / 6)
#: figure 3's two honing steps, lambda_a of the first shortened from 500 to 100 (a quick draw)
HONED_STEPS = (surfaces.GrooveParameters(45.0, (100.0, 30.0), math.pi / 4),
               surfaces.GrooveParameters(0.2, (5.0, 3.0), math.pi / 4))
KINDS = ("eq 18", "plateau-honed")
#: the real files and their F-operators (the measured-surfaces chapter's cross-validated ones)
REAL_FILES = CV_FILES
TEXTURE_KEYS = ("Sq", "Sku", "Sp", "Sv", "Sk", "Spk", "Svk")


@dataclasses.dataclass(frozen=True)
class Injected:
    """A surface with spikes and pits at known points: ``z`` (injected), ``clean``, ``truth``
    (boolean map of the injected points)."""

    z: np.ndarray
    clean: np.ndarray
    truth: np.ndarray


def draw_surface(kind, shape, seed) -> np.ndarray:
    """An eq 18 (``"eq 18"``) or plateau-honed (``"plateau-honed"``, eq 19-20) surface."""
    if kind == "eq 18":
        return surfaces.ground(shape, variance=GROUND.variance, lengthscales=GROUND.lengthscales,
                               angle=GROUND.angle, noise_variance=0.1, seed=seed)
    if kind == "plateau-honed":
        return surfaces.honed(shape, HONED_STEPS, noise_variance=0.1, seed=seed)
    raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")


def inject(clean, share, seed) -> Injected:
    """Add spikes and pits of :data:`AMPLITUDES` sd (the surface's sd) at ``share`` of the
    points, drawn with ``seed``."""
    rng = np.random.default_rng(seed)
    n = int(round(share * clean.size))
    where = rng.choice(clean.size, n, replace=False)
    size = rng.uniform(*AMPLITUDES, n) * float(np.std(clean)) * rng.choice([-1.0, 1.0], n)
    z = clean.copy()
    z.flat[where] += size
    truth = np.zeros(clean.shape, bool)
    truth.flat[where] = True
    return Injected(z, clean, truth)


@dataclasses.dataclass(frozen=True)
class BenchmarkRow:
    """One surface kind, share and method: ``detection`` (NaN without injections),
    ``false_alarm`` (the share of the other points flagged), ``injected``, ``seconds``."""

    kind: str
    share: float
    method: str
    detection: float
    false_alarm: float
    injected: int
    seconds: float


def benchmark(shape=(96, 96), *, shares=SHARES, kinds=KINDS, seed=0) -> list:
    """The detection table (module docstring): one :class:`BenchmarkRow` per surface kind,
    share and method (:data:`METHODS` and ``"GP, one pass"``: no robust rounds)."""
    rows = []
    for k, kind in enumerate(kinds):
        clean = draw_surface(kind, shape, seed + k)
        for share in shares:
            case = inject(clean, share, seed + 100 + k)
            others = ~case.truth
            n = int(case.truth.sum())
            for method in METHODS:
                start = time.perf_counter()
                if method == "GP":  # its first round is the one-pass detector
                    found = detect_spurious(case.z, seed=seed)
                    flags = {"GP": (found.flagged, found.seconds),
                             "GP, one pass": (found.first_flagged, found.first_seconds)}
                else:
                    flags = {method: (flag_by(method, case.z, seed=seed),
                                      time.perf_counter() - start)}
                for name, (flagged, seconds) in flags.items():
                    rows.append(BenchmarkRow(
                        kind, share, name,
                        float((flagged & case.truth).sum() / n) if n else math.nan,
                        float((flagged & others).sum() / others.sum()), n, seconds))
    return rows


def detection_targets(rows, detection=0.95, false_alarm=0.001) -> dict:
    """The issue's targets for the GP detector: statement -> bool."""
    gp = [r for r in rows if r.method == "GP"]
    return {
        f"the GP finds at least {detection:.0%} of the injected points on every surface":
            all(r.detection >= detection for r in gp if r.injected),
        f"the GP flags under {false_alarm:.1%} of the other points on every surface":
            all(r.false_alarm < false_alarm for r in gp),
    }


@dataclasses.dataclass(frozen=True)
class RealFileStudy:
    """:func:`real_file_study` on one file.

    Attributes:
        file, shape: the file and the (cropped) map's shape; residual: its heights with the
            form removed.
        flagged: the points the GP flagged; summary: how many, where.
        hidden: the measured, unflagged points hidden for the cross-validation.
        rmse: ``{"without flagging": {"GP", "linear"}, "with flagging": {...}}`` at them.
        band_coverage: the share of them within the GP's calibrated 95 % band (with flagging);
            band_se: its standard error over the discs (the points of a disc are correlated).
        self_check_verdict: the self-check's verdict (with flagging): ``"GP"``, ``"linear"``
            or ``"tie"`` (:func:`~roughgp.filling.self_check.verdict_of`);
            cv_verdict: the cross-validation's, on its hidden points.
        floor, noise_variances, history: the detector's noise floor, its first and last
            fits' noise variances, the points flagged in any round so far, after each.
        texture: ``{"before": params, "after": params}`` (:data:`TEXTURE_KEYS`).
        seconds: ``{"detection", "fills"}``.
        cv_difference, check_difference: the GP's minus linear interpolation's mean squared
            error at the cross-validation's hidden points and at the self-check's, with its
            standard error over the discs (the verdicts' evidence); cv_discs, check_discs:
            how many discs (connected groups of hidden points) each holds.
        converged, excluded: whether the detector's rounds reached their fixed point, and how
            many points they flagged in all (``SpuriousPoints.excluded``).
    """

    file: str
    shape: tuple
    residual: np.ndarray
    flagged: np.ndarray
    summary: str
    hidden: np.ndarray
    rmse: dict
    band_coverage: float
    self_check_verdict: str
    cv_verdict: str
    floor: float
    noise_variances: tuple
    history: tuple
    texture: dict
    seconds: dict
    cv_difference: tuple
    check_difference: tuple
    cv_discs: int
    check_discs: int
    converged: bool
    excluded: int
    band_se: float


def _discs(held_out) -> int:
    return int(scipy.ndimage.label(held_out)[1])


def real_file_study(name, *, crop=None, share=0.02, seed=0) -> RealFileStudy:
    """The real file ``data/name`` (its F-operator from :data:`REAL_FILES`; ``crop``: the side
    of a central crop, None: the whole map) through detection, fill and texture (module
    docstring)."""
    form = REAL_FILES[name]
    m = read_measurement(DATA / name)
    z = m.z if crop is None else m.z[centre_crop(name, crop)]
    start = time.perf_counter()
    detected = detect_spurious(z, spacing=m.spacing, form=form, seed=seed)
    detection_seconds = time.perf_counter() - start
    flagged = detected.flagged
    hidden = hide_discs(np.isfinite(z) & ~flagged, share, seed=seed)
    truth = z[hidden]
    rmse, start = {}, time.perf_counter()
    for label, excluded in (("without flagging", None), ("with flagging", flagged)):
        mask = hidden if excluded is None else hidden | excluded
        gp = fill_measured_surface(z, spacing=m.spacing, form=form, seed=seed, mask=mask,
                                   self_check=excluded is not None)
        source = z if excluded is None else np.where(excluded, np.nan, z)
        linear = interpolate_holes(source, hidden, methods=("linear",))["linear"]
        estimates = {"GP": gp.filled[hidden], "linear": linear}
        rmse[label] = rmse_of(estimates, truth)
    inside = np.abs(gp.filled[hidden] - truth) <= gp.band[hidden]
    texture = {}
    for label, heights in (("before", z), ("after", np.where(flagged, np.nan, z))):
        p = filtered_parameters(heights, m.spacing, form=form).parameters
        texture[label] = {k: float(p[k]) for k in TEXTURE_KEYS}
    residual = remove_form(z, m.spacing, form)[0]
    check = gp.self_check
    return RealFileStudy(name, z.shape, residual, flagged, detected.summary(), hidden, rmse,
                         float(np.mean(inside)), check.verdict,
                         verdict_of(estimates, truth, hidden), detected.floor,
                         (detected.first_noise_variance, detected.noise_variance),
                         detected.history, texture,
                         {"detection": detection_seconds,
                          "fills": time.perf_counter() - start},
                         method_difference(estimates, truth, hidden),
                         method_difference(check.estimates, check.truth, check.held_out),
                         _discs(hidden), _discs(check.held_out), bool(detected.converged),
                         int(detected.excluded.sum()),
                         disc_mean_difference(inside.astype(float), hidden)[1])


def study_record(study: RealFileStudy) -> dict:
    """The numbers of a :class:`RealFileStudy` as plain JSON values (no maps)."""
    measured = int(np.isfinite(study.residual).sum())
    return {"file": study.file, "shape": list(study.shape), "measured": measured,
            "flagged": int(study.flagged.sum()),
            "flagged_share": float(study.flagged.sum() / measured),
            "excluded": study.excluded, "history": list(study.history),
            "converged": study.converged, "rmse": study.rmse,
            "band_coverage": study.band_coverage, "band_se": study.band_se,
            "hidden": int(study.hidden.sum()),
            "cv_discs": study.cv_discs, "check_discs": study.check_discs,
            "cv_verdict": study.cv_verdict, "self_check_verdict": study.self_check_verdict,
            "cv_difference": list(study.cv_difference),
            "check_difference": list(study.check_difference),
            "floor": study.floor, "noise_variances": list(study.noise_variances),
            "texture": study.texture, "seconds": study.seconds}


#: a full-size run of :func:`real_file_study` on every file of :data:`REAL_FILES`
#: (``benchmarks/spurious_points_full.py``), one :func:`study_record` per line
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "spurious_points_full.jsonl"


def recorded_studies(path=RECORDED) -> dict:
    """``{file: record}`` of a recorded run (:data:`RECORDED`), or None where there is none."""
    path = Path(path)
    if not path.is_file():
        return None
    records = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return {r["file"]: r for r in records}


NOISE_TILE = 16  #: the side (points) of the tiles of :func:`tile_noise`


@dataclasses.dataclass(frozen=True)
class TileNoise:
    """:func:`tile_noise`: per tile, ``noise_sd`` (the root of
    :func:`~roughgp.filling.spurious.noise_floor`), ``flagged`` and ``counts`` (its
    flagged and its measured points)."""

    noise_sd: np.ndarray
    flagged: np.ndarray
    counts: np.ndarray

    @property
    def spread(self) -> float:
        """The noisiest tile's noise sd over the median tile's."""
        return float(np.max(self.noise_sd) / np.median(self.noise_sd))

    @property
    def noisy(self) -> np.ndarray:
        """The tiles whose noise sd exceeds twice the median tile's."""
        return self.noise_sd > 2 * np.median(self.noise_sd)

    def flagged_share(self, noisy: bool) -> float:
        """The share of the measured points flagged in the noisy tiles (``noisy=True``) or in
        the others; NaN where there are none."""
        pick = self.noisy if noisy else ~self.noisy
        n = int(np.sum(self.counts[pick]))
        return float(np.sum(self.flagged[pick]) / n) if n else math.nan


def tile_noise(residual, flagged, tile=NOISE_TILE) -> TileNoise:
    """Whether one noise variance describes a map: the noise bound of
    :func:`~roughgp.filling.spurious.noise_floor` on each ``tile`` x ``tile`` tile of
    ``residual`` (NaN: unmeasured; tiles with fewer than half their points measured dropped),
    beside how many of its measured points are ``flagged``. The bound's MAD ignores a band
    narrower than half a tile, hence small tiles. Where the noise sd varies several-fold
    from tile to tile, the detector's one noise variance cannot hold everywhere."""
    z = np.asarray(residual, dtype=np.float64)
    sd, flags, counts = [], [], []
    for r0 in range(0, z.shape[0] - tile + 1, tile):
        for c0 in range(0, z.shape[1] - tile + 1, tile):
            part = np.s_[r0:r0 + tile, c0:c0 + tile]
            measured = np.isfinite(z[part])
            if measured.mean() < 0.5:
                continue
            sd.append(math.sqrt(noise_floor(z[part])))
            flags.append(int(np.count_nonzero(flagged[part] & measured)))
            counts.append(int(measured.sum()))
    if not sd:
        raise ValueError(f"no {tile} x {tile} tile of the map is half measured")
    return TileNoise(np.array(sd), np.array(flags), np.array(counts))


# --------------------------------------------------------------------------- the filters' cases

def plateau_honed_profile(n=8000, seed=1):
    """A plateau-honed profile with known truth (spacing 1 um): a plateau of fine roughness
    (sd 0.2 um) cut by 40 parabolic valleys 10-40 um wide and 3-8 um deep, and a waviness of
    3 um at 4 mm. Returns ``(truth, plateau, waviness)``: the roughness, the boolean map of the
    plateau points, the waviness (the measured profile is ``truth + waviness``)."""
    rng = np.random.default_rng(seed)
    x = np.arange(n, dtype=np.float64)
    valleys = np.zeros(n)
    for c in rng.choice(n, 40, replace=False):
        width, depth = rng.uniform(10, 40), rng.uniform(3, 8)
        valleys = np.minimum(valleys, -depth * np.clip(1 - ((x - c) / width) ** 2, 0, None))
    return 0.2 * rng.normal(size=n) + valleys, valleys == 0, 3 * np.sin(2 * np.pi * x / 4000)


def feature_profiles(n=4000, cutoff=400.0, seed=3) -> dict:
    """The standard's cases on a profile of fine roughness (sd 0.1 um, spacing 1 um): a spike
    (50 um), a deep narrow valley (20 um, 10 points) and a step (10 um). ``{case: (z, the
    Gaussian mean line, the robust one)}``."""
    rng = np.random.default_rng(seed)
    x = np.arange(n, dtype=np.float64)
    noise = 0.1 * rng.normal(size=n)
    spike = noise.copy()
    spike[n // 2] = 50.0
    valley = noise.copy()
    valley[n // 2:n // 2 + 10] = -20.0
    step = noise + np.where(x < n // 2, 0.0, 10.0)
    return {name: (z, gaussian_filter(z, 1.0, cutoff), robust_gaussian_filter(z, 1.0, cutoff))
            for name, z in (("spike", spike), ("deep valley", valley), ("step", step))}


def stratified_comparison(cutoff=800.0, seed=1) -> dict:
    """Rk, Rpk, Rvk of :func:`plateau_honed_profile` after the Gaussian, the ISO 13565-1 and
    the robust L-filter, beside those of the true roughness (half a cut-off dropped at each
    end): ``{filter: {"Rk", "Rpk", "Rvk", "plateau": median roughness on the plateau}}``."""
    truth, plateau, waviness = plateau_honed_profile(seed=seed)
    z = truth + waviness
    inner = slice(int(cutoff), -int(cutoff))
    out = {}
    for name, rough in (("true roughness", truth),
                        ("Gaussian", z - gaussian_filter(z, 1.0, cutoff)),
                        ("ISO 13565-1", stratified_l_filter(z, 1.0, cutoff)),
                        ("robust", robust_l_filter(z, 1.0, cutoff))):
        p = material_ratio_parameters(rough[inner])
        out[name] = {k: float(p[k]) for k in ("Rk", "Rpk", "Rvk")}
        out[name]["plateau"] = float(np.median(rough[inner][plateau[inner]]))
    return out


# --------------------------------------------------------------------------- Sk, Spk, Svk

STRATIFIED_KEYS = ("Sk", "Spk", "Svk")  #: ISO 13565-2's parameters of a stratified surface
STRATIFIED_FILE = "sur-2.sur"  #: the real file of :func:`stratified_cases`


def figure3_surface(shape=(256, 256), seed=honed.SEED) -> np.ndarray:
    """Figure 3's plateau-honed surface (eq 19-20, :data:`roughgp.models.surfaces.FIGURE_3`,
    noise variance 1): the paper's 512 x 512 draw (:func:`roughgp.experiments.honed.figure3`)
    for ``shape=(512, 512)``, else a draw of ``shape`` with the same steps and seed."""
    if tuple(shape) == surfaces.FIGURE_3_SHAPE:
        return honed.figure3(seed).surface
    return surfaces.honed(tuple(shape), surfaces.FIGURE_3, noise_variance=honed.NOISE_VARIANCE,
                          seed=seed)


def stratified_texture(z, spacing=1.0, *, form="plane") -> dict:
    """Sk, Spk, Svk of ``z`` after each L-filter of ``roughgp texture`` (the Gaussian,
    ``--stratified``: ISO 13565-1, ``--robust``: the robust Gaussian regression filter), the
    standard's default nesting indices: ``{l_kind: {"Sk", "Spk", "Svk", "operators"}}``."""
    out = {}
    for kind in L_FILTERS:
        report = filtered_parameters(z, spacing, form=form, l_kind=kind)
        out[kind] = {k: float(report.parameters[k]) for k in STRATIFIED_KEYS}
        out[kind]["operators"] = "; ".join(report.operators)
    return out


def stratified_cases(honed_shape=(256, 256), crop=256) -> dict:
    """:func:`stratified_texture` of figure 3's plateau-honed surface
    (:func:`figure3_surface` of ``honed_shape``, spacing 1 um) and of :data:`STRATIFIED_FILE`
    (its central ``crop`` x ``crop`` points; None: the whole map), as ``roughgp texture``,
    ``--stratified`` and ``--robust`` report them: ``{label: {l_kind: {...}}}``."""
    m = read_measurement(DATA / STRATIFIED_FILE)
    z = m.z if crop is None else m.z[centre_crop(STRATIFIED_FILE, crop)]
    shape = "x".join(map(str, honed_shape))
    return {f"figure 3 ({shape})": stratified_texture(figure3_surface(honed_shape)),
            f"{STRATIFIED_FILE} ({z.shape[0]}x{z.shape[1]})":
                stratified_texture(z, m.spacing, form=REAL_FILES[STRATIFIED_FILE])}
