"""The synthetic parts of the population check (roughgp.experiments.population_check): regions
alike or drawn from a population, seeded, and the shares outside per model."""

import numpy as np
import pytest

from roughgp.experiments import population_check as pc


def test_alike_regions_share_one_model_and_hierarchical_ones_do_not():
    maps, truths = pc.part_regions("alike", 0)
    assert len(maps) == pc.REGIONS + 1 and maps[0].shape == pc.SHAPE
    assert len({t.hyperparameters["variance_um2"] for t in truths}) == 1
    assert not np.array_equal(maps[0], maps[1])       # one model, different surfaces
    maps, truths = pc.part_regions("hierarchical", 0)
    variances = [t.hyperparameters["variance_um2"] for t in truths]
    assert len(set(variances)) == len(variances)
    again, _ = pc.part_regions("hierarchical", 0)
    np.testing.assert_array_equal(maps[3], again[3])
    with pytest.raises(ValueError, match="kind must be one of alike, hierarchical"):
        pc.part_regions("gradient", 0)


def test_outside_shares_count_the_cases_per_model():
    records = [{"kind": "alike", "outside": {"population": ["Sq"], "truth": []}},
               {"kind": "alike", "outside": {"population": [], "truth": ["Sq", "Sa"]}}]
    shares = pc.outside_shares(records, "alike", "population")
    assert shares["Sq"] == 0.5 and shares["Sa"] == 0.0 and shares["cases"] == 2
    assert shares["mean"] == pytest.approx(0.5 / 13)
    assert pc.outside_shares(records, "hierarchical", "population") is None
