"""One output-path rule for every writer (issue 32, "suffix tricks" and "atomic outputs"): the
file written is the file named (no second extension), so the never-over-the-input and
``--force`` checks see it; missing folders are made by every command alike, a place that
cannot be written is refused before any computation; every write is whole or absent, also
when the command is interrupted by SIGINT; the message names the file written."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.io import writers, x3p
from cli_run import run as _run

ROOT = Path(__file__).resolve().parents[2]


def _holes(shape=(16, 20), seed=0):
    z = np.random.default_rng(seed).normal(size=shape)
    z[3, 4] = z[7, 9] = np.nan
    return z


@pytest.fixture
def profile(tmp_path):
    path = tmp_path / "p.csv"
    x = np.arange(96) * 0.5
    z = np.sin(x) + 0.1 * np.random.default_rng(1).normal(size=x.size)
    np.savetxt(path, np.column_stack((x, z)), delimiter=",", fmt="%.6f")
    return path


def test_fill_to_the_inputs_name_without_its_npy_suffix_keeps_the_input(capsys, tmp_path):
    """``fill H.NPY.npy --out H.NPY`` wrote ``H.NPY.npy`` (numpy appends .npy), the input."""
    source = tmp_path / "H.NPY.npy"
    np.save(source, _holes())
    before = source.read_bytes()
    out = tmp_path / "H.NPY"
    code, _, err = _run(capsys, "fill", source, "--out", out, "--no-check", "--block", 8)
    assert code == 0, err
    assert source.read_bytes() == before
    with open(out, "rb") as handle:  # the file named, in .npy format
        filled = np.load(handle)
    assert filled.shape == (16, 20) and np.all(np.isfinite(filled))
    assert f"wrote {out} " in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["H.NPY", "H.NPY.npy"]


def test_simulate_to_an_upper_case_npy_name_twice_needs_force(capsys, tmp_path):
    out = tmp_path / "S.NPY"
    argv = ("simulate", "ground", "--shape", 8, 8, "--lambda-a", 4, "--seed", 1, "--out", out)
    code, _, err = _run(capsys, *argv)
    assert code == 0 and f"wrote {out} " in err, err
    first = out.read_bytes()
    code, _, err = _run(capsys, *argv[:-4], "--seed", 2, "--out", out)
    assert code == 2 and "exists; give --force" in err and out.read_bytes() == first
    code, _, err = _run(capsys, *argv[:-4], "--seed", 2, "--out", out, "--force")
    assert code == 0 and out.read_bytes() != first
    assert sorted(p.name for p in tmp_path.iterdir()) == ["S.NPY"]


def _commands(tmp_path, profile, folder):
    """Every command that writes, each writing into ``folder`` (which may not exist)."""
    surface = tmp_path / "s.x3p"
    if not surface.exists():
        x3p.write_x3p(surface, _holes(), 1.0)
    model = tmp_path / "model.json"
    if not model.exists():
        assert main(["fit", "profile", str(profile), "--mixtures", "1", "--candidates", "1",
                     "--out", str(model)]) == 0
    return {
        "simulate": ["simulate", "ground", "--shape", 8, 8, "--lambda-a", 4, "--seed", 1,
                     "--out", folder / "a" / "g.csv"],
        "simulate --from": ["simulate", "--from", model, "--shape", 1, 64, "--seed", 1,
                            "--out", folder / "b" / "p.csv"],
        "fill": ["fill", surface, "--no-check", "--block", 8, "--out", folder / "c" / "f.x3p",
                 "--sd", folder / "c" / "d" / "sd.npy"],
        "fit": ["fit", "profile", profile, "--mixtures", 1, "--candidates", 1,
                "--out", folder / "e" / "m.json"],
        "texture": ["texture", surface, "--json", folder / "f" / "t.json"],
        "check": ["check", model, profile, "--simulations", 3, "--json", folder / "g" / "c.json",
                  "--plot", folder / "g" / "p" / "c.png"],
    }


@pytest.mark.parametrize("command", ["simulate", "simulate --from", "fill", "fit", "texture",
                                     "check"])
def test_every_command_makes_missing_folders(capsys, tmp_path, profile, command):
    argv = _commands(tmp_path, profile, tmp_path / "new")[command]
    capsys.readouterr()
    code, _, err = _run(capsys, *argv)
    assert code == 0, err
    written = [a for a in argv if isinstance(a, Path) and "new" in a.parts]
    assert written and all(path.is_file() and path.stat().st_size > 0 for path in written)
    for path in written:
        assert f"wrote {path}" in err
    leftovers = [p for p in (tmp_path / "new").rglob("*") if ".partial" in p.name]
    assert leftovers == []


@pytest.mark.parametrize("command", ["simulate", "simulate --from", "fill", "fit", "texture",
                                     "check"])
def test_a_folder_that_is_a_file_is_refused_before_any_computation(capsys, tmp_path, profile,
                                                                    command, monkeypatch):
    blocker = tmp_path / "blocker"
    blocker.write_text("a file, not a folder\n")
    argv = _commands(tmp_path, profile, blocker)[command]
    capsys.readouterr()
    from roughgp.io import measurement

    def no_reading(*args, **kwargs):  # the check comes before the input is even read
        raise AssertionError("read the input before checking the output path")
    monkeypatch.setattr(measurement, "read_measurement", no_reading)
    code, _, err = _run(capsys, *argv)
    assert code == 2 and "is not a directory" in err and "Traceback" not in err, err
    assert blocker.read_text() == "a file, not a folder\n"


def test_atomic_output_leaves_the_old_file_when_the_writer_fails(tmp_path):
    path = tmp_path / "kept.json"
    path.write_text("old\n")
    with pytest.raises(RuntimeError):
        with writers.atomic_output(path) as partial:
            partial.write_text("half of the new")
            raise RuntimeError("the writer failed")
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["kept.json"]


_SLOW_WRITER = """
import sys
import numpy as np
from roughgp.io.writers import write_heights
z = np.random.default_rng(0).normal(size=(3000, 2000))
try:
    write_heights(sys.argv[1], z, 1.0, "a large surface, written slowly as text")
