"""Scale a paper scenario to a robot.

The papers plan for life-size robots (paper 001: Kaleido, nominal CoM height h = 0.95 m). A smaller
robot walks the same gait when every length scales with its legs. The rule:

1. **CoM height.** h' = the robot's nominal CoM height (``RobotConfig.com_height``: whole-body CoM
   above the soles in its standing pose, whose knee bend keeps the leg clear of the straight-knee
   singularity; for the G1 h' = 0.655 m with a leg length of 0.692 m). The scale factor is
   lambda = h' / h.
2. **Lengths along the path** scale with lambda: stride (``profile.max_stride`` and explicit
   footholds), step rise, swing-foot clearance, the ZMP margin and vertical ZMP band, and the
   reachability limits (``limits``). Geometric similarity keeps the leg angles of the paper's gait.
3. **Feet** are the robot's: ``foot.size`` = the sole rectangle of the config, and the lateral step
   width = the foot separation of the standing pose (the robot's hip width, not a scaled copy of the
   paper's, so that the legs stay parallel).
4. **Timing is kept** (``time_scale="keep"``, the default). Phase durations are not scaled, so the
   stiffness is not scaled either: the planner recomputes T_w = sqrt(h'/g) and T_r, T_t0, T_t1
   (paper 001 eqs. 9-14) from the new height. This keeps the paper's rhythm, which makes the scaled
   gait slower in Froude number v^2/(g h) by the factor lambda.
   With ``time_scale="froude"`` (``gaitshift scale --time-scale froude``) every duration is multiplied
   by sqrt(lambda) (tau' = tau sqrt(lambda), :data:`TIME_KEYS`) and speeds by sqrt(lambda), so that the
   gait keeps the paper's Froude number: for robots much smaller or larger than the paper's (OP3:
   lambda ~ 0.27, durations x 0.52). lambda is the geometric scale factor of rule 1, which is the
   leg-length ratio of geometrically similar robots.

5. **The robot's own choices** (its YAML's ``gait`` key, docs/robots.md), applied last:
   ``flight_scale`` multiplies the flight time of the running steps (TV-LIPM ``timing.flight``). The
   touchdown speed of a flight is g T_f / 2 whatever the robot's size, and the stance must reverse it:
   the mean vertical force of a running stance is m g (T_s + T_f) / T_s, so a robot whose legs are weak
   for its weight (knee torque limit / (m g leg length)) runs with a shorter flight. ``step_width``
   replaces the foot separation of rule 3 (a robot whose standing feet are wide apart for its height
   swings its CoM sideways by about that much at every step). ``step_time_scale`` s multiplies the
   single and double support times (TV-LIPM ``timing``; VHIP ``step_period``) and the stride
   (``profile.max_stride``; a VHIP stride is speed x period), so the speed is kept: the LIPM's lateral
   sway over a step of duration T between feet at +-w is w (1 - 1/cosh(omega T / 2)), omega =
   sqrt(g/h), and a leg that cannot roll its foot (no ankle roll) can make only a small one; the
   shorter stride also keeps the trailing foot flat within the ankle's range. Then ``max_stride`` caps
   the stride (TV-LIPM ``profile.max_stride``, VHIP ``limits.max_stride``: min(lambda x the scenario's, cap); explicit
   footholds are kept) and ``swing_height`` replaces the swing-foot clearance (TV-LIPM ``swing_height``,
   VHIP ``swing_apex``): a robot whose joints are slow for its size (viscous damping b, torque limit
   tau_max: no-load speed tau_max / b) needs smaller joint excursions per step than geometric
   similarity gives.

Angles (yaw, yaw rate), gravity and the sampling step are unchanged. A ``planner: locomotion`` scenario
(live commands) follows the same rule on the keys it sets; the keys it leaves out default from the new
robot (:mod:`gaitshift.wholebody.scaling_locomotion`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from gaitshift.errors import InputError, check_choice
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.scenario import load_scenario
from gaitshift.wholebody.scaling_locomotion import locomotion_height, scale_locomotion_data

#: Dotted keys multiplied by lambda, per planner (lengths, and speeds of a gait whose timing is kept).
LENGTH_KEYS: dict[str, tuple[str, ...]] = {
    "tvlip": (
        "profile.max_stride",
        "profile.step_height",
        "limits.max_stride",
        "limits.max_step_height",
        "swing_height",
        "foot.zmp_margin",
        "foot.zmp_z",
    ),
    "vhip": (
        "heights.stand",
        "heights.touchdown",
        "heights.takeoff",
        "heights.z_low",
        "foot.zmp_margin",
        "foot.zmp_z",
        "limits.max_speed",
        "limits.max_stride",
        "limits.max_accel_per_step",
        "swing_apex",
    ),
}


#: Dotted keys multiplied by sqrt(lambda) with ``time_scale="froude"`` (durations), per planner.
TIME_KEYS: dict[str, tuple[str, ...]] = {
    "tvlip": ("timing.single_support", "timing.double_support", "timing.flight", "timing.start", "timing.stop"),
    "vhip": ("step_period", "start_double_support", "stop_double_support", "stop_at"),
}
#: the time scalings of :func:`scale_scenario`
TIME_SCALES = ("keep", "froude")


def _locomotion_height(scenario: Any) -> float:
    from gaitshift.api import robot_facts

    return locomotion_height(scenario, robot_facts(scenario))


#: the nominal CoM height of a scenario, m, per planner (locomotion: the height its keys resolve to on
#: its own robot, :mod:`gaitshift.wholebody.scaling_locomotion`)
NOMINAL_HEIGHT: dict[str, Callable[[Any], float]] = {
    "tvlip": lambda sc: float(sc.height),
    "vhip": lambda sc: float(sc.heights.stand),
    "locomotion": _locomotion_height,
}
#: planners whose dumped scenario is scaled by their own function (data, robot, lambda, tau), in place
DATA_SCALERS: dict[str, Callable[[dict[str, Any], RobotConfig, float, float], None]] = {
    "locomotion": scale_locomotion_data,
}


def nominal_height(scenario: Any) -> float:
    """The scenario's nominal CoM height, m: ``height`` (TV-LIPM), ``heights.stand`` (VHIP), or what a
    locomotion scenario resolves to on its robot (:data:`NOMINAL_HEIGHT`).

    Raises:
        InputError: a planner that cannot be scaled."""
    if scenario.planner not in NOMINAL_HEIGHT:
        raise InputError("planner", scenario.planner, "a scenario of: " + ", ".join(NOMINAL_HEIGHT))
    return NOMINAL_HEIGHT[scenario.planner](scenario)


def scale_factor(scenario: Any, robot: str | Path | RobotConfig) -> float:
    """lambda = robot nominal CoM height / scenario nominal CoM height (rule 1 of the module docstring)."""
    robot = load_robot(robot)
    return robot.com_height / nominal_height(scenario)


def scale_scenario(
    scenario: Any, robot: str | Path | RobotConfig, name: str | None = None, time_scale: str = "keep"
) -> Any:
    """The scenario (object, built-in name or path) scaled to ``robot`` by the rule of this module.

    TV-LIPM: ``height`` = the robot's CoM height. VHIP: every CoM height of ``heights`` x lambda (so
    ``heights.stand`` = the robot's CoM height), commanded speeds and speed limits x lambda (same step
    timing, lambda times the stride); vertical accelerations at the switches are kept.
    ``time_scale``: ``keep`` or ``froude`` (rule 4). The scaled scenario names its robot (``robot``).
    Returns a validated scenario of the same planner, named ``name`` (default ``<robot>-<name>``).

    Raises:
        InputError: unknown ``time_scale``.
    """
    check_choice("--time-scale", time_scale, TIME_SCALES)
    if not hasattr(scenario, "planner"):
        scenario = load_scenario(scenario)
    robot = load_robot(robot)
    lam = scale_factor(scenario, robot)
    tau = math.sqrt(lam) if time_scale == "froude" else 1.0
    data = scenario.model_dump(mode="python")
    data["robot"] = robot.source or robot.name
    if scenario.planner in DATA_SCALERS:
        DATA_SCALERS[scenario.planner](data, robot, lam, tau)
    else:
        _scale_paper(data, scenario.planner, robot, lam, tau)
    width = robot.step_width if robot.step_width is not None else robot.foot_separation
    data["name"] = name or f"{robot.name}-{scenario.name}"
    desc = data.get("description", "")
    data["description"] = (
        f"{desc} -- scaled to {robot.name} (lambda = {lam:.4f}: CoM height "
        f"{robot.com_height:.4f} m, lengths x lambda, robot soles and foot separation, "
        + ("timing kept" if tau == 1.0 else f"durations x sqrt(lambda) = {tau:.4f}")
        + (f", flight x {robot.flight_scale:g}" if robot.flight_scale != 1.0 else "")
        + (f", step width {width:g} m" if robot.step_width is not None else "")
        + (f", steps x {robot.step_time_scale:g}" if robot.step_time_scale != 1.0 else "")
        + (f", stride <= {robot.max_stride:g} m" if robot.max_stride is not None else "")
        + (f", swing height {robot.swing_height:g} m" if robot.swing_height is not None else "")
        + ")"
    ).strip(" -")
    return load_scenario(data)


def _scale_paper(data: dict[str, Any], planner: str, robot: RobotConfig, lam: float, tau: float) -> None:
    """Rules 1-5 on a dumped TV-LIPM or VHIP scenario ``data``, in place."""
    width = robot.step_width if robot.step_width is not None else robot.foot_separation
    for key in TIME_KEYS.get(planner, ()):
        _scale_path(data, key, tau)
    if planner == "tvlip":
        data["height"] = robot.com_height
    for key in LENGTH_KEYS.get(planner, ()):
        _scale_path(data, key, lam)
    if planner == "vhip":
        data["heights"]["stand"] = robot.com_height
        v = lam / tau
        data["commands"] = [dict(c, t=c["t"] * tau, vx=c["vx"] * v, vy=c["vy"] * v) for c in data["commands"]]
    if isinstance(data.get("foot"), dict) and "size" in data["foot"]:
        data["foot"]["size"] = list(robot.sole_size)
    if planner == "vhip":
        data["step_width"] = width
    if isinstance(data.get("profile"), dict) and "step_width" in data["profile"]:
        data["profile"]["step_width"] = width
    if isinstance(data.get("timing"), dict) and data["timing"].get("flight") is not None:
        data["timing"]["flight"] *= robot.flight_scale
    _scale_steps(data, planner, robot.step_time_scale)
    _apply_gait_caps(data, planner, robot)
    if data.get("footsteps"):
        data["footsteps"] = [[x * lam, y * lam, z * lam, yaw] for x, y, z, yaw in data["footsteps"]]


def _scale_steps(data: dict[str, Any], planner: str, s: float) -> None:
    """Quicker, shorter steps (rule 5, ``step_time_scale`` s): support times and stride x s."""
    if s == 1.0:
        return
    keys = {"tvlip": ("timing.single_support", "timing.double_support", "profile.max_stride"), "vhip": ("step_period",)}
    for key in keys.get(planner, ()):
        _scale_path(data, key, s)


#: where the robot YAML's ``gait.max_stride`` / ``gait.swing_height`` go, per planner (rule 5)
STRIDE_KEY = {"tvlip": ("profile", "max_stride"), "vhip": ("limits", "max_stride")}
SWING_KEY = {"tvlip": "swing_height", "vhip": "swing_apex"}


def _apply_gait_caps(data: dict[str, Any], planner: str, robot: RobotConfig) -> None:
    """The robot's stride cap and swing height (rule 5 of the module docstring) on the scaled data."""
    if robot.max_stride is not None and planner in STRIDE_KEY:
        parent, leaf = STRIDE_KEY[planner]
        node = data.get(parent)
        if isinstance(node, dict) and node.get(leaf) is not None:
            node[leaf] = min(node[leaf], robot.max_stride)
    if robot.swing_height is not None and planner in SWING_KEY:
        data[SWING_KEY[planner]] = robot.swing_height


