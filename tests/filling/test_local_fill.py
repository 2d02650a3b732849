"""roughgp.filling.local_fill: the moving window's solve is bounded whatever the holes (a map
measured only in a band, as an instrument that lost most of a field leaves it)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.filling.local_fill import fill_gaps_locally, nearest_to_core
from roughgp.models import surfaces

KERNEL = surfaces.GrooveParameters(2.0, (12.0, 3.0), math.radians(60.0)).kernel()


def _band_map():
    """A 96 x 96 eq 18 map measured only in rows 40 to 55 (83 % missing)."""
    z = surfaces.ground((96, 96), variance=2.0, lengthscales=(12.0, 3.0),
                        angle=math.radians(60.0), seed=8)
    holed = np.full_like(z, np.nan)
    holed[40:56] = z[40:56]
    return z, holed


def test_a_window_grown_in_a_large_hole_keeps_only_the_nearest_measured_points():
    truth, holed = _band_map()
    capped = fill_gaps_locally(holed, KERNEL, noise_variance=1e-3, tile=16, margin=4,
                               max_observed=400)
    whole = fill_gaps_locally(holed, KERNEL, noise_variance=1e-3, tile=16, margin=4,
                              max_observed=96 * 96)
    missing = np.isnan(holed)
    assert capped.largest_window <= 400 < whole.largest_window
    assert np.all(np.isfinite(capped.mean)) and np.all(np.isfinite(capped.sd))
    assert np.all(capped.sd[missing] <= math.sqrt(2.0) + 1e-9)
    # next to the band the nearest points decide: the capped fill is the whole window's there
    near = missing & (np.abs(np.arange(96)[:, None] - 47.5) < 12)
    assert np.max(np.abs(capped.mean[near] - whole.mean[near])) < 0.05 * math.sqrt(2.0)
    # far from it both give the prior (mean of the band, sd of the surface): no worse band
    far = missing & (np.abs(np.arange(96)[:, None] - 47.5) > 40)
    assert np.all(capped.sd[far] > 0.95 * math.sqrt(2.0))
    error = (capped.mean - truth)[missing]
    assert np.mean(np.abs(error) <= 2 * capped.sd[missing]) > 0.85


def test_nearest_to_core_measures_distance_to_the_core_box_in_physical_units():
    oy = np.array([0, 10, 20, 10, 10])
    ox = np.array([10, 0, 10, 20, 12])
    # core rows 9..11, cols 9..11: point 4 is inside it; x is 4x coarser than y
    keep = nearest_to_core(oy, ox, slice(9, 12), slice(9, 12), (1.0, 4.0), 3)
    np.testing.assert_array_equal(keep, [0, 2, 4])
    np.testing.assert_array_equal(nearest_to_core(oy, ox, slice(9, 12), slice(9, 12),
                                                  (1.0, 1.0), 5), np.arange(5))


def test_max_observed_below_min_observed_is_refused_naming_the_parameter():
    _, holed = _band_map()
    with pytest.raises(ValueError, match="max_observed must be an integer >= 64"):
        fill_gaps_locally(holed, KERNEL, noise_variance=1e-3, max_observed=10)
