"""The paper's experiments: one function per claim's computation, returning a result object.

A chapter calls the function and draws its figures and states its numbers (glued) from the
result; the ledger's check (:mod:`roughgp.ledger`) calls the same function and judges the
result, so the book's text, its figures and the ledger cannot drift apart.

May import: everything below it (:mod:`roughgp.api` and down); not the ledger or the cli.
"""
