"""The ``roughgp`` argument parser: the top level, the shared input options, and each command's
parser from its own module.
"""

from __future__ import annotations

import argparse

from roughgp.cli import batch, check, fill, fit, reproduce, simulate, texture
from roughgp.cli.bounds import bounds_text, integer
from roughgp.cli.output import WIDTH
from roughgp.io.measurement import READ_FORMATS

__all__ = ['build_parser']


_DESCRIPTION = """\
Rough surfaces as Gaussian processes: the companion of Jawaid & Seewig, "Model of rough
surfaces with Gaussian processes". Heights and lengths are in micrometres (um) throughout.

examples:
  roughgp reproduce --out ledger/              check every claim of the paper
  roughgp simulate ground --shape 512 512 --seed 1 --out ground.x3p
  roughgp simulate turned --profile 4096 --seed 1 --out turned.csv
  roughgp fit profile turned.csv --out profile.json     spectral-mixture fit (eq 21)
  roughgp fit ground land.x3p --form cylinder --out land.json     eq 18 on a measurement
  roughgp simulate --from land.json --shape 256 918 --seed 1 --out new.x3p
  roughgp check land.json land.x3p --plot check.png      the measurement among simulations
  roughgp texture ground.x3p                   ISO 25178-2 parameters (Sq, Ssk, Sal, ...)
  roughgp fill measured.x3p --out filled.x3p   missing (NaN) points filled by the GP
  roughgp batch data/ --out batch/             texture, fit, check of many files (Dask)

exit codes: 0 success, 1 a claim regressed (reproduce), 2 a usage or input error, 10 + N
when N files failed (batch)."""


_INPUT = f"""\
input formats: {', '.join(READ_FORMATS)}
  .npy              a 1-D profile or a 2-D surface z[iy, ix] (no spacing stored: --spacing)
  .csv .txt .dat    text tables: 1 column (heights) or 2 columns (x, z) are a profile, 3 or
                    more a surface (one row per y); a CSV written by 'roughgp simulate' says
                    which it is and its spacing in a comment line
  .xyz              x y z points on a regular grid
  .x3p              ISO 25178-72 from any writer (x3pio, x3ptools, MountainsMap, ...)
  instrument files  through SurfaceTopography, recognised by their content: Digital Surf
                    .sur, Wyko .opd, NanoScope .di, Sensofar .plu/.plux, Zygo .datx and
                    MetroPro .dat, MountainsMap .mnt, NanoFocus .nms, Keyence .vk3/.vk4/.vk6,
                    .sdf, Gwyddion .gwy, Olympus .lext/.oir, ... (units from the file)
A profile's x column may be printed rounded: it is read as a regular grid when every x lies
within the rounding of its printed digits (the spacing used is printed)."""


class formatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions kept as written; option help in a column at 20 or more."""

    def __init__(self, prog):
        super().__init__(prog, width=WIDTH, max_help_position=32)
        self._action_max_length = 16  # so "reproduce" keeps its help on its line


def add_input_options(parser, *, kind=True,
                      what="the profile or surface, heights in um (formats: see below)") -> None:
    """The input options that fit, texture and fill share: FILE, --spacing, --kind (unless
    ``kind`` is False: fill reads surfaces only), --channel and --unit."""
    parser.add_argument("file", metavar="FILE", help=what)
    parser.add_argument("--spacing", type=float, metavar="D",
                        help=f"the grid spacing in um, {bounds_text('--spacing')}, overriding "
                             f"the file's (default: from the file; 1 um when it has none, "
                             f"e.g. .npy)")
    if kind:
        parser.add_argument("--kind", choices=("auto", "profile", "surface"), default="auto",
                            help="read a text table as a profile or a surface (default: auto)")
    parser.add_argument("--channel", type=integer("--channel"), default=0, metavar="K",
                        help=f"the data channel of an instrument file with several, "
                             f"{bounds_text('--channel')} (default 0)")
    parser.add_argument("--unit", choices=("m", "mm", "um", "nm"), metavar="U",
                        help="the unit of the file's numbers (m, mm, um, nm), converted to "
                             "um and reported as '(as given)': for a .npy or text file the "
                             "heights' unit (default um; it replaces a header's '# Value "
                             "units:' or column unit; x columns and --spacing stay in um); for "
                             "an instrument file the unit of its heights and spacing, replacing "
                             "the one it states (for a file that states none or states it "
                             "wrong); refused for .x3p, which stores metres")



def build_parser() -> argparse.ArgumentParser:
    """The ``roughgp`` argument parser (all sub-commands)."""
    from roughgp.common.version import VERSION
    parser = argparse.ArgumentParser(prog="roughgp", description=_DESCRIPTION,
                                     formatter_class=formatter)
    parser.add_argument("--version", action="version", version=f"roughgp {VERSION}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                title="commands (roughgp COMMAND --help for each)")

    reproduce.add_parser(sub, formatter)
    simulate.add_parser(sub, formatter)
    fit.add_parser(sub, formatter, _INPUT, add_input_options)
    texture.add_parser(sub, formatter, _INPUT, add_input_options)
    check.add_parser(sub, formatter, _INPUT, add_input_options)
    fill.add_parser(sub, formatter, _INPUT, add_input_options)
    batch.add_parser(sub, formatter)
    return parser
