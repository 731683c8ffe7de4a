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
