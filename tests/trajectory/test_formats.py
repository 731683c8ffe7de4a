"""The .npz, .csv and .json readers turn every damaged file into one TrajectoryFileError that names
the file, the part at fault and what was found, and the writers produce the documented layouts."""

import io
import json
import zipfile

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError, TrajectoryFileError
from gaitshift.trajectory import formats
from gaitshift.trajectory.contract import Trajectory


@pytest.fixture(scope="module")
def traj():
    return gaitshift.plan(gaitshift.load_scenario({"gait": [{"gait": "run", "steps": 2}], "dt": 0.02}))


def _error(path) -> TrajectoryFileError:
    with pytest.raises(TrajectoryFileError) as exc:
        Trajectory.load(path)
    err = exc.value
    assert str(err).startswith(f"{path}: ") and "\n" not in str(err) and " is invalid: allowed " in str(err)
    return err


def test_null_from_nan_writes_null_for_every_non_finite_float():
    arr = np.array([[1.0, np.nan], [np.inf, -2.5]])
    assert formats.null_from_nan(arr) == [[1.0, None], [None, -2.5]]
    assert formats.null_from_nan(np.array([True, False])) == [True, False]


def test_csv_columns_follow_the_trailing_shape_in_c_order():
    assert formats.csv_columns("t", []) == ["t"]
    assert formats.csv_columns("foot_pos", [2, 3])[:4] == [
        "foot_pos[0.0]",
        "foot_pos[0.1]",
        "foot_pos[0.2]",
        "foot_pos[1.0]",
    ]


def test_the_csv_layout_is_header_lines_then_columns(traj, tmp_path):
    lines = traj.save(tmp_path / "p.csv").read_text().splitlines()
    assert [ln.split(":")[0] for ln in lines[:4]] == ["# meta", "# footsteps", "# footstep_side", "# shapes"]
    cols = lines[4].split(",")
    assert cols[0] == "t" and "com_pos[2]" in cols and "contact[1]" in cols
    assert len(lines) == 5 + len(traj)
    flight = np.flatnonzero(traj.phase == 2)[0]
    zmp_x = cols.index("zmp[0]")
    assert lines[5 + flight].split(",")[zmp_x] == ""  # NaN is an empty cell


def test_unknown_suffix_is_an_input_error_naming_file(tmp_path):
    with pytest.raises(InputError, match=r"^file = "):
        formats.read(tmp_path / "x.txt")


def test_missing_file_and_folder_are_told_apart(tmp_path):
    assert _error(tmp_path / "none.npz").value == "no such file"
    (tmp_path / "d.json").mkdir()
    assert "folder" in _error(tmp_path / "d.json").value


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".json"])
def test_empty_and_truncated_files_name_the_file(traj, tmp_path, suffix):
    good = traj.save(tmp_path / f"good{suffix}").read_bytes()
    for i, raw in enumerate((b"", good[: len(good) // 3])):
        path = tmp_path / f"bad{i}{suffix}"
        path.write_bytes(raw)
        err = _error(path)
        assert err.key in ("file", "header meta") or err.key.startswith("row "), str(err)


@pytest.mark.parametrize("suffix", [".csv", ".json"])
def test_text_formats_that_are_not_utf8_say_so(tmp_path, suffix):
    path = tmp_path / f"x{suffix}"
    path.write_bytes(b"\xff\xfe\x00\x01")
    err = _error(path)
    assert err.key == "file" and "UTF-8" in str(err)


def test_npz_holding_a_single_npy_array_is_rejected(tmp_path):
    path = tmp_path / "x.npz"
    with open(path, "wb") as f:
        np.save(f, np.arange(3))
    assert "single .npy" in _error(path).value


def test_npz_member_that_needs_pickle_is_rejected_without_loading_it(traj, tmp_path):
    path = tmp_path / "x.npz"
    with open(path, "wb") as f:
        np.savez(f, **traj.arrays(), meta=np.array(json.dumps(traj.meta)), evil=np.array([{}], dtype=object))
    err = _error(path)
    assert err.key == "evil" and "unreadable member" in err.value


def test_npz_member_that_is_not_npy_is_rejected(traj, tmp_path):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("t.npy", b"not an array")
    path = tmp_path / "x.npz"
    path.write_bytes(buf.getvalue())
    assert _error(path).key == "t"


def test_npz_meta_must_be_a_json_object_in_a_0d_string(traj, tmp_path):
    arrays = traj.arrays()
    for meta, fragment in ((np.array([1, 2]), "shape (2,)"), (np.array("{nope"), "not JSON")):
        path = tmp_path / "m.npz"
        np.savez(path, **arrays, meta=meta)
        err = _error(path)
        assert err.key == "meta" and fragment in err.value
    np.savez(path, **arrays)
    assert _error(path).key == "meta"


def test_csv_with_a_missing_column_names_the_column_line(traj, tmp_path):
    """The break of issue 10: a CSV without the com_vel columns raised KeyError."""
    lines = traj.save(tmp_path / "p.csv").read_text().splitlines()
    cols = lines[4].split(",")
    keep = [i for i, c in enumerate(cols) if not c.startswith("com_vel")]
    body = [",".join(row.split(",")[i] for i in keep) for row in lines[4:]]
    path = tmp_path / "cut.csv"
    path.write_text("\n".join(lines[:4] + body) + "\n")
    err = _error(path)
    assert err.key == "column line 5" and "com_vel[0]" in err.allowed


def test_csv_header_and_cells_are_checked(traj, tmp_path):
    text = traj.save(tmp_path / "p.csv").read_text()
    cases = {
        "# hello: 1\n" + text: "header line 1",
        text.replace("# shapes: {", "# shapes: [{", 1): "header shapes",
        "\n".join(ln for ln in text.splitlines() if not ln.startswith("# footsteps:")): "header footsteps",
        text.replace("\n0,", "\nzero,", 1): "row 6 column t",
        text.rstrip("\n") + ",1\n": f"row {5 + len(traj)}",
    }
    for i, (bad, key) in enumerate(cases.items()):
        path = tmp_path / f"b{i}.csv"
        path.write_text(bad)
        assert _error(path).key == key


def test_json_arrays_must_be_rectangular_numbers(traj, tmp_path):
    good = json.loads(traj.save(tmp_path / "p.json").read_text())
    for i, (key, value, fragment) in enumerate(
        (
            ("com_pos", [[1, 2, 3], [4]], "rectangular"),
            ("com_pos", [["a", "b", "c"]], "dtype <U1"),
            ("phase", [{"x": 1}], "dict"),
            ("t", [10**400], "beyond the float range"),
        )
    ):
        bad = dict(good, **{key: value})
        path = tmp_path / f"j{i}.json"
        path.write_text(json.dumps(bad))
        err = _error(path)
        assert err.key == key and fragment in str(err), str(err)


def test_json_nesting_and_giant_integers_are_file_errors(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    assert _error(path).key == "file"
    path.write_text('{"meta": {}, "t": [' + "9" * 5000 + "]}")
    assert _error(path).key == "file"


def test_json_null_is_nan_where_the_contract_allows_it(traj, tmp_path):
    back = Trajectory.load(traj.save(tmp_path / "p.json"))
    np.testing.assert_array_equal(np.isnan(back.zmp[:, 0]), back.phase == 2)
