"""The bounds of every numeric option of every command, in one table (:data:`BOUNDS`), quoted
by the options' help and checked before a command runs, and the fit's ``--block`` against the
map read. Argument handling only.
"""

from __future__ import annotations

import argparse
import dataclasses
import math

from roughgp.cli.output import UsageError

__all__ = ["Bound", "BOUNDS", "bounds_text", "check_bounds", "check_block", "integer"]


@dataclasses.dataclass(frozen=True)
class Bound:
    """The allowed range ``[low, high]`` of a numeric option, in ``unit``."""

    low: float
    high: float
    unit: str = ""

    def numbers(self, joint: str) -> str:
        """The two ends, integers as integers: ``"4 to 32"``, ``"1e-06, 1e+06"``."""
        return joint.join(f"{v}" if isinstance(v, int) else f"{v:g}"
                          for v in (self.low, self.high))

    def text(self) -> str:
        """``"4 to 32"``, ``"1e-06 to 1e+06 um"``: the range as the help states it."""
        return self.numbers(" to ") + (f" {self.unit}" if self.unit else "")


#: Every bounded numeric option of every command, checked by :func:`check_bounds` before the
#: command runs and quoted by its ``--help`` (:func:`bounds_text`). The work-bound ranges
#: were measured on the 2-core reference machine (2026-12-02): a fit of eq 18 costs about
#: block^6 (a dense likelihood of block^2 points per block and step); ``check`` simulates and
#: measures the map once per simulation. Lengths: a picometre to a metre.
BOUNDS = {
    "--seed": Bound(0, 2**32 - 1),
    "--spacing": Bound(1e-6, 1e6, "um"),
    "--s-filter": Bound(1e-6, 1e6, "um"),
    "--l-filter": Bound(1e-6, 1e6, "um"),
    "--feed": Bound(1e-6, 1e6, "um"),
    "--degree": Bound(1, 10),
    "--channel": Bound(0, 255),
    "--mixtures": Bound(1, 50),
    "--candidates": Bound(1, 200),
    "--block": Bound(4, 32),
    "--blocks": Bound(1, 200),
    "--simulations": Bound(2, 99),
    "--calibrate": Bound(1, 99),
    "--predictive": Bound(1, 99),
    "--samples": Bound(2, 256),
    "--workers": Bound(1, 256),
}


def bounds_text(option: str) -> str:
    """The range of ``option`` for its help: ``"4 to 32"``."""
    return BOUNDS[option].text()


#: the most digits an integer option is read with (Python's int() refuses over 4300 with a
#: message of its own limit; no option's range needs more than 10)
MAX_DIGITS = 30


def integer(option=None):
    """The argparse type of an integer option: ``int(text)``, refused by its length beyond
    :data:`MAX_DIGITS` digits, with the option's range (:data:`BOUNDS`) where it has one."""
    def parse(text):
        digits = text.strip().lstrip("+-")
        if len(digits) > MAX_DIGITS and digits.isdigit():
            bound = BOUNDS.get(option)
            allowed = f"give one in [{bound.numbers(', ')}]" if bound else "give a smaller one"
            raise argparse.ArgumentTypeError(f"an integer of {len(digits)} digits is out of "
                                             f"range: {allowed}")
        try:
            return int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text[:40]!r}") \
                from None
    parse.__name__ = "integer"  # argparse names the type in its messages
    return parse


def check_bounds(args) -> None:
    """Each option of :data:`BOUNDS` that the command has and was given a number: within its
    range, or a :class:`UsageError` naming the option and the range (before any work)."""
    for option, bound in BOUNDS.items():
        value = getattr(args, option.lstrip("-").replace("-", "_"), None)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue  # not this command's, not given, or a word (auto, none)
        if not (math.isfinite(value) and bound.low <= value <= bound.high):
            unit = f" {bound.unit}" if bound.unit else ""
            raise UsageError(f"{option} must be in [{bound.numbers(', ')}]{unit}, got "
                             f"{value:g}")


def check_block(path, block: int, shape) -> None:
    """The eq 18 block fit's ``--block`` against the map: at least 4 points along each axis,
    and a block that fits in it; a :class:`UsageError` says what to give instead."""
    side = min(shape)
    if side < 4:
        raise UsageError(f"{path} is {' x '.join(map(str, shape))} points: the eq 18 fit works "
                         f"on blocks of at least 4 x 4 points, so the map needs at least 4 "
                         f"points along each axis")
    if block > side:
        low, high = BOUNDS["--block"].low, BOUNDS["--block"].high
        raise UsageError(f"--block {block} exceeds the shorter side of {path} ({side} points): "
                         f"give --block {low} to {min(side, high)}")
