"""roughgp.models.arma2d: 2-D AR supports, Yule-Walker and the model's ACVF."""

import math

import numpy as np
import pytest

from roughgp.models import arma2d


def test_supports_have_their_sizes():
    assert len(arma2d.ar_support(3, "quarter")) == 15
    assert len(arma2d.ar_support(3, "half")) == 3 + 3 * 7
    half = {tuple(k) for k in arma2d.ar_support(2, "half")}
    assert (0, 0) not in half and (-2, 1) in half and (-1, 0) not in half
    with pytest.raises(ValueError, match="kind must be one of"):
        arma2d.ar_support(2, "full")
    with pytest.raises(ValueError, match="order must be an integer >= 1"):
        arma2d.ar_support(0)
    with pytest.raises(ValueError, match="coefficients"):
        arma2d.ar_support(60, "half")


def test_a_separable_exponential_is_a_quarter_plane_ar1():
    """exp(-|x|/a - |y|/b) is the product of two AR(1): a_(1,0) = rx, a_(0,1) = ry,
    a_(1,1) = -rx ry, exactly; its ACVF comes back from the PSD."""
    rx, ry = math.exp(-1 / 6), math.exp(-1 / 3)

    def acvf(lags):
        return 2.0 * rx ** np.abs(lags[..., 0]) * ry ** np.abs(lags[..., 1])

    support = arma2d.ar_support(1, "quarter")
    coefficients, sigma2 = arma2d.yule_walker_2d(acvf, support)
    expected = {(1, 0): rx, (0, 1): ry, (1, 1): -rx * ry}
    for k, a in zip(map(tuple, support), coefficients):
        assert a == pytest.approx(expected[k], abs=1e-12)
    assert sigma2 == pytest.approx(2.0 * (1 - rx**2) * (1 - ry**2))
    model = arma2d.ar_acvf_2d(coefficients, support, sigma2, 256)
    ky, kx = np.mgrid[-20:21, -20:21]
    truth = acvf(np.stack([kx, ky], axis=-1).astype(float))
    got = np.roll(model, (20, 20), axis=(0, 1))[:41, :41]
    assert np.abs(got - truth).max() < 1e-9


def test_half_plane_fits_converge_for_a_short_rotated_exponential():
    from roughgp.gp import acvf as acvfs

    def kernel(lags):
        return acvfs.rotated_exponential(lags, 1.0, (4.0, 2.0), math.pi / 6)

    ky, kx = np.mgrid[-30:31, -30:31]
    truth = kernel(np.stack([kx, ky], axis=-1).astype(float))
    errors = []
    for p in (1, 4, 8):
        support = arma2d.ar_support(p, "half")
        coefficients, sigma2 = arma2d.yule_walker_2d(kernel, support)
        model = np.roll(arma2d.ar_acvf_2d(coefficients, support, sigma2, 256), (30, 30),
                        axis=(0, 1))[:61, :61]
        errors.append(np.abs(model - truth).max())
    assert errors[0] > errors[1] > errors[2] and errors[2] < 0.02


def test_bad_input_is_refused():
    support = arma2d.ar_support(1, "quarter")
    with pytest.raises(ValueError, match="acvf must return finite values of shape"):
        arma2d.yule_walker_2d(lambda lags: np.ones(3), support)
    with pytest.raises(ValueError, match="support must have shape"):
        arma2d.yule_walker_2d(lambda lags: np.ones(lags.shape[:-1]), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="coefficients must have shape"):
        arma2d.ar_acvf_2d(np.ones(2), support, 1.0, 16)
    with pytest.raises(ValueError, match="size must exceed"):
        arma2d.ar_acvf_2d(np.zeros(3), support, 1.0, 2)
