"""Benchmark of the ``device=`` paths (roughgp.common.device): numpy on the CPU, torch on the CPU and,
where torch sees one, torch on a CUDA GPU, side by side in one run.

Cases (each timed as the best of ``--repeats`` calls, on the GPU after one untimed warm-up):

* ``circulant draw``: one exact draw of eq 18 with figure 2's hyperparameters (lambda_a = 500)
  on an n x n grid, the embedding cached (its search runs once, on the CPU, and is reported
  on its own line); per draw, from calls of 2 draws (one complex FFT on the torus).
* ``cholesky draw``: a dense exact draw of eq 18 (lambda = 30, 5) on an n x n grid
  (factorisation included: N = n^2 points, N^3 / 3 flops).
* ``patch likelihood``: one evaluation of the dense marginal likelihood of an n x n patch
  (posterior.ground_patch_model; what a maximum-likelihood or MCMC fit of eq 18 repeats).
* ``profile likelihood``: one evaluation for an n-point profile: the exact Toeplitz
  likelihood (O(n^2), the numpy path of roughgp.gp.toeplitz) against its dense route on each
  device (what toeplitz_log_likelihood and fit_spectral_mixture run with device=).
* ``gap filling``: fill_gaps on an n x n ground surface with 10 % scattered dropouts and a
  scratch, 16 pathwise draws for the sd.
* ``spectral mixture fit``: fit_spectral_mixture with Q = 5 on an n-point two-line profile
  (the fitting benchmark's): the Toeplitz recursion against the dense route on the GPU
  (torch on the CPU is left out: its dense route is far slower than the recursion there).
* ``whittle fit``: fit_whittle (the debiased spatial Whittle fit of eq 18, issue 40) on an
  n x n ground surface with the gap-filling case's holes; it is torch throughout, so its
  'numpy' column is torch on the CPU (device=None) and the 'cpu' column is left out.

Prints seconds per case and backend, and the ratios numpy / device. Not a test: run it by
hand (the sizes below fit a 2-core CPU in a few minutes with --quick):

    python benchmarks/device.py --quick     # small sizes: checks the script, any machine
    python benchmarks/device.py             # the default sizes (minutes on a GPU machine)
    python benchmarks/device.py --full      # larger grids and patches
    python benchmarks/device.py --json out.json
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np
import torch

from roughgp import sampling
from roughgp.filling import global_fill as gap_filling
from roughgp.common import device as devices
from roughgp.gp import kernels
from roughgp.gp.toeplitz import toeplitz_log_likelihood
from roughgp.inference import fitting, posterior, whittle_fit
from roughgp.models import surfaces

FIGURE_2 = dict(variance=10.0, lengthscales=(500.0, 5.0), angle=math.pi / 6)
SHORT = dict(variance=10.0, lengthscales=(30.0, 5.0), angle=math.pi / 6)
SIZES = {
    "quick": {"circulant draw": [256, 512], "cholesky draw": [24, 32],
              "patch likelihood": [24, 32], "profile likelihood": [1024, 2048],
              "gap filling": [128], "spectral mixture fit": [1024], "whittle fit": [64]},
    "default": {"circulant draw": [2048], "cholesky draw": [64, 96, 128],
                "patch likelihood": [64, 96, 128], "profile likelihood": [8192, 16384],
                "gap filling": [512], "spectral mixture fit": [8192],
                "whittle fit": [256, 512]},
    "full": {"circulant draw": [2048, 4096], "cholesky draw": [64, 96, 128, 160],
             "patch likelihood": [64, 96, 128, 160], "profile likelihood": [8192, 16384],
             "gap filling": [512, 1024, 2048], "spectral mixture fit": [8192, 16384],
             "whittle fit": [512, 1024, 2048]},
}


def _timed(fn, backend, repeats):
    """Best wall time of ``repeats`` calls of ``fn``; on a GPU after one warm-up call (CUDA
    context, FFT plans and kernels are made on first use)."""
    device = None if backend == "numpy" else torch.device(backend)
    if backend == "cuda":
        fn()
        devices.synchronize(device)
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        devices.synchronize(device)
        best = min(best, time.perf_counter() - start)
    return best


def _gappy_surface(n):
    truth = surfaces.ground((n, n), **SHORT, noise_variance=0.05, seed=1)
    z = truth.copy()
    z[np.random.default_rng(2).random(z.shape) < 0.1] = np.nan
    z[n // 2:n // 2 + 4, n // 8:7 * n // 8] = np.nan
    return z


def case(name, n, backend):
    """A function running one call of case ``name`` at size ``n`` on ``backend``."""
    device = None if backend == "numpy" else backend
    if name == "circulant draw":
        kernel = kernels.RotatedExponentialKernel(**FIGURE_2)
        return lambda: sampling.sample_grid(kernel, (n, n), n_samples=2, method="circulant",
                                            seed=0, device=device)
    if name == "cholesky draw":
        kernel = kernels.RotatedExponentialKernel(**SHORT)
        return lambda: sampling.sample_grid(kernel, (n, n), method="cholesky", seed=0,
                                            device=device)
    if name == "patch likelihood":
        z = surfaces.ground((n, n), **SHORT, noise_variance=1.0, seed=1)
        model = posterior.ground_patch_model(z, device=device)
        params = dict(variance=10.0, lambda_a=30.0, lambda_b=5.0, angle=math.pi / 6,
                      noise_variance=1.0)
        return lambda: model.log_likelihood(params)
    if name == "profile likelihood":
        x = np.arange(n, dtype=np.float64)
        z = np.sin(2 * np.pi * x / 250) + 0.1 * np.random.default_rng(0).standard_normal(n)
        r = 0.5 * np.cos(2 * np.pi * x / 250) * np.exp(-2 * np.pi**2 * 1e-6 * x**2)
        r[0] += 0.01
        return lambda: toeplitz_log_likelihood(z, r, device=device)
    if name == "gap filling":
        z = _gappy_surface(n)
        kernel = kernels.RotatedExponentialKernel(**SHORT)
        return lambda: gap_filling.fill_gaps(z, kernel, noise_variance=0.05, n_samples=16,
                                             seed=0, device=device)
    if name == "spectral mixture fit":
        from fitting import profile as two_line_profile  # benchmarks/fitting.py, beside this

        x, z = two_line_profile(n)
        return lambda: fitting.fit_spectral_mixture(x, z, 5, seed=0, device=device)
    if name == "whittle fit":
        z = _gappy_surface(n)
        return lambda: whittle_fit.fit_whittle(z, device=device)
    raise ValueError(name)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes (any machine)")
    parser.add_argument("--full", action="store_true", help="larger sizes (a GPU machine)")
    parser.add_argument("--repeats", type=int, default=1, help="timed calls per case (1)")
    parser.add_argument("--cases", nargs="+", choices=list(SIZES["default"]),
                        help="only these cases")
    parser.add_argument("--backends", nargs="+", choices=["numpy", "cpu", "cuda"],
                        help="only these (default: numpy, cpu and, where present, cuda)")
    parser.add_argument("--json", metavar="FILE", help="also write the timings as JSON")
    args = parser.parse_args()
    sizes = SIZES["quick" if args.quick else "full" if args.full else "default"]
    backends = [b for b in ["numpy"] + devices.available()
                if not args.backends or b in args.backends]
    gpu = torch.cuda.get_device_name(0) if torch.cuda.is_available() else "none"
    print(f"torch {torch.__version__}; CPU threads {torch.get_num_threads()}; GPU: {gpu}")
    print(f"seconds per call (best of {args.repeats}; on the GPU after a warm-up); 'profile "
          "likelihood' numpy is the O(n^2) Toeplitz likelihood, the others the dense one")
    if "circulant draw" in (args.cases or sizes):
        for n in sizes["circulant draw"]:
            sampling._EMBEDDINGS.clear()
            start = time.perf_counter()
            _, info = sampling.sample_grid(kernels.RotatedExponentialKernel(**FIGURE_2),
                                           (n, n), method="circulant", seed=0,
                                           return_info=True)
            print(f"  embedding search for {n} x {n} (CPU, once, cached after): "
                  f"{time.perf_counter() - start:.2f} s, torus {info.torus_shape}", flush=True)
    header = f"{'case':20s} {'size':>12s} " + " ".join(f"{b:>10s}" for b in backends)
    if "cuda" in backends:
        header += f" {'numpy/cuda':>11s} {'torch-cpu/cuda':>15s}"
    print(header)
    rows = []
    for name, ns in sizes.items():
        if args.cases and name not in args.cases:
            continue
        for n in ns:
            label = f"{n}" if name in ("profile likelihood", "spectral mixture fit") else f"{n} x {n}"
            times = {}
            for backend in backends:
                if name in ("spectral mixture fit", "whittle fit") and backend == "cpu":
                    times[backend] = None
                    continue
                try:
                    seconds = _timed(case(name, n, backend), backend, args.repeats)
                    if name == "circulant draw":
                        seconds /= 2
                    times[backend] = seconds
                except (ValueError, RuntimeError, MemoryError) as exc:
                    times[backend] = None
                    print(f"  {name} {label} {backend}: {str(exc)[:100]}")
            line = f"{name:20s} {label:>12s} " + " ".join(
                f"{times[b]:10.4f}" if times[b] is not None else f"{'-':>10s}" for b in backends)
            if "cuda" in backends and times.get("cuda"):
                for ref in ("numpy", "cpu"):
                    width = 11 if ref == "numpy" else 15
                    ratio = times[ref] / times["cuda"] if times.get(ref) else None
                    line += f" {ratio:{width}.1f}" if ratio else f" {'-':>{width}s}"
            print(line, flush=True)
            rows.append({"case": name, "size": n, **{f"seconds_{b}": t for b, t in times.items()}})
    if torch.cuda.is_available():
        print(f"peak GPU memory allocated: {torch.cuda.max_memory_allocated() / 2**30:.2f} GiB")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"gpu": gpu, "torch": torch.__version__, "rows": rows}, fh, indent=1)


if __name__ == "__main__":
    main()
