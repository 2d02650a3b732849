r"""The ``roughgp`` command: reproduce the paper's claims, simulate surfaces, fit and measure.

A command-line front end to the library, for Jawaid & Seewig, "Model of rough surfaces with
Gaussian processes" (Surf. Topogr.: Metrol. Prop.). Sub-commands, one module each:
:mod:`~roughgp.cli.reproduce`, :mod:`~roughgp.cli.simulate`, :mod:`~roughgp.cli.fit`,
:mod:`~roughgp.cli.texture`, :mod:`~roughgp.cli.check`, :mod:`~roughgp.cli.fill`; the parser:
:mod:`~roughgp.cli.parser`; shared options: :mod:`~roughgp.cli.options`.

Units: heights and lengths (spacing, lengthscales, feed, periods) are in micrometres (um).
Exit codes: 0 success, 1 a claim regressed (``reproduce``), 2 a usage or input error (a
message, never a traceback), 130 interrupted (SIGINT), 143 terminated (SIGTERM, what
``timeout`` and ``kill`` send: cleaned up as an interrupt, no partial file left), 141
(quietly) when the reader of a pipe has gone (``roughgp texture F | head``). :func:`main` is
the entry point (``main(argv) -> int``); it never raises ``SystemExit``.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import warnings

from roughgp.cli.bounds import check_bounds
from roughgp.cli.output import UsageError, err, shell_message, show_warning
from roughgp.cli.parser import build_parser
from roughgp.common.threads import one_blas_thread
from roughgp.io.readers import MalformedFileError

__all__ = ["main"]


def main(argv=None) -> int:
    """Run ``roughgp`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    parser = build_parser()
    try:
        args, unknown = parser.parse_known_args(argv)
    except SystemExit as exc:  # --help, --version (0) and argparse's usage errors (2)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    if args.command is None:
        if unknown:
            err(f"roughgp: error: unrecognized arguments: {' '.join(unknown)}")
        parser.print_help(sys.stderr)
        return 2
    kind = getattr(args, "kind", None) if args.command == "simulate" else None
    name = f"roughgp {args.command}" + (f" {kind}" if kind else "")
    if unknown:  # named by the command that does not take them, not by roughgp's usage
        err(f"{name}: error: unrecognized arguments: {' '.join(unknown)}"
            + _OPERATORS_OF_THE_MODEL.get(args.command, "")
            + f" (roughgp {args.command} --help lists its options)")
        return 2
    try:
        check_bounds(args)
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            if args.command not in _QUICK_COMMANDS:
                import scipy.linalg  # noqa: F401  (loaded now, so its BLAS is limited below)
            with one_blas_thread(), _terminate_as_interrupt():  # see roughgp.common.threads
                code = args.func(args)
            sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's exit
            return code
    except (UsageError, MalformedFileError, ValueError) as exc:
        err(f"{name}: error: {shell_message(str(exc), args)}")
        return 2
    except BrokenPipeError:  # ``roughgp texture F | head``: the reader has gone; end quietly
        _silence_stdout()
        return 141  # 128 + SIGPIPE, what a shell reports for a writer cut off by its pipe
    except OSError as exc:  # unreadable / unwritable files
        err(f"{name}: error: {exc.strerror or exc}"
             + (f": {exc.filename}" if getattr(exc, "filename", None) else ""))
        return 2
    except OverflowError as exc:  # a safety net: the options' ranges should catch it first
        err(f"{name}: error: a number overflowed ({exc}): an option or the data is out of "
            f"range")
        return 2
    except MemoryError:  # a safety net: sizes are budgeted before the large arrays
        err(f"{name}: error: out of memory: the input, or a size asked for, is too large for this "
            f"machine's memory")
        return 2
    except Terminated:
        err(f"{name}: terminated")
        return 143  # 128 + SIGTERM
    except KeyboardInterrupt:
        err(f"{name}: interrupted")
        return 130


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the command is, so that it unwinds as an interrupt does: every
    file being written is removed (:func:`roughgp.common.atomic.atomic_output`)."""


def _raise_terminated(signum, frame):
    raise Terminated()


@contextlib.contextmanager
def _terminate_as_interrupt():
    """SIGTERM raises :class:`Terminated` while the command runs (in the main thread; the
    previous handler restored after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


#: commands that load no SciPy BLAS of their own first (each saves its 0.2 s import)
_QUICK_COMMANDS = ("simulate", "texture")

#: why a command refuses the operator options: it takes them from the model file
_OPERATORS_OF_THE_MODEL = {
    "check": "; check applies the operators (form, S- and L-filter) stated in MODEL.json"}


def _silence_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's final flush into the closed pipe
    prints nothing either."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # pragma: no cover - stdout not a file
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
