"""The book's figures are readable on its page: text >= 9 pt at the text column's width
(plotting.font_sizes_on_page), for the style's figures up to 8.5 in wide and the model-check
grid."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from roughgp.common import plotting  # noqa: E402


def _figure(width, fontsize=None):
    fig, ax = plt.subplots(figsize=(width, 3.0))
    ax.plot([0, 1], [0, 1])
    ax.set(xlabel="x (µm)", ylabel="height (µm)", title="a title")
    if fontsize:
        ax.tick_params(labelsize=fontsize)
    return fig


def test_the_measure_says_no_for_small_or_shrunk_text():
    plotting.use_style()
    narrow = plotting.font_sizes_on_page(_figure(6.0))
    assert narrow["ticks"] == pytest.approx(11 * 110 / 72 * 0.75)      # not shrunk: 12.6 pt
    # the same figure twice as wide is shrunk to the column: its text with it
    wide = plotting.font_sizes_on_page(_figure(12.0))
    assert wide["ticks"] == pytest.approx(11 * 0.75 * plotting.PAGE_WIDTH_PX / (12 * 72))
    assert wide["ticks"] < plotting.MIN_FONT_PT
    # 7 pt tick labels (the old model-check grid) fail even on a narrow figure
    assert plotting.font_sizes_on_page(_figure(6.0, fontsize=7))["ticks"] < plotting.MIN_FONT_PT
    plt.close("all")


@pytest.mark.parametrize("width", [5.0, 6.4, 8.5])
def test_the_style_keeps_text_readable_up_to_eight_and_a_half_inches(width):
    plotting.use_style()
    sizes = plotting.font_sizes_on_page(_figure(width))
    assert min(v for v in sizes.values() if v is not None) >= plotting.MIN_FONT_PT, sizes
    plt.close("all")


def test_the_model_check_grid_is_readable():
    from roughgp.checking.model_check import ModelCheck, ParameterCheck, plot_model_check

    rng = np.random.default_rng(0)
    names = ("Sq", "Ssk", "Sku", "Sp", "Sv", "Sz", "Sa", "Sal", "Str", "Std", "Sdq", "Sdr")
    parameters = [ParameterCheck(n, "um" if n in ("Sq", "Sal") else "", 1.0, rng.normal(size=19),
                                 0.5, False) for n in names]
    check = ModelCheck(tuple(parameters), 19, (), (), np.zeros((4, 4)), np.zeros((4, 4)))
    fig = plot_model_check(check)
    sizes = plotting.font_sizes_on_page(fig)
    assert min(v for v in sizes.values() if v is not None) >= plotting.MIN_FONT_PT, sizes
    # every text (the suptitle too), at the figure's full width
    width = fig.get_figwidth() * fig.dpi
    assert plotting.smallest_text_on_page(fig, width) >= plotting.MIN_FONT_PT
    assert any("µm" in ax.get_title() for ax in fig.axes) and not any(
        "(um)" in ax.get_title() for ax in fig.axes)
    plt.close("all")


def test_the_chapters_figure_helpers_are_readable():
    """plotting's own figures (figure 1's ACVF, a surface in 3-D and from above, a row of axes)
    keep their text >= 9 pt on the page."""
    plotting.use_style()
    from roughgp.gp import kernels

    kernel = kernels.RotatedExponentialKernel(variance=1.0, lengthscales=(0.5, 0.1), angle=0.5)
    figures = [plotting.acvf_figure(kernel, half_width=1.0, n=41)[0],
               plotting.surface_figure(np.random.default_rng(0).normal(size=(40, 40)))[0],
               plotting.row_of_axes(2)[0]]
    figures[2].axes[0].set(xlabel="lag", ylabel="r", title="t")
    for fig in figures:
        sizes = plotting.font_sizes_on_page(fig)
        assert min(v for v in sizes.values() if v is not None) >= plotting.MIN_FONT_PT, sizes
    plt.close("all")


def test_page_text_problems_says_no_to_small_shrunk_or_um_text_and_yes_to_the_rule():
    plotting.use_style()
    good = _figure(6.4)
    good.axes[0].plot([0, 1], [1, 0], label="a legend")
    good.axes[0].legend()
    assert plotting.page_text_problems(good) == []
    small = _figure(6.4)
    small.axes[0].legend(["x"], fontsize=8)
    assert any("'x'" in p and "pt on the page" in p for p in plotting.page_text_problems(small))
    shrunk = plotting.page_text_problems(_figure(9.0))  # 11 pt shrunk to about 8.8 pt
    assert shrunk and all("pt on the page" in p for p in shrunk)
    um = _figure(6.4)
    um.axes[0].set_xlabel("x (um)")
    assert plotting.page_text_problems(um) == ["'x (um)': lengths in µm, not um"]
    plt.close("all")


def test_overlapping_tick_labels_names_labels_that_run_into_each_other():
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.set_xticks([0, 1, 2], ["a long label here", "another long label", "x"])
    found = plotting.overlapping_tick_labels(fig)
    assert found and "'a long label here' and 'another long label'" in found[0]
    ax.set_xticks([0, 1, 2], ["a", "b", "c"])
    assert plotting.overlapping_tick_labels(fig) == []
    plt.close(fig)
