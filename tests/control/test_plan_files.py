"""A plan handed between processes (gaitshift.control.plan_files): written with its arrays out of band and
read back as views of a copy-on-write mapping, equal to what was written (every dtype and shape, a
non-contiguous array in band, an error object), writable without touching the file, which stays for the
writer's side to remove."""

import numpy as np
import pytest

from gaitshift.control.plan_files import PlanFolder, read_plan, write_plan
from gaitshift.errors import GaitshiftError


def test_a_plan_comes_back_equal_with_its_arrays_mapped_copy_on_write(tmp_path):
    rng = np.random.default_rng(3)
    big = rng.normal(size=(5000, 3))
    plan = {
        "t": np.arange(5000) * 0.002,
        "com_pos": big,
        "contact": rng.random((5000, 2)) > 0.5,
        "phase": rng.integers(0, 3, 5000).astype(np.int8),
        "every_other": big[::2, 1],  # not contiguous: pickled in band
        "meta": {"planner": "locomotion", "open_end": True},
    }
    path = tmp_path / "1.plan"
    write_plan(path, plan)
    got = read_plan(path)
    for key in ("t", "com_pos", "contact", "phase", "every_other"):
        np.testing.assert_array_equal(got[key], plan[key])
        assert got[key].dtype == plan[key].dtype
    assert got["meta"] == plan["meta"]
    assert not got["com_pos"].flags.owndata  # a view of the mapping, not a copy
    assert got["com_pos"].ctypes.data % 64 == 0
    got["com_pos"][0, 0] = 99.0  # copy-on-write: the plan's owner may write, the file keeps what was written
    assert got["com_pos"][0, 0] == 99.0
    np.testing.assert_array_equal(read_plan(path)["com_pos"], plan["com_pos"])


def test_an_error_comes_back_as_itself(tmp_path):
    path = tmp_path / "2.plan"
    write_plan(path, GaitshiftError("planner: no step fits"))
    err = read_plan(path)
    assert isinstance(err, GaitshiftError) and str(err) == "planner: no step fits"


def test_a_file_that_is_not_a_plan_is_refused(tmp_path):
    path = tmp_path / "3.plan"
    path.write_bytes(b"not a plan at all, long enough to map")
    with pytest.raises(ValueError, match="not a plan file"):
        read_plan(path)


def test_a_plan_folder_names_a_file_only_when_whole_and_frees_only_those_before(tmp_path):
    files = PlanFolder(tmp_path)
    for n in range(1, 5):
        files.write(n, {"n": np.full(100, float(n))})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["1.plan", "2.plan", "3.plan", "4.plan"]
    files.free_before(3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["3.plan", "4.plan"]
    np.testing.assert_array_equal(files.read(3)["n"], np.full(100, 3.0))
    files.free_before(2)  # an older word changes nothing
    files.free_before(5)
    assert not list(tmp_path.iterdir())
