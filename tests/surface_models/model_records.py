"""Small valid model-file records shared by the tests of this folder."""

from roughgp.surface_models.model import FittedModel

EQ18_RECORD = FittedModel(
    "eq18", {"variance_um2": 2.0, "lambda_a_um": 12.0, "lambda_b_um": 3.0, "angle_deg": 60.0,
             "noise_variance_um2": 0.05, "mean_um": 0.1}, (1.0, 1.0),
    marginal={"skewness": 0.5, "kurtosis": 4.0}).to_dict()
EQ21_RECORD = FittedModel(
    "eq21", {"weights_um2": [1.0, 0.5], "frequencies_per_um": [0.1, 0.02],
             "spectral_variances_per_um2": [1e-4, 1e-5], "noise_variance_um2": 0.01},
    (0.5,)).to_dict()
