"""Blocks of emitted samples concatenate column by column, in order."""

import numpy as np

from gaitshift.planners.streaming.samples import Samples


def _block(t0, m):
    t = t0 + np.arange(m) * 0.01
    xyz = np.column_stack([t, 2 * t, 3 * t])
    cols = {
        "com_pos": xyz,
        "com_vel": xyz + 1,
        "com_acc": xyz + 2,
        "zmp": xyz + 3,
        "phase": np.zeros(m, np.int8),
        "contact": np.ones((m, 2), bool),
        "foot_pos": np.repeat(xyz[:, None], 2, 1),
        "stiffness": np.full(m, 0.3),
    }
    return Samples(t, cols, np.zeros((m, 2)))


def test_blocks_concatenate_in_order():
    a, b = _block(0.0, 3), _block(0.03, 4)
    s = Samples.concat([a, b])
    assert len(s) == 7
    np.testing.assert_array_equal(s.t, np.r_[a.t, b.t])
    np.testing.assert_array_equal(s.foot_pos[3:], b.foot_pos)
    assert s.phase.dtype == np.int8 and s.contact.shape == (7, 2)


def test_one_block_is_itself_and_unknown_columns_raise():
    a = _block(0.0, 3)
    assert Samples.concat([a]) is a
    try:
        a.no_such_column
    except AttributeError:
        pass
    else:
        raise AssertionError("an unknown column must raise AttributeError")
