"""How close the K-kernel blend of roughgp.models.nonstationary comes to the Paciorek covariance.

A 32 x 32 grid (spacing 1 um), variance 1, lambda_a 2 -> 8 um, lambda_b 1.5 -> 3 um and the
angle 0 -> 60 degrees, linear from the left edge to the right. For K = 1, 2, 4, 8 (and 16) the
blended sampler's covariance is computed exactly (the draw is linear in the white noise:
``blend_covariance``, no Monte Carlo) and compared with the exact Paciorek-Schervish
covariance, whose dense Cholesky factor is the exact (and slow) sampler. Errors are
mean |C_blend - C_PS| over the pairs (x, x + lag), x in the left, middle or right third of the
map, in units of the variance; "frob" is ||C_blend - C_PS||_F / ||C_PS||_F over the whole map.
Not a test: run it by hand (one BLAS thread, ~10 s on 2 busy cores),

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/nonstationary_sampler.py

Measured on the 2-core machine (one BLAS thread, beside a CI job):

    exponential, 32 x 32, lags (dy, dx) in points. Dense Cholesky of the
    Paciorek matrix (+ 1e-10 jitter): 0.025 s, a draw 0.3 ms
    K  anchors region   (0,0)  (0,1)  (0,2)  (0,4)  (1,0)  (2,0)  (4,0)    frob
    1        1 left    0.0000 0.0386 0.0477 0.0377 0.1219 0.1517 0.1191  0.3103
               middle  0.0000 0.0169 0.0239 0.0233 0.0272 0.0366 0.0332
               right   0.0000 0.0103 0.0144 0.0151 0.0859 0.1264 0.1377
    2        2 left    0.0000 0.0323 0.0402 0.0321 0.0267 0.0312 0.0216  0.1238
               middle  0.0000 0.0196 0.0243 0.0195 0.0122 0.0225 0.0285
               right   0.0000 0.0037 0.0060 0.0074 0.0327 0.0505 0.0601
    4        4 left    0.0000 0.0100 0.0112 0.0092 0.0046 0.0058 0.0043  0.0460
               middle  0.0000 0.0042 0.0045 0.0035 0.0029 0.0055 0.0069
               right   0.0000 0.0013 0.0027 0.0038 0.0114 0.0192 0.0254
    8        8 left    0.0000 0.0019 0.0024 0.0022 0.0009 0.0012 0.0009  0.0168
               middle  0.0000 0.0008 0.0009 0.0017 0.0007 0.0014 0.0018
               right   0.0000 0.0006 0.0018 0.0027 0.0029 0.0052 0.0073
    16      16 left    0.0000 0.0004 0.0004 0.0013 0.0002 0.0003 0.0003  0.0089
               middle  0.0000 0.0002 0.0009 0.0023 0.0002 0.0004 0.0005
               right   0.0000 0.0004 0.0010 0.0017 0.0005 0.0009 0.0012
    blend plan s/draw ms: K=1 0.004/0.3, K=2 0.006/0.5, K=4 0.009/0.9, K=8 0.016/2.0, K=16 0.031/3.7
    what K buys (frob of K=1 / frob of K): K=2: 2.5x, K=4: 6.7x, K=8: 18.5x, K=16: 34.8x

    squared_exponential (the same table in the run):
    blend plan s/draw ms: K=1 0.003/0.3, K=2 0.006/0.5, K=4 0.009/0.9, K=8 0.013/1.7, K=16 0.029/3.5
    what K buys (frob of K=1 / frob of K): K=2: 2.3x, K=4: 6.1x, K=8: 19.4x, K=16: 90.7x
    256 x 256, K = 1: plan 0.08 s, a draw 0.011 s
    256 x 256, K = 8: plan 0.26 s, a draw 0.078 s

The lag-0 error is 0 by construction (the blend is divided by its exact local standard
deviation). K = 8 takes the largest regional error at lags <= 4 points from 0.15 to 0.007
(exponential; 0.29 to 0.018 for the squared exponential). The exponential (eq 18) error stops
falling near frob 0.008 (K = 32: 0.0081): the cross-covariance of two exponential square-root
filters is not Paciorek's form. The squared exponential's tends to 0 (K = 32, one anchor per
column here: frob 2.5e-6). At 32 x 32 the dense Cholesky is as fast; the blend's plan and draw
cost O(K M log M) on the torus of M points, where the Cholesky costs O(N^3) flops and N^2
memory (256 x 256: a 65536 x 65536 matrix, 34 GB), so the blend reaches the sizes of real maps.
"""

from __future__ import annotations

import math
import time

import numpy as np

