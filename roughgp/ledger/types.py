"""The ledger's types: a claim, what its check returns, and its outcome once run.

:class:`Claim` (one checkable statement of the paper, with its verdict, from
:data:`VERDICTS`), :class:`Check` (what a check returns: our value, whether the verdict's
condition holds, a figure) and :class:`Outcome` (a claim after its check ran).
"""

from __future__ import annotations

import dataclasses
from typing import Callable

__all__ = ["VERDICTS", "Check", "Claim", "Outcome"]

VERDICTS = ("reproduced", "reproduced with a different setup", "not reproducible as stated",
            "not checkable", "beyond the paper")
"""The verdicts a claim can carry. ``beyond the paper``: a statement of the paper's outlook
(future work) that the book built and checks."""


@dataclasses.dataclass
class Check:
    """What a check returns: ``value`` (our value, as text), ``holds`` (whether the verdict's
    condition holds) and an optional matplotlib ``figure``."""

    value: str
    holds: bool
    figure: object = None


@dataclasses.dataclass(frozen=True)
class Claim:
    """One entry of the ledger.

    ``key``: short id (``"eq5-duality"``); ``where``: section / equation / figure;
    ``statement``: the claim in a sentence; ``paper_value``: the paper's number ("" if
    none); ``tolerance``: what counts as agreement; ``verdict``: one of :data:`VERDICTS`;
    ``why``: the setup that differs, or why it is not reproducible or not checkable;
    ``chapter``: the book page that shows the check (a notebook's name without extension,
    or a page's file name such as ``"running.md"``);
    ``check``: ``check(full) -> Check``, or None for ``not checkable``;
    ``search``: True when the check's value comes from an optimiser or a random search (a
    multi-start fit, a Markov chain), whose result can move with the machine's rounding: such
    claims are run under several numerical set-ups and must keep their verdict under every one
    (:mod:`roughgp.ledger.setups`).
    """

    key: str
    where: str
    statement: str
    paper_value: str
    tolerance: str
    verdict: str
    why: str
    chapter: str
    check: Callable[[bool], Check] | None
    search: bool = False

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}, got {self.verdict!r}")
        if (self.check is None) != (self.verdict == "not checkable"):
            raise ValueError(f"claim {self.key!r}: exactly the 'not checkable' claims have no "
                             f"check")


@dataclasses.dataclass
class Outcome:
    """A claim after its check ran: ``value`` (ours), ``holds``, ``seconds``, ``figure``
    (the path of the saved figure, or None), ``error`` (the exception's text if it raised)."""

    claim: Claim
    value: str
    holds: bool
    seconds: float
    figure: str | None = None
    error: str | None = None

    @property
    def regressed(self) -> bool:
        """True when the check raised or its condition no longer holds."""
        return self.error is not None or not self.holds

    @property
    def status(self) -> str:
        """``"ok"``, ``"REGRESSED"``, ``"ERROR"``, or ``"not run"`` (no check: not
        checkable)."""
        if self.claim.check is None:
            return "not run"
        return "ERROR" if self.error is not None else ("REGRESSED" if not self.holds else "ok")
