"""Issue 44 part 2, "unclear messages": each names the option or field and says what to change,
and suggests no option the command does not have."""

from __future__ import annotations

import argparse
import math

import numpy as np

from roughgp.cli.output import shell_message
from roughgp.sampling.truncation import too_large_error
from cli_run import run as _run


def test_a_correlation_too_long_for_any_torus_names_the_options():
    """``simulate ground --shape 4096 4096 --lambda-a 5000`` said "most negative nan x r(0) ...
    tried []" (40 s to reach; the message is built here as the sampler builds it)."""
    error = too_large_error((4096, 4096), (1.0, 1.0), math.nan, math.nan, 1e-10, None, [],
                            (18816, 177408), 134217728)
    args = argparse.Namespace(method="auto", kind="ground")
    message = shell_message(str(error), args)
    assert "nan" not in message and "tried []" not in message
    assert "no torus could be tried" in message and "(18816, 177408)" in message
    assert "--lambda-a" in message and "--shape" in message and "approximate=" not in message
