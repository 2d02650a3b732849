"""The claims page's section-3.1 bar chart keeps the book's rule (text >= 11 pt on the page,
µm), drawn under matplotlib's defaults as ``roughgp reproduce`` draws it."""

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from roughgp.common import plotting  # noqa: E402
from roughgp.ledger.checks_surfaces import _readings_figure  # noqa: E402


def test_the_readings_figure_keeps_the_books_rule(tmp_path):
    labels = ["as stated: grid units, latent, unbiased", "sigma_k^2 = 1",
              "unit square, figure 1's lambda, sigma_k^2 = 1", "1000 draws"]
    table = [SimpleNamespace(label=label, variance=v, n_draws=n, expected=e, ratio=e / 0.2536)
             for label, v, n, e in zip(labels, (10.0, 1.0, 1.0, 10.0), (50, 50, 50, 1000),
                                       (1.16, 0.116, 0.117, 0.258))]
    setup = SimpleNamespace(parameters=SimpleNamespace(variance=10.0), n_draws=50)
    with plt.rc_context(matplotlib.rcParamsDefault):
        fig = _readings_figure(table, setup, {"cholesky": 0.2536, "lanczos": 0.2763})
    assert plotting.page_text_problems(fig) == []
    texts = " ".join(t.get_text() for t in fig.findobj(matplotlib.text.Text))
    assert "σ_k² = 1 (σ_k² 1, 50 draws)" in texts and "sigma_k" not in texts
    plt.close(fig)
