"""The sampler's "auto" (issue 32, "simulate honed --shape 64 64 under 1 s"): the torus search
is bounded by the Cholesky it would replace, a kernel and its mirror image share one Cholesky
factor (drawn flipped: exactly the mirrored covariance), and the same seed gives the same draw
whatever was drawn before."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.models import surfaces
from roughgp.sampling import choose_method, circulant, grid_covariance, grid_sampler, sample_grid


@pytest.fixture(autouse=True)
def empty_caches(monkeypatch):
    monkeypatch.setattr(grid_sampler, "_FACTORS", {})
    monkeypatch.setattr(grid_sampler, "_CHOICES", {})
    monkeypatch.setattr(grid_sampler, "_EMBEDDINGS", {})


def _recording_search(monkeypatch):
    calls = []
    original = circulant.predict_torus

    def record(*args, **kwargs):
        calls.append(kwargs.get("max_points"))
        return original(*args, **kwargs)
    monkeypatch.setattr(circulant, "predict_torus", record)
    return calls


def test_a_long_correlation_on_a_small_grid_takes_cholesky_without_the_full_search(monkeypatch):
    """Figure 3's first step on 64 x 64: the circulant torus is about 2688 x 2688 (7.2e6
    points); the search stops at the budget of a quarter of the Cholesky it would replace: on
    the CPU the block-Levinson factor's (2.2e9 flops, a torus of ~3e5 points), on a device the
    dense factor's (2.3e10 flops, ~2.7e6 points)."""
    for device, factor_flops in ((None, 2 * 64 ** 5 + 1e6 * 64), ("cuda", 4096 ** 3 / 3)):
        calls = _recording_search(monkeypatch)
        method, reason = choose_method(surfaces.FIGURE_3[0].kernel(), (64, 64), device=device)
        assert method == "cholesky" and "more than" in reason
        assert len(calls) == 1 and calls[0] < 2688 ** 2
        cholesky = (factor_flops + 4096 ** 2) / grid_sampler._FLOPS_PER_SECOND
        assert f"Cholesky ~{cholesky:.2g} s" in reason
        assert grid_sampler._fft_cost(calls[0], 2) <= grid_sampler.SEARCH_SHARE * cholesky
        assert grid_sampler._fft_cost(2 * calls[0], 2) > grid_sampler.SEARCH_SHARE * cholesky


def test_a_short_correlation_still_takes_circulant(monkeypatch):
    method, reason = choose_method(surfaces.FIGURE_3[1].kernel(), (64, 64))
    assert method == "circulant" and "torus about (128, 128)" in reason


def test_the_choice_is_kept_for_the_kernel_and_its_mirror_image(monkeypatch):
    calls = _recording_search(monkeypatch)
    step = surfaces.FIGURE_3[0]
    first = choose_method(step.kernel(), (64, 64))
    assert choose_method(step.kernel(mirrored=True), (64, 64)) == first
    assert choose_method(step.kernel(), (64, 64)) == first
    assert len(calls) == 1
    choose_method(step.kernel(), (64, 63))  # another grid: another search
    assert len(calls) == 2


def test_a_mirror_images_draw_has_exactly_its_covariance():
    kernel = RotatedExponentialKernel(2.0, (6.0, 1.5), math.pi / 5)
    mirror = RotatedExponentialKernel(2.0, (6.0, 1.5), -math.pi / 5)
    shape, spacing = (5, 7), np.array([1.0, 1.0])
    flips = []
    for k in (kernel, mirror):
        table, mirrored, key = grid_sampler._canonical_table(k, shape, spacing)
        flips.append(mirrored)
        factor, _ = grid_sampler._cached_factor(table, shape, key,
                                                grid_sampler.SamplingInfo("cholesky"))
        flip = np.eye(35).reshape(5, 7, 35)[:, ::-1].reshape(35, 35) if mirrored else np.eye(35)
        np.testing.assert_allclose(flip @ factor @ factor.T @ flip.T,
                                   grid_covariance(k, shape), rtol=0, atol=1e-12)
    assert sorted(flips) == [False, True]  # one of the two is drawn from the other's factor
    assert len(grid_sampler._FACTORS) == 1


def test_a_wrongly_flipped_factor_is_caught():
    """Calibration of the test above: without the flip the covariance is wrong."""
    kernel = RotatedExponentialKernel(2.0, (6.0, 1.5), math.pi / 5)
    factor = np.linalg.cholesky(grid_covariance(kernel, (5, 7)))
    mirrored = grid_covariance(RotatedExponentialKernel(2.0, (6.0, 1.5), -math.pi / 5), (5, 7))
    assert np.abs(factor @ factor.T - mirrored).max() > 0.1


def test_the_same_seed_gives_the_same_draw_whatever_was_drawn_before():
    kernel = RotatedExponentialKernel(2.0, (6.0, 1.5), -math.pi / 5)
    alone = sample_grid(kernel, (6, 8), method="cholesky", seed=3)
    grid_sampler._FACTORS.clear()
    sample_grid(RotatedExponentialKernel(2.0, (6.0, 1.5), math.pi / 5), (6, 8),
                method="cholesky", seed=9)
    again, info = sample_grid(kernel, (6, 8), method="cholesky", seed=3, return_info=True)
    assert info.cached
    np.testing.assert_array_equal(again, alone)


def test_the_numpy_and_torch_cpu_cholesky_draws_agree_for_a_mirrored_kernel():
    kernel = RotatedExponentialKernel(2.0, (6.0, 1.5), -math.pi / 5)
    a = sample_grid(kernel, (6, 8), method="cholesky", seed=3)
    b = sample_grid(kernel, (6, 8), method="cholesky", seed=3, device="cpu")
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-10)


def test_a_honed_surface_factorises_its_long_step_once(monkeypatch):
    factorised = []
    original = grid_sampler._cholesky_factor

    def count(covariance):
        factorised.append(covariance.shape)
        return original(covariance)
    monkeypatch.setattr(grid_sampler, "_cholesky_factor", count)
    z = surfaces.honed((24, 24), surfaces.FIGURE_3, seed=1, method="auto")
    assert z.shape == (24, 24) and np.all(np.isfinite(z))
    assert factorised == [(576, 576)]  # step 1's +phi and -phi from one factor


def test_a_positive_lay_angle_is_factorised_as_it_is():
    """The paper's kernels (phi = 30, 45 deg) keep the draws they had before the mirror rule."""
    for step in (surfaces.FIGURE_2, *surfaces.FIGURE_3):
        _, mirrored, _ = grid_sampler._canonical_table(step.kernel(), (6, 7), np.ones(2))
        _, flipped, _ = grid_sampler._canonical_table(step.kernel(mirrored=True), (6, 7),
                                                      np.ones(2))
        assert not mirrored and flipped
