"""Metrology on measured heights: form removal and ISO filters, texture parameters, spectra.

Modules: :mod:`~roughgp.metrology.levelling` (mean, least-squares line or plane, NaN ignored),
:mod:`~roughgp.metrology.form` (F-operators: least-squares plane, polynomial, cylinder;
NaN-aware), :mod:`~roughgp.metrology.filters` (ISO 16610-21 profile and ISO 16610-61 areal
Gaussian filters as S- and L-filters, NaN-aware; default cut-offs after ISO 4288 / ISO 3274 and
ISO 25178-3; the F-S-L chain), :mod:`~roughgp.metrology.robust_filters` (the robust Gaussian
regression filter, ISO 16610-31 / -71), :mod:`~roughgp.metrology.stratified` (ISO 13565-1's
L-filter for stratified surfaces), :mod:`~roughgp.metrology.texture_heights` (height and
material-ratio parameters, ISO 25178-2 4.1 and 4.4, ISO 4287, ISO 13565-2; the conventions of
both texture modules), :mod:`~roughgp.metrology.texture` (Sal, Str, Std, RSm and the whole
parameter sets), :mod:`~roughgp.metrology.texture_report` (the parameters after the
F-, S- and L-operators, unmeasured points handled), :mod:`~roughgp.metrology.spectral`
(periodogram, Welch, empirical ACVF), :mod:`~roughgp.metrology.periodicity` (periodicity and
short-wavelength share along x). Reading and writing the files is :mod:`roughgp.io`'s.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`.
"""
