"""Measured surfaces out: fit a model to a measurement, keep it, simulate from it, check it,
fill the measurement's holes with it (beyond the paper; the loop its introduction describes).

Modules: :mod:`~roughgp.beyond.measured.model` (the fitted model and its versioned JSON file),
:mod:`~roughgp.beyond.measured.fit` (eq 18 on a surface with holes, eq 21 on a profile, after
the measurement's F-, S- and L-operators), :mod:`~roughgp.beyond.measured.check` (the
measurement's texture parameters among those of the model's simulations),
:mod:`~roughgp.beyond.measured.fill` (a measured surface's missing points filled, the form
added back).
"""
