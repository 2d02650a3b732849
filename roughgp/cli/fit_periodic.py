"""``roughgp fit ground|profile --model periodic``: the feed mark plus GPs
(:mod:`roughgp.surface_models.periodic_model`), its fall-back where no mark repeats, and the
note of ``--model auto`` on a map whose mark repeats (argument handling and printing only)."""

from __future__ import annotations

from roughgp.cli.output import UsageError, print_operators, print_wrapped

__all__ = ["fit_periodic_command", "fit_periodic_profile_command", "note_periodic_mark"]


def fit_periodic_command(args, heights, operators, data, z):
    """``fit ground --model periodic``: the feed mark plus GPs
    (roughgp.surface_models.periodic_model), or None where the map holds no mark (the caller
    falls back to the ladder)."""
    from roughgp.surface_models.periodic_model import NoPeriodError, fit_periodic_model
    try:   # NoPeriodError is a ValueError: caught first, as no mark rather than a refusal
        fitted = fit_periodic_model(z, heights.spacing, **operators, feed=args.feed, data=data,
                                    device=args.device)
    except NoPeriodError as exc:
        print_wrapped(f"{args.file}: no periodic feed mark: {exc}; falling back to --model "
                      f"auto (the stationary ladder)")
        return None
    except ValueError as exc:
        raise UsageError(f"{args.file}: {exc}") from None
    model = fitted.model
    print_wrapped(f"fitted to {args.file}: {model.describe()}")
    print_operators(model)
    how = model.fit
    print_wrapped(f"  {how['marks']} whole marks; the mark of one half of the map explains "
                  f"{how['mark_reproducibility']:.3f} of the other half's variance; the trace "
                  f"explains {how['mark_explained']:.4f} of the mean profile's, the rest "
                  f"({how['trace_misfit_um2']:.3g} um^2) is not drawn")
    return model


def fit_periodic_profile_command(args, z, spacing, how, heights, operators, data):
    """``fit profile --model periodic``: the feed mark plus GPs of a profile, or None where it
    holds no mark (the caller fits eq 21)."""
    from roughgp.surface_models.periodic_model import NoPeriodError, fit_periodic_profile
    try:
        fitted = fit_periodic_profile(z, spacing, form=operators["form"], s=operators["s"],
                                      l=operators["l"], feed=args.feed,
                                      data={**data, "profile": how})
    except NoPeriodError as exc:
        print_wrapped(f"{args.file}: no periodic feed mark: {exc}; falling back to eq 21")
        return None
    except ValueError as exc:
        raise UsageError(f"{args.file}: {exc}") from None
    model = fitted.model
    print_wrapped(f"fitted to {args.file}: {model.describe()}")
    print_wrapped(f"profile: {how}; {z.size} points, spacing {spacing:g} um "
                  f"({heights.spacing_source}); operators: {'; '.join(model.operators)}")
    how_fit = model.fit
    print_wrapped(f"  {how_fit['marks']} whole marks; the mark of one half of the profile "
                  f"explains {how_fit['mark_reproducibility']:.3f} of the other half's variance")
    return model


def note_periodic_mark(args, heights, operators, z) -> None:
    """``--model auto`` on a map whose feed mark repeats: say that --model periodic describes
    it (the ladder below is stationary; it is not among auto's choices, which krige)."""
    if getattr(args, "fell_back", False):
        return
    from roughgp.surface_models.periodic_model import find_mark
    try:
        found = find_mark(z, heights.spacing, form=operators["form"],
                          degree=operators["degree"], axis=operators["axis"])
    except ValueError:
        return
    if found is not None:
        direction, marks = found
        print_wrapped(f"note: {args.file} holds a feed mark that repeats along {direction} "
                      f"(feed {marks.feed:.5g} um; the mark of one half explains "
                      f"{marks.reproducibility:.2f} of the other half's variance): --model "
                      f"periodic describes it as a mark plus GPs; the stationary ladder below "
                      f"draws its lines with random phases (the flaw of figure 7)")
