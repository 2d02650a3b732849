"""Tests of roughgp.sampling.truncation: the smooth truncation of the ACVF beyond the grid's lags
leaves the grid covariance R of eq 10 (eq 18's ACVF here) unchanged, and draws from it have R as
their covariance, as draws from the plain wrap do (Jawaid & Seewig, section 2.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.gp.kernels import MaternKernel, RotatedExponentialKernel
from roughgp.sampling import circulant, grid_covariance, truncation
from tests.sampling.test_sampling import N_DRAWS, _bonferroni_threshold, _max_z

# eq 18 long against the grid (lambda_a = 8 on 6 x 7 points), unequal spacing (dy, dx)
KERNEL = dict(variance=2.0, lengthscales=(8.0, 2.0), angle=math.pi / 6)
SHAPE, SPACING = (6, 7), (1.0, 0.8)


def test_taper_is_one_on_the_grid_lags_and_zero_at_the_wrap():
    lags = np.linspace(0, 10, 101)
    w = truncation.taper(lags, 4.0, 9.0)
    assert np.all(w[lags <= 4.0] == 1.0) and np.all(w[lags >= 9.0] == 0.0)
    assert np.all(np.diff(w) <= 0) and 0 < w[65] < 1


@pytest.mark.parametrize("shape, spacing", [(SHAPE, SPACING), ((512, 512), (1.0, 1.0))])
def test_smooth_embedding_leaves_the_grid_covariance_unchanged(shape, spacing):
    kernel = RotatedExponentialKernel(**KERNEL) if shape == SHAPE else \
        RotatedExponentialKernel(10.0, (500.0, 5.0), math.pi / 6)
    torus = (40, 44) if shape == SHAPE else (1100, 1300)
    assert truncation.grid_lag_change(kernel.acvf, shape, spacing, torus) == 0.0


@pytest.mark.parametrize("truncation_kind", ["smooth", "none"])
def test_draws_of_either_embedding_have_the_covariance_of_eq_18(truncation_kind):
    kernel = RotatedExponentialKernel(**KERNEL)
    emb = circulant.embed(kernel.acvf, SHAPE, SPACING, truncation=truncation_kind)
    assert emb.exact and emb.truncation == truncation_kind and emb.min_eigenvalue >= -1e-10
    samples = circulant.draw(emb, N_DRAWS, np.random.default_rng(2006))
    threshold = _bonferroni_threshold(int(np.prod(SHAPE)))
    assert _max_z(samples, grid_covariance(kernel, SHAPE, SPACING)) < threshold
    wrong = RotatedExponentialKernel(2.0, (16.0, 4.0), math.pi / 6)
    assert _max_z(samples, grid_covariance(wrong, SHAPE, SPACING)) > threshold  # power


def test_smooth_embedding_is_smaller_than_the_plain_wrap():
    kernel = RotatedExponentialKernel(**KERNEL)
    smooth = circulant.embed(kernel.acvf, SHAPE, SPACING)
    plain = circulant.embed(kernel.acvf, SHAPE, SPACING, truncation="none")
    assert np.prod(smooth.torus_shape) < np.prod(plain.torus_shape)
    assert all(m >= 2 * n - 1 for m, n in zip(smooth.torus_shape, SHAPE))


def test_profile_and_bad_truncation():
    kernel = MaternKernel(0.5, dim=1, lengthscale=30.0)
    emb = circulant.embed(kernel.acvf, (50,))
    assert emb.exact and emb.torus_shape[0] >= 99
    assert truncation.grid_lag_change(kernel.acvf, (50,), (1.0,), emb.torus_shape) == 0.0
    with pytest.raises(ValueError, match="truncation"):
        circulant.embed(kernel.acvf, (50,), truncation="taper")


def test_an_invalid_acvf_is_refused_without_growing_the_torus_to_its_limit():
    # exp(-t/1000) - 0.5 exp(-t/10): its PSD is negative at high frequencies (not eq 5's
    # valid kernel); the eigenvalues settle at their negative values after a few doublings
    def invalid(lags):
        t = np.abs(lags[..., 0])
        return np.exp(-t / 1000.0) - 0.5 * np.exp(-t / 10.0)

    with pytest.raises(truncation.NotEmbeddableError, match="no larger torus") as caught:
        circulant.embed(invalid, (2048,))
    largest = int(str(caught.value).split(" to (")[1].split(",")[0])
    assert largest < 2**18 < 2**27                      # far below max_points
    # a valid ACVF of the same range (and a 100x longer one) still embeds exactly
    for length in (1000.0, 1e5):
        emb = circulant.embed(lambda lags: np.exp(-np.abs(lags[..., 0]) / length), (2048,))
        assert emb.exact and emb.min_eigenvalue >= -1e-10


def test_an_invalid_acvf_on_a_narrow_grid_is_refused_early(monkeypatch):
    """A 48 x 24 grid (the unseen half of a 48² map in `fit ground --model auto`'s check of
    the heights): the short axis' torus was doubled up to max_points (96 x 1049760 points, 217 s
    for the pre-distorted ACVF of a spectral mixture) because the long axis, left at its
    minimal torus, counted its own grid lags as "where the taper ends". Its lags beyond the
    grid's are what count: the search now stops once the eigenvalues have settled."""
    def invalid(lags):  # a Gaussian bump with a negative ring: its PSD is negative somewhere
        r2 = (lags[..., 0] ** 2 + lags[..., 1] ** 2) / 36.0
        return np.exp(-r2 / 2) * (1 - 0.6 * r2)

    tori = []
    eigenvalues = truncation.tapered_eigenvalues
    monkeypatch.setattr(truncation, "tapered_eigenvalues",
                        lambda *a, **k: tori.append(a[1]) or eigenvalues(*a, **k))
    with pytest.raises(truncation.NotEmbeddableError, match="no larger torus"):
        circulant.embed(invalid, (48, 24))
    assert all(t[0] == 96 for t in tori)             # the long axis needs no taper
    assert len(tori) <= 12 and max(np.prod(t) for t in tori) < 2**18   # was 96 x 1049760


