"""roughgp.experiments.measured_surfaces: the small helpers (the chapter "Measured surfaces" and
the ledger's measured-* rows run the computations)."""

import types

import pytest

from roughgp.experiments import measured_surfaces as ms
from roughgp.io.measurement import read_measurement


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


def test_the_chapter_tables_convert_to_the_shown_unit():
    """The cross-validation and self-check rows show the land in µm and the other files in nm
    (1000 x their µm values), one row per file, in the files' order."""
    from types import SimpleNamespace

    from roughgp.experiments import measured_surfaces as ms

    check = SimpleNamespace(rmse={"GP": 0.002, "linear": 0.003})
    cv = SimpleNamespace(nu=0.5, rmse={"GP": 0.001, "linear": 0.002, "cubic": 0.004},
                         median_abs={"GP": 0.0005, "linear": 0.0006}, coverage=0.9,
                         band_factor=2.4, calibrated_coverage=0.95,
                         self_checks={0.5: check, 1.5: check})
    cvs = {ms.LAND_FILE: cv, "sur-2.sur": cv}
    rows = ms.cross_validation_rows(cvs)
    assert [r["file"] for r in rows] == [ms.LAND_FILE, "sur-2.sur"]
    assert rows[0]["unit"] == "µm" and rows[0]["RMSE GP"] == 0.001
    assert rows[1]["unit"] == "nm" and rows[1]["RMSE cubic"] == 4.0
    assert rows[1]["median |error| linear"] == 0.6 and rows[1]["in the band"] == 0.95
    checks = ms.self_check_rows(cvs)
    assert checks[1]["GP, ν = 1.5"] == 2.0 and checks[1]["linear"] == 3.0
