"""Rerun recordings of ``gaitshift plan --rerun`` and ``gaitshift simulate --rerun``, read back with the
Rerun SDK (``rerun.chunk.RrdReader``): every promised entity is there, the timelines hold the file's
own numbers (plan CoM, logged CoM and contact forces), and the 3D content is physically right:

* the plan's left ankle-roll body frame, moved by the sole offset of the robot YAML, lands on the
  plan's left foot at the same time (the body frames are the whole-body motion of the plan);
* the plan's ZMP lies in the recorded support polygon whenever a foot is on the ground;
* the run's pelvis frame is the logged floating-base position;
* a plan with a speed command records it (``timeseries/speed/commanded``), and a plan naming no
  robot says that it has no body frames;
* a bad ``--rerun`` name is one line, exit 2, and no file is written.
"""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.cli import main
from gaitshift.robots import load_robot
from rrd_files import read, series

pytest.importorskip("rerun.chunk")


PLAN_ENTITIES = [
    *(f"timeseries/com/{a}" for a in "xyz"),
    "timeseries/zmp/x",
    "timeseries/zmp/y",
    "timeseries/feet/left/z",
    "timeseries/feet/right/z",
    "timeseries/grf/total/z",
    "timeseries/speed/com",
    "timeseries/gait",
    "timeseries/phase",
    "events/gait",
    "events/phase",
    "world/com",
    "world/zmp",
    "world/footsteps",
    "world/support",
    "world/bodies/pelvis",
    "world/bodies/left_ankle_roll_link",
]


@pytest.fixture(scope="module")
def plan_rec(motions):
    return read(motions["g1-plan-rrd"])


def test_the_plan_recording_holds_every_timeline_with_the_plans_numbers(plan_rec, motions):
    assert set(PLAN_ENTITIES) <= set(plan_rec)
    z = np.load(motions["g1-plan"])
    t, x = series(plan_rec, "timeseries/com/x")
    assert len(t) == len(z["t"]) and np.abs(t - z["t"]).max() < 1e-6
    assert np.abs(x - z["com_pos"][:, 0]).max() < 1e-12
    t, fz = series(plan_rec, "timeseries/grf/total/z")
    mass = load_robot("g1").mass
    assert np.abs(fz - mass * (z["com_acc"][:, 2] + 9.81)).max() < 1e-6
    assert abs(np.mean(fz) - mass * 9.81) < 0.01 * mass * 9.81  # starts and ends at rest: mean weight
    _, phase = series(plan_rec, "timeseries/phase")
    assert set(np.unique(phase)) == {0.0, 1.0}  # walking: DS and SS only
    gaits = [v[0] for _, v in sorted(plan_rec["events/gait"]["TextLog:text"])]
    assert gaits[:2] == ["stand", "walk"]


def _frames(rec, body):
    rows = sorted(
        (t, tr, q)
        for (t, tr), (_, q) in zip(
            rec[f"world/bodies/{body}"]["Transform3D:translation"],
            rec[f"world/bodies/{body}"]["Transform3D:quaternion"],
            strict=True,
        )
    )
    return np.array([r[0] for r in rows]), np.array([r[1][0] for r in rows]), np.array([r[2][0] for r in rows])


def test_the_plans_body_frames_put_the_left_sole_on_the_planned_foot(plan_rec, motions):
    import mujoco

    g1 = load_robot("g1")
    t, pos, quat_xyzw = _frames(plan_rec, g1.sole_bodies[0])
    z = np.load(motions["g1-plan"])
    assert len(t) > 300  # 50 Hz over 7.85 s
    offset = np.array(g1.sole_offsets[0])
    R = np.zeros(9)
    sole = np.empty((len(t), 3))
    for k, q in enumerate(quat_xyzw):
        mujoco.mju_quat2Mat(R, np.r_[q[3], q[:3]])
        sole[k] = pos[k] + R.reshape(3, 3) @ offset
    k = np.clip(np.searchsorted(z["t"], t - 1e-9), 0, len(z["t"]) - 1)
    assert np.abs(z["t"][k] - t).max() < 1e-6
    assert np.linalg.norm(sole - z["foot_pos"][k, 0], axis=1).max() < 1e-3


def test_the_plans_zmp_is_inside_the_recorded_support_polygon(plan_rec, motions):
    z = np.load(motions["g1-plan"])
    inside = 0
    for t, strips in plan_rec["world/support"]["LineStrips3D:strips"]:
        if not strips:
            continue
        poly = np.array(strips[0])[:-1, :2]
        p = z["zmp"][np.argmin(np.abs(z["t"] - t)), :2]
        edges = np.roll(poly, -1, axis=0) - poly
        cross = edges[:, 0] * (p[1] - poly[:, 1]) - edges[:, 1] * (p[0] - poly[:, 0])
        assert np.all(cross >= -1e-9) or np.all(cross <= 1e-9), t
        inside += 1
    assert inside > 300


