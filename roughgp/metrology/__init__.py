"""Measured surfaces: reading and writing them, levelling, texture parameters, spectra.

Modules: :mod:`~roughgp.metrology.readers` (text / CSV profiles and grids, x-y-z points,
``.x3p``), :mod:`~roughgp.metrology.levelling` (mean, least-squares line or plane, NaN
ignored), :mod:`~roughgp.metrology.texture` (ISO 25178-2, ISO 4287, ISO 13565-2
parameters), :mod:`~roughgp.metrology.spectral` (periodogram, Welch, empirical ACVF),
:mod:`~roughgp.metrology.periodicity` (periodicity and short-wavelength share along x).

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`.
"""
