"""The brain's browser page (``gaitshift dds control --web``): the robot as the brain estimates it, its plan,
and the live controls of :class:`~gaitshift.sim.web.WebView`, which feed the brain's command input.

The brain's tick only hands over what it has (:meth:`BrainFeed.offer`: its phase, the controller's
:class:`~gaitshift.control.controller.TickRecord` and plan, one reference assignment); a thread of its own
(``gaitshift-web``) wakes every ``1 / rate`` s of wall-clock time, hands the page's queued commands to the
view's ``on_command`` / ``on_quit`` (a :class:`~gaitshift.dds.cmdvel.CommandQueue`: the same checks as the
topic's commands), and, when a new estimate came, poses a ``MjData`` of the controller's own model at the
estimate (``qpos``, ``qvel``: forward kinematics, CoM and its velocity) and draws it with the plan's
footholds, planned ZMP and commanded speed (:meth:`WebView.show`, at most the view's ``rate`` frames per
second of plan time). viser's server runs in its own threads. While the page is served, the interpreter's
thread switch interval is :data:`SWITCH_INTERVAL` (0.5 ms, not Python's 5 ms): the tick waits less for the
GIL these threads hold.

The brain sees no truth, so none is drawn: the robot on the page is its estimate, and the measured ZMP (the
floor's contact forces) is not shown. Before the controller's first tick (damping, stand-up, hold) the
panel shows the phase only, and the robot is the model at its default pose. The scene is built (0.5-1 s
for the G1's meshes) before the run.
"""

from __future__ import annotations

import sys
import threading
from typing import Any

import mujoco

__all__ = ["SWITCH_INTERVAL", "BrainFeed"]

#: s: the interpreter's thread switch interval while the page is served (Python's default 5 ms): a thread
#: waiting for the GIL (the tick) gets it from the drawing thread or viser's within this time
SWITCH_INTERVAL = 0.0005


class BrainFeed:
    """The hand-off from the brain's tick to its page (module docstring).

    Args:
        model: the controller's robot model (``Controller.robot.model``).
        rate: wake-ups per second of wall-clock time of the drawing thread, Hz.
    """

    def __init__(self, model: mujoco.MjModel, rate: float = 30.0) -> None:
        self.data = mujoco.MjData(model)
        self.period = 1.0 / rate
        self.latest: tuple[str, Any, Any] | None = None  # (phase, TickRecord or None, plan): the tick's hand-off
        self.traj: Any = None  # the plan of the frame being drawn
        self.shown: Any = None  # the record drawn last
        self.phase = ""
        self.view: Any = None
        self.done = threading.Event()
        self.thread: threading.Thread | None = None
        self.switch = sys.getswitchinterval()  # restored by close

    def plan(self) -> Any:
        """The plan of the frame being drawn (the view's ``plan``)."""
        return self.traj

    def offer(self, phase: str, record: Any, plan: Any) -> None:
        """The brain's tick: its ``phase``, the controller's record of the tick (None outside locomotion)
        and its plan. One assignment: the drawing thread takes it when it wakes."""
        self.latest = (phase, record, plan)

    def start(self, view: Any) -> None:
        """Draw on ``view`` (a :class:`~gaitshift.sim.web.WebView`) from a thread of its own; the scene (the
        robot's meshes, 0.5-1 s) is built now, before the brain's first tick."""
        self.view = view
        m, d = self.data.model, self.data
        view.build(m)
        mujoco.mj_kinematics(m, d)
        view.scene.update(d)  # the model at its default pose until the first estimate
        sys.setswitchinterval(SWITCH_INTERVAL)
        self.thread = threading.Thread(target=self.run, name="gaitshift-web", daemon=True)
        self.thread.start()

    def run(self) -> None:
        """The drawing thread: :meth:`step` every ``period`` s until :meth:`close`."""
        while not self.done.wait(self.period):
            self.step()

    def step(self) -> None:
        """Dispatch the page's commands; draw the newest estimate if it is new (the phase alone before it)."""
        view, latest = self.view, self.latest
        record = None if latest is None else latest[1]
        view.dispatch(0.0 if record is None else record.t)
        if latest is None:
            return
        phase, _, plan = latest
        if phase != self.phase:
            self.phase = phase
            view.note = f"brain: **{phase}** · the robot as the brain estimates it\n\n"
            if record is None:
                why = "waiting for the controller's first tick (the model at its default pose)"
                view.status.content = f"brain: **{phase}** · " + (why if self.shown is None else "the robot damps")
        if record is None or record is self.shown or record.estimate is None:
            return
        self.traj = plan
        d, est = self.data, record.estimate
        d.qpos[:], d.qvel[:] = est.qpos, est.qvel
        mujoco.mj_kinematics(d.model, d)
        mujoco.mj_comPos(d.model, d)
        mujoco.mj_comVel(d.model, d)
        mujoco.mj_subtreeVel(d.model, d)
        view.show(record.t, d)
        self.shown = record

    def close(self) -> None:
        """Stop the drawing thread (waits for its current step); the switch interval restored."""
        self.done.set()
        if self.thread is not None:
            self.thread.join()
        sys.setswitchinterval(self.switch)
