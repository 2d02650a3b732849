"""The ``roughgp`` command line: one module per command plus the parser, argument handling only.

:mod:`~roughgp.cli.main` (the entry point, exit codes) ← :mod:`~roughgp.cli.parser` ← one
module per command: :mod:`~roughgp.cli.reproduce`, :mod:`~roughgp.cli.simulate`,
:mod:`~roughgp.cli.fit`, :mod:`~roughgp.cli.texture`, :mod:`~roughgp.cli.check`,
:mod:`~roughgp.cli.fill`, :mod:`~roughgp.cli.batch` ← :mod:`~roughgp.cli.options` (the
options several commands share) ← :mod:`~roughgp.cli.bounds` (every numeric option's range,
one table) ← :mod:`~roughgp.cli.output` (messages, tables, JSON, output paths). Every computation is a call
into the library, through the verbs of :mod:`roughgp.api` where one serves (the input of every
command, ``texture``, ``check``, ``fill``, ``simulate --from``) or :mod:`roughgp.batch`
(``batch``, which runs those steps over many files).

May import: all of roughgp; nothing imports it.
"""
