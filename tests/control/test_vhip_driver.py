"""Online re-planning driver (paper 003 generator in the loop).

Re-planning from exactly the planned CoM state must reproduce the plan (the generator is
deterministic and the measured state is where it expected to be); re-planning from a displaced CoM
must keep the past and change the footholds after the planning instant; re-planning happens only at
planning instants, once each, and only on the generator's time grid.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.control.vhip_driver import VhipDriver


@pytest.fixture
def driver():
    return VhipDriver(gaitshift.load_scenario("g1-online-variable-speed"))


def _first_replan(rp, displacement=(0.0, 0.0, 0.0)):
    plan = rp.trajectory
    for k in range(len(plan)):
        new = rp.maybe_replan(float(plan.t[k]), plan.com_pos[k] + np.asarray(displacement), plan.com_vel[k])
        if new is not None:
            return k, plan, new
    pytest.fail("no planning instant in the plan")


def test_replanning_from_the_planned_state_reproduces_the_plan(driver):
    k, old, new = _first_replan(driver)
    assert driver.replans == 1 and driver.trajectory is new
    assert len(new) == len(old)
    np.testing.assert_allclose(new.com_pos, old.com_pos, atol=1e-9)
    np.testing.assert_allclose(new.footsteps, old.footsteps, atol=1e-9)
    # the same instant is not re-planned twice
    assert driver.maybe_replan(float(old.t[k]), old.com_pos[k], old.com_vel[k]) is None


def test_replanning_from_a_displaced_com_keeps_the_past_and_moves_later_footholds(driver):
    k, old, new = _first_replan(driver, displacement=np.array([0.0, 0.03, 0.0]))
    np.testing.assert_array_equal(new.com_pos[:k], old.com_pos[:k])
    t_k = old.t[k]
    landed = old.t[np.flatnonzero(np.any(~old.contact[:-1] & old.contact[1:], axis=1)) + 1]
    n_past = int(np.sum(landed <= t_k)) + 2  # the two initial stance footholds come first
    np.testing.assert_allclose(new.footsteps[:n_past], old.footsteps[:n_past], atol=1e-12)
    assert np.max(np.abs(new.footsteps[n_past:, 1] - old.footsteps[n_past : len(new.footsteps), 1])) > 1e-3


def test_no_replan_off_the_time_grid_or_between_planning_instants(driver):
    plan = driver.trajectory
    assert driver.maybe_replan(0.0021, plan.com_pos[0], plan.com_vel[0]) is None
    assert driver.maybe_replan(float(plan.t[1]), plan.com_pos[1], plan.com_vel[1]) is None
    assert driver.replans == 0
