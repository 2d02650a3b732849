"""roughgp.experiments.measured_surfaces: the small helpers (the chapter "Measured surfaces" and
the ledger's measured-* rows run the computations)."""

import types

import pytest

from roughgp.experiments import measured_surfaces as ms
from roughgp.metrology.measurement import read_measurement


def test_centre_crop_takes_the_middle_and_whole_short_axes():
    ny, nx = read_measurement(ms.DATA / "sample-land.x3p").z.shape
    rows, cols = ms.centre_crop("sample-land.x3p", 300)
    assert (rows.start, rows.stop) == (0, ny)                 # 256 rows: all of them
    assert cols.stop - cols.start == 300 and cols.start == (nx - 300) // 2


@pytest.mark.parametrize("angle, deviation", [(90.0, 0.0), (-82.8, 7.2), (0.0, 90.0),
                                              (100.0, 10.0), (-90.0, 0.0)])
def test_the_lay_deviation_is_the_distance_from_y(angle, deviation):
    fit = types.SimpleNamespace(model=types.SimpleNamespace(hyperparameters={"angle_deg": angle}))
    assert ms.lay_deviation_deg(fit) == pytest.approx(deviation)


def test_the_chapter_files_exist():
    for name in ms.CV_FILES:
        assert (ms.DATA / name).is_file()


def test_the_difference_ratio_tells_white_noise_a_random_walk_and_a_smooth_surface():
    import numpy as np

    rng = np.random.default_rng(0)
    white = rng.normal(size=(300, 300))
    # a random walk along each axis (independent increments both ways; over 300 of them the
    # ratio scatters by about 3 %)
    walk = np.cumsum(rng.normal(size=300))[:, None] + np.cumsum(rng.normal(size=300))[None, :]
    y, x = np.mgrid[0:300, 0:300]
    smooth = np.sin(x / 15.0) * np.cos(y / 20.0)
    assert ms.difference_ratio(white) == pytest.approx(np.sqrt(3), rel=0.02)
    assert ms.difference_ratio(walk) == pytest.approx(np.sqrt(2), rel=0.05)
    assert ms.difference_ratio(smooth) < 0.1
