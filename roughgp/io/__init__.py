"""Reading and writing measurements: any file in, heights in µm out (and back to a file).

Modules: :mod:`~roughgp.io.measurement` (:func:`~roughgp.io.measurement.read_measurement`:
any file -> heights in µm, ``z[iy, ix]``, NaN where unmeasured, with where the spacing and the
unit came from; the format is chosen here) ← :mod:`~roughgp.io.readers` (text / CSV profiles
and grids, x-y-z points; rounded x accepted within its printed digits),
:mod:`~roughgp.io.x3p` (``.x3p`` from any writer, read and written),
:mod:`~roughgp.io.instruments` (instrument formats through SurfaceTopography, one reader at a
time: :mod:`~roughgp.io.instrument_readers`), :mod:`~roughgp.io.plausibility` (a reading
checked before it is used: heights within a metre, steps from 1 pm to 1 m);
:mod:`~roughgp.io.writers` (``.npy``, ``.csv``, ``.x3p``, whole or not at all) and
:mod:`~roughgp.io.provenance` (a file's SHA-256, the reader and the spacing's source, kept in a
model file).

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`.
"""
