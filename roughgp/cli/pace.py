"""A warning with an estimate before a long run: the pace of its first unit (a simulation, a
bootstrap copy, a detection round; or a pilot draw a sixteenth of the size) times the units
left, said once when the whole run would take longer than :data:`LONG_RUN_S`, with the options
that shorten it. Argument handling and messages only.
"""

from __future__ import annotations

import time

import numpy as np

from roughgp.cli.output import err

__all__ = ["LONG_RUN_S", "PILOT_FROM_POINTS", "Pace", "duration", "announce_long_draw"]

#: a run longer than this (seconds, at the first unit's pace) is announced with its estimate
LONG_RUN_S = 60.0


def duration(seconds: float) -> str:
    """``seconds`` in words: ``"45 s"``, ``"3.2 min"``, ``"1.5 h"``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


class Pace:
    """A progress callback ``(done, total)`` that, after the first unit, warns once when the
    ``total`` units of ``what`` would take longer than :data:`LONG_RUN_S` at that pace (timed
    from the call with ``done`` 0 where there is one, else from its creation), naming
    ``shorter`` (the options that shorten the run; None where no option does); ``then`` (a
    progress callback) is called after it."""

    def __init__(self, what: str, shorter: str | None, then=None):
        self.what, self.shorter, self.then = what, shorter, then
        self.start = time.perf_counter()
        self.estimate = None

    def __call__(self, done: int, total: int) -> None:
        if done == 0:   # the run's units start now (what came before is not their pace)
            self.start = time.perf_counter()
        elif self.estimate is None:
            self.estimate = (time.perf_counter() - self.start) / max(done, 1) * total
            if self.estimate > LONG_RUN_S:
                shorter = f"{self.shorter} make it shorter; " if self.shorter else ""
                err(f"warning: {total} {self.what} take about {duration(self.estimate)} at the "
                    f"pace of the first ({shorter}Ctrl-C stops it)")
        if self.then is not None:
            self.then(done, total)


#: draws of at least this many points are timed first on a pilot of a sixteenth of the points
PILOT_FROM_POINTS = 2 ** 20


def announce_long_draw(draw, shape) -> None:
    """Before a draw of ``shape`` with :data:`PILOT_FROM_POINTS` points or more: time
    ``draw(pilot shape)`` on a pilot a quarter as long along each axis and, where the whole
    would take longer than :data:`LONG_RUN_S` at that pace, say so with the estimate (a model
    whose draws refuse the pilot's size is left unannounced)."""
    if int(np.prod(shape)) < PILOT_FROM_POINTS:
        return
    pilot = tuple(max(n // 4, 2) for n in shape)
    start = time.perf_counter()
    try:
        draw(pilot)
    except (ValueError, MemoryError):
        return
    estimate = (time.perf_counter() - start) * np.prod(shape) / np.prod(pilot) * 1.2
    if estimate > LONG_RUN_S:
        err(f"warning: this draw takes about {duration(estimate)} at the pace of one of "
            f"{' x '.join(map(str, pilot))} points (a smaller --shape makes it shorter; "
            f"Ctrl-C stops it)")
