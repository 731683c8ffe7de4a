"""The brain's safety state machine, without DDS: what the robot is commanded in each phase, and the
faults that send it to damping.

.. code-block:: text

    damping --(damping_time)--> stand-up --(standup_time)--> hold --(hold_time)--> locomotion --(plan ended)--> stop
       \\__________________________\\_______________________\\_________________\\--(any fault)--> fault

``damping``: ``kp = 0``, ``kd = damping_kd``, ``tau = 0`` (the same command in ``stop`` and ``fault``).
``stand-up``: PD towards targets interpolated (smoothstep) from the pose measured when it began to the
controller's start pose, ``standup_kp`` / ``standup_kd`` per motor, plus the feed-forward ``standup_tau``
(the torques that hold the start pose on both soles). ``hold``: the stand-up's last command (the start
pose, zero speed, the same gains and feed-forward) for ``hold_time`` s: the robot stands still, the host
collects its gyro readings for the controller's calibration (0 s: no hold). ``locomotion``: the host ticks its
controller (:meth:`Safety.step` returns None) and passes the command through :meth:`Safety.guard`.

Faults (each one line, the machine goes to ``fault`` and stays there): the state older than
``stale`` s; a value of the state out of range (not finite, a joint speed over its limit, a quaternion
far from unit length); a joint beyond its range by more than ``joint_margin`` rad; the pelvis tilted by
more than ``tilt`` rad (a fall, from the IMU's quaternion); a command not finite. Every command leaving
the machine is clamped: q to the joint range, dq to the speed limit, and the torque the motor will apply
at the measured state, ``tau + kp (q - q_meas) + kd (dq - dq_meas)``, to the torque limit.
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.errors import InputError, number_in

__all__ = ["PHASES", "Limits", "Safety", "SafetySettings", "check_settings", "standup_gains", "tilt_angle"]

#: the phases, in the order a run goes through them (``fault`` may follow any)
PHASES = ("damping", "stand-up", "hold", "locomotion", "stop", "fault")
#: kp per unit of torque limit (1/rad) and kd per unit of torque limit (s/rad) of the stand-up PD
STANDUP_KP_PER_TAU, STANDUP_KD_PER_TAU = 4.0, 0.1


@dataclass(frozen=True)
class Limits:
    """The robot's limits, per motor in the controller's ``motor_names`` order.

    Attributes:
        q_low, q_high: (n,) joint range, rad. dq_max: (n,) joint speed limit, rad/s. tau_max: (n,)
        torque limit, N m.
    """

    q_low: np.ndarray
    q_high: np.ndarray
    dq_max: np.ndarray
    tau_max: np.ndarray

    @classmethod
    def of_robot(
        cls,
        joint_names: tuple[str, ...],
        joint_range: np.ndarray,
        speed: np.ndarray,
        torque: np.ndarray,
        motor_names: tuple[str, ...],
    ) -> "Limits":
        """The limits of ``motor_names`` from a robot's per-joint arrays (``joint_names`` order)."""
        idx = [joint_names.index(m) for m in motor_names]
        rng = np.asarray(joint_range, float)[idx]
        return cls(rng[:, 0], rng[:, 1], np.asarray(speed, float)[idx], np.asarray(torque, float)[idx])


@dataclass(frozen=True)
class SafetySettings:
    """The machine's settings (module docstring).

    Attributes:
        standup_tau: (n,) N m, the stand-up's feed-forward (the torques that hold the start pose on both
        soles, :func:`gaitshift.dds.gravity.standing_torques`); None: zero.
        damping_time: s of damping before the stand-up. standup_time: s of the stand-up. hold_time: s of
        the still hold after it (the gyro calibration's samples; 0: none).
        damping_kd: N m s/rad, the damping gain. standup_kp: (n,) N m/rad; standup_kd: (n,) N m s/rad.
        stale: s, the oldest state accepted. tilt: rad, the largest pelvis tilt (a fall beyond it).
        joint_margin: rad a joint may go past its range. speed_margin: factor on the speed limit a
        measured joint speed may reach.
    """

    standup_kp: np.ndarray
    standup_kd: np.ndarray
    standup_tau: np.ndarray | None = None
    damping_time: float = 0.1
    standup_time: float = 2.0
    damping_kd: float = 2.0
    stale: float = 0.02
    tilt: float = 0.6
    joint_margin: float = 0.05
    speed_margin: float = 1.5
    hold_time: float = 0.0

    def __post_init__(self) -> None:
        check_settings(self.damping_time, self.standup_time, self.damping_kd, self.stale, self.tilt)
        number_in("--hold", self.hold_time, (0.0, 60.0), "s")


