"""``roughgp fit ground --model auto``: the ladder's rung by the kriging of held-out points,
its heights by the out-of-sample check (:mod:`roughgp.checking.auto_choice`; argument handling
and printing only)."""

from __future__ import annotations

from roughgp.cli.output import print_wrapped, refused_by

__all__ = ["choose_auto_command"]


def choose_auto_command(args, heights, z, settings):
    """``fit ground --model auto``: the rung by the kriging of held-out points, its heights
    by the out-of-sample check (roughgp.checking.auto_choice)."""
    from roughgp.checking.auto_choice import N_SIMULATIONS, check_halves, choose_checked
    given = args.marginal is not None or args.non_gaussian
    print(f"choosing a model for {args.file} by the kriging of held-out measured points:")
    print(f"  {'model':<7} {'held-out RMSE (um)':>19} {'+-2 sd held':>12} {'seconds':>8}")

    def show(rung):
        if rung.refused is not None:
            print(f"  {rung.name:<7} {'refused':>19} {'':>12} {rung.seconds:>8.1f}", flush=True)
            print_wrapped(f"    {rung.refused}")
            return
        print(f"  {rung.name:<7} {rung.rmse:>19.5g} {rung.check.coverage():>12.1%} "
              f"{rung.seconds:>8.1f}", flush=True)

    def chosen(ladder):
        print_wrapped(f"chose {ladder.chosen}: {ladder.reason}")
        fitted, held = check_halves(z.shape)
        if fitted is not None:
            what = "its heights" if given else "the heights' distribution"
            print_wrapped(f"checking {what} out of sample: {ladder.chosen} fitted on rows "
                          f"{fitted.rows[0]}:{fitted.rows[1]}, columns {fitted.cols[0]}:"
                          f"{fitted.cols[1]}, checked on rows {held.rows[0]}:{held.rows[1]}, "
                          f"columns {held.cols[0]}:{held.cols[1]} ({N_SIMULATIONS} "
                          f"simulations):")
            print(f"  {'heights':<9} {'outside':>7} {'seconds':>8}  (of the texture parameters, "
                  f"on the unseen half)")

    def checked(candidate):
        told = "refused" if candidate.outside is None else str(len(candidate.outside))
        print(f"  {candidate.marginal:<9} {told:>7} {candidate.seconds:>8.1f}  "
              f"{', '.join(candidate.outside or ())}", flush=True)
        if candidate.refused:
            print_wrapped(f"    {candidate.refused}")
    ladder_settings = {k: v for k, v in settings.items() if k != "marginal"}
    with refused_by(args.file):
        choice = choose_checked(z, heights.spacing, marginal=settings["marginal"] if given
                                else None, progress=show, on_rung=chosen, on_check=checked,
                                **ladder_settings)
    print_wrapped(f"chose {choice.chosen} with {choice.marginal} heights: {choice.reason}")
    return choice.model, choice.range_notes
