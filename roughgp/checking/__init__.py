"""The model check: does a fitted model reproduce the measurement?

Modules: :mod:`~roughgp.checking.ranks` (the check's ranks: the chance of "outside", its
Rao-Blackwellised share over many simulations, the ranks' uniformity) ←
:mod:`~roughgp.checking.model_check` (the measurement's texture parameters among those of the
model's simulations, put through the rest of the operator chain and the holes as the
measurement was; ``roughgp check``, :func:`roughgp.check`) ←
:mod:`~roughgp.checking.calibrated` (the check calibrated for a model fitted to the measurement
itself: refitted bootstrap copies; ``roughgp check --calibrate``);
:mod:`~roughgp.checking.held_out` and :mod:`~roughgp.checking.tiles` (a model checked on parts
of the map it did not see; ``check --held-out``, ``--part``, ``--tiles``);
:mod:`~roughgp.checking.predictive` (simulations that carry the fit's uncertainty, from
bootstrap refits; ``check --predictive B``) and :mod:`~roughgp.checking.sandwich_draws` (from
the Whittle fit's sandwich covariance, no refits; ``--predictive-from sandwich``).

May import: every package below it, :mod:`roughgp.surface_models` and down.
"""
