"""roughgp.filling.self_check and what it rests on: the fill checked on held-out
measured points (the conformal band, the choice of nu), the per-hole interpolation, the local
fill's ``predict`` and the block fit's ``start`` (small seeded grids)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.filling import self_check as sc
from roughgp.filling.interpolants import interpolate_baseline, interpolate_holes
from roughgp.filling.local_fill import fill_gaps_locally
from roughgp.filling.measured import fill_measured_surface
from roughgp.gp.acvf import rotated_matern
from roughgp.inference.block_fit import fit_ground_to_valid_points
from roughgp.models import surfaces
from roughgp.sampling import sample_grid
from roughgp.surface_models.model import FittedModel

GROOVE = surfaces.GrooveParameters(2.0, (12.0, 3.0), math.radians(60.0))
NOISE = 0.05


def _ground(shape=(96, 96), seed=3):
    return surfaces.ground(shape, variance=GROOVE.variance, lengthscales=GROOVE.lengthscales,
                           angle=GROOVE.angle, noise_variance=NOISE, seed=seed)


def test_conformal_factor_is_the_finite_sample_quantile():
    scores = np.arange(1.0, 20.0)                 # 19 scores: rank ceil(20 * 0.95) = 19
    assert sc.conformal_factor(scores) == 19.0
    assert sc.conformal_factor(scores[::-1]) == 19.0
    assert sc.conformal_factor(np.arange(1.0, 11.0)) == math.inf   # 10 are too few for 95 %
    normal = np.abs(np.random.default_rng(0).normal(size=20000))
    assert sc.conformal_factor(normal) == pytest.approx(sc.GAUSSIAN_FACTOR, abs=0.05)


def test_held_out_points_are_seeded_and_sized():
    measured = np.ones((80, 80), dtype=bool)
    measured[10:20, 10:30] = False
    a, b = sc.held_out_points(measured, 3), sc.held_out_points(measured, 3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, sc.held_out_points(measured, 4))
    assert not np.any(a & ~measured)
    assert sc.CHECK_SHARE * measured.sum() <= a.sum() < sc.CHECK_SHARE * measured.sum() + 40
    # a stream of its own: not the discs that hide_discs draws with the same seed
    assert not np.array_equal(a, sc.hide_discs(measured, sc.CHECK_SHARE, seed=3))
    assert sc.held_out_points(np.ones((30, 30), dtype=bool), 0) is None   # 18 points < 40


def test_interpolate_holes_is_exact_on_a_plane_like_one_triangulation():
    iy, ix = np.indices((40, 50))
    plane = 1.0 + 0.3 * ix - 0.2 * iy
    holes = sc.hide_discs(np.ones(plane.shape, dtype=bool), 0.05, seed=1)
    plane_with_gaps = plane.copy()
    plane_with_gaps[5, :] = np.nan                   # unmeasured points are not used
    holes &= np.isfinite(plane_with_gaps)
    got = interpolate_holes(plane_with_gaps, holes, methods=("linear", "cubic"))
    np.testing.assert_allclose(got["linear"], plane[holes], atol=1e-9)
    np.testing.assert_allclose(got["cubic"], plane[holes], atol=1e-6)
    whole = interpolate_baseline(np.where(holes, np.nan, plane_with_gaps),
                                 holes | np.isnan(plane_with_gaps), np.s_[0:40, 0:50])
    np.testing.assert_allclose(whole.values["linear"][holes[whole.evaluate]], got["linear"],
                               atol=1e-9)
    with pytest.raises(ValueError, match="methods must be a non-empty subset"):
        interpolate_holes(plane, holes, methods=("spline",))


def test_baseline_widens_its_margin_where_a_hole_has_too_few_measured_neighbours():
    # a map measured only in two strips (as an FRT map with 27 % holes in large regions): a
    # held-out point between them has no measured neighbour within 6 points (SciPy's
    # Delaunay: "No points given"), and within 12 only one column (all on a line)
    y, x = np.mgrid[0:40, 0:40].astype(float)
    z = 0.5 * x - 0.25 * y + 3.0
    z[:, 8:32] = np.nan
    holes = np.zeros(z.shape, dtype=bool)
    holes[20, 20] = True
    z[20, 20] = 0.5 * 20 - 0.25 * 20 + 3.0  # measured, held out
    notes = []
    got = interpolate_holes(z, holes, methods=("linear",), margin=6, notes=notes)["linear"]
    assert got == pytest.approx([8.0])  # a plane: linear interpolation is exact
    assert notes and "1 of 1 held-out discs had too few measured neighbours" in notes[0]
    base = interpolate_baseline(np.where(holes, np.nan, z), ~np.isfinite(z) | holes,
                                np.s_[20:21, 20:21], margin=6, methods=("linear",))
    assert base.margin == 24 and not base.nearest_only
    # two measured points on the whole grid: no triangle anywhere, the nearest value
    sparse = np.full((10, 10), np.nan)
    sparse[0, 0], sparse[9, 9] = 1.0, 2.0
    base = interpolate_baseline(sparse, np.isnan(sparse), np.s_[1:2, 1:2], margin=2)
    assert base.nearest_only and base.values["linear"] == pytest.approx([1.0])
    with pytest.raises(ValueError, match="no measured point"):
        interpolate_baseline(np.full((5, 5), np.nan), np.ones((5, 5), bool), np.s_[1:2, 1:2])


def test_local_fill_predicts_only_what_it_is_asked():
    z = _ground((48, 48), seed=5)
    z[10:14, 10:14] = np.nan
    held = np.zeros(z.shape, dtype=bool)
    held[30:32, 30:33] = True
    kernel = GROOVE.kernel()
    every = fill_gaps_locally(z, kernel, noise_variance=NOISE, mask=held, tile=8, margin=6)
    some = fill_gaps_locally(z, kernel, noise_variance=NOISE, mask=held, predict=held, tile=8,
                             margin=6)
    np.testing.assert_allclose(some.mean[held], every.mean[held], rtol=1e-12)
    np.testing.assert_allclose(some.sd[held], every.sd[held], rtol=1e-12)
    assert np.all(np.isnan(some.mean[10:14, 10:14])) and np.all(some.sd[10:14, 10:14] == 0)
    with pytest.raises(ValueError, match="predict must be a boolean array"):
        fill_gaps_locally(z, kernel, noise_variance=NOISE, predict=np.ones((3, 3), bool))


def test_self_check_of_a_gaussian_surface_is_calibrated_and_beats_linear():
    z = _ground((96, 96), seed=7)
    held = sc.hide_discs(np.ones(z.shape, dtype=bool), 0.06, seed=2)
    check = sc.self_check_fill(z, GROOVE.kernel(), noise_variance=NOISE, spacing=1.0,
                               held_out=held)
    assert check.n_points == held.sum() and check.nu == 0.5
    assert check.rmse["GP"] < check.rmse["linear"]
    assert 0.9 < check.coverage() <= 1.0
    # a Gaussian surface: the conformal factor is near the normal quantile 1.96
    assert 1.5 < check.band_factor < 2.5
    # heavy tails (spikes on 2 % of the points): the Gaussian band undercovers, k grows
    spiky = z.copy()
    spikes = np.random.default_rng(3).random(z.shape) < 0.02
    spiky[spikes] += 8.0
    heavy = sc.self_check_fill(spiky, GROOVE.kernel(), noise_variance=NOISE, spacing=1.0,
                               held_out=held)
    assert heavy.coverage() < check.coverage() and heavy.band_factor > check.band_factor + 0.5
    assert "measured points held out and filled (nu 0.5)" in check.summary()
    assert check.verdict == "GP" and "(the GP better)" in check.summary()
    with pytest.raises(ValueError, match="held_out marks no measured point"):
        sc.self_check_fill(z, GROOVE.kernel(), noise_variance=NOISE, spacing=1.0,
                           held_out=np.zeros(z.shape, dtype=bool))


def test_verdict_is_a_tie_within_one_standard_error_and_can_say_either():
    """Errors drawn per disc: equal spreads give a tie, a clearly smaller spread a verdict for
    that method; the standard error is over discs, so many points in few discs decide less."""
    rng = np.random.default_rng(4)
    held = sc.hide_discs(np.ones((80, 80), dtype=bool), 0.05, seed=1)
    n = int(held.sum())
    truth = np.zeros(n)
    small, large = 0.5 * rng.normal(size=n), 2.0 * rng.normal(size=n)
    assert sc.verdict_of({"GP": small, "linear": large}, truth, held) == "GP"
    mean, se = sc.method_difference({"GP": small, "linear": large}, truth, held)
    assert mean == pytest.approx(np.mean(small ** 2 - large ** 2)) and mean < -se < 0
    assert sc.verdict_of({"GP": large, "linear": small}, truth, held) == "linear"
    ties = [sc.verdict_of({"GP": rng.normal(size=n), "linear": rng.normal(size=n)}, truth, held)
            for _ in range(20)]
    assert ties.count("tie") >= 12  # about 68 % of draws of equal spread
    one_disc = np.zeros((80, 80), dtype=bool)
    one_disc[10:14, 10:14] = True
    assert sc.disc_mean_difference(np.ones(16), one_disc)[1] == math.inf


def _smooth(seed=2):
    return sample_grid(lambda t: rotated_matern(t, 1.0, np.array([10.0, 4.0]), 0.5, 2.5),
                       (72, 72), seed=seed)[0]


def test_fill_with_nu_auto_picks_a_smooth_kernel_for_a_smooth_surface():
    z = _smooth()
    z[30:34, 20:30] = np.nan
    result = fill_measured_surface(z, seed=0, block=16, n_blocks=6, nu="auto")
    assert set(result.self_checks) == set(sc.NU_CHOICES)
    checks = result.self_checks
    assert result.nu == sc.choose_nu(checks) and result.nu != 0.5
    assert checks[result.nu].rmse["GP"] < checks[0.5].rmse["GP"]
    assert result.fit.nu == result.nu and result.self_check is checks[result.nu]
    band = result.band
    assert np.all(band[~result.missing] == 0) and np.all(band[result.missing] > 0)
    # the band's factor by hole size and depth (roughgp.filling.hole_band) times the sd
    np.testing.assert_allclose(band[result.missing],
                               result.hole_band.factor_map(result.missing)[result.missing]
                               * np.sqrt(result.sd[result.missing] ** 2
                                         + result.noise_variance))
    # without a self-check the band is the Gaussian one and nothing is held out
    plain = fill_measured_surface(z, seed=0, block=16, n_blocks=6)
    assert plain.self_check is None and plain.band_factor == sc.GAUSSIAN_FACTOR


def test_fill_refuses_nu_it_cannot_use():
    z = _ground((48, 48))
    z[5:8, 5:8] = np.nan
    with pytest.raises(ValueError, match=r"nu must be one of \(0.5, 1.5, 2.5\) or 'auto'"):
        fill_measured_surface(z, nu=1.0)
    model = FittedModel("eq18", {"variance_um2": 2.0, "lambda_a_um": 12.0, "lambda_b_um": 3.0,
                                 "angle_deg": 60.0, "noise_variance_um2": 0.05}, (1.0, 1.0))
    with pytest.raises(ValueError, match="nu='auto' chooses the smoothness of a fit"):
        fill_measured_surface(z, model=model, nu="auto")
    small = _ground((30, 30))
    small[3:5, 3:5] = np.nan
    with pytest.raises(ValueError, match="too few to hold some out"):
        fill_measured_surface(small, nu="auto", block=8)
    # a model can be self-checked: its own smoothness is the one checked
    checked = fill_measured_surface(z, model=model, self_check=True, seed=0)
    assert list(checked.self_checks) == [0.5] and checked.fit is None
    # and its summary names the model's kernel, not a smoothness it may not have
    assert "held out and filled (the model's eq18)" in checked.self_check.summary()


def test_block_fit_from_a_start_reaches_the_optimum_of_the_grid_of_starts():
    z = _smooth(seed=4)
    eq18 = fit_ground_to_valid_points(z, block=16, n_blocks=6, seed=0)
    grid = fit_ground_to_valid_points(z, block=16, n_blocks=6, seed=0, nu=2.5)
    started = fit_ground_to_valid_points(z, block=16, n_blocks=6, seed=0, nu=2.5, start=eq18)
    assert started.log_likelihood == pytest.approx(grid.log_likelihood, abs=0.5)
    with pytest.raises(ValueError, match="start must be a BlockFit"):
        fit_ground_to_valid_points(z, block=16, n_blocks=6, nu=2.5, start={"variance": 1.0})


def test_choose_nu_keeps_eq18_unless_a_smoother_kernel_is_clearly_better():
    rng = np.random.default_rng(0)
    held = sc.hide_discs(np.ones((60, 60), dtype=bool), 0.1, seed=1)
    truth = rng.normal(size=held.sum())

    def check(errors, nu):
        return sc.FillSelfCheck(held, truth, {"GP": truth + errors, "linear": truth},
                                np.ones(truth.size), nu, 0.0)

    base = rng.normal(size=truth.size)
    slightly = check(0.99 * rng.normal(size=truth.size), 1.5)   # 2 % lower MSE, other errors
    clearly = check(0.5 * rng.normal(size=truth.size), 1.5)     # a quarter of the MSE
    excess, se = sc.mse_difference(check(base, 0.5), slightly)
    assert abs(excess) < se
    assert sc.choose_nu({0.5: check(base, 0.5), 1.5: slightly}) == 0.5
    assert sc.choose_nu({0.5: check(base, 0.5), 1.5: clearly}) == 1.5
    # the smaller of two within reach of the best is kept: 1.5 rather than 2.5
    assert sc.choose_nu({0.5: check(base, 0.5), 1.5: check(0.51 * base, 1.5),
                         2.5: check(0.5 * rng.normal(size=truth.size), 2.5)}) == 1.5
    with pytest.raises(ValueError, match="the same points"):
        sc.mse_difference(check(base, 0.5), sc.FillSelfCheck(
            ~held, truth, {"GP": truth}, np.ones(truth.size), 1.5, 0.0))
