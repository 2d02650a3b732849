"""Like with like: a model of the form-removed heights, its simulations put through the rest of
the operator chain (holes, F, S, L) as the measurement went (roughgp.surface_models)."""

from __future__ import annotations

import numpy as np

from roughgp.checking.model_check import check_model
from roughgp.surface_models.chain import rest_of_chain
from roughgp.surface_models.fit import fit_surface_model
from roughgp.surface_models.model import FittedModel

TRUTH = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 8.0, "lambda_b_um": 3.0,
                             "angle_deg": 30.0, "noise_variance_um2": 0.01}, (1.0, 1.0))


def test_rest_of_chain_gives_the_simulation_the_holes_and_the_l_filter():
    model = FittedModel("eq18", TRUTH.hyperparameters, (1.0, 1.0),
                        cutoffs={"form": "plane", "s_um": None, "l_um": 10.0})
    draw = model.simulate((64, 64), seed=1)
    holes = np.zeros(draw.shape, dtype=bool)
    holes[10:20, 5:25] = True
    chained = rest_of_chain(model, draw, (1.0, 1.0), holes).sl
    assert np.array_equal(np.isnan(chained), holes)
    # an L-filter of 10 um on lengths of 8 and 3 um takes a good share of the variance away
    assert np.nanstd(chained) < 0.9 * np.std(draw)
    plain = rest_of_chain(FittedModel(**{**model.__dict__, "stage": "filtered"}), draw,
                          (1.0, 1.0), holes).sl
    assert abs(np.nanstd(plain) - np.nanstd(draw[~holes])) < 0.05 * np.std(draw)


def test_an_l_filtered_eq18_surface_is_reproduced_only_like_with_like():
    z = TRUTH.simulate((96, 96), seed=104)
    fits = {stage: fit_surface_model(z, 1.0, l=20.0, block=16, n_blocks=10, seed=0,
                                     stage=stage).model for stage in ("form-removed", "filtered")}
    # the form-removed fit finds the truth's lengths; the filtered one about half of them
    assert abs(fits["form-removed"].hyperparameters["lambda_a_um"] / 8.0 - 1) < 0.3
    assert fits["filtered"].hyperparameters["lambda_a_um"] < 0.7 * 8.0
    like = check_model(fits["form-removed"], z, n_simulations=19, seed=0)
    assert not {"Sq", "Sz", "Sal"} & set(like.outside), like.outside
    assert any("L: Gaussian" in op for op in like.operators)
    unlike = check_model(fits["filtered"], z, n_simulations=19, seed=0)
    assert "Sal" in unlike.outside


def test_simulate_from_puts_the_draw_through_the_chain_unless_asked_not_to(tmp_path, capsys):
    from roughgp.cli.main import main
    model = FittedModel("eq18", TRUTH.hyperparameters, (1.0, 1.0),
                        cutoffs={"form": "plane", "s_um": None, "l_um": 10.0})
    path = model.save(tmp_path / "m.json")
    heights = {}
    for name, extra in (("chain", []), ("stage", ["--model-stage"])):
        out = tmp_path / f"{name}.npy"
        argv = ["simulate", "--from", str(path), "--shape", "64", "64", "--seed", "2", "--out",
                str(out), *extra]
        assert main(argv) == 0
        heights[name] = np.load(out)
    err = capsys.readouterr().err
    assert "L: Gaussian 10 um" in err
    assert np.std(heights["chain"]) < 0.9 * np.std(heights["stage"])
    code = main(["simulate", "--model-stage", "ground", "--shape", "8", "8", "--out",
                 str(tmp_path / "g.npy")])
    assert code == 2 and "--model-stage is for a draw from a model file" in capsys.readouterr().err
