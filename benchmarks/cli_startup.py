"""Benchmark of the command line's start-up (issue 32: "``roughgp --help`` under 0.5 s,
``roughgp texture data/opd-1.opd`` under 2 s on this machine").

Each case runs the whole command as a subprocess of this interpreter (``python -m
roughgp.cli.main ...``: interpreter start-up, imports, the work, output to /dev/null) and
measures its wall time, ``--repeats`` times; it prints the fastest and the median, for
``simulate`` also of the draw's own time (the "drawn in" it prints), the target (the issue's
"simulate honed --shape 64 64 under 1 s" read both ways: the whole command and the draw),
whether the median meets it, the 1-minute load average during the case, and which heavy
packages the command imported (from ``python -X importtime``, run once more), with the
seconds their imports took. Not a test: run it by hand at the repository root,

    python benchmarks/cli_startup.py                 # 5 repeats of each case
    python benchmarks/cli_startup.py --repeats 11 --targets     # the issue's three targets
    python benchmarks/cli_startup.py --against /tmp/base   # another revision, side by side

``SurfaceTopography`` in the last column is its whole package (all readers, pandas,
matplotlib, ...); ``SurfaceTopography.IO.Reader`` alone is the one-reader path of
:mod:`roughgp.io.instrument_readers` (an ``.opd`` needs no more).

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

#: the issue's three targets (the arguments of their CASES)
TARGETS = (CASES[0][0], CASES[2][0], CASES[4][0])

#: the packages whose import a person would notice (seconds each on the 2-core machine)
HEAVY = ("torch", "gpytorch", "SurfaceTopography", "SurfaceTopography.IO.Reader", "scipy.signal",
         "scipy.stats", "scipy.optimize", "scipy.ndimage", "pandas", "matplotlib", "x3pio")


def _command(arguments, tmp) -> list[str]:
    return [sys.executable, "-m", "roughgp.cli.main",
            *(a.replace("{tmp}", str(tmp)) for a in arguments)]


def _environment(root=ROOT) -> dict:
    """The caller's environment (its thread settings too: a command runs as a user runs it;
    pinning OMP_NUM_THREADS=1 here hid a slowdown of the default two BLAS threads)."""
    return {**os.environ, "PYTHONPATH": str(root)}


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


def _summary(runs) -> str:
    """``fastest median`` of the wall times, and of the draw's own times where printed."""
    times = [seconds for seconds, _ in runs]
    drawn = [d for _, d in runs if d is not None]
    text = f"{min(times):.2f} {statistics.median(times):.2f}"
    if drawn:
        text += f" (draw {min(drawn):.2f} {statistics.median(drawn):.2f})"
    return f"{text:<25}"


def _verdict(runs, target) -> str:
    """Whether the median wall time (and, for ``simulate``, the median draw) is under target."""
    times = [seconds for seconds, _ in runs]
    drawn = [d for _, d in runs if d is not None]
    verdict = "ok" if statistics.median(times) < target else "OVER"
    if drawn:
        verdict = (f"wall {verdict}, draw "
                   f"{'ok' if statistics.median(drawn) < target else 'OVER'}")
    return verdict


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs of each case (default 5)")
    parser.add_argument("--against", metavar="DIR",
                        help="also time another revision's tree (its roughgp/ and data/, e.g. "
                             "git archive 5cc80b4 roughgp data | tar -x -C DIR), its runs "
                             "interleaved with these so that both see the same load; printed "
                             "side by side")
    parser.add_argument("--targets", action="store_true",
                        help="only the issue's three targets: --help, texture data/opd-1.opd, "
                             "simulate honed --shape 64 64")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be >= 1, got {args.repeats}")
    if args.against is not None and not (Path(args.against) / "roughgp").is_dir():
        parser.error(f"--against {args.against}: no roughgp/ folder there")
    cases = [c for c in CASES if not args.targets or c[0] in TARGETS]
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        threads = os.environ.get("OMP_NUM_THREADS", "unset")
        print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores, OMP_NUM_THREADS="
              f"{threads}; "
              f"{args.repeats} runs per case; times: fastest, median (wall, and simulate's "
              f"own draw)")
        header = f"{'command':<56} {'this tree (s)':<25}"
        if args.against is not None:
            header += f" {args.against + ' (s)':<25}"
        print(header + " target  verdict (median)    load  heavy imports (s)")
        for arguments, target in cases:
            runs, others = [], []
            load = os.getloadavg()[0]
            for _ in range(args.repeats):
                runs.append(wall_time(arguments, tmp))
                if args.against is not None:
                    others.append(wall_time(arguments, tmp, Path(args.against).resolve()))
            load = (load + os.getloadavg()[0]) / 2
            heavy = heavy_imports(arguments, tmp)
            label = "roughgp " + " ".join(a.replace("{tmp}/", "") for a in arguments
                                          if a != "--force")
            imports = ", ".join(f"{k} {v:.2f}" for k, v in heavy.items()) or "none"
            line = f"{label[:56]:<56} {_summary(runs)}"
            if others:
                line += f" {_summary(others)}"
            print(f"{line} {target:>5.1f}s  {_verdict(runs, target):<18} {load:>5.2f}  "
                  f"{imports}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