def test_a_grid_whose_torus_is_too_large_is_refused_on_the_coarse_copy(monkeypatch):
    """4096² with lambda_a 5000 (`simulate ground`) took 26 s to refuse: the coarse copy's
    search doubled its small tori up to max_points while the fine torus they implied was
    already too large. Now it stops at the first failing margins whose fine torus is too large,
    and a case searched on a coarse copy whose fine torus fits still embeds."""
    calls = []
    eigenvalues = truncation.tapered_eigenvalues
    monkeypatch.setattr(truncation, "tapered_eigenvalues",
                        lambda *a, **k: calls.append(a[1]) or eigenvalues(*a, **k))
    kernel = RotatedExponentialKernel(variance=10.0, lengthscales=(5000.0, 5.0),
                                      angle=math.pi / 6)
    with pytest.raises(truncation.NotEmbeddableError, match="no torus could be tried") as caught:
        circulant.embed(kernel.acvf, (4096, 4096))
    assert "(4096, 4096)" in str(caught.value)
    assert len(calls) <= 8 and max(np.prod(t) for t in calls) < 2 ** 22   # coarse tori only
    # margins whose grid torus is too large are refused before their coarse torus is
    # evaluated: 5 tori, the largest (1029, 1568); the old code evaluated a sixth, (1029, 2100)
    assert len(calls) == 5 and max(np.prod(t) for t in calls) < 1029 * 2100
    calls.clear()
    shorter = RotatedExponentialKernel(variance=10.0, lengthscales=(60.0, 5.0), angle=math.pi / 6)
    emb = circulant.embed(shorter.acvf, (1024, 1024))   # a coarse search that fits
    assert emb.exact
