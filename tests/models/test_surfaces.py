"""Ground (eq 18 + noise) and honed (eq 19, 20) surfaces: presets, determinism, structure."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from roughgp.common.checks import as_numpy
from roughgp.models import surfaces
from roughgp.models.surfaces import FIGURE_2, FIGURE_3, GrooveParameters, ground, honed

SMALL = dict(variance=2.0, lengthscales=(6.0, 2.0), angle=math.pi / 6)
STEPS = (GrooveParameters(4.0, (8.0, 3.0), math.pi / 4), GrooveParameters(0.5, (3.0, 2.0), 0.3))


def test_presets_are_the_papers_figure_parameters():
    assert FIGURE_2 == GrooveParameters(10.0, (500.0, 5.0), math.pi / 6)
    assert surfaces.FIGURE_2_SHAPE == (2000, 2000)
    assert FIGURE_3 == (GrooveParameters(45.0, (500.0, 30.0), math.pi / 4),
                        GrooveParameters(0.2, (5.0, 3.0), math.pi / 4))
    assert surfaces.FIGURE_3_SHAPE == (512, 512)
    kernel = FIGURE_2.kernel()
    along = np.array([[500 * math.cos(math.pi / 6), 500 * math.sin(math.pi / 6)]])
    assert kernel.acvf(along)[0] == pytest.approx(10 / math.e, rel=1e-12)
    assert FIGURE_2.kernel(mirrored=True).acvf(along * [[1, -1]])[0] == pytest.approx(
        10 / math.e, rel=1e-12)


def test_same_seed_same_surface_different_seed_different():
    a = ground((24, 20), **SMALL, seed=3)
    np.testing.assert_array_equal(a, ground((24, 20), **SMALL, seed=3))
    assert not np.allclose(a, ground((24, 20), **SMALL, seed=4))
    h = honed((24, 20), STEPS, seed=3)
    np.testing.assert_array_equal(h, honed((24, 20), STEPS, seed=3))
    assert not np.allclose(h, honed((24, 20), STEPS, seed=4))


def test_noise_is_added_to_the_latent_draw_with_its_variance():
    # the latent draw takes the generator first, so the same seed gives the same latent surface
    shape, noise_variance = (128, 128), 2.25
    z = ground(shape, **SMALL, noise_variance=noise_variance, seed=5)
    g = ground(shape, **SMALL, latent=True, seed=5)
    noise = (z - g).ravel()
    # white noise: sd of the sample variance is var * sqrt(2 / N); 5 of them
    assert abs(noise.var() - noise_variance) < 5 * noise_variance * math.sqrt(2 / noise.size)
    assert abs(np.corrcoef(noise[:-1], noise[1:])[0, 1]) < 5 / math.sqrt(noise.size)


def _state(kernel):
    """(variance, lengthscales, angle) of an eq 18 kernel (GPyTorch's or the numpy one the
    draws use) as plain floats."""
    hyper = {k: as_numpy(v) for k, v in kernel.hyperparameters().items()}
    return (float(hyper["variance"]), tuple(hyper["lengthscales"].tolist()),
            float(hyper["angle"]))


def test_ground_matches_the_kernel_it_names(monkeypatch):
    calls = []
    original = surfaces.sample_grid

    def recording(kernel, shape, **kwargs):
        calls.append((*_state(kernel), shape, kwargs))
        return original(kernel, shape, **kwargs)

    monkeypatch.setattr(surfaces, "sample_grid", recording)
    ground((10, 12), **SMALL, spacing=(0.5, 0.25), method="cholesky", seed=0)
    (variance, lengthscales, angle, shape, kwargs), = calls
    assert (variance, angle) == pytest.approx((2.0, math.pi / 6)) and shape == (10, 12)
    assert lengthscales == pytest.approx((6.0, 2.0))
    assert kwargs["method"] == "cholesky" and np.allclose(kwargs["spacing"], (0.5, 0.25))


def test_honed_is_the_minimum_over_mirrored_ground_surfaces_of_every_step(monkeypatch):
    """eq 19 and 20: each step draws +phi and -phi; the result is the pointwise minimum."""
    calls, draws = [], []

    def fake(kernel, shape, **kwargs):
        variance, _, angle = _state(kernel)
        calls.append((variance, angle))
        draw = np.random.default_rng(len(calls)).standard_normal((1, *shape))
        draws.append(draw[0])
        return draw

    monkeypatch.setattr(surfaces, "sample_grid", fake)
    z = honed((6, 7), STEPS, latent=True, seed=0)
    assert calls == [(4.0, pytest.approx(math.pi / 4)), (4.0, pytest.approx(-math.pi / 4)),
                     (0.5, pytest.approx(0.3)), (0.5, pytest.approx(-0.3))]
    np.testing.assert_array_equal(z, np.minimum.reduce(draws))


def test_honing_stack_holds_the_ground_surfaces_of_honed():
    stack = surfaces.honing_stack((12, 10), STEPS, seed=9)
    assert stack.shape == (2, 2, 12, 10)
    np.testing.assert_array_equal(stack.min(axis=(0, 1)), honed((12, 10), STEPS, seed=9))


def test_honed_draws_are_independent_across_steps_and_mirrors(monkeypatch):
    seen = []
    original = surfaces.sample_grid

    def recording(kernel, shape, **kwargs):
        out = original(kernel, shape, **kwargs)
        seen.append(out[0])
        return out

    monkeypatch.setattr(surfaces, "sample_grid", recording)
    # identical hyperparameters and angle 0 (so +phi = -phi): the four draws must still differ
    same = GrooveParameters(1.0, (3.0, 3.0), 0.0)
    honed((16, 16), (same, same), latent=True, seed=1)
    assert len(seen) == 4
    for i in range(4):
        for j in range(i):
            assert not np.allclose(seen[i], seen[j])


def test_one_step_honed_latent_mean_is_that_of_the_minimum_of_two_gaussians():
    # E min(X, Y) = -sigma / sqrt(pi) for independent N(0, sigma^2); spread from 8 surfaces
    step = GrooveParameters(1.0, (2.0, 1.0), math.pi / 4)
    means = [honed((64, 64), (step,), latent=True, seed=s).mean() for s in range(8)]
    assert abs(np.mean(means) + 1 / math.sqrt(math.pi)) < 5 * np.std(means, ddof=1) / math.sqrt(8)


def test_presets_unpack_into_ground():
    z = ground((8, 9), **dataclasses.asdict(FIGURE_2), method="cholesky", seed=0)  # small: dense
    assert z.shape == (8, 9) and np.all(np.isfinite(z))


@pytest.mark.parametrize("kwargs, name", [
    (dict(shape=(10,)), "shape"),
    (dict(variance=-1.0), "variance"),
    (dict(lengthscales=(1.0, 0.0)), "lengthscale"),
    (dict(noise_variance=-0.1), "variance"),
    (dict(spacing=-1.0), "spacing"),
])
def test_ground_argument_errors_name_the_parameter(kwargs, name):
    args = dict(shape=(8, 8), **SMALL) | kwargs
    with pytest.raises(ValueError, match=name):
        ground(args.pop("shape"), **args, seed=0)


def test_honed_steps_errors():
    with pytest.raises(ValueError, match="steps"):
        honed((8, 8), (), seed=0)
    with pytest.raises(ValueError, match="steps"):
        honed((8, 8), [dict(variance=1.0)], seed=0)
