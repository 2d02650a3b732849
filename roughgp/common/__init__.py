"""Shared helpers: input checks, grid conventions, devices, settings, the figure style.

Modules: :mod:`~roughgp.common.checks` (argument checks that name the parameter and the
allowed range; seeds to generators), :mod:`~roughgp.common.grid` (``shape`` / ``spacing`` in
array order, lags and frequencies with ``(x, y)`` components), :mod:`~roughgp.common.device`
(the ``device=`` argument through torch), :mod:`~roughgp.common.settings` (quick or full
sizes, ``ROUGHGP_FULL``), :mod:`~roughgp.common.plotting` (the book's figure style),
:mod:`~roughgp.common.version` (the version that the files roughgp writes record).

May import: numpy, scipy, torch, matplotlib; nothing else of roughgp.
"""
