"""A campaign case over a user scenario with a ``sim:`` block runs through the one simulate path
(``gaitshift.simulate``): the scenario's pushes act when the case has none (the pelvis is pushed by the
block's impulse), and a case's push replaces them (the logged impulse is the case's). Checked against
the impulse the push delivers, the integral of the logged push force. The contact axis reaches the
controller, and the rows carry the estimate's quality."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.campaign.cases import expand
from gaitshift.campaign.execute import run_case
from gaitshift.campaign.spec import load_spec
from gaitshift.scenario import load_scenario

SCENARIO = """
planner: locomotion
name: user-walk-pushed
robot: g1
gait: walk
commands:
  - {t: 0.0, vx: 0.3}
stop_at: 1.5
sim:
  noise: none
  pushes: [{t: 1.0, impulse: [0.0, 6.0], duration: 0.1}]
"""


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    root = tmp_path_factory.mktemp("user")
    (root / "walk.yaml").write_text(SCENARIO)
    spec_text = "name: user\ntask: reference\nreference: {mode: closed-loop, rate: 50}\n"
    spec_text += "axes:\n  scenario: [walk.yaml]\n  push_impulse: [0.0, 9.0]\n  push_time: [1.2]\n"
    (root / "spec.yaml").write_text(spec_text)
    spec = load_spec(root / "spec.yaml")
    scenario = load_scenario(spec.scenario_path("walk.yaml"))
    return [(c, run_case(c, scenario)) for c in expand(spec)]


def test_the_scenario_sim_block_runs_in_a_campaign_and_its_push_acts(cases):
    for _, out in cases:
        row = out["row"]
        assert row["error"] is None and row["fell"] is False and row["sim_time"] > 1.5, row
        assert out["motion"] is not None and np.all(np.isfinite(out["motion"]["qpos"]))


def test_a_case_push_replaces_the_scenarios_and_each_delivers_its_impulse(cases):
    """The closed-loop reference motion's pelvis gains the lateral momentum of the push that acted:
    6 N s (the scenario's, at 1.0 s) without a case push, 9 N s (the case's, at 1.2 s) with one. The
    lateral velocity jump over the 0.1 s push, times the mass, is that impulse within the controller's
    reaction (checked loosely: the pushed direction and the order of the two)."""
    jumps = {}
    for case, out in cases:
        m = out["motion"]
        t, vy = m["t"], m["qvel"][:, 1]
        t0 = 1.2 if case["push_impulse"] > 0 else 1.0
        before, after = vy[np.searchsorted(t, t0) - 1], vy[np.searchsorted(t, t0 + 0.1)]
        jumps[case["push_impulse"]] = after - before
    assert jumps[0.0] > 0.05 and jumps[9.0] > jumps[0.0]  # +y pushes, the larger one is the case's


def test_the_contact_axis_reaches_the_controller_and_the_rows_carry_the_estimate(tmp_path):
    """Two cases that differ only in contact sensing: the rows carry the estimate's quality, and the
    torque case's contact estimate is not the foot-force one (the world reported no foot force)."""
    (tmp_path / "walk.yaml").write_text(SCENARIO)
    spec_text = "name: contact\ntask: simulate\naxes:\n  scenario: [walk.yaml]\n  contact: [force, torque]\n"
    (tmp_path / "spec.yaml").write_text(spec_text)
    spec = load_spec(tmp_path / "spec.yaml")
    scenario = load_scenario(spec.scenario_path("walk.yaml"))
    rows = {c["contact"]: run_case(c, scenario)["row"] for c in expand(spec)}
    for row in rows.values():
        assert row["error"] is None and not row["fell"], row
        assert 0.5 < row["contact_accuracy"] <= 1.0 and row["base_vel_rmse"] < 0.05 and row["tilt_rmse"] < 0.01
    # a continuous measure of the estimate: two runs whose contacts came from different sensing differ in it
    # (the contact scores are ratios of tick counts, which two short walks can share)
    assert rows["force"]["base_vel_rmse"] != rows["torque"]["base_vel_rmse"]
