"""Benchmark of the command line's start-up (issue 32: "``roughgp --help`` under 0.5 s,
``roughgp texture data/opd-1.opd`` under 2 s on this machine").

Each case runs the whole command as a subprocess of this interpreter (``python -m
roughgp.cli.main ...``: interpreter start-up, imports, the work, output to /dev/null) and
measures its wall time, ``--repeats`` times; it prints the fastest and the median, the target
(for ``simulate`` the target is the draw's own time, the "drawn in" it prints: the issue's
"simulate honed --shape 64 64 under 1 s"), and which heavy packages the command imported (from ``python -X importtime``, run once more),
with the seconds their imports took. Not a test: run it by hand at the repository root,

    python benchmarks/cli_startup.py                 # 5 repeats of each case
    python benchmarks/cli_startup.py --repeats 11
    python benchmarks/cli_startup.py --against /tmp/base   # another revision, side by side

``SurfaceTopography`` in the last column is its whole package (all readers, pandas,
matplotlib, ...); ``SurfaceTopography.IO.Reader`` alone is the one-reader path of
:mod:`roughgp.metrology.instrument_readers` (an ``.opd`` needs no more).

The machine's load shows in the figures (it prints the 1-minute load average): compare the
fastest times across runs on a busy machine.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: (the command's arguments, the target in seconds)
CASES = (
    (["--help"], 0.5),
    (["simulate", "--help"], 0.5),
    (["texture", "data/opd-1.opd"], 2.0),
    (["texture", "data/sample-land.x3p"], 2.0),
    (["simulate", "honed", "--shape", "64", "64", "--seed", "1", "--out", "{tmp}/h.npy",
      "--force"], 1.0),
)

#: the packages whose import a person would notice (seconds each on the 2-core machine)
HEAVY = ("torch", "gpytorch", "SurfaceTopography", "SurfaceTopography.IO.Reader", "scipy.signal",
         "scipy.stats", "scipy.optimize", "scipy.ndimage", "pandas", "matplotlib", "x3pio")


def _command(arguments, tmp) -> list[str]:
    return [sys.executable, "-m", "roughgp.cli.main",
            *(a.replace("{tmp}", str(tmp)) for a in arguments)]


def _environment(root=ROOT) -> dict:
    return {**os.environ, "PYTHONPATH": str(root), "OMP_NUM_THREADS": "1"}


def wall_time(arguments, tmp, root=ROOT) -> tuple[float, float | None]:
    """Seconds the command takes, start to exit, and the draw's own seconds where it prints
    them (``simulate``: "drawn in X s"); raises if it fails."""
    start = time.perf_counter()
    done = subprocess.run(_command(arguments, tmp), cwd=root, env=_environment(root), check=True,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    drawn = re.search(r"drawn in ([0-9.]+) s", done.stderr)
    return seconds, (float(drawn.group(1)) if drawn else None)


def heavy_imports(arguments, tmp) -> dict:
    """The packages of :data:`HEAVY` the command imports, with their cumulative import
    seconds (``python -X importtime``)."""
    done = subprocess.run([sys.executable, "-X", "importtime", *_command(arguments, tmp)[1:]],
                          cwd=ROOT, env=_environment(), capture_output=True, text=True)
    found = {}
    for line in done.stderr.splitlines():
        if not line.startswith("import time:"):
            continue
        _, cumulative, name = line.split("|")  # "import time: self | cumulative | name"
        name = name.strip()
        if name in HEAVY and cumulative.strip().isdigit():
            found[name] = int(cumulative) / 1e6
    return found


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs of each case (default 5)")
    parser.add_argument("--against", metavar="DIR",
                        help="also time another revision's tree (its roughgp/ and data/, e.g. "
                             "git archive b6154c1 roughgp data | tar -x -C DIR), its runs "
                             "interleaved with these so that both see the same load")
    args = parser.parse_args(argv)
    if args.against is not None and not (Path(args.against) / "roughgp").is_dir():
        parser.error(f"--against {args.against}: no roughgp/ folder there")
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores, load average "
              f"{os.getloadavg()[0]:.2f}; {args.repeats} runs per case")
        print(f"{'command':<52} {'fastest':>8} {'median':>8} {'target':>7}  heavy imports (s)")
        for arguments, target in CASES:
            runs, others = [], []
            for _ in range(args.repeats):
                runs.append(wall_time(arguments, tmp))
                if args.against is not None:
                    others.append(wall_time(arguments, tmp, Path(args.against).resolve()))
            times = [seconds for seconds, _ in runs]
            drawn = [d for _, d in runs if d is not None]
            heavy = heavy_imports(arguments, tmp)
            label = "roughgp " + " ".join(a.replace("{tmp}/", "") for a in arguments)
            measured = min(drawn) if drawn else min(times)  # simulate: the target is the draw's
            verdict = "ok" if measured < target else "OVER"
            verdict += f" (the draw: fastest {min(drawn):.2f}s)" if drawn else ""
            imports = ", ".join(f"{k} {v:.2f}" for k, v in heavy.items()) or "none"
            print(f"{label[:52]:<52} {min(times):>7.2f}s {statistics.median(times):>7.2f}s "
                  f"{target:>6.1f}s  {verdict}; {imports}")
            if others:
                seconds = [t for t, _ in others]
                drawn = [d for _, d in others if d is not None]
                draw = f" (the draw: fastest {min(drawn):.2f}s)" if drawn else ""
                print(f"{'  the same, ' + args.against:<52} {min(seconds):>7.2f}s "
                      f"{statistics.median(seconds):>7.2f}s{draw}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
