"""The paper's models of surfaces and profiles (sections 2.3 and 3).

Modules: :mod:`~roughgp.models.arma` (ARMA(p, q) in the paper's signs, eq 12-14),
:mod:`~roughgp.models.arma2d` (2-D quarter- and half-plane AR, Yule-Walker, eq 12 in 2-D),
:mod:`~roughgp.models.moving_average` (a GP as a moving average of white noise, eq 16-17),
:mod:`~roughgp.models.surfaces` (ground and honed surfaces, eq 18-20, with the figures'
presets), :mod:`~roughgp.models.turned` (synthetic turned profiles and surfaces with known
truth: the stand-ins for figures 4 and 6), :mod:`~roughgp.models.nonstationary` (eq 18 with
parameters that vary over the map: Paciorek's covariance and a K-kernel blended sampler).

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`.
"""