except KeyboardInterrupt:
    sys.exit(130)
"""


def _writing(folder: Path, before: dict) -> bool:
    """Whether a file in ``folder`` is being written: a new file with bytes in it, or one of
    ``before`` (name -> size) changed (whatever way the writer writes)."""
    for path in folder.iterdir():
        size = path.stat().st_size
        if (path.name not in before and size > 0) or before.get(path.name, size) != size:
            return True
    return False


def _interrupt_while_writing(argv, folder: Path, *, env=None, sig=signal.SIGINT) -> int:
    """Start ``argv``, wait until it writes into ``folder``, send ``sig`` (SIGINT), and return
    the exit code."""
    before = {p.name: p.stat().st_size for p in folder.iterdir()}
    process = subprocess.Popen(argv, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT),
                                                     **(env or {})},
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 240
    try:
        while time.monotonic() < deadline:
            if _writing(folder, before):
                break
            if process.poll() is not None:
                raise AssertionError(f"ended before writing: {process.stderr.read()!r}")
            time.sleep(0.02)
        else:
            raise AssertionError("nothing was written")
        process.send_signal(sig)
        return process.wait(timeout=120)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_sigterm_during_simulate_leaves_no_partial_file(tmp_path):
    """Issue 44 part 2: SIGTERM (what ``timeout`` and ``kill`` send) left the temporary
    ``.NAME.<hex>.partial.csv``; it is cleaned up as SIGINT is, exit 143."""
    out = tmp_path / "x.csv"
    argv = [sys.executable, "-m", "roughgp.cli.main", "simulate", "ground", "--shape", "1200",
            "1200", "--lambda-a", "4", "--lambda-b", "2", "--seed", "1", "--out", str(out)]
    code = _interrupt_while_writing(argv, tmp_path, sig=signal.SIGTERM)
    assert code == 143
    assert list(tmp_path.iterdir()) == []


def test_sigint_during_a_write_leaves_no_partial_file(tmp_path):
    out = tmp_path / "x.csv"
    code = _interrupt_while_writing([sys.executable, "-c", _SLOW_WRITER, str(out)], tmp_path)
    assert code == 130
    assert list(tmp_path.iterdir()) == []  # neither x.csv nor its temporary file


def test_sigint_during_simulate_keeps_the_old_file_whole(tmp_path):
    out = tmp_path / "x.csv"
    out.write_text("# the file from before\n1,2,3\n")
    argv = [sys.executable, "-m", "roughgp.cli.main", "simulate", "ground", "--shape", "1200",
            "1200", "--lambda-a", "4", "--lambda-b", "2", "--seed", "1", "--out", str(out),
            "--force"]
    code = _interrupt_while_writing(argv, tmp_path)
    assert code == 130
    assert out.read_text() == "# the file from before\n1,2,3\n"
    assert [p.name for p in tmp_path.iterdir()] == ["x.csv"]
