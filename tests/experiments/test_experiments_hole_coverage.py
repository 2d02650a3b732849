"""The recorded run of the band in holes of every size: the holes it cuts and how it pools and
judges the cases (roughgp.experiments.hole_coverage)."""

import math

import numpy as np
import pytest
import scipy.ndimage

from roughgp.experiments import hole_coverage as hc


def test_punch_holes_cuts_each_class_within_its_widths_and_repeats_with_its_seed():
    valid = np.ones((256, 256), dtype=bool)
    classes = hc.punch_holes(valid, seed=3)
    np.testing.assert_array_equal(classes, hc.punch_holes(valid, seed=3))
    assert not np.array_equal(classes, hc.punch_holes(valid, seed=4))
    for c, (lo, hi, count) in enumerate(hc.HOLE_CLASSES, 1):
        labels, n = scipy.ndimage.label(classes == c)
        assert 1 <= n <= count
        widths = [max(s.stop - s.start for s in box) for box in scipy.ndimage.find_objects(labels)]
        assert max(widths) <= 2 * hi     # two discs of a class may touch: at most two across


def test_punch_holes_only_over_measured_points():
    valid = np.ones((128, 128), dtype=bool)
    valid[:, :64] = False
    assert not (hc.punch_holes(valid, seed=0)[:, :64]).any()


def test_clustered_standard_error_is_the_ratio_estimators():
    inside, points = [90, 50, 190], [100, 50, 200]
    share = sum(inside) / sum(points)
    expected = math.sqrt(3 / 2 * sum((a - share * n) ** 2 for a, n in zip(inside, points))) / 350
    assert hc.clustered_standard_error(inside, points) == pytest.approx(expected)
    assert math.isnan(hc.clustered_standard_error([5], [10]))
    assert math.isnan(hc.clustered_standard_error([5, 0], [10, 0]))   # one case with points


def test_clustered_standard_error_matches_the_scatter_of_clustered_shares():
    """Cases whose points err together (one shared draw per case): the standard error from one
    set of cases matches the spread of the pooled share over many such sets, where the
    binomial error of independent points would be far too small."""
    rng = np.random.default_rng(0)
    shares, errors = [], []
    for _ in range(400):
        p = np.clip(rng.normal(0.95, 0.04, size=8), 0, 1)    # each case's own coverage
        points = rng.integers(300, 600, size=8)
        inside = rng.binomial(points, p)
        shares.append(inside.sum() / points.sum())
        errors.append(hc.clustered_standard_error(inside, points))
    spread = np.std(shares)
    assert np.median(errors) == pytest.approx(spread, rel=0.2)
    assert math.sqrt(0.95 * 0.05 / 3600) < spread / 3


def _records(coverages, points=1000):
    return [{"map": "m", "seed": seed, "classes": [
        {"across": [2, 5], "points": points, "inside": round(c * points),
         "inside_one_factor": 0}]} for seed, c in enumerate(coverages)]


def test_coverage_table_tells_noise_from_a_miss():
    scattered = hc.coverage_table(_records([0.82, 0.99, 0.86, 0.99, 0.88, 0.99]))[0]
    assert not scattered["on_target"] and scattered["consistent"]
    assert not scattered["clearly_below"]
    missed = hc.coverage_table(_records([0.85, 0.86, 0.84, 0.85, 0.86, 0.85]))[0]
    assert not missed["consistent"] and missed["clearly_below"]
    over = hc.coverage_table(_records([0.995, 0.99, 1.0, 0.995, 0.99, 1.0]))[0]
    assert over["clearly_above"] and not over["clearly_below"]
    assert over["coverage"] == pytest.approx(np.mean([0.995, 0.99, 1.0, 0.995, 0.99, 1.0]))
