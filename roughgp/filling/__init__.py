"""Gap filling: unmeasured points filled with the GP posterior, checked on the measurement
itself, and spurious measured points found (the paper's conclusion, ref [48]).

Modules, bottom up: :mod:`~roughgp.filling.interpolants` (linear and cubic interpolation, the
baseline a GP fill must beat), :mod:`~roughgp.filling.global_fill` (the posterior mean and sd
given all measured points: conjugate gradients, pathwise draws; ``method="global"``) and
:mod:`~roughgp.filling.local_fill` (the same by moving-window kriging; ``method="local"``) ←
:mod:`~roughgp.filling.self_check` (measured points held out in discs, filled, compared with
their heights and with linear interpolation: the verdict, the calibrated band, the choice of
the smoothness) ← :mod:`~roughgp.filling.measured` (a measured surface filled end to end: form
off, fit or model, self-check, fill, form back; ``roughgp fill``, :func:`roughgp.fill`),
:mod:`~roughgp.filling.spurious` (spikes and pits found by the GP's leave-one-out scores, and
the metrologists' methods beside it).

A model file (:mod:`roughgp.surface_models`) is used through what it gives (its kernel and
noise variance), so this package sits below the models, whose ladder scores its rungs with the
self-check.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`, :mod:`roughgp.models`,
:mod:`roughgp.non_gaussian`, :mod:`roughgp.targets`, :mod:`roughgp.inference`.
"""
