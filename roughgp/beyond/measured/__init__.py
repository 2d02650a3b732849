"""Measured surfaces out: fit a model to a measurement, keep it, simulate from it, check it,
fill the measurement's holes with it (beyond the paper; the loop its introduction describes).

Modules: :mod:`~roughgp.beyond.measured.schema` (the model file's schema, validated once) ←
:mod:`~roughgp.beyond.measured.model` (the fitted model and its versioned JSON file, the stage
of the operator chain it describes) ← :mod:`~roughgp.beyond.measured.in_range` (a fit on a
bound or far beyond the field named, capped, or refused),
:mod:`~roughgp.beyond.measured.provenance` (the data file's SHA-256) ←
:mod:`~roughgp.beyond.measured.fit` (eq 18 on a surface with holes, eq 21 on a profile, after
the measurement's F-operator; the rest of the chain for simulations),
:mod:`~roughgp.beyond.measured.check` (the measurement's texture parameters among those of the
model's simulations), :mod:`~roughgp.beyond.measured.fill` (a measured surface's missing points
filled, the form added back).
"""
