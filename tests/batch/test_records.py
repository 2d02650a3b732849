"""roughgp.batch without a cluster: the plan and its digest, each file's seed, the atomic record
and the resume rule, the table, the inputs a folder gives, and one file through its steps
(:func:`roughgp.batch.steps.run_file`, in this process)."""

import json

import numpy as np
import pytest

from roughgp.batch.engine import expand_inputs
from roughgp.batch.records import (
    Plan,
    current_record,
    file_seed,
    read_record,
    record_name,
    write_record,
)
from roughgp.batch.steps import run_file
from roughgp.batch.table import columns, read_csv_table, rows, write_table
from roughgp.common.digests import file_sha256


def test_the_plan_orders_its_steps_and_refuses_what_it_cannot_run():
    assert Plan(steps=("check", "texture", "fit")).steps == ("texture", "fit", "check")
    with pytest.raises(ValueError, match="unknown step 'polish'"):
        Plan(steps=("polish",))
    with pytest.raises(ValueError, match="the step simulate needs the step fit"):
        Plan(steps=("simulate",))
    a = Plan(steps=("texture",), seed=1, options={"texture": {"form": "plane"}})
    assert a.digest() == Plan(steps=("texture",), seed=1,
                              options={"texture": {"form": "plane"}}).digest()
    assert a.digest() != Plan(steps=("texture",), seed=1,
                              options={"texture": {"form": "none"}}).digest()


def test_a_file_s_seed_depends_on_the_seed_and_its_bytes_only():
    sha = "0f" * 32
    assert file_seed(3, sha) == file_seed(3, sha)
    assert len({file_seed(s, sha) for s in range(50)}) == 50
    assert all(0 <= file_seed(s, sha) <= 2**32 - 1 for s in range(50))
    assert record_name("/x/a b.x3p").startswith("a_b.x3p-")
    assert record_name("/x/a.x3p") != record_name("/y/a.x3p")


def test_a_record_is_current_only_for_the_same_bytes_plan_and_version(tmp_path):
    plan = Plan(steps=("texture",))
    record = {"record_format": 1, "roughgp_version": __import__("roughgp").__version__,
              "plan_digest": plan.digest(), "sha256": "ab", "status": "done",
              "value": float("nan")}
    path = tmp_path / "records" / "a.json"
    write_record(path, record)
    assert read_record(path)["value"] is None  # NaN as null: JSON
    assert not list(path.parent.glob(".*partial*"))
    assert current_record(path, "ab", plan) is not None
    assert current_record(path, "cd", plan) is None  # the file changed
    assert current_record(path, "ab", Plan(steps=("texture",), seed=1)) is None
    write_record(path, {**record, "status": "failed"})
    assert current_record(path, "ab", plan) is None  # a failed file is tried again
    path.write_text('{"sha256": "ab", "stat')  # a torn record (never written so) is no record
    assert current_record(path, "ab", plan) is None


def test_a_folder_gives_its_measurements_and_never_the_output_folder(tmp_path):
    for name in ("a.x3p", "b.txt", "README.md", "LICENSE-x.txt", ".hidden.x3p"):
        (tmp_path / name).write_text("1 2 3")
    out = tmp_path / "out"
    (out / "files" / "a").mkdir(parents=True)
    (out / "files" / "a" / "filled.x3p").write_text("1")
    found = expand_inputs([tmp_path, str(tmp_path / "*.x3p"), str(tmp_path / "**" / "*.x3p")],
                          exclude=out)
    assert [p.name for p in found] == ["a.x3p", "b.txt"]
    assert expand_inputs([str(tmp_path / "nothing*")]) == []


def test_one_file_through_its_steps_and_a_corrupt_one_in_its_row(tmp_path):
    z = np.random.default_rng(0).normal(size=(32, 32))
    z[3:6, 4:9] = np.nan
    path = tmp_path / "map.npy"
    np.save(path, z)
    plan = Plan(steps=("texture", "fit", "check", "fill", "simulate"), seed=5,
                options={"fit": {"block": 8, "blocks": 3, "l": "none"},
                         "check": {"simulations": 3, "plot": True},
                         "fill": {"self_check": False}})
    sha = file_sha256(path)
    record = run_file(str(path), sha, plan, str(tmp_path / "files" / "map"))
    assert record["status"] == "done", record["error"]
    assert record["seed"] == file_seed(5, sha) and record["missing"] == 15
    assert record["fit"]["model_file"] == "files/map/model.json"
    for name in ("model.json", "filled.x3p", "simulated.x3p", "check.png"):
        assert (tmp_path / "files" / "map" / name).is_file()
    assert record["fill"]["filled"] == 15
    bad = tmp_path / "bad.npy"
    bad.write_bytes(b"\x93NUMPY garbage")
    failed = run_file(str(bad), file_sha256(bad), plan, str(tmp_path / "files" / "bad"))
    assert failed["status"] == "failed" and failed["error"].startswith("read: ")
    json.dumps(failed)
    written = write_table([record, failed], tmp_path)
    table = read_csv_table(written[0])
    assert [r["status"] for r in table] == ["done", "failed"]
    assert float(table[0]["Sq"]) == record["texture"]["parameters"]["Sq"]  # every digit
    names = columns(rows([record, failed]))
    assert names[:4] == ["path", "sha256", "status", "error"]
    assert names[-1] == "seconds.total" and "fit.variance_um2" in names


def test_a_profile_s_table_row_is_the_same_from_this_run_and_from_its_record(tmp_path):
    """eq 21's hyperparameters are numpy arrays in this run's record: the table once wrote
    them as numpy's repr (six digits, a line break inside the cell) and its NaN parameters as
    'nan', where the same record read back from its file gave JSON lists and empty cells."""
    x = np.arange(600) * 0.5
    z = np.sin(x / 7.0) + 0.1 * np.random.default_rng(1).normal(size=x.size)
    path = tmp_path / "profile.npy"
    np.save(path, z)
    plan = Plan(steps=("texture", "fit"), seed=2, options={"fit": {"mixtures": 2}})
    record = run_file(str(path), file_sha256(path), plan, str(tmp_path / "files" / "p"))
    assert record["status"] == "done", record["error"]
    write_record(tmp_path / "record.json", record)
    fresh, reread = rows([record])[0], rows([read_record(tmp_path / "record.json")])[0]
    assert fresh == reread
    weights = json.loads(fresh["fit.weights_um2"])
    np.testing.assert_array_equal(weights, record["fit"]["hyperparameters"]["weights_um2"])
    assert all(isinstance(v, (str, int, float, bool, type(None))) for v in fresh.values())