def test_the_run_recording_holds_the_measured_motion(motions):
    rec = read(motions["g1-sim-rrd"])
    expected = {
        "timeseries/com/x",
        "timeseries/com_ref/x",
        "timeseries/zmp/x",
        "timeseries/grf/left/z",
        "timeseries/grf_ref/right/z",
        "timeseries/speed/reference",
        "timeseries/speed/measured",
        "timeseries/gait",
        "timeseries/phase",
        "timeseries/contact/left",
        "world/support",
        "world/bodies/pelvis",
        "world/bodies/torso_link",
    }
    assert expected <= set(rec)
    log = np.load(motions["g1-sim"])
    t, fz = series(rec, "timeseries/grf/left/z")
    assert len(t) == len(log["t"]) and np.abs(fz - log["grf"][:, 0, 2]).max() < 1e-9
    _, v = series(rec, "timeseries/speed/measured")
    assert np.abs(v - np.linalg.norm(log["com_vel"][:, :2], axis=1)).max() < 1e-12
    t, pos, _ = _frames(rec, "pelvis")
    k = np.clip(np.searchsorted(log["t"], t - 1e-9), 0, len(log["t"]) - 1)
    assert np.abs(pos - log["qpos"][k, :3]).max() < 1e-6  # Rerun stores translations as float32


def test_a_commanded_plan_records_the_commanded_speed_and_says_why_it_has_no_bodies(tmp_path):
    with pytest.raises(SystemExit) as exc:
        main(["plan", "paper003-variable-speed", "--out", str(tmp_path / "p.npz"), "--rerun", str(tmp_path / "p.rrd")])
    assert exc.value.code == 0
    rec = read(tmp_path / "p.rrd")
    z = np.load(tmp_path / "p.npz")
    t, v = series(rec, "timeseries/speed/commanded")
    given = np.all(np.isfinite(z["command_vel"]), axis=1)
    assert len(t) == given.sum() > 0
    assert np.abs(v - np.linalg.norm(z["command_vel"][given], axis=1)).max() < 1e-12
    assert len(np.unique(v)) > 2  # the command really varies
    assert not any(e.startswith("world/bodies/") for e in rec)
    assert "no robot" in rec["events/notes"]["TextLog:text"][0][1][0]


def test_a_bad_rerun_name_is_one_line_exit_2_and_no_file(tmp_path, capsys):
    for argv in (
        ["plan", "g1-walk", "--out", tmp_path / "p.npz", "--rerun", tmp_path / "p.txt"],
        ["simulate", "g1-walk", "--out", tmp_path / "s.npz", "--rerun", tmp_path / "s.rrdx"],
    ):
        with pytest.raises(SystemExit) as exc:
            main([str(a) for a in argv])
        err = capsys.readouterr().err
        assert exc.value.code == 2 and err.count("\n") == 1 and "--rerun" in err
    assert list(tmp_path.iterdir()) == []


def test_the_run_recording_holds_the_controllers_map_from_the_log(motions):
    """The G1 has a depth camera: the recording's last map cloud is the log's final map (one point per
    seen cell, at the cell's centre and height), each earlier one is its logged snapshot, and the map
    under the left sole its logged height."""
    rec = read(motions["g1-sim-rrd"])
    log = np.load(motions["g1-sim"])
    seen = log["map_seen"].astype(bool)
    maps = sorted((t, np.asarray(c, dtype=float)) for t, c in rec["world/elevation_map"]["Points3D:positions"])
    assert len(maps) == len(log["map_t"]) + 1
    for k, (tk, cells) in enumerate(maps[:-1]):
        assert tk == pytest.approx(log["map_t"][k], abs=1e-6)
        np.testing.assert_allclose(cells, log["map_cells"][log["map_cells_set"] == k], atol=1e-6)
    t_map, cloud = maps[-1]
    assert t_map == pytest.approx(log["t"][-1], abs=1e-6) and len(cloud) == seen.sum() > 100
    r, corner = float(log["map_resolution"]), log["map_corner"]
    ij = np.floor((cloud[:, :2] - corner) / r).astype(int)
    assert np.abs(cloud[:, 2] - log["map_heights"][ij[:, 0], ij[:, 1]]).max() < 1e-6
    t, h = series(rec, "timeseries/map/left")
    known = log["map_known"][:, 0].astype(bool)
    assert len(t) == known.sum() and np.abs(h - log["map_height"][known, 0]).max() < 1e-9
