"""The ``roughgp`` command line: one module per command plus the parser, argument handling only.

:mod:`~roughgp.cli.main` (the entry point, exit codes), :mod:`~roughgp.cli.parser`,
:mod:`~roughgp.cli.output` (messages, tables, JSON, output paths), and one module per command:
:mod:`~roughgp.cli.reproduce`, :mod:`~roughgp.cli.simulate`, :mod:`~roughgp.cli.fit`,
:mod:`~roughgp.cli.texture`, :mod:`~roughgp.cli.fill`. Every computation is a call into the
library.

May import: all of roughgp; nothing imports it.
"""
