"""Benchmark of roughgp.inference.fitting.fit_spectral_mixture (section 3.3) against the issue's targets:
Q = 5 on an 8,192-point profile in under 60 s, Q = 10 on 16,384 points in under 5 minutes.

The profile: one circulant draw of a known two-component spectral mixture (periods 20 and 5
samples) plus white noise of variance 0.01. Prints, per case, the wall time, the number of
likelihood-and-gradient evaluations, the log marginal likelihood and the dominant fitted
frequency against the truth. Then the period-recovery target: Q = 5 fitted to turned
profiles of :mod:`roughgp.models.turned` (8,192 points at 1 um, feed 250 um) for 10 seeds; the fitted
dominant period should be within 1 % of the feed in at least 9. Not a test: run it by hand,

    python benchmarks/fitting.py                 # all (about 11 minutes on 2 cores)
    python benchmarks/fitting.py --cases 8192:5 --seeds 0  # only this n:Q, no recovery
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from roughgp import sampling
from roughgp.gp import kernels
from roughgp.inference import fitting
from roughgp.models import turned

TARGETS = {(8192, 5): 60.0, (16384, 10): 300.0}


def profile(n, seed=1):
    kernel = kernels.SpectralMixtureKernel(2, dim=1, weights=[1.0, 0.3], means=[[0.05], [0.2]],
                                           variances=[[1e-6], [1e-4]])
    z = sampling.sample_grid(kernel, (n,), spacing=1.0, seed=seed, method="circulant")[0]
    noise = 0.1 * np.random.default_rng(seed + 1).standard_normal(n)
    return np.arange(n, dtype=np.float64), z + noise


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="*", default=["8192:5", "16384:10"],
                        help="n:Q pairs (default: the two targets)")
    parser.add_argument("--seeds", type=int, default=10,
                        help="turned profiles in the period-recovery check (default 10)")
    args = parser.parse_args()
    print(f"{'n':>6} {'Q':>3} {'time [s]':>9} {'target':>7} {'evals':>6} {'log ML':>12} "
          f"{'dominant f':>11} {'true f':>7}")
    for case in args.cases:
        n, q = (int(v) for v in case.split(":"))
        x, z = profile(n)
        start = time.perf_counter()
        fit = fitting.fit_spectral_mixture(x, z, q, seed=0)
        elapsed = time.perf_counter() - start
        evals = sum(c.n_evaluations for c in fit.candidates) + len(fit.candidates)
        target = TARGETS.get((n, q))
        print(f"{n:>6} {q:>3} {elapsed:>9.1f} {'-' if target is None else f'{target:.0f}':>7} "
              f"{evals:>6} {fit.log_marginal_likelihood:>12.2f} {fit.means[0]:>11.5f} "
              f"{0.05:>7.5f}", flush=True)
    if args.seeds:
        feed = turned.RUBERT_LIKE.feed
        print(f"\nperiod recovery, Q = 5, 8192 points at 1 um, feed {feed:g} um")
        print(f"{'seed':>4} {'time [s]':>9} {'period [um]':>12} {'error [%]':>10}")
        hits = 0
        for seed in range(args.seeds):
            x, z = turned.turned_profile(8192, spacing=1.0, seed=seed)
            start = time.perf_counter()
            fit = fitting.fit_spectral_mixture(x, z, 5, seed=seed)
            error = 100 * (fit.dominant_period / feed - 1)
            hits += abs(error) < 1
            print(f"{seed:>4} {time.perf_counter() - start:>9.1f} {fit.dominant_period:>12.3f} "
                  f"{error:>10.3f}", flush=True)
        print(f"within 1 %: {hits} of {args.seeds} (target: at least 9 of 10)")


if __name__ == "__main__":
    main()
