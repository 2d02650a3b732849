"""Models of measured surfaces: the ladder of models, fitted to a measurement and kept as a
model file, from which new surfaces are simulated (the loop the paper's introduction
describes: measure, fit, simulate).

Modules, bottom up: :mod:`~roughgp.surface_models.schema` (the model file's schema, validated
once), :mod:`~roughgp.surface_models.spectral_mixture` (the 2-D spectral mixture's covariance,
spectrum and Whittle fit), :mod:`~roughgp.surface_models.psd_table` ←
:mod:`~roughgp.surface_models.measured_psd` (the measured PSD as a model: its table, ACVF and
draws), :mod:`~roughgp.surface_models.iaaft` (the IAAFT marginal: the measured heights'
distribution matched exactly) ← :mod:`~roughgp.surface_models.model` (the fitted model and its
versioned JSON file: the equation of each rung, its marginal Gaussian, Johnson or IAAFT, the
stage of the operator chain it describes, its draws) ← :mod:`~roughgp.surface_models.chain`
(the operator chain around a model: the measurement's, and the rest of it for simulations;
what a fit keeps of the heights), :mod:`~roughgp.surface_models.in_range` (a fit on a bound or
far beyond the field named, capped, or refused) ← :mod:`~roughgp.surface_models.fit` (each
rung fitted: eq 18 and its Matérn variant on a surface with holes, eq 21 on a profile, the 2-D
spectral mixture, the measured PSD) ← :mod:`~roughgp.surface_models.ladder` (the rung chosen
by a held-out kriging score).

Checking a model against the measurement is :mod:`roughgp.checking`'s, filling the
measurement's holes with it :mod:`roughgp.filling`'s.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`, :mod:`roughgp.models`,
:mod:`roughgp.non_gaussian`, :mod:`roughgp.targets`, :mod:`roughgp.inference`,
:mod:`roughgp.filling`.
"""
