"""Figure helpers for the book: one style, and the plots that several chapters draw.

Chapters call :func:`use_style` once; every helper takes an ``ax`` and labels it with units.
"""

from __future__ import annotations

from importlib.resources import files

import matplotlib.pyplot as plt
import numpy as np

__all__ = ["use_style", "STYLE", "image", "compare_curves"]

STYLE = str(files("roughgp") / "roughgp.mplstyle")
"""Path of the book's matplotlib style file."""


def use_style():
    """Apply the book's figure style (colour-blind-safe cycle, light grid, tight layout)."""
    plt.style.use(STYLE)


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
