"""Benchmark of the samplers of roughgp.sampling against the classic FFT filter.

Prints a table: wall time per sample (each call draws two) and peak memory (max RSS of a fresh process per case) of each
method against the grid size, for eq 18 with figure 2's hyperparameters, side by side in one
run, and the ratios the sampling issue sets as targets. Not a test: run it by hand,

    python benchmarks/sampling.py            # up to 2048^2 (a few minutes on 2 cores)
    python benchmarks/sampling.py --full     # also 4096^2 exactly (float32 FFTs)
    python benchmarks/sampling.py --sizes 2000 4096   # only these grids (circulant, FFT filter)
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time

CASE = r'''
import json, math, resource, sys, time
import numpy as np
from roughgp.sampling import fft_filter
from roughgp.gp import kernels
from roughgp import sampling
method, n, dtype, draws = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
kernel = kernels.RotatedExponentialKernel(variance=10.0, lengthscales=(500.0, 5.0), angle=math.pi / 6)
times = []
info = None
per_call = 2  # circulant: one complex FFT gives two samples; times are per sample
for k in range(draws):
    start = time.perf_counter()
    if method == "fft_filter":
        fft_filter.fft_filter(kernel.psd, (n, n), n_samples=per_call, seed=k)
    else:
        _, info = sampling.sample_grid(kernel, (n, n), method=method, seed=k, rank=100,
                                       n_samples=per_call, dtype=np.dtype(dtype), return_info=True)
    times.append((time.perf_counter() - start) / per_call)
print(json.dumps({"times": times, "peak_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
                  "torus": getattr(info, "torus_shape", None), "cached": getattr(info, "cached", None)}))
'''


def run(method, n, dtype="float64", draws=2):
    out = subprocess.run([sys.executable, "-c", CASE, method, str(n), dtype, str(draws)],
                         capture_output=True, text=True)
    if out.returncode:
        return {"error": out.stderr.strip().splitlines()[-1][:120]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="also 4096 x 4096")
    parser.add_argument("--sizes", type=int, nargs="+", help="only these grid sizes n (n x n)")
    args = parser.parse_args()
    sizes = [32, 64, 100, 128, 256, 512, 1024, 2000, 2048] + ([4096] if args.full else [])
    sizes = args.sizes or sizes
    dense = [n for n in (32, 64, 100) if n in sizes]
    plan = {"cholesky": dense, "lanczos": dense, "circulant": sizes, "fft_filter": sizes}
    rows = []
    print("seconds per sample: 'first' includes set-up (factorisation / embedding search), "
          "'next' is a second call on the same kernel and grid")
    print(f"{'method':12s} {'grid':>11s} {'first s':>9s} {'next s':>8s} {'peak GiB':>9s}  torus")
    for method, ns in plan.items():
        for n in ns:
            dtype = "float32" if (method == "circulant" and n >= 4096) else "float64"
            r = run(method, n, dtype)
            rows.append((method, n, r))
            if "error" in r:
                print(f"{method:12s} {n:5d}x{n:<5d} {r['error']}")
                continue
            print(f"{method:12s} {n:5d}x{n:<5d} {r['times'][0]:9.2f} {r['times'][-1]:8.2f} "
                  f"{r['peak_gib']:9.2f}  {r['torus'] or ''}{' (' + dtype + ')' if dtype != 'float64' else ''}",
                  flush=True)
    table = {(m, n): r for m, n, r in rows}
    print("\nTargets (ratios measured in this run):")
    for n in (2000, 2048):
        c, f = table.get(("circulant", n)), table.get(("fft_filter", n))
        if c and f and "error" not in c and "error" not in f:
            print(f"  {n}^2: circulant first draw / FFT filter = {c['times'][0] / f['times'][-1]:.1f}x "
                  f"(target <= 40x); cached draw / FFT filter = {c['times'][-1] / f['times'][-1]:.1f}x "
                  f"(target <= 10x); peak {c['peak_gib']:.2f} GiB (target < 4 GiB)")
    c = table.get(("circulant", 4096))
    if c and "error" not in c:
        print(f"  4096^2 exact (float32 FFTs): peak {c['peak_gib']:.2f} GiB (target < 12 GiB)")
    ch, ci = table.get(("cholesky", 100)), table.get(("circulant", 100))
    if ch and ci and "error" not in ch and "error" not in ci:
        print(f"  100^2: Cholesky {ch['times'][0]:.1f} s vs circulant first draw {ci['times'][0]:.1f} s "
              f"(auto picks the cheaper: see sampling.choose_method)")


if __name__ == "__main__":
    main()
