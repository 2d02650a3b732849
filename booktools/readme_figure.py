"""The README's figure (``python -m booktools.readme_figure``, writes ``book/images/surfaces.png``):
a ground surface (eq 18, figure 2's hyperparameters on a 512 x 512 corner), a plateau-honed
surface (eq 20, figure 3's steps) and the measured bullet land of ``data/`` with its holes."""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "book" / "images" / "surfaces.png"


def main(out: Path = OUT) -> Path:
    from roughgp.common import plotting
    from roughgp.io.measurement import read_measurement
    from roughgp.metrology.texture_report import filtered_parameters
    from roughgp.models import surfaces

    plotting.use_style()
    p2 = surfaces.FIGURE_2
    ground = surfaces.ground((512, 512), variance=p2.variance, lengthscales=p2.lengthscales,
                             angle=p2.angle, seed=2)
    honed = surfaces.honed(surfaces.FIGURE_3_SHAPE, surfaces.FIGURE_3, seed=3)
    land = read_measurement(ROOT / "data" / "sample-land.x3p")
    sl = filtered_parameters(land.z, land.spacing, form="cylinder", l=250.0).texture.sl
    fig, axes = plt.subplots(1, 3, figsize=(9, 3.0))
    panels = ((ground, 1.0, "ground (eq 18, figure 2)", "grid unit"),
              (honed, 1.0, "plateau-honed (eq 20, figure 3)", "grid unit"),
              (sl[:224, 331:587], land.spacing[1], "measured bullet land (holes white)", "µm"))
    for ax, (z, step, title, unit) in zip(axes, panels):
        ny, nx = z.shape
        low, high = np.nanpercentile(z, [1, 99])
        ax.imshow(z, origin="lower", extent=(0, nx * step, 0, ny * step), vmin=low, vmax=high,
                  cmap="viridis", interpolation="nearest")
        ax.set(title=title, xlabel=f"x ({unit})", ylabel=f"y ({unit})")
        ax.grid(False)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=80)
    return out


if __name__ == "__main__":
    print(f"wrote {main()}")
    sys.exit(0)
