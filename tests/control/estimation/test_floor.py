"""A known flat floor as a measurement of the invariant EKF (control/estimation/floor.py).

Oracles: the exact group action of a right-invariant error on a contact point (scipy's rotation
exponential), against eq. (2)'s rows; a still robot whose height estimate starts 1 cm low, with and
without the floor (without it the height is unobservable and must stay wrong, or the test proves
nothing); a sole tilted past the tilt gate gives no measurement, nor one 5 cm up (the innovation gate,
eq. (3), with the gate opened as the control).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation import FilterTuning, FootKinematics, ImuReading, InvariantEKF
from gaitshift.control.estimation import floor as floor_module
from gaitshift.control.estimation.floor import FLOOR_TILT, floor_rows

G = 9.81
DT = 0.002
RIGID = FilterTuning(contact_density=1e-4)
FEET = np.array([[0.05, 0.1, -0.7], [0.0, -0.1, -0.7]])  # soles in the IMU frame, m


def test_the_rows_are_the_first_order_change_of_the_contact_heights():
    rng = np.random.default_rng(3)
    d_hat = rng.normal(0.0, 0.4, (2, 3))
    h, y = floor_rows(d_hat, 0.8, 0.0, [0, 1], 21)
    np.testing.assert_allclose(y, 0.0 - 0.8 - d_hat[:, 2])
    for _ in range(5):
        xi = rng.normal(0.0, 1e-6, 21)
        exp_r = Rotation.from_rotvec(xi[0:3]).as_matrix()
        for r, i in enumerate((0, 1)):
            d = exp_r @ d_hat[i] + xi[9 + 3 * i : 12 + 3 * i]  # J_l(xi_R) = I + O(|xi_R|)
            np.testing.assert_allclose(d[2] - d_hat[i, 2], h[r] @ xi, atol=1e-11)


def _still(
    floor: float | None, tilt: float = 0.0, seconds: float = 1.0, start: float = 0.69, feet_pos: np.ndarray = FEET
) -> float:
    """The height estimate of a still, level robot on both soles (``feet_pos`` in the IMU frame) whose
    true height is 0.7 m (soles at z = 0) and whose estimate starts at ``start`` m."""
    sole = Rotation.from_rotvec([0.0, tilt, 0.0]).as_matrix()
    feet = FootKinematics(
        pos=feet_pos, vel=np.zeros((2, 3)), var=np.zeros(2), rot=np.stack([sole, sole]), rot_var=np.zeros(2)
    )
    imu = ImuReading(gyro=np.zeros(3), accel=np.array([0.0, 0.0, G]))
    f = InvariantEKF(RIGID)
    f.floor = floor
    f.reset(np.eye(3), np.array([0.0, 0.0, start]))
    for _ in range(round(seconds / DT)):
        state = f.step(imu, feet, np.array([True, True]), DT)
    return float(state.pos[2])


def test_a_known_floor_brings_a_sunken_height_back_and_without_it_the_error_stays():
    assert abs(_still(0.0) - 0.7) < 1e-3
    assert abs(_still(None) - 0.69) < 1e-3  # the control: the height is unobservable without the floor


def test_a_sole_tilted_past_the_gate_is_not_measured():
    assert abs(_still(0.0, tilt=2 * FLOOR_TILT) - 0.69) < 1e-3
    assert abs(_still(0.0, tilt=0.5 * FLOOR_TILT) - 0.7) < 1e-3


def test_a_sole_held_in_stance_off_the_floor_is_not_pinned_to_it(monkeypatch):
    """The right sole 5 cm up (a lift-off the contact flags missed): eq. (3) drops it and the left sole
    keeps the height right; without the gate the floor pulls the base toward the lifted sole."""
    lifted = FEET + np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.05]])
    assert abs(_still(0.0, start=0.7, feet_pos=lifted) - 0.7) < 1e-3
    monkeypatch.setattr(floor_module, "GATE", np.inf)
    assert abs(_still(0.0, start=0.7, feet_pos=lifted) - 0.7) > 5e-3
