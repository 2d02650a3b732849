"""What builds and tests the book, beside the library (never imported by ``roughgp``):
:mod:`booktools.notebook_cache` (the notebook cache shared by ``make test`` and ``make book``)
and :mod:`booktools.student` (``make student``: the labs without their solutions)."""
