"""The flag checks every command runs before any work: output files, output folders and numbers, each
failing with one InputError that names the flag, the value and what is allowed."""

import math
import os
from pathlib import Path

import pytest

from gaitshift.cli.app import number, out_file, out_folder
from gaitshift.errors import InputError

SUFFIXES = (".npz", ".csv", ".json")


def _allowed(fn, *args, **kw) -> str:
    with pytest.raises(InputError) as exc:
        fn(*args, **kw)
    assert exc.value.field == args[1]
    return exc.value.allowed


def test_out_file_accepts_new_and_existing_files_and_new_folders(tmp_path):
    (tmp_path / "old.npz").write_bytes(b"")
    for path in (tmp_path / "a.npz", tmp_path / "old.npz", tmp_path / "new" / "deeper" / "b.JSON"):
        assert out_file(path, "--out", SUFFIXES) == path
    assert sorted(os.listdir(tmp_path)) == ["old.npz"]  # the check writes nothing


def test_out_file_rejects_suffix_folder_special_file_and_file_parent(tmp_path):
    (tmp_path / "dir.npz").mkdir()
    (tmp_path / "file.npz").write_bytes(b"x")
    os.mkfifo(tmp_path / "fifo.npz")
    assert "ending in .npz" in _allowed(out_file, tmp_path / "x.txt", "--out", SUFFIXES)
    assert "ending in" in _allowed(out_file, tmp_path / ".npz", "--out", SUFFIXES)
    assert "folder or a special file" in _allowed(out_file, tmp_path / "dir.npz", "--out", SUFFIXES)
    assert "folder or a special file" in _allowed(out_file, tmp_path / "fifo.npz", "--out", SUFFIXES)
    assert "is a folder, not a file" in _allowed(out_file, tmp_path / "file.npz" / "x.npz", "--out", SUFFIXES)


def test_unwritable_locations_are_found_by_probing(tmp_path):
    assert "a writable location" in _allowed(out_file, Path("/proc/gaitshift/x.npz"), "--out", SUFFIXES)
    assert "a writable location" in _allowed(out_folder, Path("/proc/gaitshift"), "--out")


def test_out_folder_accepts_folders_and_rejects_files(tmp_path):
    (tmp_path / "f").write_bytes(b"")
    assert out_folder(tmp_path, "--out") == tmp_path and out_folder(tmp_path / "new", "--out") == tmp_path / "new"
    assert not (tmp_path / "new").exists()
    assert "this is a file" in _allowed(out_folder, tmp_path / "f", "--out")


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, -1.0, 0.0, 600.5])
def test_number_rejects_non_finite_and_out_of_range(value):
    assert _allowed(number, value, "--max-time", 0.0, 600.0, open_low=True) == "a number in (0, 600]"


def test_number_accepts_its_bounds():
    assert number(600.0, "--max-time", 0.0, 600.0, open_low=True) == 600.0
    assert number(0.05, "--height", 0.05, 5.0) == 0.05
