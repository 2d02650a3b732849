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
    p.add_argument("--setups", action="store_true",
                   help="also run the claims whose value comes from an optimiser or a random "
                        "search ('search' in --list) under each numerical set-up of "
                        "roughgp.ledger.setups (1 and 2 BLAS threads; optimiser starts as "
                        "computed and moved by 1e-6), each in its own process, "
                        "and exit 1 when a claim's verdict differs between them; with --out "
                        "DIR also DIR/setups.md and DIR/setups.json")
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
            print(f"{c.key}  ({c.where}; {c.verdict}{'; search' if c.search else ''})")
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
        figures = sum(o.figure is not None for o in outcomes)
        err(f"wrote {written}" + (f" and {figures} figure(s) in {out / 'figures'}" if figures
                                  else " (these checks draw no figure)"))
    differing = _compare_setups(args, outcomes, reused, full, out) if args.setups else []
    if regressed:
        err(f"REGRESSED (the verdict must be revisited): {', '.join(regressed)}")
    if differing:
        err("VERDICTS THAT DEPEND ON THE NUMERICAL SET-UP (state the claim over what varies, "
            "or make it land on one answer):\n  " + "\n  ".join(differing))
    return 1 if regressed or differing else 0


def _compare_setups(args, outcomes, reused, full, out) -> list[str]:
    """``--setups``: the search claims of this run under every set-up of
    :data:`roughgp.ledger.setups.SETUPS`, this run standing for the set-up it ran under (a
    saved run's recorded one); prints the table, writes it with ``--out``; returns the
    differences."""
    import dataclasses
    import json

    from roughgp.ledger import setups, stored, to_records

    keys = [o.claim.key for o in outcomes if o.claim.search]
    if not keys:
        err("--setups: none of the claims run depends on an optimiser or a random search")
        return []
    saved = stored.saved_setup(out) if reused else None
    here = (setups.Setup(int(saved["blas_threads"]), int(saved["start_jitter"]))
            if saved else None if reused else setups.Setup.of_this_process())
    mine = [o for o in outcomes if o.claim.key in keys]
    runs = setups.run_setups(keys, setups.SETUPS, full=full,
                             reuse={here: mine} if here is not None else None, progress=err)
    print("\nthe search claims under each numerical set-up:")
    for run in runs:
        print(f"  {run.setup.label}: " + ", ".join(
            f"{o.claim.key} {o.status}" for o in run.outcomes)
            + (" (this run)" if run.reused else f" ({run.seconds:.0f} s)"))
    differing = setups.differences(runs)
    print(f"{len(keys)} claim(s) under {len(runs)} set-ups: "
          + ("the same verdict under every one" if not differing
             else f"{len(differing)} verdict(s) differ"))
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        (out / "setups.md").write_text("# The search claims under each numerical set-up\n\n"
                                       + setups.to_markdown(runs), encoding="utf-8")
        (out / "setups.json").write_text(json.dumps(
            [{"setup": dataclasses.asdict(r.setup), "reused": r.reused, "seconds": r.seconds,
              "claims": to_records(r.outcomes)} for r in runs], indent=1), encoding="utf-8")
        err(f"wrote {out / 'setups.md'} and {out / 'setups.json'}")
    return differing

