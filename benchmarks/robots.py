"""Per-robot sweep of issue 12: for each shipped robot, scale a G1 walk and walk-run-walk scenario to it
(timing kept; the robot YAML's ``gait`` choices applied), solve the whole-body IK (joint speeds not
refused, measured: peak and fraction of ``RobotConfig.speed_limits``), simulate closed loop (no
joint-speed pre-check, unlike the CLI; the fraction of walking / running time with a leg joint at
>= 0.95 of its torque limit), and print one table row per run with the numbers of docs/robots.md.
Long (minutes): run alone.

    python benchmarks/robots.py [ROBOT ...]
"""

from __future__ import annotations

import sys

import numpy as np

from gaitshift.api import plan
from gaitshift.robots import RobotConfig, load_robot
from gaitshift.robots.statics import standing_statics
from gaitshift.sim.scenario_run import simulate_scenario
from gaitshift.trajectory.contract import Trajectory
from gaitshift.wholebody.ik import IKInfeasibleError, IKSettings, WholeBodyIK
from gaitshift.wholebody.scaling import scale_scenario

ROBOTS = ("g1", "t1", "h1", "op3", "berkeley")
SCENARIOS = ("g1-walk", "g1-walk-run-walk")
#: robots planned with Froude time scaling (durations x sqrt(lambda)); none since the OP3's ``gait`` key
FROUDE: tuple[str, ...] = ()


def run(name: str, scenario: str) -> dict[str, object]:
    """Scale, IK and simulate one robot on one scenario; the measured numbers."""
    robot = load_robot(name)
    sc = scale_scenario(scenario, robot, time_scale="froude" if name in FROUDE else "keep")
    traj = plan(sc)
    row: dict[str, object] = {"robot": name, "scenario": scenario, "com_height": traj.meta.get("height")}
    row.update(step_width=sc.profile.step_width, flight_time=sc.timing.flight)  # the YAML's gait choices
    row.update(max_stride=sc.profile.max_stride, swing_height=sc.swing_height)
    try:
        ik = WholeBodyIK(robot, IKSettings()).solve(traj, 1.0 / (10 * traj.dt), check_velocities=False)
        model = robot.model()
        vadr = [model.jnt_dofadr[model.joint(n).id] for n in robot.joint_names]
        vj = np.max(np.abs(ik.qvel[:, vadr]), axis=0)
        row["ik_com_mm"] = 1e3 * ik.meta["ik"]["max_com_error_m"]
        row["ik_sole_mm"] = 1e3 * ik.meta["ik"]["max_sole_position_error_m"]
        j = int(np.argmax(vj))
        row["peak_speed"] = f"{vj[j]:.2f} ({robot.joint_names[j]})"
        lim, _ = robot.speed_limits()
        if np.any(np.isfinite(lim)):
            frac = np.where(np.isfinite(lim), vj / np.where(np.isfinite(lim), lim, 1.0), 0.0)
            k = int(np.argmax(frac))
            row["speed_frac"] = f"{frac[k]:.2f} ({robot.joint_names[k]})"
    except IKInfeasibleError as exc:
        row["ik"] = str(exc)
    res = simulate_scenario(sc, robot, state="oracle").result  # the table is on the truth (docs)
    m = res.metrics
    row.update(leg_saturation(res.arrays, traj, robot))
    strides = np.diff(traj.footsteps[:, 0])
    row.update(
        fell=m["fell"],
        fall=m.get("fall_reason"),
        fall_time=m.get("fall_time"),
        steps=f"{m['steps_completed']}/{m['steps_planned']}",
        stride=float(np.max(strides)) if len(strides) else 0.0,
        speed=m.get("mean_forward_speed_max"),
        flight_ratio=m.get("flight_ratio"),
        torque_frac=m.get("peak_torque_fraction"),
    )
    return row


def leg_saturation(a: dict[str, np.ndarray], traj: Trajectory, robot: RobotConfig) -> dict[str, float | None]:
    """Fraction of the simulated walking / running time with some leg joint at >= 0.95 of its torque limit."""
    legs = [robot.joint_names.index(n) for n in robot.leg_joints]
    sat = np.any(np.abs(a["tau"][:, legs]) >= 0.95 * robot.torque_limit[legs], axis=1)
    running = np.interp(a["t"], traj.t, traj.gait) > 1.5
    return {
        "leg_sat_walk": float(np.mean(sat[~running])) if np.any(~running) else None,
        "leg_sat_run": float(np.mean(sat[running])) if np.any(running) else None,
    }


def knee_strength(robot: RobotConfig) -> float:
    """Smaller knee torque limit / (m g leg length): the leg's strength for the robot's weight."""
    knees = [robot.joint_names.index(k) for k in robot.knees]
    return float(np.min(robot.torque_limit[knees]) / (robot.mass * 9.81 * robot.leg_length))


def main(robots: list[str]) -> None:
    for name in robots or ROBOTS:
        r = load_robot(name)
        st = standing_statics(r)
        print(
            f"# {name}: mass {r.mass:.2f} kg, leg {r.leg_length:.3f} m, CoM height {r.com_height:.3f} m, "
            f"standing torque {st.torque_fraction.max():.2f} of the limit, knee strength "
            f"{knee_strength(r):.3f} (knee torque limit / (m g leg)), "
            f"gait {r.flight_scale=} {r.step_width=} {r.step_time_scale=}",
            flush=True,
        )
        for scenario in SCENARIOS:
            print(run(name, scenario), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
