"""eq18_coordinates: the one centre of the sandwich draws and the population's regions."""

import math

import numpy as np
import pytest

from roughgp.surface_models.coordinates import eq18_coordinates

HP = {"variance_um2": 2.0, "lambda_a_um": 8.0, "lambda_b_um": 3.0, "angle_deg": 30.0,
      "noise_variance_um2": 0.01}


def test_coordinates_are_logs_and_radians_in_the_fits_order():
    u = eq18_coordinates(HP)
    np.testing.assert_allclose(u, [math.log(2.0), math.log(8.0), math.log(3.0),
                                   math.pi / 6, math.log(0.01)])


@pytest.mark.parametrize("name, value", [("variance_um2", 0.0), ("lambda_b_um", -1.0),
                                         ("noise_variance_um2", float("nan")),
                                         ("angle_deg", float("inf")), ("lambda_a_um", "8")])
def test_a_bad_hyperparameter_is_named(name, value):
    with pytest.raises(ValueError, match=name):
        eq18_coordinates({**HP, name: value})
