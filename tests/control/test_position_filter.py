"""The horizontal position the controller acts on (gaitshift.control.position_filter, eq. (1)): a position
that moves with the velocity is followed without lag, a correction's kick arrives spread over tau as the
discretised first-order lag says, tau = 0 is the estimate itself, and the controller acts on eq. (1) of its
estimate while the estimate it records stays the estimator's."""

import numpy as np
import pytest

from gaitshift.control.controller import Controller
from gaitshift.control.position_filter import PositionFilter
from gaitshift.control.settings import ControllerSettings
from gaitshift.errors import InputError
from standing import rest_frame

H = 0.002


def test_a_position_that_moves_with_the_velocity_is_followed_without_lag():
    f = PositionFilter(2.0)
    p0, v = np.array([0.3, -0.2]), np.array([1.5, 0.4])
    f.reset(p0)
    for k in range(1, 2001):
        out = f.step(p0 + v * k * H, v, H)
    np.testing.assert_allclose(out, p0 + v * 2000 * H, atol=1e-12)


def test_a_correction_kick_arrives_spread_over_tau():
    """p jumps 1 cm at rest: p_bar - p_before = 0.01 (1 - (1 - h / tau)^n), the first-order lag e^{-t/tau}."""
    tau, f = 2.0, PositionFilter(2.0)
    f.reset(np.zeros(2))
    kicked = np.array([0.01, 0.0])
    n = np.arange(1, 3001)
    out = np.array([f.step(kicked, np.zeros(2), H)[0] for _ in n])
    np.testing.assert_allclose(out, 0.01 * (1.0 - (1.0 - H / tau) ** n), rtol=1e-9)
    np.testing.assert_allclose(out[-1], 0.01 * (1.0 - np.exp(-n[-1] * H / tau)), rtol=1e-3)
    assert out[0] <= 1.0001e-5  # one tick takes 1/1000 of the kick, not the kick


def test_off_is_the_estimate_and_a_bad_tau_is_one_input_error():
    f = PositionFilter(0.0)
    f.reset(np.zeros(2))
    np.testing.assert_array_equal(f.step(np.array([0.4, 0.1]), np.array([9.0, 9.0]), H), [0.4, 0.1])
    for bad in (-1.0, float("nan"), True, "2", 61.0):
        with pytest.raises(InputError, match="position_tau"):
            PositionFilter(bad)
        with pytest.raises(InputError, match="position_tau"):
            ControllerSettings(position_tau=bad)


@pytest.mark.parametrize("tau", [0.0, 2.0])
def test_the_controller_acts_on_eq_1_of_its_estimate_and_records_the_estimators(tau):
    """A standing robot whose accelerometer reads 0.3 m/s^2 forward that is not there: the estimate's
    velocity drifts and the stance soles' corrections pull its position back in steps."""
    ctrl = Controller.from_scenario("g1-walk", settle=5.0, position_tau=tau)
    replay = PositionFilter(tau)
    est, acted = [], []
    for k in range(400):
        frame = rest_frame(ctrl, k * H, foot_force=False)
        frame = type(frame)(**{**frame.__dict__, "imu_acc": frame.imu_acc + np.array([0.3, 0.0, 0.0])})
        ctrl.tick(frame)
        rec = ctrl.state.record
        if k == 0:
            replay.reset(rec.qpos)
        expected = replay.step(rec.qpos, rec.qvel, H) if k else rec.qpos[:2]
        est.append(rec.qpos[:2].copy())
        acted.append(ctrl.state.cdata.qpos[:2].copy())
        np.testing.assert_allclose(acted[-1], expected, atol=1e-12)
    gap = np.abs(np.array(acted) - np.array(est)).max()
    assert (gap > 1e-5) if tau else (gap == 0.0)
