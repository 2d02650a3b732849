r"""The tile check: where on the map the model fails (beyond the paper; issue 40).

The map is cut into ``m x n`` tiles after the model's operators (F, S, L) have been applied
to the whole map; each of ``n_simulations`` simulations of the whole map goes through the rest
of the chain with the measurement's holes (:func:`roughgp.surface_models.chain.rest_of_chain`,
as :func:`roughgp.checking.model_check.check_model` does) and is cut the same way. Each tile's
Sq, Sal, Str and Std (:data:`TILE_PARAMETERS`) is ranked among the same tile's values in the
simulations: outside their range with probability :math:`2 / (n + 1)` when the model describes
the surface everywhere. A stationary model of a surface whose roughness changes across the
part puts the rough tiles above and the smooth ones below: the outside tiles, drawn as a map
(:func:`plot_tile_check`), show where. Tiles of one map are not independent (they share the
model and the filters' reach): the share of outside tiles varies more from map to map than a
binomial count would; how often it says so on synthetic surfaces of known models is measured
by ``benchmarks/held_out_calibration.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from roughgp.checking.model_check import (
    axial_frame,
    chain_parameters,
    draw_models,
)
from roughgp.common.checks import as_generator
from roughgp.common.tiling import MIN_TILE, tile_slices
from roughgp.metrology.texture_report import unit_of
from roughgp.surface_models.chain import apply_operators, rest_of_chain
from roughgp.surface_models.model import FittedModel

__all__ = ["TILE_PARAMETERS", "MIN_TILE", "TileCheck", "tile_check", "tile_slices",
           "plot_tile_check"]

TILE_PARAMETERS = ("Sq", "Sal", "Str", "Std")
_SPATIAL = ("Sal", "Str", "Std")


@dataclasses.dataclass(frozen=True)
class TileCheck:
    """What :func:`tile_check` returns.

    Attributes:
        tiles: ``(m, n)``.
        names: the parameters.
        measured: ``(m, n, P)`` the measurement's value per tile and parameter.
        simulated: ``(N, m, n, P)`` the simulations' (Std framed per tile as the check
            frames it, :func:`~roughgp.checking.model_check.axial_frame`).
        outside: ``(m, n, P)`` the measured value below or above every simulated one.
        notes: what the check did.
    """

    tiles: tuple
    names: tuple
    measured: np.ndarray
    simulated: np.ndarray
    outside: np.ndarray
    notes: tuple

    @property
    def n_simulations(self) -> int:
        return int(self.simulated.shape[0])

    @property
    def expected_share(self) -> float:
        """The share of outside tiles for a model that describes the surface, 2 / (N + 1)."""
        return 2.0 / (self.n_simulations + 1)

    @property
    def side(self) -> np.ndarray:
        """``(m, n, P)``: +1 where the measured value lies above every simulation, -1 below
        every one, 0 within."""
        finite = np.isfinite(self.simulated)
        high = np.where(finite, self.simulated, -np.inf).max(axis=0)
        return np.where(self.outside, np.where(self.measured > high, 1, -1), 0)

    def outside_share(self, name) -> float:
        """The share of the tiles where ``name`` lies outside the simulated range."""
        return float(self.outside[..., self.names.index(name)].mean())

    def to_dict(self) -> dict:
        return {"tiles": list(self.tiles), "n_simulations": self.n_simulations,
                "expected_share": self.expected_share, "notes": list(self.notes),
                "parameters": [{"name": name, "unit": unit_of(name),
                                "outside_share": self.outside_share(name),
                                "outside": self.outside[..., k].astype(int).tolist(),
                                "measured": self.measured[..., k].tolist()}
                               for k, name in enumerate(self.names)]}


def _tile_values(heights, holes, spacing, slices, names):
    out = []
    for rows, cols in slices:
        h, gaps = heights[rows, cols], holes[rows, cols]
        spatial = [n for n in names if n in _SPATIAL] if gaps.any() else []
        values = chain_parameters(h, gaps, spacing, names, True, spatial)
        out.append([values[n] for n in names])
    return np.asarray(out, dtype=np.float64)


def tile_check(model: FittedModel, z, spacing=None, *, tiles=(2, 2), n_simulations=19, seed=0,
               names=TILE_PARAMETERS, models=None) -> TileCheck:
    """Rank each tile's parameters among the same tile of ``n_simulations`` simulations of
    ``model`` (module docstring).

    Args:
        model: a surface :class:`~roughgp.surface_models.model.FittedModel`.
        z: the measurement ``z[iy, ix]``, um, NaN where unmeasured (raw heights).
        spacing: of ``z`` (default: the model's).
        tiles: ``(m, n)`` rows and columns of tiles (:func:`tile_slices`).
        n_simulations: an integer in [2, 999].
        seed: of the simulations; the same seed, the same verdicts.
        names: parameters of :func:`~roughgp.metrology.texture.areal_parameters`.
        models: None (the plug-in draws) or the predictive draws' models
            (:func:`~roughgp.checking.model_check.draw_models`).
    """
    if model.kind != "surface":
        raise ValueError(f"the tile check is for surface models, got a {model.kind} model")
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"the tile check needs a surface z[iy, ix], got shape {z.shape}")
    if not isinstance(n_simulations, (int, np.integer)) or not 2 <= n_simulations <= 999:
        raise ValueError(f"n_simulations must be an integer in [2, 999], got {n_simulations!r}")
    slices = tile_slices(z.shape, tiles)
    m, n = (int(t) for t in tiles)
    names = tuple(names)
    spacing = model.spacing if spacing is None else spacing
    rng = as_generator(seed)
    chain = apply_operators(z, spacing, model.cutoffs)
    heights = chain.sl
    holes = ~np.isfinite(heights)
    measured = _tile_values(heights, holes, spacing, slices, names)
    simulated = []
    for source in draw_models(model, models, n_simulations):
        draw = source.simulate(z.shape, seed=rng, spacing=spacing)
        h = rest_of_chain(model, draw, spacing, holes if holes.any() else None).sl
        simulated.append(_tile_values(h, holes, spacing, slices, names))
    simulated = np.asarray(simulated)  # (N, tiles, P)
    if "Std" in names:
        k = names.index("Std")
        for t in range(len(slices)):
            simulated[:, t, k] = axial_frame(simulated[:, t, k], measured[t, k])
    finite = np.isfinite(simulated)
    low = np.where(finite, simulated, np.inf).min(axis=0)
    high = np.where(finite, simulated, -np.inf).max(axis=0)
    outside = np.isfinite(measured) & finite.any(axis=0) & ((measured < low) | (measured > high))
    notes = [f"{m} x {n} tiles of the map after its operators ("
             f"{'; '.join(chain.operators)}); each tile ranked among the same tile of "
             f"{n_simulations} simulations of the whole map"]
    if holes.any():
        notes.append(f"{holes.mean():.1%} of the points unmeasured: the simulations have the "
                     f"same holes; Sal, Str and Std with the holes set to the mean height")
    if models is not None:
        notes.append("predictive simulations: drawn from the fit's bootstrap refits in turn")
    return TileCheck((m, n), names, measured.reshape(m, n, -1),
                     simulated.reshape(len(simulated), m, n, -1), outside.reshape(m, n, -1),
                     tuple(notes))


def plot_tile_check(check: TileCheck, path=None, *, title=None):
    """One panel per parameter: the tiles, red where the measured value lies above every
    simulation, blue where below every one, grey within. Returns the figure; saves it to
    ``path`` when given."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    from roughgp.common.plotting import use_style

    use_style()
    p = len(check.names)
    fig, axes = plt.subplots(1, p, figsize=(1.7 * p + 0.4, 2.3), squeeze=False)
    colours = ListedColormap(["tab:blue", "0.85", "tab:red"])
    sides = check.side
    for k, (ax, name) in enumerate(zip(axes.flat, check.names)):
        side = sides[..., k]
        ax.imshow(side, cmap=colours, vmin=-1, vmax=1)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"{name}: {int(check.outside[..., k].sum())}/{side.size} out",
                     fontsize=10)
    fig.suptitle(title or f"tiles outside {check.n_simulations} simulations (red above, blue "
                 f"below)", fontsize=10)
    if path is not None:
        fig.savefig(path, dpi=110, bbox_inches="tight")
    return fig
