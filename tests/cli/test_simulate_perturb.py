"""``gaitshift simulate``'s perturbation flags (issue 13): a bad ``--push``, ``--bump``,
``--mass-scale``, ``--joint-vel-noise``, ``--com-offset`` or ``--motor-strength`` is one line naming
the flag, exit 2, no file; good ones reach the run (the pushes' impulses are in the log, the bump, mass
scale, noise, base CoM offset and motor strength in its metadata), and a scenario's ``sim:`` pushes
apply unless ``--push`` replaces them."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from gaitshift.scenario.loader import builtin_text


@pytest.mark.parametrize(
    ("flag", "value"),
    [
        ("--push", "1,2"),
        ("--push", "-5"),
        ("--push", "1,0,5,0,-0.1"),
        ("--bump", "1,0"),
        ("--bump", "x,0.1"),
        ("--mass-scale", "9"),
        ("--joint-vel-noise", "-1"),
        ("--com-offset", "0,0.5,0"),
        ("--com-offset", "0.01,0.02"),
        ("--com-offset", "a,b,c"),
        ("--motor-strength", "0"),
    ],
)
def test_a_bad_perturbation_flag_is_one_line_naming_it_and_exit_2(cli, tmp_path, flag, value):
    out = tmp_path / "o.npz"
    code, _, stderr = cli(["simulate", "g1-walk", "--out", str(out), flag, value])
    assert code == 2, stderr
    assert stderr.count("\n") == 1 and flag in stderr and "Traceback" not in stderr
    assert not out.exists()


def test_perturbation_flags_reach_the_run(cli, tmp_path):
    data = yaml.safe_load(builtin_text("g1-walk"))
    data["gait"] = [{"gait": "walk", "steps": 2}]
    data["profile"] |= {"accelerate_steps": 1, "decelerate_steps": 1}
    data["sim"] = {"pushes": [{"t": 0.5, "impulse": [0.0, 99.0]}]}  # replaced by --push below
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(data))
    out = tmp_path / "o.npz"
    argv = ["simulate", str(path), "--out", str(out), "--json", "--push", "0.5,1,-2,0,0.05", "--push", "1.0,0,0,3"]
    argv += ["--bump", "4,0.02,0.1", "--mass-scale", "1.05", "--joint-vel-noise", "0.3"]
    argv += ["--com-offset", "0.02,-0.01,0", "--motor-strength", "0.95"]
    code, stdout, stderr = cli(argv)
    assert code == 0, stderr
    json.loads(stdout)
    with np.load(out) as z:
        f, t = z["push_force"], z["t"]
        meta = json.loads(str(z["meta"]))
    dt = t[1] - t[0]
    np.testing.assert_allclose(f[t < 0.9].sum(axis=0) * dt, [1.0, -2.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(f[t >= 0.9].sum(axis=0) * dt, [0.0, 0.0, 3.0], atol=1e-9)
    assert meta["bumps"] == [{"x": 4.0, "height": 0.02, "length": 0.1}]
    assert meta["mass_scale"] == 1.05 and meta["joint_vel_noise"] == 0.3
    assert meta["com_offset"] == [0.02, -0.01, 0.0] and meta["motor_strength"] == 0.95
