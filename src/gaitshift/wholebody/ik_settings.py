"""The settings of the whole-body IK (:mod:`gaitshift.wholebody.ik`): tolerances, weights and which
freedoms and limits it uses; :data:`REFERENCE_SETTINGS`, those of the reference motions that ``gaitshift
export`` makes of a plan (docs/export.md "Fit for training")."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["REFERENCE_SETTINGS", "IKSettings"]


@dataclass(frozen=True)
class IKSettings:
    """Tolerances and weights of the whole-body IK.

    Attributes:
        com_tol, pos_tol, rot_tol: a sample whose CoM error (m), sole position error (m) or sole
            orientation error (rad) stays above these after ``max_iter`` iterations is infeasible.
        converged_pos, converged_rot: stop iterating below these errors (m, rad).
        max_iter: Newton iterations per sample; ``first_iter`` for the first sample (from standing).
        knee_margin: a knee within this angle (rad) of straight is a singularity.
        torso_cost, posture_cost, arm_cost: weights of the soft tasks (unitless, per rad).
        damping: Levenberg-Marquardt damping of the QP.
        extrapolate: warm-start each sample at q_{k-1} ⊕ (q_{k-1} ⊖ q_{k-2}) (else at q_{k-1}).
        soft_limits: keep every joint within its soft range (``RobotConfig.soft_joint_fraction`` of its
            range), else within the MJCF range.
        pelvis_cost: weight of the floating base's orientation task (upright, yaw = mean sole yaw;
            unitless, per rad); 0: none.
        swing_pitch_cost: weight of a swing sole's pitch as a soft task (per rad); None: a hard
            constraint like the stance soles' (:mod:`gaitshift.wholebody.ik_tasks`).
        terrain_soles: a sole in contact lies on the plan's terrain (inclined as the ramp under its
            foothold), else flat.
        toe_off_cost: the rear sole of a double support may pivot about its toe edge, its pitch a soft
            task of this weight (per rad); None: it stays flat.
        check_plan_fit: after solving, refuse a motion that breaks the plan's physics (the ZMP outside
            the support a toe-off leaves, a sole below the ground; :mod:`gaitshift.wholebody.plan_fit`)
            and report its deviation from the plan in ``meta["ik"]["plan_fit"]``; with ``toe_off_cost``,
            a sole may only pivot where the plan's ZMP lies in the support its toe-off would leave
            (:func:`gaitshift.wholebody.plan_fit.toe_off_margins`).
        speed_limits: each joint moves at most its speed limit (``RobotConfig.velocity_limit``) times the
            sample period from one sample to the next (a box around q_{k-1} intersected with the joint
            range, in the QP's joint limits), so that no joint speed of the motion exceeds its limit.
        flight_reach_cost: a flight sample (no sole in contact) that fails with the soles' poses hard is
            solved again with them soft (position weight per m, roll and yaw per rad), only the CoM hard,
            every sole corner above the ground (:mod:`gaitshift.wholebody.ik_ground`), ``4 max_iter``
            iterations and the damping ``reach_damping``; None: no second attempt.
        pelvis_pitch_cost: weight of the pelvis task about its pitch axis (per rad); None: ``pelvis_cost``.
        swing_lift_cost: a swing sole's height is a soft task of this weight (per m), its centre on or above
            its planned height and every corner on or above the plan's terrain (its horizontal position,
            roll and yaw stay hard; :mod:`gaitshift.wholebody.ik_tasks`); None: its height is hard and its
            corners free.
    """

    com_tol: float = 1e-3
    pos_tol: float = 5e-4
    rot_tol: float = 5e-3
    converged_pos: float = 2e-5
    converged_rot: float = 2e-4
    max_iter: int = 12
    first_iter: int = 200
    knee_margin: float = 0.05
    torso_cost: float = 1.0
    posture_cost: float = 0.02
    arm_cost: float = 0.5
    damping: float = 1e-6
    extrapolate: bool = True
    soft_limits: bool = False
    pelvis_cost: float = 0.0
    swing_pitch_cost: float | None = None
    terrain_soles: bool = False
    toe_off_cost: float | None = None
    check_plan_fit: bool = False
    speed_limits: bool = False
    flight_reach_cost: float | None = None
    reach_damping: float = 1e-2
    pelvis_pitch_cost: float | None = None
    swing_lift_cost: float | None = None


#: the IK of reference motions (``gaitshift export`` of a plan, docs/export.md "Fit for training"): joints
#: within their soft range, the pelvis upright (g1-walk-run-walk: roll within +-0.4 deg instead of -21 to
#: +25 deg), the swing soles' pitch soft (up to 16 deg toe down in its running swings), soles in contact on
#: the plan's terrain, the rear sole of a double support free to lift its heel (toe-off) where the plan's
#: ZMP allows it, the motion checked against the plan's physics; joint speeds within their limits, the
#: pelvis pitch weight 1 (not 10: the pelvis leans forward where a stance ankle would pass its soft
#: limit), a swing sole out of reach in flight a soft task, the swing soles' corners above the ground, their
#: centres lifted as much as that needs (docs/export.md "Fit for training")
REFERENCE_SETTINGS = IKSettings(
    soft_limits=True,
    pelvis_cost=10.0,
    swing_pitch_cost=1.0,
    terrain_soles=True,
    toe_off_cost=1.0,
    check_plan_fit=True,
    speed_limits=True,
    flight_reach_cost=1000.0,
    pelvis_pitch_cost=1.0,
    swing_lift_cost=10.0,
)
