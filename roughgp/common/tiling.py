"""A map cut into tiles: the rows and columns of each (the tile check of
:mod:`roughgp.checking.tiles` and the local fits of :mod:`roughgp.inference.tile_fit` cut
alike)."""

from __future__ import annotations

__all__ = ["MIN_TILE", "tile_slices"]

MIN_TILE = 16  #: the fewest rows and columns of a tile


def tile_slices(shape, tiles) -> list:
    """The ``(row slice, column slice)`` of each of ``tiles = (m, n)`` tiles of a map of
    ``shape``, row by row (the last row and column of tiles take what does not divide).
    Raises ValueError when a tile would have fewer than :data:`MIN_TILE` rows or columns."""
    ny, nx = (int(s) for s in shape)
    try:
        m, n = (int(t) for t in tiles)
    except (TypeError, ValueError):
        raise ValueError(f"tiles must be two integers (rows, columns), got {tiles!r}") from None
    if m < 1 or n < 1 or ny // m < MIN_TILE or nx // n < MIN_TILE:
        raise ValueError(f"tiles must be (m, n) with m in [1, {max(ny // MIN_TILE, 1)}] and n in"
                         f" [1, {max(nx // MIN_TILE, 1)}] on this {ny} x {nx} map (a tile of "
                         f"at least {MIN_TILE} x {MIN_TILE} points), got {tiles!r}")
    rows = [i * (ny // m) for i in range(m)] + [ny]
    cols = [j * (nx // n) for j in range(n)] + [nx]
    return [(slice(rows[i], rows[i + 1]), slice(cols[j], cols[j + 1]))
            for i in range(m) for j in range(n)]
