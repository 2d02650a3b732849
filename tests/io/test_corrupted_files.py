"""Hostile input: every file of ``data/`` truncated, bit-flipped and emptied. Each either
reads as a plausible measurement or is refused with a message that names the file; never a
traceback, never a silent absurd number (issue 32)."""

import time

import numpy as np
import pytest

from roughgp.experiments.real_maps import DATA
from roughgp.io import plausibility
from roughgp.io.measurement import read_measurement
from roughgp.io.readers import MalformedFileError

FILES = sorted(p.name for p in DATA.iterdir() if p.suffix != ".md" and "LICENSE" not in p.name)


def _variants(raw: bytes, seed: int):
    rng = np.random.default_rng(seed)
    out = {"empty": b"", "first-100-bytes": raw[:100], "half": raw[:len(raw) // 2]}
    for kind, end in (("header", min(len(raw), 2048)), ("anywhere", len(raw)),
                      ("anywhere", len(raw))):
        flipped = bytearray(raw)
        at = int(rng.integers(end))
        flipped[at] ^= 0xFF
        out[f"flip-{kind}-{at}"] = bytes(flipped)
    return out


@pytest.mark.parametrize("name", FILES)
def test_corrupted_copies_read_plausibly_or_are_refused_by_name(tmp_path, name):
    raw = (DATA / name).read_bytes()
    for variant, data in _variants(raw, seed=FILES.index(name)).items():
        path = tmp_path / f"{variant}-{name}"
        path.write_bytes(data)
        start = time.perf_counter()
        try:
            m = read_measurement(path)
        except (MalformedFileError, ValueError) as error:
            assert str(error).startswith(str(path)), (variant, str(error))
            assert "physical_sizes" not in str(error) and "[0, 0)" not in str(error)
            assert len(str(error)) < len(str(path)) + 400, (variant, str(error)[:500])
            assert str(error).isprintable(), (variant, str(error)[:500])
        else:
            plausibility.check_reading(m.z, m.spacing, path)  # what read_measurement checked
            assert np.nanmax(np.abs(m.z)) <= plausibility.BOUNDS["height"]
        assert time.perf_counter() - start < 30, variant
