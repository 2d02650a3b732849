"""Measured surfaces: reading and writing them, form removal and ISO filters, texture
parameters, spectra.

Modules: :mod:`~roughgp.metrology.readers` (text / CSV profiles and grids, x-y-z points;
rounded x accepted within its printed digits), :mod:`~roughgp.metrology.x3p` (``.x3p`` from any
writer, read and written), :mod:`~roughgp.metrology.instruments` (instrument formats through
SurfaceTopography), :mod:`~roughgp.metrology.measurement` (any file -> heights in µm, with where
spacing and unit came from), :mod:`~roughgp.metrology.writers` (``.npy``, ``.csv``, ``.x3p``),
:mod:`~roughgp.metrology.levelling` (mean, least-squares line or plane, NaN ignored),
:mod:`~roughgp.metrology.form` (F-operators: least-squares plane, polynomial, cylinder;
NaN-aware), :mod:`~roughgp.metrology.filters` (ISO 16610-21 profile and ISO 16610-61 areal
Gaussian filters as S- and L-filters, NaN-aware; default cut-offs after ISO 4288 / ISO 3274 and
ISO 25178-3; the F-S-L chain), :mod:`~roughgp.metrology.texture_heights` (height and
material-ratio parameters, ISO 25178-2 4.1 and 4.4, ISO 4287, ISO 13565-2; the conventions of
both texture modules), :mod:`~roughgp.metrology.texture` (Sal, Str, Std, RSm and the whole
parameter sets), :mod:`~roughgp.metrology.texture_report` (the parameters after the
F-, S- and L-operators, unmeasured points handled), :mod:`~roughgp.metrology.spectral`
(periodogram, Welch, empirical ACVF), :mod:`~roughgp.metrology.periodicity` (periodicity and
short-wavelength share along x).

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`.
"""
