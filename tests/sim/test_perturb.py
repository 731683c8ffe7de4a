"""Mass scale: the physics model's total mass is s M, every body's mass and inertia scale by s (its CoM
stays), the nominal model is untouched, and SimOptions refuses a scale outside its range."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.robots import load_robot
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.perturb import scaled_masses


def test_scaled_model_has_s_times_the_mass_and_nominal_is_untouched():
    """mj_getTotalmass(scaled) = s mj_getTotalmass(nominal); body CoM offsets unchanged; s = 1 is a no-op."""
    model = load_robot("g1").model()
    m0 = mujoco.mj_getTotalmass(model)
    before = model.body_mass.copy()
    heavy = scaled_masses(model, 1.3)
    assert mujoco.mj_getTotalmass(heavy) == pytest.approx(1.3 * m0, rel=1e-12)
    assert np.allclose(heavy.body_inertia, 1.3 * model.body_inertia)
    assert np.array_equal(heavy.body_ipos, model.body_ipos)
    assert np.array_equal(model.body_mass, before)
    assert scaled_masses(model, 1.0) is model


@pytest.mark.parametrize(("scale", "offset"), [(0.9, (0.0, 0.0, 0.0)), (1.1, (0.04, -0.03, 0.01))])
def test_the_perturbed_plants_com_is_the_mass_weighted_mean_of_its_bodies(scale, offset):
    """MuJoCo's whole-body CoM of the perturbed plant, the one the run's log and metrics read, is
    sum_b m_b x_b / sum_b m_b of that plant's own masses and body CoMs (on the old code, with the
    compile-time subtree mass left nominal, it was ``scale`` times that: 6 cm low at 0.9 on a standing
    G1), and its CoM velocity sum_b m_b v_b / sum_b m_b."""
    from gaitshift.sim.perturb import perturbed_physics
    from gaitshift.sim.plant import build_plant

    plant = build_plant(0.002, "g1")
    m = perturbed_physics(plant.model, scale, np.array(offset), 1.0, plant.pelvis_body)
    d = mujoco.MjData(m)
    d.qpos[:] = m.qpos0
    d.qvel[:] = np.random.default_rng(0).normal(0.0, 0.5, m.nv)
    mujoco.mj_forward(m, d)
    mujoco.mj_subtreeVel(m, d)
    mass = m.body_mass[1:, None]
    assert np.allclose(d.subtree_com[0], (mass * d.xipos[1:]).sum(0) / mass.sum(), atol=1e-12)
    v = np.zeros((m.nbody, 6))
    for b in range(1, m.nbody):
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_XBODY, b, v[b], 0)
    vcom = v[1:, 3:] + np.cross(v[1:, :3], d.xipos[1:] - d.xpos[1:])  # each body's CoM velocity
    assert np.allclose(d.subtree_linvel[0], (mass * vcom).sum(0) / mass.sum(), atol=1e-9)


@pytest.mark.parametrize("bad", [0.0, -1.0, 10.0, float("nan"), True])
def test_sim_options_refuse_bad_mass_scale(bad):
    """A mass scale outside [0.25, 4] (or not a number) is one InputError naming mass_scale."""
    with pytest.raises(InputError, match="mass_scale"):
        SimOptions(mass_scale=bad)


def test_heavier_plant_weighs_more_on_the_floor_while_the_controller_keeps_its_model():
    """Newton: over a short walk that starts and ends at rest, the mean measured vertical ground force
    is the weight of the SCALED robot, 1.2 M g (M: the nominal mass the controller uses)."""
    from gaitshift.api import robot_facts
    from gaitshift.control.drivers import driver_for
    from gaitshift.scenario import load_scenario
    from gaitshift.sim.loop import simulate

    sc = load_scenario(
        {"planner": "locomotion", "robot": "g1", "gait": "walk", "commands": [{"vx": 0.3}], "stop_at": 0.6}
    )
    driver = driver_for(sc, robot_facts(sc), 0.002)
    res = simulate(driver.trajectory, SimOptions(mass_scale=1.2), driver=driver, robot="g1")
    assert not res.fell
    a = res.arrays
    weight = 1.2 * mujoco.mj_getTotalmass(load_robot("g1").model()) * 9.81
    assert np.linalg.norm(a["com_vel"][-1]) < 0.05  # ended at rest
    assert np.mean(a["grf"][:, :, 2].sum(axis=1)) == pytest.approx(weight, rel=0.02)


def test_a_base_com_offset_moves_the_whole_robots_com_by_the_bases_share_of_it():
    """Mass-weighted mean: moving the base's CoM by c (base frame, base at identity) moves the robot's
    CoM by (m_base / M) c; the nominal model keeps its CoM."""
    from gaitshift.sim.perturb import perturbed_physics
    from gaitshift.sim.plant import build_plant

    plant = build_plant(0.002, "g1")
    model, base = plant.model, plant.pelvis_body
    c = np.array([0.04, -0.03, 0.01])
    moved = perturbed_physics(model, 1.0, c, 1.0, base)
    coms = []
    for m in (model, moved):
        d = mujoco.MjData(m)
        d.qpos[:] = m.qpos0
        d.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
        mujoco.mj_forward(m, d)
        coms.append(d.subtree_com[0].copy())
    share = model.body_mass[base] / mujoco.mj_getTotalmass(model)
    assert np.allclose(coms[1] - coms[0], share * c, atol=1e-12)
    assert np.array_equal(model.body_ipos[base], build_plant(0.002, "g1").model.body_ipos[base])


def test_motor_strength_scales_the_joint_torque_and_its_limit_but_not_tau_est():
    """qfrc_actuator = k tau for a command inside the limit and k tau_max beyond it; the reported
    actuator force (tau_est) is the command, as a driver with the nominal torque constant reports it."""
    from gaitshift.sim.perturb import perturbed_physics
    from gaitshift.sim.plant import build_plant

    plant = build_plant(0.002, "g1")
    model = plant.model
    for k in (0.9, 1.1):
        weak = perturbed_physics(model, 1.0, (0.0, 0.0, 0.0), k, plant.pelvis_body)
        d = mujoco.MjData(weak)
        limit = weak.actuator_ctrlrange[:, 1]
        dofs = weak.jnt_dofadr[weak.actuator_trnid[:, 0]]
        for cmd in (0.5 * limit, 2.0 * limit):
            d.ctrl[:] = cmd
            mujoco.mj_forward(weak, d)
            assert np.allclose(d.qfrc_actuator[dofs], k * np.minimum(cmd, limit), rtol=1e-12)
            assert np.allclose(d.actuator_force, np.minimum(cmd, limit), rtol=1e-12)


@pytest.mark.parametrize(
    ("key", "bad"), [("com_offset", (0.0, 0.5, 0.0)), ("com_offset", (0.0, 0.1)), ("com_offset", "abc"),
                     ("motor_strength", 0.0), ("motor_strength", float("nan"))],
)  # fmt: skip
def test_sim_options_refuse_a_bad_com_offset_or_motor_strength(key, bad):
    """Out of range or malformed: one InputError naming the field."""
    with pytest.raises(InputError, match=key):
        SimOptions(**{key: bad})
