"""What the commands share: the usage error, messages on stderr, plain-text tables, JSON and
the checks of output paths. Argument handling and presentation only; no computation."""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import sys
import textwrap
from pathlib import Path

from roughgp.common.atomic import atomic_output, longest_name
from roughgp.common.json_values import plain
from roughgp.io.writers import check_write_format

__all__ = ["UsageError", "WIDTH", "err", "show_warning", "wrap", "print_wrapped", "table",
           "refused_by", "print_operators",
           "write_json", "check_output", "check_outputs", "add_force_option",
           "check_device", "describe_groove", "shell_message", "rename_parameters"]

WIDTH = 100  # the plain-text tables are laid out for a 100-column terminal


class UsageError(Exception):
    """A user error: reported as ``roughgp CMD: error: MESSAGE``, exit code 2."""


_NUMPY_REPR = re.compile(r"\bnp\.(?:float|int|uint|complex)\d*\(([^()]*)\)|\bnp\.(True|False)_")


def _sampler_advice(args, message) -> str:
    if getattr(args, "method", None) is not None and getattr(args, "kind", None) in (
            "ground", "honed"):
        lengths = " (--lambda-a, --lambda-b)" if args.kind == "ground" else ""
        return (f" Give a smaller --shape, shorter correlation lengths{lengths}, or --method "
                "cholesky on a grid of a few thousand points.")
    return " Give a smaller --shape (or a model with shorter correlation lengths)."


def _plane_advice(args, message) -> str:
    ways = (["--form none (no F-operator)"] if hasattr(args, "form") else []) + (
        ["--kind profile (a one-row map read as a profile)"]
        if getattr(args, "kind", None) in ("auto", "surface", "profile") else [])
    return ("; give " + " or ".join(ways)) if ways else \
        ": give a map with at least 2 measured rows and columns"


def _block_advice(args, message) -> str:
    if message.startswith("--spurious") or not hasattr(args, "block"):
        return ("; --spurious fits the GP on such blocks: crop the map to a part with fewer "
                "holes, or leave out --spurious")
    return "; give a smaller --block (at least 4)"


#: The library's advice of its own keyword arguments, and what a shell user can do instead:
#: (pattern, advice of the command ``args`` ran and the message).
_LIBRARY_ADVICE = (
    (re.compile(r"\s*Use approximate=True to clip .*?method='cholesky'\."), _sampler_advice),
    (re.compile(r"; use order=0 or level rows / columns as profiles"), _plane_advice),
    (re.compile(r"; use a smaller block or a lower min_valid"), _block_advice),
)


def shell_message(message: str, args=None) -> str:
    """A library error's message for a shell user: numpy scalar reprs (``np.float64(1.0)``)
    as plain numbers, and advice of keyword arguments (``approximate=True``,
    ``method='cholesky'``, ``order=0``, ``min_valid``) replaced by the options of the command
    ``args`` ran (never one it does not have)."""
    message = _NUMPY_REPR.sub(lambda m: m.group(1) if m.group(1) is not None else m.group(2),
                              message)
    for pattern, advice in _LIBRARY_ADVICE:
        if pattern.search(message):
            message = pattern.sub(lambda m: advice(args, message), message)
    return message


def rename_parameters(message: str, names: dict) -> str:
    """``message`` with the library's parameter names (whole words, the keys of ``names``)
    replaced by the command's options (the values)."""
    if not names:
        return message
    words = "|".join(map(re.escape, sorted(names, key=len, reverse=True)))
    return re.sub(rf"(?<![\w.-])({words})(?![\w(-])", lambda m: names[m.group(1)], message)


def err(message: str) -> None:
    """Print ``message`` on stderr (progress, notes, warnings: stdout keeps the results); the
    bytes of a file name that is not UTF-8 as ``\\xNN`` where the stream is strict."""
    try:
        print(message, file=sys.stderr, flush=True)
    except UnicodeEncodeError:
        print(message.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace"),
              file=sys.stderr, flush=True)


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Library warnings as one line on stderr (``warning: ...``), without source lines."""
    err(f"warning: {message}")


def wrap(text: str, width: int) -> list[str]:
    """``text`` wrapped to ``width`` columns (at least one line)."""
    return textwrap.wrap(str(text), width, break_on_hyphens=False) or [""]


def print_wrapped(text: str, indent: str = "  ") -> None:
    """Print ``text`` wrapped to :data:`WIDTH`, indented."""
    print(textwrap.fill(text, WIDTH, initial_indent=indent, subsequent_indent=indent + "  ",
                        break_on_hyphens=False))


@contextlib.contextmanager
def refused_by(source):
    """Report a library's ``ValueError`` (a refused input) as a :class:`UsageError` prefixed
    with ``source`` (the file or files it concerns): exit 2, no traceback."""
    try:
        yield
    except ValueError as exc:
        raise UsageError(f"{source}: {exc}") from None


def print_operators(model) -> None:
    """The fitted model's chain of operators, and what its heights are."""
    print_wrapped(f"operators: {'; '.join(model.operators)} (the model describes the heights "
                  f"after the F-operator; the filters are applied to its simulations)")


def table(rows: list[tuple], widths: tuple[int, ...], header: tuple) -> str:
    """A plain-text table; each cell wrapped to its column's width."""
    lines = []
    for row in [header, tuple("-" * w for w in widths)] + rows:
        cells = [wrap(c, w) for c, w in zip(row, widths)]
        for k in range(max(len(c) for c in cells)):
            parts = [(c[k] if k < len(c) else "").ljust(w) for c, w in zip(cells, widths)]
            lines.append("  ".join(parts).rstrip())
    return "\n".join(lines)


