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


def test_the_increment_kurtosis_is_three_for_a_gaussian_surface_and_large_with_spikes():
    import numpy as np
    import scipy.ndimage

    rng = np.random.default_rng(0)
    # a stationary Gaussian surface with correlated heights: Gaussian increments (kurtosis 3)
    smooth = scipy.ndimage.gaussian_filter(rng.normal(size=(300, 300)), 4.0)
    assert ms.increment_kurtosis(smooth) == pytest.approx(3.0, abs=0.15)
    spiky = smooth.copy()
    spiky[rng.integers(0, 300, 30), rng.integers(0, 300, 30)] += 20 * smooth.std()  # 30 spikes
    assert ms.increment_kurtosis(spiky) > 30
    spiky[0, 0] = np.nan                                                  # NaN are left out
    assert np.isfinite(ms.increment_kurtosis(spiky))


def test_largest_errors_share_and_median_abs_of_a_cross_validation():
    import numpy as np

    truth = np.zeros(100)
    gp = np.full(100, 0.1)
    gp[0] = 10.0                                  # one point carries almost all squared error
    cv = ms.CrossValidation("x", np.ones(100, bool), truth, {"GP": gp, "linear": gp * 0 + 0.2},
                            np.ones(100), {}, 0.0, {}, 0.0, 0.5, 2.0, 0.95, {})
    assert cv.largest_errors_share("GP", top=0.01) == pytest.approx(100 / (100 + 99 * 0.01))
    assert cv.median_abs == {"GP": pytest.approx(0.1), "linear": pytest.approx(0.2)}
    assert cv.worse_tail() == pytest.approx(0.01)          # only the one large error is worse
    assert cv.worse_tail("linear", "GP") == 0.0
