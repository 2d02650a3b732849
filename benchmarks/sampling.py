"""Benchmark of the samplers of roughgp.sampling against the FFT filter and SurfaceTopography.

Prints, in one run, for figure 2 (eq 18: sigma_k^2 = 10, lambda_a = 500, lambda_b = 5,
phi = pi/6 on 2000 x 2000 points) and for a short-range kernel (eq 18 with lengthscales 20, 20
on 2048 x 2048): the numpy FFT filter (approximate, periodic), SurfaceTopography's
``fourier_synthesis`` (isotropic only: for figure 2 a self-affine PSD of the same size, timing
only) and every roughgp method (``auto``; ``circulant`` with the smooth truncation, float64 and
float32 FFTs; the plain wrap ``truncation="none"``; ``cholesky`` and ``lanczos``, which refuse
these sizes). Per case, in a fresh process: the first draw (set-up and search included), the
next draw, the time per draw in a batch of 4, the peak memory (max RSS) and the torus; then the
ratios to the FFT filter (next draw over its next draw, batch over its batch) and the targets of the sampling issue. Not a test: run it by hand,

    python benchmarks/sampling.py            # both cases, ~2 minutes on 2 cores
    python benchmarks/sampling.py --quick    # no plain wrap of figure 2 (the slow old one)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CASE = r'''
import json, math, resource, sys, time
import numpy as np
from roughgp import sampling
from roughgp.gp import kernels
from roughgp.sampling import fft_filter
method, case = sys.argv[1], sys.argv[2]
if case == "figure2":
    kernel, n = kernels.RotatedExponentialKernel(10.0, (500.0, 5.0), math.pi / 6), 2000
else:
    kernel, n = kernels.RotatedExponentialKernel(10.0, (20.0, 20.0), 0.0), 2048

def st_psd(q):  # the isotropic exponential's PSD in SurfaceTopography's q = 2 pi f
    return 2 * math.pi * 10.0 * 20.0**2 / (1 + (20.0 * q) ** 2) ** 1.5

def once(n_samples, seed):
    info = None
    if method == "fft_filter":
        fft_filter.fft_filter(kernel.psd, (n, n), n_samples=n_samples, seed=seed)
    elif method == "surface_topography":
        from SurfaceTopography.Generation import fourier_synthesis
        rng = np.random.default_rng(seed)
        for _ in range(n_samples):
            if case == "figure2":
                fourier_synthesis((n, n), (n, n), hurst=0.8, rms_height=math.sqrt(10.0), rng=rng)
            else:
                fourier_synthesis((n, n), (n, n), psd=st_psd, rng=rng)
    else:
        name, _, option = method.partition(":")
        extra = {"float32": dict(dtype=np.float32), "none": dict(truncation="none")}.get(option, {})
        _, info = sampling.sample_grid(kernel, (n, n), method=name, seed=seed, rank=100,
                                       n_samples=n_samples, return_info=True, **extra)
    return info

times = []
for n_samples, seed in ((1, 0), (1, 1), (4, 2)):
    start = time.perf_counter()
    try:
        info = once(n_samples, seed)
    except ValueError as error:
        print(json.dumps({"error": str(error).split(":")[0][:70]}))
        sys.exit(0)
    times.append((time.perf_counter() - start) / n_samples)
print(json.dumps({"times": times, "peak_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
                  "torus": getattr(info, "torus_shape", None)}))
'''

METHODS = ("fft_filter", "surface_topography", "auto", "circulant", "circulant:float32",
           "circulant:none", "cholesky", "lanczos")


def run(method, case):
    out = subprocess.run([sys.executable, "-c", CASE, method, case], capture_output=True,
                         text=True)
    if out.returncode:
        return {"error": (out.stderr.strip().splitlines() or ["?"])[-1][:70]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the plain wrap of figure 2")
    args = parser.parse_args()
    print("seconds per draw: 'first' includes the set-up (embedding search), 'next' is a second "
          "call on the same kernel and grid, 'batch' one call of 4 draws; x: over the FFT filter's next (its batch for batch)")
    for case, label in (("figure2", "figure 2, eq 18 (500, 5, pi/6), 2000 x 2000"),
                        ("short", "short range, eq 18 (20, 20), 2048 x 2048")):
        print(f"\n{label}")
        print(f"{'method':22s} {'first s':>8s} {'next s':>7s} {'batch s':>8s} {'first x':>8s} "
              f"{'next x':>7s} {'batch x':>8s} {'peak GiB':>9s}  torus (x grid)")
        base = batch_base = None
        results = {}
        for method in METHODS:
            if args.quick and case == "figure2" and method == "circulant:none":
                continue
            r = run(method, case)
            results[method] = r
            if "error" in r:
                print(f"{method:22s} refused: {r['error']}", flush=True)
                continue
            first, nxt, batch = r["times"]
            if base is None:
                base, batch_base = nxt, batch
            torus = r["torus"]
            grid = (2000 if case == "figure2" else 2048) ** 2
            size = f"{tuple(torus)} ({torus[0] * torus[1] / grid:.1f})" if torus else ""
            print(f"{method:22s} {first:8.2f} {nxt:7.2f} {batch:8.2f} {first / base:8.1f} "
                  f"{nxt / base:7.1f} {batch / batch_base:8.1f} {r['peak_gib']:9.2f}  {size}",
                  flush=True)
        c = results.get("circulant", {})
        if base and "times" in c:
            first, nxt = (t / base for t in c["times"][:2])
            batch = c["times"][2] / batch_base
            if case == "figure2":
                print(f"targets: batch {batch:.1f}x (<= 5x), first {first:.1f}x (<= 15x), "
                      f"peak {c['peak_gib']:.2f} GiB (< 3 GiB)")
            else:
                print(f"target: next {nxt:.1f}x, batch {batch:.1f}x (<= 3x)")


if __name__ == "__main__":
    main()
