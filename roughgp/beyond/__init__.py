"""Beyond the paper: what its outlook asks for, built and checked.

Modules: :mod:`~roughgp.beyond.non_gaussian` (heights with a prescribed skewness and
kurtosis: the Johnson system and a pre-distorted ACVF), :mod:`~roughgp.beyond.targets`
(prescribed Sq, Sal, Str, Std: the closed form both ways, measuring drawn surfaces) and
:mod:`~roughgp.beyond.prescribed` (its calibration on a finite field; drawing the surfaces),
:mod:`~roughgp.beyond.gap_filling` (unmeasured points filled with the GP posterior mean and sd),
:mod:`~roughgp.beyond.local_fill` (the same by moving-window kriging),
:mod:`~roughgp.beyond.measured` (a measurement's fitted model as a file: fit, simulate, check,
fill).

May import: everything below it: :mod:`roughgp.common`, :mod:`roughgp.gp`,
:mod:`roughgp.sampling`, :mod:`roughgp.metrology`, :mod:`roughgp.models`,
:mod:`roughgp.inference`.
"""
