"""Figure helpers for the book: one style, and the plots that several chapters draw.

Chapters call :func:`use_style` once; every helper takes an ``ax`` and labels it with units.
"""

from __future__ import annotations

import re
from importlib.resources import files

import matplotlib.pyplot as plt
import numpy as np

from roughgp.common.page import (MIN_FONT_PT, PAGE_WIDTH_PX, points_on_page,
                                 smallest_text_on_page, visible_texts)
from roughgp.common.shown_figures import record_shown_figures

__all__ = ["use_style", "STYLE", "PAGE_WIDTH_PX", "MIN_FONT_PT", "PAGE_TEXT_PT",
           "font_sizes_on_page", "page_text_problems", "smallest_text_on_page",
           "overlapping_tick_labels", "row_of_axes", "ROW_WIDTH_IN",
           "image", "compare_curves",
           "acvf_figure", "surface_figure"]

STYLE = str(files("roughgp.common") / "roughgp.mplstyle")
"""Path of the book's matplotlib style file."""


PAGE_TEXT_PT = 11.0
"""The book's rule for a chapter's figures: every text (ticks, labels, titles, legends,
colour bars, annotations) at least this size on the page, lengths in µm
(:func:`page_text_problems`). A figure at most 6.25 in wide (the text column at the style's
110 dpi) keeps the style's 10-11 pt text at 11.5-12.6 pt; a wider one is shrunk with its text."""


_UM = re.compile(r"\bum\b")


def page_text_problems(fig, min_pt=PAGE_TEXT_PT, page_width_px=PAGE_WIDTH_PX) -> list[str]:
    """What breaks the book's rule (:data:`PAGE_TEXT_PT`) in ``fig``: each visible text smaller
    than ``min_pt`` CSS points on the page (as :func:`font_sizes_on_page` measures, but every
    text of the figure: legends, colour bars and annotations too), and each that writes a
    length in ``um`` instead of µm. An empty list when the figure keeps the rule."""
    scale = points_on_page(fig, page_width_px)
    problems = []
    for text in visible_texts(fig):
        words = text.get_text()
        size = text.get_fontsize() * scale
        if size < min_pt - 1e-9:
            problems.append(f"{words!r}: {size:.1f} pt on the page (< {min_pt:g})")
        if _UM.search(words):
            problems.append(f"{words!r}: lengths in µm, not um")
    return problems


