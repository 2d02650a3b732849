"""The command line starts without torch (issue 32, "a command line that starts in a blink"):
``roughgp --help`` and ``roughgp texture`` import no torch; the commands that compute with it
import it themselves. The times are measured by ``benchmarks/cli_startup.py``, not here."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from roughgp.metrology import x3p

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


def test_the_probe_sees_torch_where_a_command_imports_it():
    """Calibration: the probe above can say no."""
    modules = _modules_after("import roughgp.common.device")
    assert "torch" in modules
