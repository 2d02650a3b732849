"""How long ``import roughgp`` takes (the verbs without numpy or torch; issue 39: under 0.5 s),
in fresh interpreters, the fastest and the median of ``--repeat`` runs. Not a test: run it by
hand at the repository root, ``.venv/bin/python benchmarks/import_time.py``."""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PROBE = ("import time, sys; t = time.perf_counter(); import roughgp; "
         "print(time.perf_counter() - t, 'torch' in sys.modules, 'numpy' in sys.modules)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args(argv)
    seconds = []
    for _ in range(args.repeat):
        out = subprocess.run([sys.executable, "-c", PROBE], cwd=ROOT, capture_output=True,
                             text=True, check=True).stdout.split()
        seconds.append(float(out[0]))
        torch, numpy = out[1] == "True", out[2] == "True"
    print(f"import roughgp: fastest {min(seconds) * 1e3:.1f} ms, median "
          f"{statistics.median(seconds) * 1e3:.1f} ms over {args.repeat} fresh interpreters; "
          f"torch imported: {torch}, numpy imported: {numpy}")
    return 0 if max(seconds) < 0.5 and not torch else 1


if __name__ == "__main__":
    sys.exit(main())
