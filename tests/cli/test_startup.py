"""The command line starts without torch (issue 32, "a command line that starts in a blink"):
``roughgp --help``, ``roughgp texture`` and ``roughgp simulate ground|honed|turned`` on the
CPU import no torch; the commands that compute with it import it themselves. The times are
measured by ``benchmarks/cli_startup.py``, not here."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughgp.io import x3p

ROOT = Path(__file__).resolve().parents[2]


def _modules_after(code: str) -> set:
    """The names in ``sys.modules`` after ``code`` runs in a fresh interpreter."""
    probe = f"{code}\nimport sys\nprint(' '.join(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True,
                          text=True, env={"PYTHONPATH": str(ROOT), "PATH": ""}, timeout=120)
    assert done.returncode == 0, done.stderr
    return set(done.stdout.split())


def test_the_entry_point_imports_no_torch():
    modules = _modules_after("import roughgp.cli.main")
    assert "roughgp.cli.main" in modules
    assert "torch" not in modules and "scipy.signal" not in modules


def test_help_imports_no_torch():
    modules = _modules_after("from roughgp.cli.main import main\n"
                             "assert main(['--help']) == 0")
    assert "torch" not in modules


def test_texture_of_a_file_imports_no_torch(tmp_path):
    path = tmp_path / "s.x3p"
    x3p.write_x3p(path, np.random.default_rng(0).normal(size=(40, 48)), 1.0)
    modules = _modules_after("from roughgp.cli.main import main\n"
                             f"assert main(['texture', {str(path)!r}]) == 0")
    assert "roughgp.metrology.texture_report" in modules  # the work was done
    assert "torch" not in modules


def test_texture_of_an_opd_imports_no_scipy_optimize_special_or_fft():
    """The one-reader path defers NuMPI (its scipy.optimize), the filters convolve with
    numpy.fft and the robust filters' gamma needs no scipy.special: 0.5-1 s off every
    ``roughgp texture`` on the 2-core machine (benchmarks/cli_startup.py)."""
    modules = _modules_after("from roughgp.cli.main import main\n"
                             "assert main(['texture', 'data/opd-1.opd']) == 0")
    assert "roughgp.metrology.texture_report" in modules
    assert not {"torch", "scipy.optimize", "scipy.special", "scipy.fft"} & modules


@pytest.mark.parametrize("kind", [
    ["honed", "--shape", "24", "24", "--method", "cholesky"],
    ["honed", "--shape", "24", "24", "--method", "circulant"],
    ["ground", "--shape", "16", "20"],
    ["turned", "--shape", "32", "32"],
    ["turned", "--profile", "256"],
])
def test_a_draw_on_the_cpu_imports_no_torch(tmp_path, kind):
    """simulate's exact samplers on the CPU (dense Cholesky, circulant) run in numpy and scipy
    alone: no torch, no GPyTorch in the process (the draw's kernels are those of
    roughgp.gp.numpy_kernels)."""
    out = tmp_path / "s.npy"
    modules = _modules_after("from roughgp.cli.main import main\n"
                             f"assert main(['simulate', *{kind!r}, '--seed', '1', "
                             f"'--out', {str(out)!r}]) == 0")
    assert "roughgp.models.surfaces" in modules and out.exists()  # the work was done
    assert "torch" not in modules and "gpytorch" not in modules


def test_the_probe_sees_torch_where_a_command_imports_it(tmp_path):
    """Calibration: the probe above can say no (a GPyTorch kernel, a draw on a torch device)."""
    assert "torch" in _modules_after("import roughgp.gp.kernels")
    modules = _modules_after("from roughgp.cli.main import main\n"
                             f"assert main(['simulate', 'ground', '--shape', '8', '8', "
                             f"'--device', 'cpu', '--out', {str(tmp_path / 'd.npy')!r}]) == 0")
    assert "torch" in modules
