"""The controller's friction belief (:meth:`gaitshift.control.state.ControllerState.friction`).

A slide is evidence of the floor's friction only where the controller loads the sole: the belief drops
by ``FRICTION_DROP`` at a slip onset of a sole in the plan's stance, and not at one of a sole the plan
swings (an early running touchdown sliding in on its impact, a swinging sole taken for a stance one);
on the oracle it never drops.
"""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.controller import Controller
from gaitshift.control.state import FRICTION_DROP, FRICTION_MIN, StateView
from gaitshift.control.wbc import Gains


def _view(slip: tuple[bool, bool]) -> StateView:
    return StateView(data=None, touching=np.ones(2, bool), slip=np.array(slip))


@pytest.fixture(scope="module")
def estimated():
    return Controller.from_scenario("g1-walk")


def test_only_slip_onsets_of_soles_in_the_plans_stance_lower_the_friction_belief(estimated):
    state = estimated.state
    mu0 = state.mu
    plan_left = np.array([True, False])
    gains = state.friction(Gains(), _view((False, True)), plan_left)  # the swinging right sole slides
    assert gains.mu == pytest.approx(Gains().mu) and state.mu == mu0
    state.friction(gains, _view((False, False)), plan_left)
    gains = state.friction(gains, _view((True, False)), plan_left)  # the loaded left sole slides
    assert state.mu == pytest.approx(FRICTION_DROP * mu0) and gains.mu == state.mu
    gains = state.friction(gains, _view((True, False)), plan_left)  # the same slide: no new onset
    assert state.mu == pytest.approx(FRICTION_DROP * mu0)
    for k in range(60):  # alternate onsets: down to the floor, never below
        gains = state.friction(gains, _view((k % 2 == 0, False)), plan_left)
    assert state.mu == pytest.approx(FRICTION_MIN)


def test_the_oracle_keeps_its_friction():
    state = Controller.from_scenario("g1-walk", state="oracle").state
    mu0 = state.mu
    for k in range(10):
        state.friction(Gains(), _view((k % 2 == 0, False)), np.array([True, True]))
    assert state.mu == mu0
