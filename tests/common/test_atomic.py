"""``gaitshift.common.atomic.atomic_path`` writes a whole file or nothing: the target appears only on
success, with the usual permissions; a failure leaves neither target nor temporary file; a target
that is not a regular file (a folder, a device, a FIFO) or a folder that cannot hold a file is
refused with one InputError that names the field and the path."""

from __future__ import annotations

import os

import pytest

from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError


def test_success_renames_the_whole_file_into_place(tmp_path):
    target = tmp_path / "new" / "a.json"
    with atomic_path(target) as tmp:
        assert tmp.parent == target.parent and tmp.suffix == ".json" and not target.exists()
        tmp.write_text("{}")
    assert target.read_text() == "{}" and os.listdir(target.parent) == ["a.json"]
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


def test_a_failure_leaves_no_file(tmp_path):
    target = tmp_path / "a.npz"
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_bytes(b"half")
        raise RuntimeError("writer failed")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("kind", ["folder", "device", "fifo", "under_file", "proc"])
def test_a_target_that_is_not_a_regular_file_is_refused_in_one_line(kind, tmp_path):
    (tmp_path / "dir.npz").mkdir()
    (tmp_path / "file.npz").write_bytes(b"x")
    os.mkfifo(tmp_path / "fifo.npz")
    target = {
        "folder": tmp_path / "dir.npz",
        "device": "/dev/null",
        "fifo": tmp_path / "fifo.npz",
        "under_file": tmp_path / "file.npz" / "a.npz",
        "proc": "/proc/gaitshift/a.npz",
    }[kind]
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(InputError) as exc, atomic_path(target, "--out"):
        pytest.fail("the body must not run")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("--out = ") and str(target) in msg and "allowed" in msg
    assert sorted(os.listdir(tmp_path)) == before
