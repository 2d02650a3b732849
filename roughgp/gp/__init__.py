"""The Gaussian process itself (section 2 of the paper).

Modules: :mod:`~roughgp.gp.acvf` (ACVFs and closed-form PSDs as functions: eq 18, 21, 22,
the Matérn family), :mod:`~roughgp.gp.kernels` (the same as GPyTorch kernels),
:mod:`~roughgp.gp.numpy_kernels` (eq 18 and the Matérn ACVF in numpy alone: draws without
torch),
:mod:`~roughgp.gp.fourier` (eq 5 on a grid by FFT), :mod:`~roughgp.gp.noise` (the noise
model of eq 8), :mod:`~roughgp.gp.toeplitz` (the exact log-likelihood of a regularly sampled
profile, O(n²)).

May import: :mod:`roughgp.common`.
"""