def write_json(path_text: str, record: dict) -> None:
    """Write ``record`` as JSON to the file named, whole or not at all (numpy scalars as
    numbers, NaN as null); says which file it wrote."""
    path = Path(path_text)
    text = json.dumps(plain(record), indent=1) + "\n"
    with atomic_output(path) as partial:
        partial.write_text(text, encoding="utf-8")
    err(f"wrote {path}")


def check_output(path_text: str, option: str = "--out") -> Path:
    """The path of an output file of a format that roughgp writes; a usage error naming
    ``option`` otherwise."""
    try:
        return check_write_format(path_text)
    except ValueError as exc:
        raise UsageError(f"{option}: {exc}") from None


def _same_file(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    try:
        return a.resolve() == b.resolve()
    except (OSError, RuntimeError):  # a symbolic link loop: compare the names as given
        return os.path.abspath(a) == os.path.abspath(b)


def _check_writable(path: Path, option: str) -> None:
    """A usage error unless ``path`` can be written: its folder (or the nearest existing one
    above it, where it is made) is a writable directory, and its name leaves room for the
    temporary name it is written through (:func:`roughgp.common.atomic.longest_name`)."""
    size, most = len(os.fsencode(path.name)), longest_name(path)
    if size > most:
        raise UsageError(f"{option}: the file name is {size} bytes long; roughgp writes it "
                         f"through a longer temporary name, so give a name of at most {most} "
                         f"bytes")
    if path.exists():
        if not path.is_file():
            raise UsageError(f"{option}: {path} exists and is not a file")
        if not os.access(path, os.W_OK):
            raise UsageError(f"{option}: {path} is not writable")
        return
    folder = path.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise UsageError(f"{option}: cannot write {path}: {folder} is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(f"{option}: cannot write {path}: the directory {folder} is not "
                         "writable")


PLOT_FORMATS = (".png", ".pdf", ".svg")


def check_outputs(*outputs, inputs=(), force=False) -> list:
    """The output-path rule of every command, applied before it computes anything.

    ``outputs``: ``(option, path text or None, kind)`` (every file the command writes, in
    one call, so that each is checked against every other), where ``kind`` is ``"heights"`` (a
    format of :data:`roughgp.io.writers.WRITE_FORMATS`, by the extension) or
    ``"json"`` (the extension must be ``.json``) or ``"plot"`` (:data:`PLOT_FORMATS`).

    The rule: the file written is the file named, letter for letter (the writers add no
    extension: ``--out H.NPY`` writes ``H.NPY``), so the checks below look at the file that
    will be written. A usage error naming the option refuses an output that is one of
    ``inputs`` (``(option, path text or None)`` pairs, e.g. ``("FILE", args.file)``, or bare
    path texts; never written over, even with ``--force``; the message names both), two
    options naming one file, an
    existing file without ``force`` (``--force``), and a place that cannot be written: the
    nearest existing folder above the file must be a writable directory. Missing folders
    are made when the file is written, by every command alike. Each file is then written
    whole or not at all (:func:`roughgp.common.atomic.atomic_output`) and the command
    says ``wrote PATH`` with this path.
    Returns the paths (None for an option not given), in order.
    """
    paths, given = [], []
    for option, text, kind in outputs:
        if text is None:
            paths.append(None)
            continue
        if kind == "json":
            path = Path(text)
            if path.suffix.lower() != ".json":
                raise UsageError(f"{option}: this command writes JSON: give a file name "
                                 f"ending in .json, got {text!r}")
        elif kind == "plot":
            path = Path(text)
            if path.suffix.lower() not in PLOT_FORMATS:
                raise UsageError(f"{option}: a figure is written as "
                                 f"{', '.join(PLOT_FORMATS)}: got {text!r}")
        else:
            path = check_output(text, option)
        for name, source in _named(inputs):
            if _same_file(path, Path(source)):
                raise UsageError(f"{option}: {path} is the input file ({name}); roughgp never "
                                 f"writes over its input, even with --force: give {option} "
                                 "another file name")
        for other, earlier in given:
            if _same_file(path, earlier):
                raise UsageError(f"{option} and {other} name the same file {path}: give two "
                                 "file names")
        if path.exists() and path.is_file() and not force:
            raise UsageError(f"{option}: {path} exists; give --force to write over it, or "
                             "another file name")
        _check_writable(path, option)
        given.append((option, path))
        paths.append(path)
    return paths


def _named(inputs):
    """``(option, path text)`` of each input given: ``inputs`` holds pairs or bare texts (named
    ``the input``)."""
    for item in inputs:
        name, source = item if isinstance(item, tuple) else ("the input", item)
        if source is not None:
            yield name, source


def add_force_option(parser) -> None:
    """``--force``: the option that lets a command write over an existing file."""
    parser.add_argument("--force", action="store_true",
                        help="write over existing output files (never over the input)")


def check_device(device, option: str = "--device") -> None:
    """A usage error naming ``option`` unless ``device`` is None or a usable torch device."""
    if device is None:
        return
    from roughgp.common.device import resolve
    try:
        resolve(device, name=option)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def describe_groove(step) -> str:
    """The eq 18 hyperparameters of ``step`` in words, with units."""
    return (f"variance {step.variance:g} um^2, lambda_a {step.lengthscales[0]:g} um, "
            f"lambda_b {step.lengthscales[1]:g} um, angle {math.degrees(step.angle):g} deg")

