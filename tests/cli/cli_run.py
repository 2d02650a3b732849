"""The command line run in-process for the tests of tests/cli/: ``run(capsys, *argv)``."""

from roughgp.cli.main import main


def run(capsys, *argv):
    """``(exit code, stdout, stderr)`` of ``roughgp *argv``."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err
