"""``gaitshift dds robot`` rejects a bad flag value before it opens any DDS endpoint: one line naming the
flag, the value and what is allowed, exit code 2; the command is listed in ``gaitshift dds --help``; a
``--world`` scenario builds the world on its terrain (a ray cast down meets each tread at its height)."""

import mujoco
import numpy as np
import pytest

from gaitshift.dds.robot import scenario_world
from gaitshift.sim.plant import build_plant


@pytest.mark.parametrize(
    ("flags", "name"),
    [
        (["--domain", "300"], "--domain"),
        (["--damping-kd", "-1"], "--damping-kd"),
        (["--duration", "-2"], "--duration"),
        (["--mode-machine", "256"], "--mode-machine"),
        (["--drop", "0.9"], "--drop"),
        (["--delay-ms", "2", "--jitter-ms", "3"], "--jitter-ms"),
        (["--world", "nowhere"], "--world"),
        (["--rt-priority", "100"], "--rt-priority"),
        (["--record", "run.npy"], "--record"),
    ],
)
def test_a_bad_flag_is_one_line_and_exit_2(cli, flags, name):
    code, _, err = cli(["dds", "robot", "g1", *flags])
    assert code == 2
    assert err.startswith(f"gaitshift: error: {name} = ") and err.count("\n") == 1


def test_the_robot_command_is_listed(cli):
    code, out, _ = cli(["dds", "--help"])
    assert code == 0 and "robot" in out


def test_the_world_of_a_scenario_is_its_terrain():
    ground, friction = scenario_world("g1-stairs-up")
    plant = build_plant(0.002, "g1", ground)
    d = mujoco.MjData(plant.model)
    mujoco.mj_forward(plant.model, d)
    geomid = np.zeros(1, np.int32)
    for piece in ground.pieces:
        x = 0.5 * (piece.x0 + piece.x1)
        dist = mujoco.mj_ray(plant.model, d, np.array([x, 3.0, 2.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geomid)
        assert 2.0 - dist == pytest.approx(piece.z0, abs=1e-6)
    assert friction is None and scenario_world(None)[0].flat
