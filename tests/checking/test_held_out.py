"""The check out of sample (roughgp.checking.held_out, issue 40): parts of a map by name and by
indices, their refusals, and a held-out check that says no where the surface changes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from roughgp.checking.held_out import (
    MIN_PART,
    Part,
    held_out_check,
    held_out_of,
    part_of,
)
from roughgp.experiments.held_out import synthetic_map


@pytest.mark.parametrize("spec, rows, cols", [
    ("left", (0, 40), (0, 32)), ("right", (0, 40), (32, 65)),
    ("top", (0, 20), (0, 65)), ("bottom", (20, 40), (0, 65)),
    (" 4:36 , 10:50 ", (4, 36), (10, 50)),
])
def test_a_part_by_name_or_by_indices(spec, rows, cols):
    part = part_of((40, 65), spec)
    assert (part.rows, part.cols) == (rows, cols)
    z = np.arange(40 * 65.0).reshape(40, 65)
    assert np.array_equal(part.cut(z), z[rows[0]:rows[1], cols[0]:cols[1]])
    assert Part.from_dict(part.to_dict()) == part


@pytest.mark.parametrize("spec, words", [
    ("middle", "part must be one of left, right, top, bottom or 'R0:R1,C0:C1'"),
    ("0:20", "part must be one of"),
    ("0:50,0:20", "rows must lie in 0:40 and columns in 0:65"),
    ("20:10,0:30", "start < stop"),
    ("0:40,0:10", f"at least {MIN_PART} rows and columns"),
])
def test_a_bad_part_is_refused_with_the_allowed_forms(spec, words):
    with pytest.raises(ValueError, match="part") as error:
        part_of((40, 65), spec)
    assert words in str(error.value)


def test_a_half_holds_out_the_other_half_and_indices_hold_out_nothing_by_themselves():
    assert held_out_of(part_of((40, 64), "top")).name == "bottom"
    assert held_out_of(part_of((40, 64), "right")).cols == (0, 32)
    with pytest.raises(ValueError, match="name the held-out part"):
        held_out_of(part_of((40, 64), "0:20,0:20"))


def test_a_part_refuses_a_map_of_another_shape_and_a_record_that_contradicts_its_name():
    part = part_of((40, 64), "left")
    with pytest.raises(ValueError, match="40 x 64 map"):
        part.cut(np.zeros((40, 60)))
    with pytest.raises(ValueError, match="does not match its name"):
        Part.from_dict({**part.to_dict(), "cols": [0, 20]})
    with pytest.raises(ValueError, match="needs name and of_shape"):
        Part.from_dict({"rows": [0, 10]})


def test_the_held_out_part_must_be_unseen():
    z, left, _ = synthetic_map("stationary", 0, shape=(32, 64))
    with pytest.raises(ValueError, match="overlaps the fitted part"):
        held_out_check(left, z, fitted_part=part_of(z.shape, "left"),
                       held_out_part=part_of(z.shape, "0:32,16:48"), n_simulations=4)


def test_the_held_out_check_says_no_where_the_surface_is_rougher():
    """The true model of the left half, checked on a right half three times as rough: Sq
    outside on the held-out part (certainly, not at 10 %), not on the fitted one."""
    z, left, _ = synthetic_map("stationary", 1, shape=(32, 64))
    z = z.copy()
    z[:, 32:] *= 3.0
    result = held_out_check(left, z, fitted_part=part_of(z.shape, "left"), n_simulations=19,
                            seed=2)
    assert result.held_out_part.name == "right"
    assert "Sq" in result.held_out.outside and "Sq" not in result.fitted.outside
    record = result.to_dict()
    assert record["held_out_part"]["cols"] == [32, 64]
    again = held_out_check(left, z, fitted_part=part_of(z.shape, "left"), n_simulations=19,
                           seed=2)
    assert again.held_out.outside == result.held_out.outside


def test_a_held_out_check_of_the_truth_says_outside_about_as_often_as_its_level():
    """Over 30 stationary maps the true model's held-out Sq lies outside 19 simulations in
    about 10 % of them (binomial: 9 or fewer of 30 with probability 0.998)."""
    outside = 0
    for index in range(30):
        z, left, right = synthetic_map("stationary", index, shape=(32, 64), seed=11)
        result = held_out_check(right, z, fitted_part=part_of(z.shape, "left"),
                                n_simulations=19, seed=index, names=("Sq",))
        outside += "Sq" in result.held_out.outside
    assert outside <= 9


def test_the_predictive_models_reach_the_held_out_check():
    z, left, _ = synthetic_map("stationary", 2, shape=(32, 64))
    rough = dataclasses.replace(left, hyperparameters={
        **left.hyperparameters, "variance_um2": 100.0 * left.hyperparameters["variance_um2"]})
    plug_in = held_out_check(left, z, fitted_part=part_of(z.shape, "left"), n_simulations=9,
                             names=("Sq",))
    predictive = held_out_check(left, z, fitted_part=part_of(z.shape, "left"), n_simulations=9,
                                names=("Sq",), models=(rough,))
    assert "Sq" not in plug_in.fitted.outside
    assert "Sq" in predictive.fitted.outside  # ten times the roughness: all draws above
    assert any("predictive" in note for note in predictive.held_out.notes)