def check_settings(damping_time: float, standup_time: float, damping_kd: float, stale: float, tilt: float) -> None:
    """:class:`InputError` naming the command-line flag of the first setting out of its range (s, N m s/rad,
    rad): damping_time [0, 60], standup_time [0.01, 60], damping_kd [0, 20], stale [0.001, 10], tilt
    [0.05, 1.5]."""
    number_in("--damping-time", damping_time, (0.0, 60.0), "s")
    number_in("--standup-time", standup_time, (0.01, 60.0), "s")
    number_in("--damping-kd", damping_kd, (0.0, 20.0), "N m s/rad")
    number_in("--stale-limit", stale, (1e-3, 10.0), "s")
    number_in("--tilt-limit", tilt, (0.05, 1.5), "rad")


def standup_gains(tau_max: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The stand-up PD gains from the torque limits (N m): kp = 4 rad^-1 x tau_max N m/rad, kd = 0.1 s/rad x
    tau_max N m s/rad (the G1: hip 352/8.8, knee 556/13.9, ankle 200/5, arms 100/2.5). The ankles set the
    floor: standing is an inverted pendulum, stable under a PD only when the two ankles' kp exceed
    m g h (33 kg x 9.81 x 0.7 m = 227 N m/rad on the G1); 1 x tau_max (ankle 50) let it tip over backwards
    in the simulation, 2 x too, 4 x stands it up with 0.02 rad of error left (with the feed-forward
    :attr:`SafetySettings.standup_tau`)."""
    t = np.where(np.isfinite(tau_max), tau_max, 50.0)
    return STANDUP_KP_PER_TAU * t, STANDUP_KD_PER_TAU * t


def tilt_angle(quat: np.ndarray) -> float:
    """The angle, rad, between the body's z axis and the vertical for a unit quaternion w x y z."""
    _, x, y, _ = (float(c) for c in quat)
    return math.acos(max(-1.0, min(1.0, 1.0 - 2.0 * (x * x + y * y))))


def smoothstep(s: float) -> float:
    """3 s^2 - 2 s^3 of s clipped to [0, 1]: zero speed at both ends."""
    s = min(max(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


class Safety:
    """The state machine (module docstring) of one run.

    Args:
        limits: the robot's limits. settings: the machine's settings. start_pose: (n,) rad, the
        controller's start pose (the joints of ``Controller.initial_qpos()``, motor order).
    """

    def __init__(self, limits: Limits, settings: SafetySettings, start_pose: np.ndarray) -> None:
        self.limits, self.settings = limits, settings
        n = len(limits.tau_max)
        self.start_pose = np.clip(np.asarray(start_pose, float), limits.q_low, limits.q_high)
        if self.start_pose.shape != (n,):
            raise InputError("start_pose", np.shape(start_pose), f"{n} joint angles")
        self.phase, self.reason = "damping", ""
        self.since = 0.0  # s, when the phase began
        self.locomotion_start = math.nan  # s, when locomotion began (the controller's clock zero)
        self.standup_from = np.zeros(n)
        zero = np.zeros(n)
        self.damping = MotorCommand(q=zero, dq=zero, kp=zero, kd=np.full(n, settings.damping_kd), tau=zero)

    @property
    def ended(self) -> bool:
        """The machine is in ``stop`` or ``fault``: damping from now on."""
        return self.phase in ("stop", "fault")

    def enter(self, phase: str, t: float, reason: str = "") -> None:
        """Go to ``phase`` at time ``t`` s (``stop`` and ``fault`` are final: a later call is ignored)."""
        if self.ended:
            return
        self.phase, self.since, self.reason = phase, t, reason

    def fault(self, t: float, reason: str) -> None:
        """A fault at ``t`` s: damping from now on, ``reason`` kept (the first fault's)."""
        self.enter("fault", t, reason)

    def stop(self, t: float, reason: str = "the plan ended") -> None:
        """The run's end at ``t`` s: damping from now on."""
        self.enter("stop", t, reason)

    def check_state(self, frame: SensorFrame, age: float) -> str:
        """Why the state ``frame`` (received ``age`` s ago) is unsafe, or "" when it is fine."""
        lim, s = self.limits, self.settings
        if age > s.stale:
            return f"state stale: the newest rt/lowstate is {age * 1e3:.1f} ms old (limit {s.stale * 1e3:.1f} ms)"
        for name in ("imu_quat", "imu_gyro", "imu_acc", "q", "dq", "tau_est"):
            a = np.asarray(getattr(frame, name), float)
            if not np.isfinite(a).all():
                return f"state out of range: {name}[{int(np.argmax(~np.isfinite(a)))}] is not finite"
        if abs(float(np.linalg.norm(frame.imu_quat)) - 1.0) > 0.05:
            return (
                f"state out of range: |imu_quat| = {float(np.linalg.norm(frame.imu_quat)):.3f} (not a unit quaternion)"
            )
        over = np.abs(frame.dq) > s.speed_margin * lim.dq_max
        if over.any():
            i = int(np.argmax(over))
            limit = s.speed_margin * lim.dq_max[i]
            return f"state out of range: motor {i} speed {frame.dq[i]:.2f} rad/s beyond {limit:.1f} rad/s"
        out = (frame.q < lim.q_low - s.joint_margin) | (frame.q > lim.q_high + s.joint_margin)
        if out.any():
            i = int(np.argmax(out))
            rng = f"[{lim.q_low[i]:.3f}, {lim.q_high[i]:.3f}]"
            return (
                f"joint limit: motor {i} at {frame.q[i]:.3f} rad, beyond its range {rng} by over {s.joint_margin:g} rad"
            )
        tilt = tilt_angle(frame.imu_quat)
        if tilt > s.tilt:
            return f"fall: the pelvis is tilted {tilt:.2f} rad (limit {s.tilt:.2f} rad)"
        return ""

    def step(self, t: float, frame: SensorFrame, age: float) -> MotorCommand | None:
        """The command at time ``t`` s (the machine's clock) for the state ``frame`` received ``age`` s ago:
        the phase's command, or None in locomotion (the host ticks its controller, then :meth:`guard`)."""
        why = "" if self.ended else self.check_state(frame, age)
        if why:
            self.fault(t, why)
        s = self.settings
        if self.phase == "damping" and t - self.since >= s.damping_time:
            self.standup_from = np.asarray(frame.q, float).copy()
            self.enter("stand-up", t)
        if self.phase == "stand-up" and t - self.since >= s.standup_time:
            self.enter("hold", t)
        if self.phase == "hold" and t - self.since >= s.hold_time:
            self.enter("locomotion", t)
            self.locomotion_start = t
        if self.phase == "stand-up":
            return self.guard(self.standup_command(t), frame, t)
        if self.phase == "hold":
            return self.guard(self.hold_command(), frame, t)
        if self.phase == "locomotion":
            return None
        return self.damping

    def standup_command(self, t: float) -> MotorCommand:
        """The stand-up's PD command at ``t`` s: targets and target speeds on the smoothstep from
        :attr:`standup_from` to :attr:`start_pose` over ``standup_time`` s."""
        T = self.settings.standup_time
        u = (t - self.since) / T
        h = smoothstep(u)
        dh = 6.0 * u * (1.0 - u) / T if 0.0 < u < 1.0 else 0.0
        span = self.start_pose - self.standup_from
        n = len(span)
        return MotorCommand(
            q=self.standup_from + h * span,
            dq=dh * span,
            kp=self.settings.standup_kp.copy(),
            kd=self.settings.standup_kd.copy(),
            tau=np.zeros(n) if self.settings.standup_tau is None else self.settings.standup_tau.copy(),
        )

    def hold_command(self) -> MotorCommand:
        """The hold's PD command: the start pose at zero speed, the stand-up's gains and feed-forward."""
        s, n = self.settings, len(self.start_pose)
        tau = np.zeros(n) if s.standup_tau is None else s.standup_tau.copy()
        return MotorCommand(
            q=self.start_pose.copy(), dq=np.zeros(n), kp=s.standup_kp.copy(), kd=s.standup_kd.copy(), tau=tau
        )

    def guard(self, cmd: MotorCommand, frame: SensorFrame, t: float) -> MotorCommand:
        """``cmd`` clamped to the limits at the measured state ``frame`` (module docstring); damping, and
        the machine in ``fault`` at ``t`` s, when the command is not finite or has a negative gain."""
        for name in ("q", "dq", "kp", "kd", "tau"):
            a = np.asarray(getattr(cmd, name), float)
            if not np.isfinite(a).all():
                self.fault(t, f"command out of range: {name}[{int(np.argmax(~np.isfinite(a)))}] is not finite")
                return self.damping
            if name in ("kp", "kd") and (a < 0).any():
                self.fault(t, f"command out of range: {name}[{int(np.argmax(a < 0))}] = {a[a < 0][0]:g} < 0")
                return self.damping
        lim = self.limits
        q = np.clip(cmd.q, lim.q_low, lim.q_high)
        dq = np.clip(cmd.dq, -lim.dq_max, lim.dq_max)
        pd = cmd.kp * (q - frame.q) + cmd.kd * (dq - frame.dq)
        tau = np.clip(cmd.tau + pd, -lim.tau_max, lim.tau_max) - pd
        return replace(cmd, q=q, dq=dq, tau=tau)
