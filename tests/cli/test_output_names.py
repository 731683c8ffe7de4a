"""Output names are checked before any work (issue 28): a suffix in upper case writes the file it names
(the whole trajectory, loadable) and nothing else; a file or folder name longer than the file system
allows is one line naming the flag, exit 2, and no file."""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift


def test_an_upper_case_suffix_writes_the_named_file_and_nothing_else(cli, tmp_path):
    out = tmp_path / "p.NPZ"
    code, _, _ = cli(["plan", "g1-walk", "--out", str(out)])
    assert code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.NPZ"]  # no hidden temporary file
    with np.load(out) as z:  # the whole plan: the contract's arrays, as planned
        np.testing.assert_array_equal(z["com_pos"], gaitshift.plan("g1-walk").com_pos)


@pytest.mark.parametrize("name", ["a" * 300 + ".npz", "a" * 300 + "/x.npz", "b" * 245 + ".npz"])
def test_a_name_too_long_is_one_line_and_exit_2(cli, tmp_path, name):
    out = tmp_path / name
    code, _, err = cli(["plan", "g1-walk", "--out", str(out)])
    assert code == 2 and err.count("\n") == 1 and "--out" in err and "bytes" in err
    assert list(tmp_path.iterdir()) == []


def test_export_reads_the_robot_a_locomotion_plan_names(tmp_path):
    """The locomotion planner writes ``meta.robot`` (a string); the others ``meta.scenario.robot``:
    both name the plan's robot for export and the Rerun recording."""
    from gaitshift.api import named_robot

    assert named_robot(gaitshift.plan("g1-tour").meta) == "g1"
    assert named_robot(gaitshift.plan("g1-walk").meta) == "g1"
    assert named_robot(gaitshift.plan("paper001-table2-walk-run-walk").meta) is None


def test_a_log_whose_meta_is_not_json_is_one_line(cli, tmp_path):
    from gaitshift.export.source import LOG_KEYS

    log = tmp_path / "log.npz"
    arrays = {k: np.zeros((3, 2)) for k in LOG_KEYS}
    arrays["meta"] = np.array("{not json")
    np.savez(log, **arrays)
    out = tmp_path / "m.csv"
    code, _, err = cli(["export", str(log), "--format", "unitree-csv", "--out", str(out)])
    assert code == 2 and err.count("\n") == 1 and "meta" in err and not out.exists()
