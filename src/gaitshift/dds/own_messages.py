"""gaitshift's own DDS messages, beside Unitree's (:mod:`gaitshift.dds.messages`): a velocity command that
another program writes to steer the brain, and the brain's state estimate that the robot process scores.

* ``rt/gaitshift/cmd_vel`` (:class:`VelocityCommand_`): read by the brain (``gaitshift dds control
  --cmd-topic``), written by ``gaitshift dds cmd`` or any program with this IDL.
* ``rt/gaitshift/estimate`` (:class:`Estimate_`): written by the brain, read by the robot process, which
  alone holds the truth and scores the estimate in its summary. Nothing flows the other way.
* ``rt/gaitshift/clock`` (:class:`Clock_`): lockstep only, written by the robot process at each of its
  ticks, read by the brain, which ticks once per robot tick as it would in real time
  (:mod:`gaitshift.dds.lockstep`). It carries tick counts, nothing of the truth.

All are ``@final`` structs with sequential member ids (as Unitree's), type names in the module
``gaitshift.msg``. Units: m, m/s, rad, rad/s, s; quaternions w, x, y, z.
"""

# no ``from __future__ import annotations`` here: cyclonedds reads the field annotations as objects
from dataclasses import dataclass, field

import cyclonedds.idl.annotations as annotate
from cyclonedds import idl
from cyclonedds.idl import types

__all__ = ["CLOCK_TOPIC", "CMD_VEL_TOPIC", "ESTIMATE_TOPIC", "Clock_", "Estimate_", "VelocityCommand_"]

CMD_VEL_TOPIC = "rt/gaitshift/cmd_vel"
ESTIMATE_TOPIC = "rt/gaitshift/estimate"
CLOCK_TOPIC = "rt/gaitshift/clock"


@dataclass
@annotate.final
@annotate.autoid("sequential")
class VelocityCommand_(idl.IdlStruct, typename="gaitshift.msg.VelocityCommand_"):
    """A live velocity command: ``vx``, ``vy`` m/s in the robot's heading frame, ``yaw_rate`` rad/s;
    ``stop`` 1: ramp down, stand and end the run (the velocities are then ignored). ``seq`` counts the
    sender's commands; ``stamp`` s on the sender's clock (informative: the brain does not compare clocks)."""

    seq: types.uint32 = 0
    stamp: types.float64 = 0.0
    vx: types.float64 = 0.0
    vy: types.float64 = 0.0
    yaw_rate: types.float64 = 0.0
    stop: types.uint8 = 0


@dataclass
@annotate.final
@annotate.autoid("sequential")
class Estimate_(idl.IdlStruct, typename="gaitshift.msg.Estimate_"):
    """The brain's state estimate at one tick: ``tick`` the ``LowState_.tick`` it acted on, ``t`` s the
    brain's machine clock, ``phase`` the safety machine's phase (``locomotion`` while the controller ticks),
    ``valid`` 1 when the controller estimated (locomotion), else 0 and the rest zeros. ``base_pos`` (3,) m
    and ``base_quat`` (4,) w x y z: the pelvis in the controller's world frame; ``base_vel`` (3,) m/s the
    pelvis's linear velocity in that frame; ``contact`` (2,) the fused contact flags, left and right."""

    tick: types.uint32 = 0
    t: types.float64 = 0.0
    phase: str = ""
    valid: types.uint8 = 0
    base_pos: types.array[types.float64, 3] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    base_quat: types.array[types.float64, 4] = field(default_factory=lambda: [1.0, 0.0, 0.0, 0.0])
    base_vel: types.array[types.float64, 3] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    contact: types.array[types.uint8, 2] = field(default_factory=lambda: [0, 0])


@dataclass
@annotate.final
@annotate.autoid("sequential")
class Clock_(idl.IdlStruct, typename="gaitshift.msg.Clock_"):
    """Lockstep: the robot's tick ``tick`` has begun and waits for one command; ``state_tick`` is the
    ``LowState_.tick`` of the newest intact state the robot has written up to this tick (a state the link
    delays is written at a later tick than its own; one it drops or corrupts is not counted)."""

    tick: types.uint32 = 0
    state_tick: types.uint32 = 0
