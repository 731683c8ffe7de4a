"""Every built-in TV-LIPM scenario satisfies the physics at every sample (paper 001 §II).

Checks use tests/physics.py, which re-derives everything from the file's arrays.
"""

import numpy as np
import pytest

import gaitshift
import physics

SCENARIOS = ["paper001-table1-running", "paper001-table2-running", "paper001-table2-walk-run-walk"]


@pytest.fixture(scope="module", params=SCENARIOS)
def planned(request, tmp_path_factory):
    sc = gaitshift.load_scenario(request.param)
    path = tmp_path_factory.mktemp("plans") / f"{request.param}.npz"
    gaitshift.plan(sc).save(path)
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    return sc, d


def test_eq1_holds_at_every_support_sample(planned):
    sc, d = planned
    assert physics.eq1_error(d, sc.gravity) < 1e-6


def test_flight_is_ballistic(planned):
    sc, d = planned
    assert physics.flight_error(d, sc.gravity) < 1e-9


def test_eq1_holds_under_independent_numerical_integration(planned):
    sc, d = planned
    within, _ = physics.ode_errors(d, sc.gravity)
    assert within < 1e-6


def test_velocity_and_acceleration_match_finite_differences(planned):
    _, d = planned
    ev, ea, ea2 = physics.finite_difference_errors(d)
    assert ev < 1e-4 and ea < 1e-3 and ea2 < 1e-3


def test_com_is_continuous_across_phase_switches(planned):
    sc, d = planned
    _, across = physics.ode_errors(d, sc.gravity)
    assert across < 1e-6  # position and velocity carried across every switch by the ODE


def test_zmp_stays_inside_the_support_polygon(planned):
    sc, d = planned
    assert physics.zmp_outside_polygon(d, sc.foot.size) < 1e-3


def test_running_segments_have_real_flight(planned):
    sc, d = planned
    segs = [(a, b) for a, b in physics.segments(d["phase"]) if d["phase"][a] == physics.F]
    n_run = sum(s.steps for s in sc.gait if s.gait == "run")
    assert len(segs) == n_run
    dt = d["t"][1] - d["t"][0]
    for a, b in segs:
        assert not d["contact"][a:b].any()
        assert (b - a) * dt == pytest.approx(sc.timing.flight, abs=1.5 * dt)
        assert np.all(d["foot_pos"][a + 1 : b, :, 2] > 0.0)  # both soles off the ground after take-off
        assert np.all(np.isnan(d["zmp"][a:b]))


def test_running_touchdown_and_takeoff_heights_equal_h(planned):
    sc, d = planned
    bp = d["boundary_com_pos"]
    kinds = d["phase_kind"]
    fl = np.flatnonzero(kinds == physics.F)
    # at both ends of every flight the CoM is at the nominal height above the flat ground
    np.testing.assert_allclose(bp[fl, 2], sc.height, atol=1e-9)
    np.testing.assert_allclose(bp[fl + 1, 2], sc.height, atol=1e-9)


def test_plan_ends_at_rest_at_the_goal(planned):
    sc, d = planned
    goal = d["footsteps"][-2:, :3].mean(axis=0) + np.array([0.0, 0.0, sc.height])
    assert np.linalg.norm(d["com_vel"][-1]) < 1e-3
    assert np.linalg.norm(d["com_pos"][-1] - goal) < 1e-3
    assert np.linalg.norm(d["com_vel"][0]) < 1e-12


def test_feet_in_contact_do_not_move(planned):
    _, d = planned
    c = d["contact"]
    for s in (0, 1):
        stay = c[1:, s] & c[:-1, s]
        assert np.max(np.abs(np.diff(d["foot_pos"][:, s], axis=0)[stay])) < 1e-12


def test_file_has_no_nan_outside_the_documented_places(planned):
    _, d = planned
    for key in ("t", "com_pos", "com_vel", "com_acc", "foot_pos", "footsteps"):
        assert np.all(np.isfinite(d[key])), key
    sup = d["phase"] != physics.F
    assert np.all(np.isfinite(d["zmp"][sup])) and np.all(np.isfinite(d["stiffness"][sup]))


def test_stairs_and_turning_plan_satisfy_the_same_physics():
    sc = gaitshift.load_scenario(
        {
            "gait": [{"gait": "walk", "steps": 6}],
            "foot": {"zmp_z": [-0.05, 0.05]},
            "profile": {
                "max_stride": 0.3,
                "step_height": 0.05,
                "yaw_rate": 0.1,
                "accelerate_steps": 2,
                "decelerate_steps": 2,
            },
        }
    )
    d = gaitshift.plan(sc).arrays()
    assert physics.eq1_error(d, sc.gravity) < 1e-6
    assert max(physics.ode_errors(d, sc.gravity)) < 1e-6
    assert d["footsteps"][-1, 2] == pytest.approx(0.30)
    goal = d["footsteps"][-2:, :3].mean(axis=0) + np.array([0.0, 0.0, sc.height])
    assert np.linalg.norm(d["com_pos"][-1] - goal) < 1e-3 and np.linalg.norm(d["com_vel"][-1]) < 1e-3
