"""The model check's calibration (roughgp.experiments.model_check): the synthetic measurements
and the shares outside, on a few small cases."""

from __future__ import annotations

import numpy as np

from roughgp.experiments.model_check import calibrate, synthetic_measurement


def test_synthetic_measurements_cycle_the_chain_and_the_holes():
    kinds = []
    for index in range(4):
        truth, l_filter, z = synthetic_measurement(index, (64, 64), seed=0)
        holes = np.isnan(z).mean()
        assert (holes > 0.05) == bool(index % 2) and holes < 0.2
        assert truth.cutoffs["l_um"] == l_filter
        kinds.append((l_filter is not None, holes > 0))
    assert len(set(kinds)) == 4  # every combination of L-filter and holes
    again = synthetic_measurement(3, (64, 64), seed=0)[2]
    np.testing.assert_array_equal(np.isnan(again), np.isnan(z))
    np.testing.assert_array_equal(again[~np.isnan(again)], z[~np.isnan(z)])


def test_calibrate_counts_the_parameters_outside_per_case():
    result = calibrate(2, shape=(40, 40), n_simulations=5, block=8, n_blocks=6)
    assert len(result.cases) == 2 and result.expected == 2 / 6
    fractions = result.fractions("true")
    assert set(fractions) == set(result.names)
    for case in result.cases:
        assert set(case.outside_true) <= set(result.names)
    counted = sum(len(c.outside_fitted) for c in result.cases) / (2 * len(result.names))
    assert np.isclose(result.mean_fraction("fitted"), counted)
    assert list(result.table().columns) == ["parameter", "outside, true model (%)",
                                            "outside, fitted model (%)"]
