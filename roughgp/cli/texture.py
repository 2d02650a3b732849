"""``roughgp texture FILE``: ISO surface-texture parameters of a measurement. Argument
handling and the printed table only.
"""

from __future__ import annotations

from roughgp.cli.options import (
    add_l_kind_options,
    add_operator_options,
    add_spurious_options,
    check_cutoffs,
    flagged_output,
    operator_settings,
    read_input,
    remove_spurious,
    write_flagged,
)
from roughgp.cli.output import UsageError, add_force_option, check_outputs, print_wrapped, write_json

__all__ = ['add_parser', 'run']


_TEXTURE = """\
Print ISO surface-texture parameters of a measurement after the standard's operators: the
F-operator (form removal: a least-squares plane by default; --form cylinder for a curved
part such as a bullet land, polynomial, none), then the Gaussian S-filter (ISO 16610-61,
16610-21 for a profile) that removes the shortest wavelengths and the Gaussian L-filter that
removes the waviness, with the nesting indices of the standard's tables unless given (ISO
4288 / 3274 for a profile, chosen from its Ra; ISO 25178-3's preferred series for a surface:
the largest <= a fifth of the field for L). The parameters are those of the SL surface
(roughness profile): for a surface ISO 25178-2 (Sa, Sq, Ssk, Sku, Sp, Sv, Sz, Sal, Str, Std,
Sk, Spk, Svk, Smr1, Smr2), for a profile ISO 4287 / 13565-2 (Ra, Rq, Rsk, Rku, Rp, Rv, Rt,
RSm, Rk, Rpk, Rvk, Mr1, Mr2). The operators and cut-offs applied are printed. Unmeasured
points are left out of the height and material-ratio parameters; Sal, Str, Std (RSm) need a
complete grid and print as nan then. Heights and lengths in um, Std in degrees, material
ratios in percent; a parameter the data do not define prints as nan (null in the JSON).

examples:
  roughgp texture measured.sur
  roughgp texture land.x3p --form cylinder --l-filter 250 --json texture.json
  roughgp texture ground.x3p --unfiltered"""


def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``texture`` to the sub-command parsers ``sub``."""
    x = sub.add_parser("texture", formatter_class=formatter, description=_TEXTURE,
                       epilog=input_epilog,
                       help="ISO texture parameters (Sq, Sal, Str, ... / Ra, Rq, ...)")
    add_input_options(x)
    add_operator_options(x)
    add_l_kind_options(x)
    add_spurious_options(x)
    x.add_argument("--unfiltered", action="store_true",
                   help="no F-, S- or L-operator: the parameters of the heights as read, "
                        "referred to their mean (not with --form, --degree, --axis, "
                        "--s-filter, --l-filter)")
    x.add_argument("--json", metavar="OUT", help="also write the parameters as JSON (.json)")
    add_force_option(x)
    x.set_defaults(func=run)


def run(args) -> int:
    """``roughgp texture FILE``: ISO surface-texture parameters."""
    from roughgp.api import texture
    from roughgp.metrology.texture_report import unit_of
    given = getattr(args, "given", ())
    if args.unfiltered and given:
        raise UsageError(f"--unfiltered applies no operator: drop {', '.join(given)} (or "
                         f"--unfiltered)")
    operators = operator_settings(args)
    if args.unfiltered and args.l_kind != "gaussian":
        raise UsageError(f"--{args.l_kind} chooses the L-filter; --unfiltered applies none")
    json_out, flagged_out = check_outputs(("--json", args.json, "json"), flagged_output(args),
                                          inputs=(("FILE", args.file),), force=args.force)
    heights = read_input(args, args.kind)
    if not args.unfiltered:
        check_cutoffs(operators, heights.z.shape, heights.spacing)
    z, found = remove_spurious(args, heights, operators["form"])
    try:
        report = texture(z, heights.spacing, **operators, filtered=not args.unfiltered,
                         l_kind=args.l_kind)
    except ValueError as exc:
        raise UsageError(f"{args.file}: {exc}") from None
    shape = " x ".join(map(str, heights.z.shape))
    spacing = ", ".join(f"{d:g}" for d in heights.spacing)
    print(f"{report.standard} of {args.file}")
    print_wrapped(f"{heights.kind} of {shape} points, spacing {spacing} um "
                  f"({heights.spacing_source}); heights: {heights.unit_source}; read by "
                  f"{heights.reader}")
    print_wrapped("operators: " + ("; ".join(report.operators) if report.operators
                                   else "none (unfiltered)"))
    for note in (*heights.notes, *report.notes):
        print_wrapped(f"note: {note}")
    for name, value in report.parameters.items():
        print(f"  {name:<5} {value:>12.5g} {unit_of(name)}".rstrip())
    if args.json:
        write_json(args.json, {"file": str(args.file), "kind": heights.kind,
                               "shape": list(heights.z.shape),
                               "spacing_um": list(heights.spacing),
                               "spacing_from": heights.spacing_source,
                               "height_unit_from": heights.unit_source,
                               "reader": heights.reader, "standard": report.standard,
                               "operators": report.operators,
                               "notes": [*heights.notes, *report.notes],
                               "parameters": report.parameters,
                               "units": {k: unit_of(k) for k in report.parameters}})
    write_flagged(flagged_out, found, args, heights)
    return 0
