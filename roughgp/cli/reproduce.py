"""``roughgp reproduce``: run the claims ledger (:mod:`roughgp.ledger`), print the verdicts;
exit 1 when a check regressed.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from roughgp.cli.output import WIDTH, UsageError, err, table, wrap

__all__ = ['add_parser', 'run']


def add_parser(sub, formatter) -> None:
    """Add ``reproduce`` to the sub-command parsers ``sub``."""
    p = sub.add_parser("reproduce", formatter_class=formatter,
                       help="run the claims ledger: every checkable claim of the paper",
                       description="Run the checks of the claims ledger (roughgp.ledger) and "
                                   "print each claim's verdict, status and our value;\nexit 1 "
                                   "when a check regressed (progress goes to stderr, the table "
                                   "to stdout).\n\nexamples:\n"
                                   "  roughgp reproduce --list\n"
                                   "  roughgp reproduce --only eq5-duality --out ledger/")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--full", action="store_const", const=True, default=None,
                      help="use the paper's sizes (slower) instead of the quick defaults "
                           "(default: as ROUGHGP_FULL says, quick when it is unset)")
    size.add_argument("--quick", dest="full", action="store_const", const=False,
                      help="the quick sizes even when ROUGHGP_FULL=1")
    p.add_argument("--only", nargs="+", metavar="KEY",
                   help="run only these claims (see --list)")
    p.add_argument("--out", metavar="DIR",
                   help="write DIR/ledger.md, DIR/ledger.json and DIR/figures/KEY.png")
    p.add_argument("--reuse", action="store_true",
                   help="with --out DIR: report the run saved in DIR (the book's chapter "
                        "'Claims ledger' saves one in book/_build/ledger) if roughgp, its data "
                        "and the libraries are unchanged since; otherwise run the checks")
    p.add_argument("--list", action="store_true", help="list the claims and exit")
    p.set_defaults(func=run)


def run(args) -> int:
    """``roughgp reproduce``: run the claims ledger, print it, exit 1 on a regression."""
    from roughgp import ledger
    from roughgp.common.settings import resolve_full
    from roughgp.ledger import stored
    full = resolve_full(args.full)  # the one rule: --full / --quick, else ROUGHGP_FULL
    if args.list:
        for c in ledger.CLAIMS:
            print(f"{c.key}  ({c.where}; {c.verdict})")
            for line in wrap(c.statement, WIDTH - 4):
                print(f"    {line}")
        return 0
    for key in args.only or ():
        try:
            ledger.claim(key)
        except ValueError as exc:
            raise UsageError(f"--only: {exc}") from None
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")  # checks draw figures; never open a window
    out = Path(args.out) if args.out else None
    if out is not None and out.exists() and not out.is_dir():
        raise UsageError(f"--out {args.out} exists and is not a directory")
    if args.reuse and out is None:
        raise UsageError("--reuse needs --out DIR (the folder of the saved run)")
    start = time.perf_counter()
    outcomes = None
    if args.reuse:
        outcomes, why = stored.load(out, full=full)
        err(f"reusing {why} in {out}" if outcomes is not None
            else f"--reuse: {why}; running the checks")
        if outcomes is not None and args.only:
            keep = set(args.only)
            outcomes = [o for o in outcomes if o.claim.key in keep]
    reused = outcomes is not None
    if outcomes is None:
        outcomes = ledger.run(full=full, only=args.only,
                              figures_dir=None if out is None else out / "figures",
                              progress=err)
    rows = [(o.claim.key, o.claim.verdict, o.status,
             o.value if o.error is None else f"{o.value} ({o.error})") for o in outcomes]
    key_width = min(28, max([5] + [len(o.claim.key) for o in outcomes]))
    widths = (key_width, 18, 9, WIDTH - key_width - 18 - 9 - 6)
    print(table(rows, widths, ("claim", "verdict", "status", "our value")))
    regressed = [o.claim.key for o in outcomes if o.regressed]
    seconds = sum(o.seconds for o in outcomes) if reused else time.perf_counter() - start
    print(f"\n{len(outcomes)} claim(s) in {seconds:.1f} s"
          f"{' (reused)' if reused else ''}{' (paper sizes)' if full else ''}: "
          f"{len(outcomes) - len(regressed)} ok, {len(regressed)} regressed")
    if out is not None and not reused:
        if args.only:  # a partial run is not one that --reuse may report
            (out / stored.RUN_FILE).unlink(missing_ok=True)
            written = ", ".join(str(p) for p in ledger.write(outcomes, out))
        else:
            run_file = stored.save(outcomes, out, full=full)
            written = f"{out / 'ledger.md'}, {out / 'ledger.json'}, {run_file}"
        err(f"wrote {written} and the figures in {out / 'figures'}")
    if regressed:
        err(f"REGRESSED (the verdict must be revisited): {', '.join(regressed)}")
        return 1
    return 0

