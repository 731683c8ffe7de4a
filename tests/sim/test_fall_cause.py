"""The fall's cause from the log (sim/fall_cause.py): each rule fires on the evidence it names and only
then; a run with none of the evidence is a reach fall."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.sim.fall_cause import SLIP_SPEED, TILT_ERROR, fall_cause, longest_run

DT = 0.002
N = 500  # 1 s of log; the fall at its end
LIMIT = np.full(4, 50.0)


def calm_log() -> dict[str, np.ndarray]:
    """A log where nothing is wrong: feet planted, estimate exact, torques at half their limit."""
    q = np.zeros((N, 7))
    q[:, 3] = 1.0
    return {
        "t": np.arange(N) * DT,
        "legs_touch": np.zeros(N, bool),
        "feet_overlap": np.zeros(N, bool),
        "foot_pos": np.tile([[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]], (N, 1, 1)),
        "contact": np.ones((N, 2), bool),
        "tau": np.full((N, 4), 25.0),
        "qpos": q,
        "qvel": np.zeros((N, 6)),
        "est_qpos": q.copy(),
        "est_qvel": np.zeros((N, 6)),
        "est_contact": np.ones((N, 2), bool),
    }


T_FALL = (N - 1) * DT
WINDOW = slice(N - 200, N - 100)  # 0.4 .. 0.2 s before the fall: inside every rule's window


def test_a_calm_log_is_a_reach_fall():
    assert fall_cause(calm_log(), T_FALL, LIMIT, DT) == "reach"


def test_legs_touching_before_the_fall_is_a_crossing():
    a = calm_log()
    a["legs_touch"][N - 10] = True
    assert fall_cause(a, T_FALL, LIMIT, DT) == "crossing"


@pytest.mark.parametrize(("speed", "ticks", "cause"), [(2 * SLIP_SPEED, 30, "slip"), (2 * SLIP_SPEED, 5, "reach"),
                                                         (0.5 * SLIP_SPEED, 30, "reach")])  # fmt: skip
def test_a_loaded_sole_sliding_fast_for_long_enough_is_a_slip(speed, ticks, cause):
    """The sole moves at ``speed`` m/s for ``ticks`` ticks while the truth says it is on the floor."""
    a = calm_log()
    k0 = N - 200
    a["foot_pos"][k0 : k0 + ticks + 1, 0, 0] = speed * DT * np.arange(ticks + 1)
    a["foot_pos"][k0 + ticks + 1 :, 0, 0] = speed * DT * ticks
    assert fall_cause(a, T_FALL, LIMIT, DT) == cause


def test_a_sole_swinging_fast_in_the_air_is_no_slip():
    a = calm_log()
    a["contact"][:, 0] = False
    a["est_contact"][:, 0] = False
    a["foot_pos"][:, 0, 0] = 1.0 * DT * np.arange(N)
    assert fall_cause(a, T_FALL, LIMIT, DT) == "reach"


def test_an_estimated_tilt_off_the_truth_is_an_estimate_fall():
    a = calm_log()
    half = 0.6 * TILT_ERROR  # rotation of 1.2 TILT_ERROR about x
    a["est_qpos"][WINDOW, 3:7] = [np.cos(half), np.sin(half), 0.0, 0.0]
    assert fall_cause(a, T_FALL, LIMIT, DT) == "estimate"


def test_a_wrong_contact_estimate_for_long_enough_is_an_estimate_fall():
    a = calm_log()
    a["est_contact"][N - 200 : N - 160, 1] = False  # 80 ms
    assert fall_cause(a, T_FALL, LIMIT, DT) == "estimate"
    b = calm_log()
    b["est_contact"][N - 200 : N - 190, 1] = False  # 20 ms: a touchdown's lag
    assert fall_cause(b, T_FALL, LIMIT, DT) == "reach"


def test_a_motor_at_its_limit_is_a_torque_fall_and_the_collapse_itself_is_not():
    a = calm_log()
    a["tau"][N - 200 : N - 180, 2] = -LIMIT[2]
    assert fall_cause(a, T_FALL, LIMIT, DT) == "torque"
    b = calm_log()
    b["tau"][N - 40 :, 2] = LIMIT[2]  # the last 80 ms: the collapse, outside the window
    assert fall_cause(b, T_FALL, LIMIT, DT) == "reach"


def test_longest_run_reads_any_column():
    m = np.zeros((10, 2), bool)
    m[2:5, 0] = True
    m[4:9, 1] = True
    assert longest_run(m) == 5
    assert longest_run(np.zeros(0, bool)) == 0
