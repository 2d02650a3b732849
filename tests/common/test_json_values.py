"""roughgp.common.json_values.plain: one way to make values JSON for every file written."""

from __future__ import annotations

import json
import math

import numpy as np

from roughgp.common.json_values import plain


def test_numpy_values_become_python_and_nan_becomes_null_unless_kept():
    value = {1: np.arange(3), "x": (np.float64(0.5), np.int64(4), np.bool_(True)),
             "nan": [math.nan, np.float64(np.inf)], "s": "text"}
    out = plain(value)
    assert out == {"1": [0, 1, 2], "x": [0.5, 4, True], "nan": [None, None], "s": "text"}
    assert type(out["x"][1]) is int and type(out["x"][2]) is bool
    json.dumps(out, allow_nan=False)
    kept = plain(value, nan_as_null=False)["nan"]
    assert math.isnan(kept[0]) and kept[1] == math.inf
