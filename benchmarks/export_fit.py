"""Plan exports fit for training (docs/export.md "Fit for training"): for every G1 built-in scenario, the
whole-body IK of the export (200 Hz, resampled to mjlab's 50 fps) with the default settings (the MJCF
joint range, no pelvis task, flat swing soles) and with ``REFERENCE_SETTINGS`` (what ``gaitshift export``
uses): frames with a joint outside the soft range (robot YAML ``limits.soft_joint_fraction``), pelvis
roll range and peak rate about the pelvis's x axis, pelvis pitch range, the largest joint speed over its
limit (of the 50 fps frames), IK time per sample; or why the IK refuses the plan.
For the reference IK also the motion's deviation from the plan (``meta["ik"]["plan_fit"]``,
:mod:`gaitshift.wholebody.plan_fit`): max CoM error, max error of a flat sole in contact, toe-off
(samples, largest pivot angle and sole-centre rise), smallest margin of the plan's ZMP inside the
support left by a toe-off, smallest sole-corner clearance above the ground of the soles in contact
and of the swing soles (both checked), the largest lift of a swing sole above the plan's swing path,
flight samples solved with soft sole poses and the largest sole error there.
With ``--sim``, also the closed-loop alternative: ``gaitshift simulate`` of g1-walk-run-walk, exported
from its log, measured the same way (about 25 s more).

    PYTHONPATH=src python benchmarks/export_fit.py [--sim] [SCENARIO ...]
"""

from __future__ import annotations

import sys

import numpy as np

from gaitshift.api import plan
from gaitshift.export.resample import resample
from gaitshift.export.source import MIN_IK_RATE
from gaitshift.robots import load_robot
from gaitshift.scenario.loader import builtin_names, load_scenario
from gaitshift.wholebody.ik import REFERENCE_SETTINGS, IKInfeasibleError, IKSettings, WholeBodyIK
from gaitshift.wholebody.ik_tasks import soft_range

FPS = 50


def measure(t: np.ndarray, qpos: np.ndarray) -> dict[str, object]:
    """Frames outside the G1's soft range, pelvis roll range (deg), peak roll rate (rad/s), pelvis pitch
    range (deg) and the largest joint speed over its limit (ratio) at 50 fps."""
    robot = load_robot("g1")
    _, q, v = resample(t, qpos, FPS)
    model = robot.model()
    adr = [model.jnt_qposadr[model.joint(n).id] for n in robot.joint_names]
    soft = soft_range(robot.joint_range, robot.soft_joint_fraction)
    out = np.any((q[:, adr] < soft[:, 0] - 1e-9) | (q[:, adr] > soft[:, 1] + 1e-9), axis=1)
    w, x, y, z = q[:, 3:7].T
    roll = np.degrees(np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    pitch = np.degrees(np.arcsin(np.clip(2 * (w * y - z * x), -1, 1)))
    vadr = [model.jnt_dofadr[model.joint(n).id] for n in robot.joint_names]
    return {
        "frames": len(q),
        "outside_soft": int(out.sum()),
        "roll_deg": (round(float(roll.min()), 2), round(float(roll.max()), 2)),
        "roll_rate": round(float(np.abs(v[:, 3]).max()), 3),  # body-frame angular velocity about x
        "pitch_deg": (round(float(pitch.min()), 1), round(float(pitch.max()), 1)),
        "speed_ratio": round(float((np.abs(v[:, vadr]) / robot.velocity_limit).max()), 2),
    }


def run(name: str, settings: IKSettings) -> dict[str, object]:
    """One scenario through the export's IK with ``settings``."""
    traj = plan(load_scenario(name))
    step = max(1, int(1.0 / (traj.dt * max(MIN_IK_RATE, 4.0 * FPS)) + 1e-9))
    try:
        ik = WholeBodyIK("g1", settings)
        joints = ik.solve(traj, rate=1.0 / (step * traj.dt))
    except IKInfeasibleError as exc:
        return {"refused": str(exc)[:160]}
    row = measure(joints.t, joints.qpos)
    row["ik_ms_per_sample"] = round(1e3 * joints.meta["ik"]["time_per_sample_median_s"], 2)
    if "plan_fit" in joints.meta["ik"]:
        row["fit"] = joints.meta["ik"]["plan_fit"]
    return row


def fit_cell(fit: dict[str, float | None]) -> str:
    """The plan-fit numbers of one export: mm, deg, samples."""
    zmp = fit["zmp_margin_m"]
    toe = (
        f"toe-off {fit['toe_off_samples']} samples, <= {np.degrees(fit['toe_off_angle_rad']):.1f} deg, "  # type: ignore[arg-type]
        f"rise {1e3 * fit['toe_off_rise_m']:.1f} mm, ZMP margin {1e3 * zmp:.1f} mm"  # type: ignore[operator]
        if zmp is not None
        else "no toe-off"
    )
    return (
        f"CoM {1e3 * fit['com_error_m']:.3f} mm, contact sole {1e3 * fit['contact_sole_error_m']:.2f} mm, "  # type: ignore[operator]
        f"{toe}, ground clearance {1e3 * fit['ground_clearance_m']:+.2f} mm"  # type: ignore[operator]
        + (f", swing {1e3 * swing:+.2f} mm" if (swing := fit.get("swing_clearance_m")) is not None else "")
        + (f", swing lift {1e3 * lift:.1f} mm" if (lift := fit.get("swing_lift_m")) else "")
        + (
            f", flight reach {fit['flight_reach_samples']} samples, <= {1e3 * fit['flight_reach_error_m']:.1f} mm"  # type: ignore[operator]
            if fit.get("flight_reach_samples")
            else ""
        )
    )


def closed_loop(name: str = "g1-walk-run-walk") -> dict[str, object]:
    """The closed-loop alternative: the simulated run of ``name``, measured like an export of its log."""
    from gaitshift.sim.scenario_run import simulate_scenario

    res = simulate_scenario(name).result
    return {"fell": res.fell, **measure(res.arrays["t"], res.arrays["qpos"])}


def main(argv: list[str]) -> None:
    sim = "--sim" in argv
    names = [a for a in argv if a != "--sim"] or [n for n in builtin_names() if n.startswith("g1-")]
    print(
        "| scenario | default IK: outside soft / frames, roll (deg), rate (rad/s), pelvis pitch (deg), "
        "max joint speed / limit, IK ms/sample | reference IK: same |"
    )
    print("| --- | --- | --- |")
    for name in names:
        cells = []
        for settings in (IKSettings(), REFERENCE_SETTINGS):
            r = run(name, settings)
            if "refused" in r:
                cells.append(f"refused: {r['refused']}")
                continue
            roll = r["roll_deg"]
            cells.append(
                f"{r['outside_soft']} / {r['frames']}, {roll[0]:+.2f} .. {roll[1]:+.2f}, {r['roll_rate']:.3f}"  # type: ignore[index]
                + f", pitch {r['pitch_deg'][0]:+.1f} .. {r['pitch_deg'][1]:+.1f}, speed {r['speed_ratio']}"  # type: ignore[index]
                + f", {r['ik_ms_per_sample']} ms"
                + (f"; {fit_cell(r['fit'])}" if "fit" in r else "")  # type: ignore[arg-type]
            )
        print(f"| {name} | {cells[0]} | {cells[1]} |", flush=True)
    if sim:
        print("closed loop (simulated g1-walk-run-walk, its log exported):", closed_loop())


if __name__ == "__main__":
    main(sys.argv[1:])
