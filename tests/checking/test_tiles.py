"""The tile check (roughgp.checking.tiles, issue 40): tiles that cover the map once, their
refusals, and a map of where a stationary model fails on a surface whose roughness grows."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.checking.tiles import MIN_TILE, plot_tile_check, tile_check, tile_slices
from roughgp.experiments.held_out import synthetic_map


def test_the_tiles_cover_every_point_once():
    cover = np.zeros((50, 70), dtype=int)
    slices = tile_slices(cover.shape, (3, 4))
    for rows, cols in slices:
        cover[rows, cols] += 1
    assert len(slices) == 12 and (cover == 1).all()


@pytest.mark.parametrize("tiles", [(4, 1), (0, 2), (1, 5)])
def test_too_many_tiles_are_refused_with_the_allowed_range(tiles):
    with pytest.raises(ValueError, match=r"m in \[1, 3\] and n in \[1, 4\]") as error:
        tile_slices((50, 70), tiles)
    assert f"{MIN_TILE} x {MIN_TILE} points" in str(error.value)


def test_tiles_must_be_two_integers():
    with pytest.raises(ValueError, match="two integers"):
        tile_slices((50, 70), (2,))


def test_the_tile_map_shows_the_rough_side():
    """A stationary map made three times rougher on its right half, checked against the true
    model of its left half: Sq outside (above) in every right tile, in few of the left."""
    z, left, _ = synthetic_map("stationary", 3, shape=(32, 128))
    z = z.copy()
    z[:, 64:] *= 3.0
    result = tile_check(left, z, tiles=(1, 4), n_simulations=19, seed=4)
    k = result.names.index("Sq")
    assert result.outside[0, 2:, k].all()
    assert result.outside[0, :2, k].sum() <= 1
    assert (result.measured[0, 2:, k] > result.simulated[:, 0, 2:, k].max(axis=0)).all()
    assert (result.side[0, 2:, k] == 1).all() and (result.side != 0).sum() == result.outside.sum()
    assert result.expected_share == pytest.approx(0.1)
    assert 0.5 <= result.outside_share("Sq") <= 0.75
    record = result.to_dict()
    assert record["tiles"] == [1, 4] and record["parameters"][k]["outside"][0][2:] == [1, 1]
    again = tile_check(left, z, tiles=(1, 4), n_simulations=19, seed=4)
    assert np.array_equal(again.simulated, result.simulated, equal_nan=True)


def test_the_tile_check_keeps_the_holes_and_refuses_bad_counts(tmp_path):
    z, left, _ = synthetic_map("holes", 0, shape=(32, 64))
    assert np.isnan(z).any()
    result = tile_check(left, z, tiles=(2, 2), n_simulations=4, seed=0)
    assert any("unmeasured" in note for note in result.notes)
    assert np.isfinite(result.measured).all()
    figure = plot_tile_check(result, tmp_path / "tiles.png")
    assert (tmp_path / "tiles.png").stat().st_size > 0
    figure.clf()
    with pytest.raises(ValueError, match=r"n_simulations must be an integer in \[2, 999\]"):
        tile_check(left, z, n_simulations=1)
    with pytest.raises(ValueError, match="z\\[iy, ix\\]"):
        tile_check(left, z[0])
