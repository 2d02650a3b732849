"""The speed targets of the models of the surface (issue 40), timed as a user runs them:

* ``roughgp fit ground MAP --model auto`` on a 512 x 512 map (target: under 120 s);
* ``roughgp simulate --from FIELD.json --shape 1024 1024``: a non-stationary draw (eq18-field,
  fitted with ``--model field --anchors 4 4`` on a 256 x 256 map; target: under 20 s);
* ``roughgp check MODEL MAP --predictive 9`` on 256 x 256 (target: under 60 s), and the same
  with ``--held-out`` (both halves checked: about twice the work);
* the same held-out check of a model fitted by ``--likelihood whittle``: its predictive
  simulations from 9 Whittle refits, and from 19 parameter sets of its sandwich covariance
  (``--predictive-from sandwich``, no refits), side by side.

The maps are eq 18 surfaces drawn by ``roughgp simulate ground`` (seed 1), written to a
temporary folder. Each command runs once, in series, in a fresh process (its start-up counted);
the wall seconds, the target and the machine's load before each are printed. Not a test (the
machine may be busy: a timed test would flip with it); run by hand on a quiet machine,

    python benchmarks/surface_model_speed.py            # about 5 minutes on 2 cores
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROUGHGP = str(Path(sys.executable).with_name("roughgp"))


def timed(*argv) -> float:
    """Wall seconds of ``roughgp ARGV`` (its output kept quiet; a failure ends the run)."""
    start = time.perf_counter()
    done = subprocess.run([ROUGHGP, *map(str, argv)], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"roughgp {' '.join(map(str, argv))} failed:\n{done.stderr}")
    return seconds


def main() -> int:
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        for side in (256, 512):
            timed("simulate", "ground", "--shape", side, side, "--lambda-a", 20, "--lambda-b",
                  8, "--spacing", 1, "--seed", 1, "--out", tmp / f"map{side}.x3p")
        cases = [
            ("fit ground --model auto, 512 x 512", 120,
             ("fit", "ground", tmp / "map512.x3p", "--model", "auto", "--out",
              tmp / "auto.json")),
            ("fit ground --model field --anchors 4 4, 256 x 256 (setup)", None,
             ("fit", "ground", tmp / "map256.x3p", "--model", "field", "--anchors", 4, 4,
              "--out", tmp / "field.json")),
            ("simulate --from field.json --shape 1024 1024", 20,
             ("simulate", "--from", tmp / "field.json", "--shape", 1024, 1024, "--seed", 2,
              "--out", tmp / "field1024.x3p")),
            ("fit ground --part left, 256 x 256 (setup)", None,
             ("fit", "ground", tmp / "map256.x3p", "--part", "left", "--out",
              tmp / "left.json")),
            ("check --predictive 9, 256 x 256", 60,
             ("check", tmp / "left.json", tmp / "map256.x3p", "--predictive", 9)),
            ("check --held-out --predictive 9, 256 x 256 (both halves)", None,
             ("check", tmp / "left.json", tmp / "map256.x3p", "--held-out", "--predictive",
              9)),
            ("fit ground --part left --likelihood whittle, 256 x 256 (setup)", None,
             ("fit", "ground", tmp / "map256.x3p", "--part", "left", "--likelihood", "whittle",
              "--out", tmp / "left-whittle.json")),
            ("check --held-out --predictive 9 (Whittle refits), 256 x 256", None,
             ("check", tmp / "left-whittle.json", tmp / "map256.x3p", "--held-out",
              "--predictive", 9)),
            ("check --held-out --predictive 19 --predictive-from sandwich, 256 x 256", 60,
             ("check", tmp / "left-whittle.json", tmp / "map256.x3p", "--held-out",
              "--predictive", 19, "--predictive-from", "sandwich")),
        ]
        for name, target, argv in cases:
            load = os.getloadavg()[0]
            seconds = timed(*argv)
            verdict = "" if target is None else ("met" if seconds < target else "NOT met")
            rows.append((name, seconds, target, load, verdict))
            print(f"{name}: {seconds:.1f} s" + (f" (target {target} s: {verdict})"
                                                 if target else "") + f", load {load:.1f}",
                  flush=True)
    print()
    print("| command | seconds | target | load before | |")
    print("|---|---|---|---|---|")
    for name, seconds, target, load, verdict in rows:
        print(f"| `{name}` | {seconds:.1f} | {'' if target is None else f'< {target}'} | "
              f"{load:.1f} | {verdict} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
