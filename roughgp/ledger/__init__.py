"""The claims ledger: every checkable claim of the paper, its check, and a verdict.

A one-way chain of modules: :mod:`~roughgp.ledger.types` (:class:`Claim`, :class:`Check`,
:class:`Outcome`, :data:`VERDICTS`) ← the checks (:mod:`~roughgp.ledger.checks_gp`,
:mod:`~roughgp.ledger.checks_surfaces`, :mod:`~roughgp.ledger.checks_turned`,
:mod:`~roughgp.ledger.checks_beyond`: each calls the library's computation and judges it) ←
:mod:`~roughgp.ledger.table` (the claims' text, in the paper's order) ←
:mod:`~roughgp.ledger.runner` (:func:`run`, the Markdown and JSON renderings) ←
:mod:`~roughgp.ledger.stored` (a run kept on disk) and :mod:`~roughgp.ledger.setups` (the claims
that depend on a search, run under several numerical set-ups). The public names
of the types and the runner are re-exported here: ``from roughgp import ledger; ledger.run()``.

May import: everything of roughgp below it (not :mod:`roughgp.cli`).
"""

from roughgp.ledger.runner import (
                                   CLAIMS,
                                   claim,
                                   claim_keys,
                                   run,
                                   to_markdown,
                                   to_markdown_details,
                                   to_records,
                                   write,
)
from roughgp.ledger.types import VERDICTS, Check, Claim, Outcome

__all__ = ["VERDICTS", "Check", "Claim", "Outcome", "CLAIMS", "claim", "claim_keys", "run",
           "to_markdown", "to_markdown_details", "to_records", "write"]
