"""Samples emitted from the plan buffer: velocity and acceleration are the central and second
differences of the planned CoM, force-free samples have no horizontal acceleration, the ZMP and the
stiffness are NaN in flight, contacts follow the phase, and the rest after a stop holds still.

Oracles: differences and sqrt(z / (z'' + g)) recomputed here from the values written.
"""

import numpy as np

from gaitshift.planners.vhip.emission import contact_of, emit_samples, hold_at_rest, plan_buffer, write_segment
from gaitshift.planners.vhip.swings import FootTracks
from gaitshift.trajectory.contract import DS, FLIGHT, SS

G, DT = 9.81, 0.01


def _plan(n=30):
    buf = plan_buffer(capacity=64)
    t = np.arange(n) * DT
    c = np.column_stack([0.3 * t + 0.5 * t**2, np.sin(t)])
    phase = np.where(t < 0.1, DS, np.where(t < 0.2, SS, FLIGHT)).astype(np.int8)
    zdd = np.where(phase == FLIGHT, -G, 0.4)
    z = 0.8 + 0.01 * t
    write_segment(buf, 0, c, (z, np.full(n, 0.01), zdd), np.c_[c[:, 0], -c[:, 1]], phase, contact_of(phase, 0))
    feet = FootTracks({0: np.array([0.0, 0.1, 0.0]), 1: np.array([0.0, -0.1, 0.0])}, 0.05, DT)
    return buf, feet, c, z, zdd, phase


def test_samples_are_the_differences_of_the_planned_com():
    buf, feet, c, z, zdd, phase = _plan()
    s = emit_samples(buf, feet, 5, 20, DT, G, np.array([0.3, 0.0]), 1e-9)
    i = np.arange(5, 25)
    np.testing.assert_array_equal(s.t, i * DT)
    np.testing.assert_array_equal(s.com_pos[:, :2], c[i])
    np.testing.assert_allclose(s.com_vel[:, :2], (c[i + 1] - c[i - 1]) / (2 * DT), atol=1e-12)
    fd2 = (c[i + 1] - 2 * c[i] + c[i - 1]) / DT**2
    free = zdd[i] + G <= 1e-9 * G
    np.testing.assert_allclose(s.com_acc[~free, :2], fd2[~free], atol=1e-9)
    assert np.all(s.com_acc[free, :2] == 0.0) and free.any()
    fl = phase[i] == FLIGHT
    assert np.all(np.isnan(s.zmp[fl])) and np.all(np.isnan(s.stiffness[fl]))
    np.testing.assert_allclose(s.stiffness[~fl], np.sqrt(z[i][~fl] / (zdd[i][~fl] + G)))
    np.testing.assert_array_equal(s.command, np.broadcast_to([0.3, 0.0], (20, 2)))


def test_contacts_follow_the_phase_and_the_stance_side():
    phase = np.array([DS, SS, FLIGHT], dtype=np.int8)
    np.testing.assert_array_equal(contact_of(phase, 1), [[True, True], [False, True], [False, False]])


def test_the_rest_after_a_stop_holds_the_last_state():
    buf, *_ = _plan(10)
    hold_at_rest(buf, 15, np.array([0.2, 0.0]))
    assert buf.n == 16
    np.testing.assert_array_equal(buf["c"][10:16], np.broadcast_to(buf["c"][9], (6, 2)))
    assert np.all(buf["zd"][10:16] == 0) and np.all(buf["phase"][10:16] == DS) and buf["contact"][10:16].all()
