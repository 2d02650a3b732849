"""``roughgp fill FILE``: the unmeasured (NaN) points of a surface filled by the GP
(:func:`roughgp.beyond.measured_fill.fill_measured_surface`). Argument handling and messages only.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_device,
    check_outputs,
    check_spacing,
    describe_groove,
    err,
)
from roughgp.metrology.measurement import read_measurement
from roughgp.metrology.writers import WRITE_FORMATS, write_heights

__all__ = ['add_parser', 'run']


_FILL = """\
Fill the unmeasured (NaN) points of a surface, e.g. the non-measured points an optical
instrument leaves at steep flanks: the surface is levelled (least-squares plane), eq 18 plus
white noise is fitted to the measured points alone (block composite likelihood,
roughgp.inference.block_fit), and the missing points get the GP posterior mean (roughgp.beyond.gap_filling,
conjugate gradients with FFT products). --sd also writes the posterior standard deviation
at the filled points (pathwise draws). Suited to stationary, ground-like textures; heights
and lengths in um.

example:
  roughgp fill measured.x3p --out filled.x3p --sd sd.x3p --seed 0"""



def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``fill`` to the sub-command parsers ``sub``."""
    f = sub.add_parser("fill", formatter_class=formatter, description=_FILL, epilog=input_epilog,
                       help="fill the missing (NaN) points of a surface with the GP")
    add_input_options(f, kind=False, what="the surface, heights in um, NaN where missing")
    f.add_argument("--out", required=True, metavar="FILE",
                   help="the filled surface: " + ", ".join(WRITE_FORMATS))
    f.add_argument("--sd", metavar="FILE", help="also write the posterior sd map")
    f.add_argument("--samples", type=int, default=16, metavar="N",
                   help="pathwise draws for the sd (default 16; 0: the mean only)")
    f.add_argument("--seed", type=int, default=0, metavar="S",
                   help="seed of the blocks chosen for the fit and of the draws (default 0)")
    add_force_option(f)
    f.add_argument("--block", type=int, default=24, metavar="B",
                   help="side of the fit's blocks in points (default 24)")
    f.add_argument("--blocks", type=int, default=12, metavar="K",
                   help="blocks used by the fit (default 12)")
    f.add_argument("--device", metavar="DEV",
                   help="run the fill's FFTs and CG through torch on DEV (cpu, cuda, cuda:N)")
    f.set_defaults(func=run)


def run(args) -> int:
    """``roughgp fill FILE``: fill the unmeasured points of a surface with the GP posterior."""
    from roughgp.beyond.measured_fill import fill_measured_surface
    out, sd_out = check_outputs(("--out", args.out, "heights"), ("--sd", args.sd, "heights"),
                                inputs=(args.file,), force=args.force)
    if args.samples < 0:
        raise UsageError(f"--samples must be >= 0, got {args.samples}")
    if sd_out is not None and args.samples < 2:
        raise UsageError("--sd needs --samples >= 2 (the sd is estimated from the draws)")
    check_device(args.device)
    check_spacing(args.spacing)
    heights = read_measurement(args.file, kind="surface", spacing=args.spacing,
                               channel=args.channel, unit=args.unit)
    for note in heights.notes:
        err(f"note: {args.file}: {note}")
    if heights.kind != "surface":
        raise UsageError(f"{args.file} holds a profile; fill needs a surface z[iy, ix]")
    (dy, dx), z = heights.spacing, heights.z
    spacing = dx if dy == dx else (dy, dx)
    if dy != dx and ".csv" in {out.suffix.lower(), (sd_out or out).suffix.lower()}:
        raise UsageError(f"the spacing differs along y and x ({dy:g}, {dx:g} um): a .csv "
                         f"stores one spacing; write .x3p or .npy")
    missing = np.isnan(z)
    if not missing.any():
        raise UsageError(f"{args.file} has no missing (NaN) point: nothing to fill")
    err(f"{args.file}: {z.shape[0]} x {z.shape[1]} points, spacing {dy:g} x {dx:g} um "
        f"({heights.spacing_source}), {missing.sum()} missing ({missing.mean():.1%})")
    start = time.perf_counter()
    result = fill_measured_surface(z, spacing=heights.spacing, n_samples=args.samples,
                                   seed=args.seed, block=args.block, n_blocks=args.blocks,
                                   device=args.device)
    fit, fill = result.fit, result.gaps
    fit_seconds = time.perf_counter() - start - fill.seconds
    err(f"eq 18 fitted on {fit.n_points} measured points of {len(fit.blocks)} blocks in "
        f"{fit_seconds:.1f} s: {describe_groove(fit.groove)}, noise variance "
        f"{fit.noise_variance:.4g} um^2")
    if not fill.converged:
        err("warning: conjugate gradients did not reach their tolerance; the fill is "
            "approximate")
    err(f"filled in {fill.seconds:.1f} s ({fill.iterations} CG iterations"
        + (f", {args.samples} draws for the sd" if args.samples else "") + ")")
    comment = (f"roughgp fill {Path(args.file).name} --seed {args.seed}: levelled by a "
               f"least-squares plane (added back), eq 18 plus white noise fitted to the "
               f"measured points ({describe_groove(fit.groove)}, noise variance "
               f"{fit.noise_variance:.4g} um^2), the {missing.sum()} missing points filled by "
               f"the GP posterior mean")
    write_heights(out, result.filled, spacing, comment, source=heights.meta)
    err(f"wrote {out} (the measured heights, the {missing.sum()} missing ones filled by the "
        f"posterior mean)")
    if sd_out is not None:
        offset = heights.meta.get("offset")  # an sd is no height: no z offset
        sd_offset = None if offset is None else (*tuple(offset)[:2], 0.0)
        write_heights(sd_out, result.sd, spacing,
                      comment + f"; this file: the posterior sd ({args.samples} draws)",
                      source={**heights.meta, "offset": sd_offset})
        sd = result.sd[missing]
        err(f"wrote {sd_out} (posterior sd of the latent surface at the filled points, 0 at "
            f"measured ones; median {np.median(sd):.3g} um, largest {sd.max():.3g} um)")
    return 0