from roughgp.common.grid import coordinates
from roughgp.models import nonstationary as ns

SHAPE = (32, 32)
LAGS = ((0, 0), (0, 1), (0, 2), (0, 4), (1, 0), (2, 0), (4, 0))  # (dy, dx) in points
KS = (1, 2, 4, 8, 16)


def _ramp(low, high):
    return lambda x, y: low + (high - low) * x / (SHAPE[1] - 1)


FIELD = ns.ParameterField(variance=1.0, lambda_a=_ramp(2.0, 8.0), lambda_b=_ramp(1.5, 3.0),
                          angle=_ramp(0.0, math.pi / 3))
REGIONS = {"left": slice(0, 11), "middle": slice(11, 21), "right": slice(21, 32)}


def lag_errors(blend, exact):
    """{region: [mean |difference| per lag]} over pairs (x, x + lag) with x in the region."""
    ny, nx = SHAPE
    diff = np.abs(blend - exact).reshape(ny, nx, ny, nx)
    out = {}
    for name, cols in REGIONS.items():
        row = []
        for dy, dx in LAGS:
            iy, ix = np.meshgrid(np.arange(ny - dy), np.arange(nx)[cols], indexing="ij")
            keep = ix + dx < nx
            iy, ix = iy[keep], ix[keep]
            row.append(float(diff[iy, ix, iy + dy, ix + dx].mean()))
        out[name] = row
    return out


def timed(function, *args, repeat=3, **kwargs):
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        result = function(*args, **kwargs)
        best = min(best, time.perf_counter() - start)
    return result, best


def main():
    points = coordinates(SHAPE, 1.0).reshape(-1, 2)
    header = "K  anchors region " + "".join(f"{f'({dy},{dx})':>7}" for dy, dx in LAGS) \
        + "    frob"
    for correlation in ns.CORRELATIONS:
        exact = ns.paciorek_covariance(points, points, FIELD, correlation=correlation)
        jitter = 1e-10 * np.trace(exact) / len(exact)
        factor, t_chol = timed(np.linalg.cholesky, exact + jitter * np.eye(len(exact)))
        rng = np.random.default_rng(0)
        _, t_chol_draw = timed(lambda: factor @ rng.standard_normal(len(exact)))
        print(f"\n{correlation}, {SHAPE[0]} x {SHAPE[1]}, lags (dy, dx) in points. Dense "
              f"Cholesky of the\nPaciorek matrix (+ {jitter:.0e} jitter): {t_chol:.3f} s, "
              f"a draw {t_chol_draw * 1e3:.1f} ms")
        print(header)
        frobs, times = {}, []
        for k in KS:
            plan, t_plan = timed(ns.blend_plan, SHAPE, 1.0, FIELD, n_kernels=k,
                                 correlation=correlation, repeat=1)
            _, t_draw = timed(ns.sample_nonstationary, SHAPE, 1.0, FIELD, plan=plan, seed=1)
            blend = ns.blend_covariance(plan)
            frobs[k] = np.linalg.norm(blend - exact) / np.linalg.norm(exact)
            times.append(f"K={k} {t_plan:.3f}/{t_draw * 1e3:.1f}")
            for i, (region, row) in enumerate(lag_errors(blend, exact).items()):
                lead = f"{k:<2} {len(plan.anchors):>7} " if i == 0 else " " * 11
                tail = f" {frobs[k]:7.4f}" if i == 0 else ""
                print(f"{lead}{region:<7}" + "".join(f"{e:7.4f}" for e in row) + tail)
        print("blend plan s/draw ms: " + ", ".join(times))
        gains = ", ".join(f"K={k}: {frobs[KS[0]] / frobs[k]:.1f}x" for k in KS[1:])
        print(f"what K buys (frob of K=1 / frob of K): {gains}")
    big = (256, 256)  # the dense Cholesky would factor a 65536 x 65536 matrix (34 GB)
    scale = ns.ParameterField(variance=1.0, lambda_a=lambda x, y: 2 + 6 * x / 255,
                              lambda_b=lambda x, y: 1.5 + 1.5 * x / 255,
                              angle=lambda x, y: math.pi / 3 * x / 255)
    for k in (1, 8):
        plan, t_plan = timed(ns.blend_plan, big, 1.0, scale, n_kernels=k, repeat=1)
        _, t_draw = timed(ns.sample_nonstationary, big, 1.0, scale, plan=plan, seed=1)
        print(f"{big[0]} x {big[1]}, K = {k}: plan {t_plan:.2f} s, a draw {t_draw:.3f} s")


if __name__ == "__main__":
    main()