def _scale_path(data: dict[str, Any], dotted: str, lam: float) -> None:
    *parents, leaf = dotted.split(".")
    node: Any = data
    for p in parents:
        if not isinstance(node, dict) or not isinstance(node.get(p), dict):
            return
        node = node[p]
    if not isinstance(node, dict) or leaf not in node or node[leaf] is None:
        return
    v = node[leaf]
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        node[leaf] = v * lam
    elif isinstance(v, (list, tuple)) and all(isinstance(x, (int, float)) for x in v):
        node[leaf] = [x * lam for x in v]
    else:  # pragma: no cover - the schemas hold numbers or lists of numbers at these keys
        raise InputError(dotted, v, "a length (number or list of numbers) to scale")


def scenario_yaml(scenario: Any, header: str = "", folder: Path | None = None) -> str:
    """YAML text of a scenario (``gaitshift scale --out``), floats to 12 significant digits; with
    ``folder`` (the output file's), a robot given by an absolute YAML path is written relative to it
    (the loader resolves it from the scenario file's folder)."""
    import os

    import yaml

    data = scenario.model_dump(mode="json")
    robot = data.get("robot")
    if folder is not None and isinstance(robot, str) and Path(robot).is_absolute():
        data["robot"] = Path(os.path.relpath(robot, Path(folder).resolve())).as_posix()

    def _round(v: Any) -> Any:
        if isinstance(v, float):
            return float(f"{v:.12g}")
        if isinstance(v, list):
            return [_round(x) for x in v]
        if isinstance(v, dict):
            return {k: _round(x) for k, x in v.items() if x is not None}
        return v

    body = yaml.safe_dump(_round(data), sort_keys=False, default_flow_style=None, width=110, allow_unicode=True)
    return "".join(f"# {line}\n" for line in header.splitlines()) + body


def scaled_yaml(
    scenario: Any, robot: str | Path | RobotConfig, folder: Path, time_scale: str = "keep"
) -> tuple[str, float]:
    """The YAML text of ``scenario`` scaled to ``robot`` (:func:`scale_scenario`), for a file in
    ``folder`` (:func:`scenario_yaml`), headed by what was scaled by how much; and the scale factor."""
    sc = scenario if hasattr(scenario, "planner") else load_scenario(scenario)
    lam = scale_factor(sc, robot)
    label = robot.name if isinstance(robot, RobotConfig) else robot
    header = f"{sc.name} scaled to robot {label} by {lam:.4f} (gaitshift scale)"
    return scenario_yaml(scale_scenario(sc, robot, time_scale=time_scale), header, folder), lam