def overlapping_tick_labels(fig) -> list[str]:
    """Neighbouring tick labels on an axis of ``fig`` whose drawn boxes overlap (text the
    reader cannot read), as ``"'a' and 'b'"``; an empty list when none do."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    problems = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for labels in (ax.get_xticklabels(), ax.get_yticklabels()):
            boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in labels
                     if t.get_visible() and t.get_text()]
            problems += [f"{a!r} and {b!r}" for (a, box_a), (b, box_b) in zip(boxes, boxes[1:])
                         if box_a.overlaps(box_b)]
    return problems


def font_sizes_on_page(fig, page_width_px=PAGE_WIDTH_PX):
    """The sizes (CSS points, 1 pt = 4/3 px) at which the tick labels, axis labels and titles of
    ``fig`` appear on the book's page: the notebook shows a figure at ``fig.dpi`` pixels per
    inch, shrunk to the text column when wider (``page_width_px``). Returns
    ``{"ticks": smallest, "labels": smallest, "titles": smallest}`` over the visible axes."""
    to_page = points_on_page(fig, page_width_px)  # figure points -> CSS points on the page
    sizes = {"ticks": [], "labels": [], "titles": []}
    fig.canvas.draw()
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for label in ax.get_xticklabels() + ax.get_yticklabels():
            if label.get_visible() and label.get_text():
                sizes["ticks"].append(label.get_fontsize())
        for text in (ax.xaxis.label, ax.yaxis.label):
            if text.get_text():
                sizes["labels"].append(text.get_fontsize())
        if ax.title.get_text():
            sizes["titles"].append(ax.title.get_fontsize())
    return {kind: min(values) * to_page if values else None for kind, values in sizes.items()}


def use_style():
    """Apply the book's figure style (colour-blind-safe cycle, light grid, tight layout); in a
    notebook, also record with each figure shown its size on the page
    (:func:`roughgp.common.shown_figures.record_shown_figures`)."""
    plt.style.use(STYLE)
    record_shown_figures()


ROW_WIDTH_IN = 7.6
"""Widest row of axes (inches at the style's 110 dpi: 836 px) whose 10 pt legends stay >= 9 pt
once shrunk to the column."""


def row_of_axes(ncols=1, width=None, height=3.4):
    """A new figure with ``ncols`` axes in a row, each ``width`` x ``height`` inches (by default
    4 in, or :data:`ROW_WIDTH_IN` shared by the row when that is narrower): ``(figure, axes)``."""
    if width is None:
        width = min(4.0, ROW_WIDTH_IN / ncols)
    fig, axes = plt.subplots(1, ncols, figsize=(width * ncols, height), squeeze=False)
    return fig, axes[0]


def image(ax, values, extent, *, xlabel, ylabel, colorbar_label, cmap=None, symmetric=False,
          **kwargs):
    """Show a 2-D array ``values[iy, ix]`` with y upwards, labelled axes and a colour bar.

    ``extent`` is ``(x0, x1, y0, y1)`` in the axis unit; ``symmetric=True`` centres the colour
    scale on zero.
    """
    if symmetric:
        vmax = float(np.nanmax(np.abs(values)))
        kwargs.setdefault("vmin", -vmax)
        kwargs.setdefault("vmax", vmax)
        cmap = cmap or "RdBu_r"
    artist = ax.imshow(values, origin="lower", extent=extent, cmap=cmap, aspect="equal",
                       interpolation="nearest", **kwargs)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    ax.figure.colorbar(artist, ax=ax, label=colorbar_label, shrink=0.85)
    return artist


def compare_curves(ax, x, curves, *, xlabel, ylabel, logy=False, styles=None):
    """Plot several named curves over the same ``x`` (``curves``: label -> values)."""
    styles = styles or {}
    for label, y in curves.items():
        ax.plot(x, y, label=label, **styles.get(label, {}))
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend()
    return ax


def acvf_figure(kernel, half_width, *, n=201, angle=None, level=None, height_unit="height"):
    """Figure 1 style: a 2-D ACVF as a 3-D surface and as an image over lags in
    ``[-half_width, half_width]^2``; ``angle`` draws the groove direction, ``level`` a contour
    (e.g. ``r(0)/e``). Returns the figure and the axes ``(ax3d, ax)``."""
    from roughgp.common.grid import centred_lags

    lags = centred_lags((n, n), 2 * half_width / (n - 1))
    r = kernel.acvf(lags)
    fig = plt.figure(figsize=(8, 3.6))
    ax3d = fig.add_subplot(1, 2, 1, projection="3d")
    stride = max(1, n // 200)  # fine enough for a thin ridge (figure 2: 5 wide in 400)
    ax3d.plot_surface(lags[..., 0], lags[..., 1], r, cmap="viridis", rstride=stride,
                      cstride=stride, linewidth=0)
    ax3d.set(xlabel=r"$\tau_x$", ylabel=r"$\tau_y$", zlabel=r"$r(\tau)$")
    ax = fig.add_subplot(1, 2, 2)
    w = half_width
    image(ax, r, (-w, w, -w, w), xlabel=r"$\tau_x$ (length unit)", ylabel=r"$\tau_y$ (length unit)",
          colorbar_label=rf"$r(\tau)$ ({height_unit}$^2$)")
    if level is not None:
        ax.contour(lags[..., 0], lags[..., 1], r, levels=[level], colors="w")
    if angle is not None:
        d = 0.8 * w
        ax.plot([-d * np.cos(angle), d * np.cos(angle)], [-d * np.sin(angle), d * np.sin(angle)],
                "w--", lw=1)
    return fig, (ax3d, ax)


def surface_figure(z, spacing=1.0, *, height_unit="height unit", length_unit="grid unit",
                   max_points_3d=200, title=None):
    """A surface ``z[iy, ix]`` twice: a 3-D perspective view (as the paper renders its
    figures; subsampled to at most ``max_points_3d`` per axis) and a height map with a colour
    bar in ``height_unit``. Returns the figure and the axes ``(ax3d, ax)``."""
    z = np.asarray(z, dtype=np.float64)
    ny, nx = z.shape
    dy, dx = np.broadcast_to(np.asarray(spacing, dtype=np.float64), (2,))
    step = max(1, int(np.ceil(max(ny, nx) / max_points_3d)))
    y, x = np.mgrid[0:ny:step, 0:nx:step]
    fig = plt.figure(figsize=(8, 3.8))
    ax3d = fig.add_subplot(1, 2, 1, projection="3d")
    ax3d.plot_surface(x * dx, y * dy, z[::step, ::step], cmap="viridis", linewidth=0,
                      antialiased=False, rcount=z[::step, ::step].shape[0],
                      ccount=z[::step, ::step].shape[1])
    ax3d.set(xlabel=f"x ({length_unit})", ylabel=f"y ({length_unit})",
             zlabel=f"z ({height_unit})")
    ax = fig.add_subplot(1, 2, 2)
    image(ax, z, (0, nx * dx, 0, ny * dy), xlabel=f"x ({length_unit})",
          ylabel=f"y ({length_unit})", colorbar_label=f"height z ({height_unit})", cmap="viridis")
    if title:
        fig.suptitle(title)
    return fig, (ax3d, ax)
