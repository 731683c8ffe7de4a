"""Writing committed steps into the sample buffer: the CoM by closed forms, the feet by their swings.

:class:`StepWriter` owns the look-ahead buffer (:class:`~gaitshift.planners.streaming.buffer.SampleBuffer`
of :data:`~.samples.FIELDS`), the two foot tracks (:class:`~gaitshift.gait.swing_track.FootTrack`), the
list of footholds landed on and the CoM state at the end of the last step written. Every step is written whole when it
is committed (and again from the re-plan sample on after a re-plan): the step's end state is
computed at once (the next plan starts from it), its rows lazily, one phase segment at a time, when
emission (or a re-plan) first needs them. A planning instant thus costs the solve alone, and the
sampling is spread over the control ticks (each row is written once, as before, from the closed
forms of :mod:`.sampling`). The foot columns are evaluated from the swing tracks the same way,
up to the end of the CoM rows written, and again from any sample where a swing is re-targeted.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from gaitshift.gait.swing_track import FootTrack, Swing
from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.planner import Plan, is_start, touchdown_offset
from gaitshift.planners.locomotion.record import StepRecord
from gaitshift.planners.locomotion.samples import FIELDS
from gaitshift.planners.locomotion.sampling import Segment, sample_segment, segment_end
from gaitshift.planners.locomotion.steps import STEP_CODES
from gaitshift.planners.streaming.buffer import SampleBuffer
from gaitshift.planners.streaming.samples import Samples
from gaitshift.trajectory.contract import DS, FLIGHT, LEFT, RIGHT, SS

__all__ = ["StepWriter"]

Foothold = tuple[float, float, float, float, int]


class StepWriter:
    """Buffer, feet and footholds of one generator (module docstring).

    Args:
        dt: sample step, s; g: gravity, m/s^2; height: standing CoM height, m; width: step width, m;
        swing_height: swing apex above the higher end, m.

    Attributes:
        footsteps: footholds landed on or committed, in order: (x, y, z, yaw, side).
        end_state: CoM position and velocity (3,) each at the end of the last step written.
        bounds: sample index of every phase boundary committed.
    """

    def __init__(self, dt: float, g: float, height: float, width: float, swing_height: float) -> None:
        self.dt, self.g, self.height, self.swing_height = dt, g, height, swing_height
        self.buf = SampleBuffer(FIELDS)
        self.feet = {
            LEFT: FootTrack(np.array([0.0, 0.5 * width, 0.0, 0.0])),
            RIGHT: FootTrack(np.array([0.0, -0.5 * width, 0.0, 0.0])),
        }
        self.footsteps: list[Foothold] = [(0.0, 0.5 * width, 0.0, 0.0, LEFT), (0.0, -0.5 * width, 0.0, 0.0, RIGHT)]
        self.end_state: tuple[FloatArray, FloatArray] = (np.array([0.0, 0.0, height]), np.zeros(3))
        self.bounds: list[int] = [0]
        self.jobs: list[tuple[Segment, StepRecord, int]] = []  # CoM segments planned, not yet written
        self.feet_upto = 0  # foot columns are written (and valid) before this sample

    def standing(self, a: int, b: int, heading: float, step: int) -> None:
        """Rows a..b-1 standing at rest over the feet (CoM at the last end state, ZMP under it)."""
        m = b - a
        p = self.end_state[0]
        self.buf.write(
            a,
            com_pos=np.tile(p, (m, 1)),
            com_vel=np.zeros((m, 3)),
            com_acc=np.zeros((m, 3)),
            zmp=np.tile([p[0], p[1], 0.0], (m, 1)),
            phase=np.full(m, DS, np.int8),
            contact=np.ones((m, 2), bool),
            stiffness=np.full(m, math.sqrt(self.height / self.g)),
            heading=np.full(m, heading),
            gait=np.zeros(m, np.int8),
            step=np.full(m, step, np.int32),
            step_type=np.full(m, -1, np.int8),
        )
        self.feet_upto = min(self.feet_upto, a)

    def commit(self, rec: StepRecord, plan: Plan, p: FloatArray, v: FloatArray, step: int) -> None:
        """A newly committed step: its phase boundaries, its swings and its samples from its start."""
        self.bounds += [int(b) for b in rec.bounds if b > self.bounds[-1]]
        self.set_swings(rec, plan)
        self.sample(rec, rec.i0, p, v, step)

    def set_swings(self, rec: StepRecord, plan: Plan) -> None:
        """Create or re-target the swings the plan decides: the other foot lands on ``rec.next`` (a
        swing from now, or the one already in the air re-targeted); in running the stance foot lifts
        at the take-off and swings to the plan's second foothold."""
        step = rec.step
        if is_start(step):
            return
        other = 1 - rec.own_side
        target = np.array([rec.next[0], rec.next[1], rec.ground, rec.next_yaw])
        sw = self.feet[other].pending(rec.i0)
        if sw is None:
            i_land = rec.i0 + round(touchdown_offset(step) / self.dt)
            self.feet[other].swings.append(
                Swing(rec.i0, i_land, self.feet[other].rest.copy(), target, self.dt, self.swing_height)
            )
        else:
            sw.retarget(rec.i0, target)
        self.footsteps.append((float(rec.next[0]), float(rec.next[1]), rec.ground, rec.next_yaw, other))
        if step.phases[-1].kind == FLIGHT and len(plan.footholds) > 1:
            land2 = rec.i1 + round(touchdown_offset(plan.types[1]) / self.dt)
            t2 = np.array([plan.footholds[1][0], plan.footholds[1][1], rec.ground, plan.yaws[1]])
            lift = int(rec.bounds[1])
            pose = np.array([rec.own[0], rec.own[1], rec.ground, self.feet[rec.own_side].landed(lift)[3]])
            self.feet[rec.own_side].swings.append(Swing(lift, land2, pose, t2, self.dt, self.swing_height))

    def retarget(self, rec: StepRecord, plan: Plan, i: int, next_moves: bool) -> None:
        """After a re-plan at sample ``i``: the feet still in the air aim at the new footholds."""
        if next_moves:
            target = np.array([rec.next[0], rec.next[1], rec.ground, rec.next_yaw])
            sw = self.feet[1 - rec.own_side].pending(i)
            if sw is not None:
                sw.retarget(i, target)
            self.footsteps[-1] = (float(rec.next[0]), float(rec.next[1]), rec.ground, rec.next_yaw, 1 - rec.own_side)
        if rec.step.phases[-1].kind == FLIGHT and len(plan.footholds) > 1:
            own_sw = self.feet[rec.own_side].pending(i)
            if own_sw is not None:
                own_sw.retarget(i, np.array([plan.footholds[1][0], plan.footholds[1][1], rec.ground, plan.yaws[1]]))

    def sample(self, rec: StepRecord, i: int, p: FloatArray, v: FloatArray, step: int) -> None:
        """Plan the CoM rows from sample ``i`` (state p, v (3,)) to the end of the step: the segments
        and the end state now, the rows when :meth:`ensure` needs them; the feet from ``i`` again."""
        segs = rec.segments(i, p, v, self.dt)
        for k in range(1, len(segs)):  # start state: the previous segment's end (vertical from the phase spec)
            pe, ve = segment_end(segs[k - 1], self.dt, self.g)
            segs[k] = replace(
                segs[k], p0=np.array([pe[0], pe[1], segs[k].p0[2]]), v0=np.array([ve[0], ve[1], segs[k].v0[2]])
            )
        self.end_state = segment_end(segs[-1], self.dt, self.g)
        self.jobs = [(seg, rec, step) for seg in segs]
        self.feet_upto = min(self.feet_upto, i)

    def ensure(self, upto: int, feet: bool = True) -> None:
        """Write every planned row before sample ``upto``: the CoM segments that start before it
        (whole), then (``feet``) the foot columns up to the end of the CoM rows written."""
        while self.jobs and self.jobs[0][0].i0 < upto:
            self.write_segment(*self.jobs.pop(0))
        if feet and self.feet_upto < upto:
            b = max(upto, self.buf.n)
            self.buf.write(self.feet_upto, **self.feet_rows(self.feet_upto, b))
            self.feet_upto = b

    def write_segment(self, seg: Segment, rec: StepRecord, step: int) -> None:
        """The CoM rows of one segment, eqs. (1)-(6) of paper 001 in closed form (:mod:`.sampling`)."""
        pos, vel, acc, zmp = sample_segment(seg, self.dt, self.g)
        m = seg.n
        ph = rec.step.phases[rec.phase_at(seg.i0)]
        contact = np.ones((m, 2), bool)
        if ph.kind == SS:
            contact[:, 1 - rec.own_side] = False
        elif ph.kind == FLIGHT:
            contact[:] = False
        idx = np.arange(seg.i0, seg.i0 + m)
        self.buf.write(
            seg.i0,
            com_pos=pos[:-1],
            com_vel=vel[:-1],
            com_acc=acc[:-1],
            zmp=zmp[:-1],
            phase=np.full(m, ph.kind, np.int8),
            contact=contact,
            stiffness=np.full(m, ph.stiffness if ph.kind != FLIGHT else np.nan),
            heading=rec.psi0 + rec.omega * (idx - rec.i0) * self.dt,
            gait=np.full(m, int(rec.step.gait), np.int8),
            step=np.full(m, step, np.int32),
            step_type=np.full(m, STEP_CODES[rec.step.name], np.int8),
        )

    def feet_rows(self, a: int, b: int) -> dict[str, FloatArray]:
        """Foot columns (pose, rates, accelerations) for rows a..b-1 from the swing tracks."""
        pos = np.empty((b - a, 2, 4))
        vel = np.empty_like(pos)
        acc = np.empty_like(pos)
        for side in (LEFT, RIGHT):
            self.feet[side].evaluate(a, b, (pos[:, side], vel[:, side], acc[:, side]))
        return {"foot_pos": pos[:, :, :3], "foot_yaw": pos[:, :, 3], "foot_vel": vel, "foot_acc": acc}

    def vertical_at(self, i: int) -> tuple[float, float]:
        """The planned CoM height and vertical velocity at sample ``i``."""
        self.ensure(i + 1, feet=False)
        return float(self.buf["com_pos"][i][2]), float(self.buf["com_vel"][i][2])

    def emit(self, i: int, m: int, command: FloatArray) -> Samples:
        """Rows i..i+m-1 as a block (with the applied command), then release them."""
        self.ensure(i + m)
        rows: dict[str, Any] = self.buf.rows(i, i + m)
        out = Samples(np.arange(i, i + m, dtype=np.float64) * self.dt, rows, np.tile(command, (m, 1)))
        self.buf.release(i + m - 1)
        for track in self.feet.values():
            track.prune(i + m - 1)
        return out
