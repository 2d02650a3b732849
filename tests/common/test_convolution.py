"""roughgp.common.convolution.convolve_same against scipy.signal.fftconvolve(mode="same")."""

import numpy as np
import pytest
from scipy.signal import fftconvolve

from roughgp.common.convolution import convolve_same


@pytest.mark.parametrize("shape, size, axis", [
    ((50,), 7, 0), ((50,), 8, 0), ((6,), 31, 0), ((1,), 5, 0),  # odd, even, kernel > array
    ((20, 33), 9, 0), ((20, 33), 10, 1), ((20, 33), 80, -1), ((4, 5, 6), 3, 1),
])
def test_matches_scipy_fftconvolve_same(shape, size, axis):
    rng = np.random.default_rng(size)
    a = rng.standard_normal(shape)
    kernel = rng.standard_normal(size)  # not symmetric: convolution, not correlation
    k_shape = [1] * a.ndim
    k_shape[axis] = size
    expected = fftconvolve(a, kernel.reshape(k_shape), mode="same", axes=axis % a.ndim)
    got = convolve_same(a, kernel, axis)
    assert got.shape == a.shape
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_a_shifted_impulse_lands_where_the_convolution_puts_it():
    a = np.zeros(11)
    a[5] = 1.0
    out = convolve_same(a, [0.0, 0.0, 1.0])  # the kernel's centre is index 1: shift by +1
    assert np.argmax(out) == 6 and out[6] == pytest.approx(1.0)


def test_the_fft_length_is_scipys_next_fast_len():
    """The 5-smooth FFT length taken without scipy.fft is scipy's, for every n up to 3000."""
    from scipy.fft import next_fast_len

    from roughgp.common import convolution
    assert [convolution._fast_length(n) for n in range(1, 3001)] == [
        next_fast_len(n, real=True) for n in range(1, 3001)]
