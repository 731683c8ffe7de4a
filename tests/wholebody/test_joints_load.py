"""A joints file that is not one (truncated, not a zip, pickled data, meta not JSON) is one
``InputError`` naming the file, never ``EOFError``/``BadZipFile``/``ValueError`` (issue 28), and
``animate --joints`` on it is one line, exit 2, no video."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.wholebody.joints import JointTrajectory


def _files(tmp_path):
    good = tmp_path / "good.npz"
    np.savez(good, t=np.zeros(3), qpos=np.zeros((3, 7)), qvel=np.zeros((3, 6)), meta='{"robot": "g1"}')
    data = good.read_bytes()
    out = {"truncated": data[: len(data) // 2], "garbage": b"not a zip at all"}
    paths = {}
    for name, blob in out.items():
        p = tmp_path / f"{name}.npz"
        p.write_bytes(blob)
        paths[name] = p
    np.savez(
        tmp_path / "pickled.npz", t=np.array([{"a": 1}], dtype=object), qpos=np.zeros(1), qvel=np.zeros(1), meta="{}"
    )
    paths["pickled"] = tmp_path / "pickled.npz"
    np.savez(tmp_path / "badmeta.npz", t=np.zeros(3), qpos=np.zeros((3, 7)), qvel=np.zeros((3, 6)), meta="{oops")
    paths["badmeta"] = tmp_path / "badmeta.npz"
    return good, paths


@pytest.mark.parametrize("kind", ["truncated", "garbage", "pickled", "badmeta"])
def test_a_damaged_joints_file_is_one_input_error(tmp_path, kind, cli):
    good, paths = _files(tmp_path)
    assert JointTrajectory.load(good).meta == {"robot": "g1"}
    with pytest.raises(InputError) as info:
        JointTrajectory.load(paths[kind])
    assert "\n" not in str(info.value) and str(paths[kind]) in str(info.value)
    out = tmp_path / "m.mp4"
    code, _, err = cli(["animate", "g1-walk", "--joints", str(paths[kind]), "--out", str(out)])
    assert code == 2 and err.count("\n") == 1 and not out.exists()
