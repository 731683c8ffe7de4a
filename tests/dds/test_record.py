"""The recording's file (gaitshift.dds.record): every row kept across its blocks, each column its width,
a value that is not finite refused with no file left behind, and the options refusing a bad path in one
InputError naming --record (the Python API as the command line)."""

import json

import numpy as np
import pytest

from gaitshift.dds.record import Recorder, brain_widths, check_record
from gaitshift.errors import InputError


def test_every_row_is_kept_in_order_past_the_first_block(tmp_path):
    rec = Recorder(tmp_path / "r.npz", {"t": 1, "q": 3}, {"process": "test"})
    n = 10_000  # three blocks of 4096 rows, the last one part-filled
    for k in range(n):
        rec.add(t=k * 0.002, q=np.full(3, k))
    rec.save()
    z = np.load(tmp_path / "r.npz")
    assert z["t"].shape == (n,) and z["q"].shape == (n, 3)
    assert np.array_equal(z["q"][:, 1], np.arange(n)) and z["t"][-1] == pytest.approx((n - 1) * 0.002)
    meta = json.loads(str(z["meta"]))
    assert meta["rows"] == n and meta["columns"] == ["t", "q"] and meta["process"] == "test"


def test_a_column_not_given_is_zeros_and_the_widths_follow_the_robot():
    w = brain_widths(29, 36, 35)
    assert (w["q"], w["est_qpos"], w["est_qvel"], w["quat"], w["ref_foot"], w["t"]) == (29, 36, 35, 4, 6, 1)
    rec = Recorder("unused.npz", w, {})
    rec.add(t=1.0)
    assert not rec.arrays()["cmd_tau"].any()


def test_a_value_that_is_not_finite_is_refused_and_leaves_no_file(tmp_path):
    rec = Recorder(tmp_path / "r.npz", {"t": 1}, {})
    rec.add(t=float("nan"))
    with pytest.raises(ValueError, match="not finite"):
        rec.save()
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("bad", ["run.csv", ".npz", 3, b"run.npz"])
def test_the_options_refuse_a_recording_that_is_not_an_npz_path(bad):
    with pytest.raises(InputError, match="--record"):
        check_record(bad)
    check_record(None)
    check_record("run.NPZ")


def test_meet_pairs_each_brain_row_with_the_robot_row_of_its_tick():
    """A brain acting on ticks 3, 3, 5, 9 (a held state, a lost one) against a robot that stepped 0..7."""
    from gaitshift.dds.record import meet

    rows = meet({"tick": np.array([3.0, 3.0, 5.0, 9.0])}, {"tick": np.arange(8.0)[::-1]})
    assert rows.tolist() == [4, 4, 2, -1]
