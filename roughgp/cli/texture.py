"""``roughgp texture FILE``: ISO surface-texture parameters of a measurement. Argument
handling and the printed table only.
"""

from __future__ import annotations

from roughgp.cli.output import check_spacing, print_wrapped, write_json
from roughgp.metrology.measurement import read_measurement

__all__ = ['add_parser', 'run']


_TEXTURE = """\
Print ISO surface-texture parameters: for a surface the ISO 25178-2 set (Sa, Sq, Ssk, Sku,
Sp, Sv, Sz, Sal, Str, Std, Sk, Spk, Svk, Smr1, Smr2), for a profile ISO 4287 / 13565-2 (Ra,
Rq, Rsk, Rku, Rp, Rv, Rt, RSm, Rk, Rpk, Rvk, Mr1, Mr2), without filtering. Heights and
lengths in um, Std in degrees, material ratios in percent. A parameter the data do not
define (e.g. the skewness of a flat surface) prints as nan (null in the JSON).

example:
  roughgp texture ground.x3p --level --json texture.json"""



def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``texture`` to the sub-command parsers ``sub``."""
    x = sub.add_parser("texture", formatter_class=formatter, description=_TEXTURE,
                       epilog=input_epilog,
                       help="ISO texture parameters (Sq, Sal, Str, ... / Ra, Rq, ...)")
    add_input_options(x)
    x.add_argument("--level", action="store_true",
                   help="refer heights to the least-squares plane / line (default: the mean)")
    x.add_argument("--json", metavar="OUT", help="also write the parameters as JSON")
    x.set_defaults(func=run)


_UNITS = {"Ssk": "", "Sku": "", "Rsk": "", "Rku": "", "Str": "", "Std": "deg",
          "Smr1": "%", "Smr2": "%", "Mr1": "%", "Mr2": "%"}


def _unit(name: str) -> str:
    """The unit of a texture parameter: um unless listed in ``_UNITS``."""
    return _UNITS.get(name, "um")


def run(args) -> int:
    """``roughgp texture FILE``: ISO surface-texture parameters."""
    from roughgp.metrology import texture
    check_spacing(args.spacing)
    heights = read_measurement(args.file, kind=args.kind, spacing=args.spacing)
    if heights.kind == "surface":
        values = texture.areal_parameters(heights.z, spacing=heights.spacing,
                                          level=args.level, undefined="nan")
        standard = "ISO 25178-2 areal parameters"
    else:
        values = texture.profile_parameters(heights.z, spacing=heights.spacing[0],
                                            level=args.level, undefined="nan")
        standard = "ISO 4287 / ISO 13565-2 profile parameters (whole profile, unfiltered)"
    shape = " x ".join(map(str, heights.z.shape))
    spacing = ", ".join(f"{d:g}" for d in heights.spacing)
    print(f"{standard} of {args.file}")
    print_wrapped(f"{heights.kind} of {shape} points, spacing {spacing} um "
                   f"({heights.spacing_source}); heights referred to the "
                   f"{'least-squares plane' if args.level else 'mean'}")
    for name, value in values.items():
        print(f"  {name:<5} {value:>12.5g} {_unit(name)}".rstrip())
    if args.json:
        write_json(args.json, {"file": str(args.file), "kind": heights.kind,
                                "shape": list(heights.z.shape),
                                "spacing_um": list(heights.spacing),
                                "spacing_from": heights.spacing_source,
                                "level": args.level, "parameters": values,
                                "units": {k: _unit(k) for k in values}})
    return 0

