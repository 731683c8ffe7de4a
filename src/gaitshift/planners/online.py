"""The online VHIP running generator of paper 003: start, run with streamed speed commands, stop.

:class:`OnlineGenerator` holds the plan across calls so a controller can call it every control tick:

* :meth:`OnlineGenerator.command` sets the commanded speed (vx, vy). Values beyond the scenario
  limits are clamped to the nearest feasible value and reported in :attr:`OnlineGenerator.events`.
* :meth:`OnlineGenerator.tick` advances one control period and returns that sample;
  :meth:`OnlineGenerator.step` advances to the next planning instant (one running step);
  :meth:`OnlineGenerator.advance` advances any number of ticks.
* :meth:`OnlineGenerator.replan` re-plans from a measured CoM state (position, velocity).
* :meth:`OnlineGenerator.stop` requests the stop to standstill.

Timeline. The stance of step k ends with the take-off ``to_k``. At ``to_k`` the foot of stance k
lifts off and swings to the foothold of stance k+2, so that foothold, and the CoM of the step
``(to_{k+1}, to_{k+2}]``, are planned at ``to_k`` by Algorithm 1 (:mod:`.foothold`). A command that
arrives before ``to_k`` is therefore reached exactly at ``to_{k+2}``: the take-off of the second step
after the command, as in the paper (Fig. 7). The start (State Switching 1) and the stop (State
Switching 3) are planned by the segmented ZMP optimisation (:mod:`.switching`).

Samples (see docs/vhip.md, "What exact means"): ``com_acc`` is the second difference of
eqs. (7)-(9), so eq. (2) holds at every stance sample to rounding and a flight sample has zero
horizontal acceleration (eq. (14)); ``com_vel`` is the central difference ``(c_{i+1} - c_{i-1})/(2 dt)``
(the mean of the two Euler velocities of eq. (8)); at a take-off both Euler velocities equal the
target of eq. (12), so the sampled take-off speed is exact too. The vertical values are
the analytic polynomials (3) and (5). Lateral take-off speeds are the command plus the periodic
oscillation ``-/+ u`` (stance on the left/right foot) whose footholds are exactly ``step_width`` apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InfeasibleError, InputError
from ..models.vhip import FORCE_EPS, Horizon, row_weights, stance_profiles
from ..swing import min_jerk, sextic_height_coefficients
from ..trajectory import DS, FLIGHT, LEFT, RIGHT, SS, Trajectory
from .foothold import target_foothold
from .switching import SwitchingProblem, SwitchingSolver, solve_stop

__all__ = ["Event", "Samples", "Takeoff", "OnlineGenerator", "plan_scenario"]


@dataclass(frozen=True)
class Event:
    """Something the generator changed or refused: a clamp, an ignored command, a re-plan."""

    t: float
    kind: str
    field: str
    requested: float
    applied: float
    note: str = ""

    def as_dict(self) -> dict[str, Any]:
        return {"t": self.t, "kind": self.kind, "field": self.field, "requested": self.requested,
                "applied": self.applied, "note": self.note}


@dataclass(frozen=True, eq=False)
class Samples:
    """A block of m consecutive samples (shapes as in :class:`gaitshift.Trajectory`)."""

    t: np.ndarray            # (m,)
    com_pos: np.ndarray      # (m, 3)
    com_vel: np.ndarray      # (m, 3)
    com_acc: np.ndarray      # (m, 3)
    zmp: np.ndarray          # (m, 3), NaN in flight
    phase: np.ndarray        # (m,) int8
    contact: np.ndarray      # (m, 2) bool
    foot_pos: np.ndarray     # (m, 2, 3)
    command: np.ndarray      # (m, 2)
    stiffness: np.ndarray    # (m,) sqrt(z / (z'' + g)) in support, NaN in flight

    def __len__(self) -> int:
        return len(self.t)

    @staticmethod
    def concat(blocks: list["Samples"]) -> "Samples":
        names = Samples.__dataclass_fields__
        return Samples(**{k: np.concatenate([getattr(b, k) for b in blocks]) for k in names})


@dataclass(frozen=True, eq=False)
class Takeoff:
    """One planned step: sample index and time of its take-off, target take-off velocity (2,),
    foothold (2,), Algorithm 1 iterations per axis (2,) and the kind (start, run, stop)."""

    index: int
    t: float
    target: np.ndarray
    foothold: np.ndarray
    iterations: np.ndarray
    kind: str


def _clip_change(cmd: np.ndarray, last: np.ndarray, dv: np.ndarray) -> np.ndarray:
    """Clamp ``cmd`` to ``last +/- dv``; changes within ``dv`` up to rounding pass unchanged."""
    ok = np.abs(cmd - last) <= dv * (1 + 1e-9) + 1e-12
    return np.where(ok, cmd, np.clip(cmd, last - dv, last + dv))


class _Col:
    """One column of :class:`_Buffer`, indexed by global sample index (ints and slices)."""

    __slots__ = ("buf", "name")

    def __init__(self, buf: "_Buffer", name: str):
        self.buf, self.name = buf, name

    def _key(self, key):
        base = self.buf.base
        if isinstance(key, slice):
            return slice(None if key.start is None else key.start - base,
                         None if key.stop is None else key.stop - base, key.step)
        return key - base

    def __getitem__(self, key):
        return self.buf.arrays[self.name][self._key(key)]

    def __setitem__(self, key, value) -> None:
        self.buf.arrays[self.name][self._key(key)] = value


class _Buffer:
    """Planned samples (CoM x,y; z, z', z''; ZMP x,y; phase; contact), addressed by global sample
    index. Samples before :meth:`release` are dropped when space runs out, so memory and copy cost
    stay bounded by the look-ahead (about two steps), however long the run."""

    FIELDS = {"c": (2,), "z": (), "zd": (), "zdd": (), "zmp": (2,), "phase": (), "contact": (2,)}
    DTYPES = {"phase": np.int8, "contact": np.bool_}

    def __init__(self, capacity: int = 4096):
        self.n = 0          # global index one past the last planned sample
        self.base = 0       # global index of row 0
        self._keep = 0      # rows before this global index may be dropped
        self.arrays = {k: np.zeros((capacity, *shape), dtype=self.DTYPES.get(k, np.float64))
                       for k, shape in self.FIELDS.items()}
        for k in self.FIELDS:
            setattr(self, k, _Col(self, k))

    def release(self, upto: int) -> None:
        """Samples before global index ``upto`` are no longer needed."""
        self._keep = max(self._keep, upto)

    def write(self, start: int, **arrays: np.ndarray) -> None:
        m = len(arrays["c"])
        cap = len(self.arrays["c"])
        if start + m - self.base > cap:
            drop = min(self._keep, start) - self.base
            if drop > 0:                       # slide the live rows to the front
                live = self.n - self.base
                for arr in self.arrays.values():
                    arr[: live - drop] = arr[drop:live]
                self.base += drop
            if start + m - self.base > cap:    # still too small: grow
                new = max(2 * cap, start + m - self.base + 1024)
                for k, arr in self.arrays.items():
                    grown = np.zeros((new, *arr.shape[1:]), dtype=arr.dtype)
                    grown[: self.n - self.base] = arr[: self.n - self.base]
                    self.arrays[k] = grown
        for k, v in arrays.items():
            self.arrays[k][start - self.base:start - self.base + m] = v
        self.n = max(self.n, start + m)


class OnlineGenerator:
    """Stateful running generator for a :class:`~gaitshift.scenario.VhipScenario` (see module doc)."""

    def __init__(self, scenario: Any, keep_history: bool = True):
        """``keep_history=False`` drops emitted samples (a controller that only needs each tick):
        memory then stays bounded, and :meth:`trajectory` is unavailable."""
        sc = scenario
        self.keep_history = keep_history
        self.sc = sc
        self.dt, self.g = float(sc.dt), float(sc.gravity)
        dt, g = self.dt, self.g
        self.n_step = round(sc.step_period / dt)
        self.n_sup = round(sc.step_period * sc.stance_ratio / dt)
        self.n_fly = self.n_step - self.n_sup
        self.n_start = round(sc.start_double_support / dt)
        self.n_stop = round(sc.stop_double_support / dt)
        self.vertical = stance_profiles(sc.heights, g, self.n_sup * dt, self.n_fly * dt)
        vg = self.vertical
        # cyclic running step (take-off to take-off): one factorisation for the whole run
        self._run_z = vg.running_step(dt, self.n_fly, self.n_sup)
        self._run_w = row_weights(self._run_z[0], self._run_z[2], g, dt)
        self._run_h = Horizon(self._run_w, dt)
        zero = np.zeros(self.n_step + 1)
        self._U = self._run_h.solve(zero, 1.0, 0.0)     # response to the start velocity
        self._V = self._run_h.solve(zero, 0.0, 1.0)     # response to the end velocity
        U, V = self._U, self._V
        self.width = float(sc.step_width)
        #: take-off lateral velocity after a left stance for footholds exactly step_width apart
        self.u_left = self.width / (U[-1] - V[-1] + U[0] - V[0])
        self._start_z = vg.start_horizon(dt, self.n_start, self.n_sup)
        self._start_w = row_weights(self._start_z[0], self._start_z[2], g, dt)
        self._start_h = Horizon(self._start_w, dt)
        self._stop_z = vg.stop_horizon(dt, self.n_fly, self.n_sup, self.n_stop)
        self._stop_w = row_weights(self._stop_z[0], self._stop_z[2], g, dt)
        self._start_solver = SwitchingSolver(self._start_w, self.n_start, dt, self._start_h)
        self._stop_solver = SwitchingSolver(self._stop_w[::-1].copy(), self.n_stop, dt)
        L, W = sc.foot.size
        self._half = np.array([0.5 * L - sc.foot.zmp_margin, 0.5 * W - sc.foot.zmp_margin])
        self.first = LEFT if sc.first_support == "left" else RIGHT
        d = 0.5 * self.width
        self._home = {LEFT: np.array([0.0, d, 0.0]), RIGHT: np.array([0.0, -d, 0.0])}
        self._swings: dict[int, list[tuple]] = {LEFT: [], RIGHT: []}
        self._swing_basis: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._buf = _Buffer()
        self._i = 0                       # next sample to emit
        self._next_plan: int | None = None
        self._end: int | None = None      # last sample of the stop (at rest)
        self._state = "standing"
        self._cmd = np.zeros(2)
        self._stop_requested = False
        self._last_cmd_target = np.zeros(2)   # commanded part of the last planned take-off velocity
        self._last_target = np.zeros(2)
        self._footholds: list[tuple[np.ndarray, int]] = [(self._home[LEFT][:2].copy(), LEFT),
                                                        (self._home[RIGHT][:2].copy(), RIGHT)]
        self._stance_sides: list[int] = []
        self._stance_feet: list[np.ndarray] = []
        self.takeoffs: list[Takeoff] = []
        self.events: list[Event] = []
        self._blocks: list[Samples] = []
        self._last_vel = np.zeros(3)

    # ----------------------------------------------------------------- public state
    @property
    def t(self) -> float:
        """Time of the next sample, s."""
        return self._i * self.dt

    @property
    def tick_index(self) -> int:
        """Index of the next sample to emit."""
        return self._i

    @property
    def next_plan_index(self) -> int | None:
        """Sample index of the next planning instant (a take-off), None once the stop is planned."""
        return self._next_plan

    @property
    def state(self) -> str:
        """standing, starting, running, stopping or stopped."""
        if self._state == "stopping" and self._end is not None and self._i > self._end:
            return "stopped"
        if self._state == "starting" and self.takeoffs and self._i > self.takeoffs[0].index:
            return "running"
        return self._state

    @property
    def finished(self) -> bool:
        """True once the last sample of the stop (at rest) has been emitted."""
        return self.state == "stopped"

    @property
    def step_count(self) -> int:
        """Number of take-offs emitted so far."""
        return sum(1 for tk in self.takeoffs if tk.index < self._i)

    @property
    def planned_velocity(self) -> np.ndarray:
        """CoM velocity (3,) of the last emitted sample, m/s."""
        return self._last_vel.copy()

    @property
    def command_velocity(self) -> np.ndarray:
        """The command in force (after the speed limits), (2,) m/s."""
        return self._cmd.copy()

    def _side(self, k: int) -> int:
        return self.first if k % 2 == 0 else 1 - self.first

    def _osc(self, side: int) -> float:
        return self.u_left if side == LEFT else -self.u_left

    def _event(self, kind: str, fld: str, requested: float, applied: float, note: str = "") -> None:
        self.events.append(Event(round(self.t, 9), kind, fld, float(requested), float(applied), note))

    # ----------------------------------------------------------------- inputs
    def command(self, vx: float, vy: float = 0.0) -> np.ndarray:
        """Set the commanded speed, m/s. Returns the accepted command (clamped to max_speed).

        Raises:
            InputError: a non-finite value (the generator never produces NaN).
        """
        req = np.array([vx, vy], dtype=float)
        for k, name in enumerate(("command.vx", "command.vy")):
            if not math.isfinite(req[k]):
                raise InputError(name, float(req[k]), "a finite speed in m/s")
        if self._stop_requested:
            for k, name in enumerate(("command.vx", "command.vy")):
                if req[k] != self._cmd[k]:
                    self._event("ignored", name, req[k], self._cmd[k], "stop requested")
            return self._cmd.copy()
        vmax = self.max_speed
        acc = np.clip(req, -vmax, vmax)
        for k, name in enumerate(("command.vx", "command.vy")):
            if acc[k] != req[k]:
                self._event("clamp_speed", name, req[k], acc[k], f"|v| <= {vmax[k]:.4g} ({self._vmax_why[k]})")
        self._cmd = acc
        return acc.copy()

    @property
    def max_speed(self) -> np.ndarray:
        """Largest sustainable |command| per axis, m/s: the scenario's max_speed, and the speeds at
        which the steady strides (x: v T_step; y: step_width +/- v T_step) stay within max_stride and
        keep the feet one foot width apart."""
        lim = self.sc.limits
        T = self.n_step * self.dt
        wmin = float(self.sc.foot.size[1])
        stride = np.array([lim.max_stride / T, max(0.0, min(self.width - wmin, lim.max_stride - self.width)) / T])
        return np.minimum(np.asarray(lim.max_speed, float), stride)

    @property
    def _vmax_why(self) -> list[str]:
        lim = np.asarray(self.sc.limits.max_speed, float)
        return ["limits.max_speed" if self.max_speed[k] >= lim[k] else "steady strides within limits"
                for k in range(2)]

    def stop(self) -> None:
        """Request the stop: the command ramps to zero, then State Switching 3 ends at rest."""
        if not self._stop_requested:
            self._stop_requested = True
            self._event("stop", "command", float(np.hypot(*self._cmd)), 0.0, "stop requested")
            self._cmd = np.zeros(2)

    # ----------------------------------------------------------------- planning
    def _write(self, start: int, c, z3, zmp, phase, contact) -> None:
        self._buf.write(start, c=c, z=z3[0], zd=z3[1], zdd=z3[2], zmp=zmp, phase=phase, contact=contact)

    def _contact(self, phase: np.ndarray, side: int) -> np.ndarray:
        contact = np.zeros((len(phase), 2), dtype=bool)
        contact[phase == DS] = True
        contact[phase == SS, side] = True
        return contact

    def _clamp_target(self, cmd: np.ndarray, side: int, c_prev, v_prev, p_prev) -> np.ndarray:
        """Commanded part of the next take-off velocity after the per-step and stride limits."""
        lim = self.sc.limits
        dv = np.asarray(lim.max_accel_per_step, float)
        out = _clip_change(cmd, self._last_cmd_target, dv)
        for k, name in enumerate(("command.vx", "command.vy")):
            if out[k] != cmd[k]:
                self._event("clamp_accel", name, cmd[k], out[k], f"|change| <= {dv[k]} m/s per step")
        # foothold of Algorithm 1 in closed form: p = c_prev - v_prev U_0 - v1 V_0 (unit ZMP response is 1)
        U0, V0 = self._U[0], self._V[0]
        K = np.asarray(c_prev) - np.asarray(v_prev) * U0 - np.asarray(p_prev)
        sgn = 1.0 if side == LEFT else -1.0
        lo_d = np.array([-lim.max_stride, -np.inf])
        hi_d = np.array([lim.max_stride, np.inf])
        # lateral: the new foot stays on its side, at least one foot width away, at most max_stride
        wmin = float(self.sc.foot.size[1])
        if sgn > 0:
            lo_d[1], hi_d[1] = wmin, lim.max_stride
        else:
            lo_d[1], hi_d[1] = -lim.max_stride, -wmin
        osc = np.array([0.0, self._osc(side)])
        v1 = out + osc
        slack = 1e-9 * abs(V0)
        v_lo, v_hi = (K - hi_d) / V0, (K - lo_d) / V0
        v1c = np.clip(v1, np.minimum(v_lo, v_hi) - slack, np.maximum(v_lo, v_hi) + slack)
        # never faster changes than the per-step limit: a stride clamp that needs more would feed back
        # into ever larger corrections (the horizontal dynamics are unstable); the stride then gives
        v1c = _clip_change(v1c, self._last_cmd_target + osc, dv)
        v1c = np.where(np.abs(v1c - v1) <= 1e-12, v1, v1c)
        for k, name in enumerate(("command.vx", "command.vy")):
            if v1c[k] != v1[k]:
                self._event("clamp_stride", name, v1[k] - osc[k], v1c[k] - osc[k],
                            f"foothold step within [{lo_d[k]:.3f}, {hi_d[k]:.3f}] m")
        return v1c - osc

    def _plan_start(self) -> None:
        n_ds, n_sup, dt = self.n_start, self.n_sup, self.dt
        side = self.first
        y1 = self._home[side][:2]
        lo = np.array([-self._half[0], -0.5 * self.width - self._half[1]])
        hi = -lo
        dv = np.asarray(self.sc.limits.max_accel_per_step, float)
        want = _clip_change(self._cmd, np.zeros(2), dv)
        for k, name in enumerate(("command.vx", "command.vy")):
            if want[k] != self._cmd[k]:
                self._event("clamp_accel", name, self._cmd[k], want[k], f"|change| <= {dv[k]} m/s per step")
        osc = np.array([0.0, self._osc(side)])

        def attempt(scale: float):
            prob = SwitchingProblem(self._start_w, n_ds, dt, np.zeros(2), y1, np.zeros(2),
                                    scale * want + osc, lo, hi)
            return self._start_solver.solve(prob)

        try:
            sol, scale = attempt(1.0), 1.0
        except InfeasibleError:
            a, b = 0.0, 1.0
            sol = attempt(0.0)  # raises if even the in-place start is impossible
            for _ in range(20):
                mid = 0.5 * (a + b)
                try:
                    sol, a = attempt(mid), mid
                except InfeasibleError:
                    b = mid
            scale = a
            for k, name in enumerate(("command.vx", "command.vy")):
                if want[k] != 0:
                    self._event("clamp_start", name, want[k], scale * want[k],
                                "fastest start keeping the ZMP in the feet")
        target = scale * want
        n = n_ds + n_sup
        w = self._start_w
        phase = np.where(np.arange(n + 1) < n_ds, DS, np.where(w > 0, SS, FLIGHT)).astype(np.int8)
        zmp = np.empty((n + 1, 2))
        zmp[: n_ds] = sol.zmp[: n_ds]
        zmp[n_ds:] = y1
        zmp[phase == FLIGHT] = np.nan
        self._write(0, sol.com, self._start_z, zmp, phase, self._contact(phase, side))
        self._stance_sides.append(side)
        self._stance_feet.append(y1.copy())
        self._lift = {side: (n, self._home[side]), 1 - side: (n_ds, self._home[1 - side])}
        v_end = target + osc
        self.takeoffs.append(Takeoff(n, n * dt, v_end, y1.copy(), np.zeros(2, int), "start"))
        self._last_cmd_target, self._last_target = target, v_end
        self.start_solution = sol
        self._state = "starting"
        self._plan_run()
        self._next_plan = n

    def _planning_state(self) -> tuple[int, int, np.ndarray, np.ndarray]:
        """At a planning instant: (side of the next stance, index a of the last planned sample,
        CoM at a (copy), take-off velocity target of the step being flown)."""
        side = self._side(len(self._stance_sides))
        a = self._buf.n - 1
        return side, a, self._buf.c[a].copy(), self._last_target

    def _plan_run(self) -> None:
        side, a, c_prev, v_prev = self._planning_state()
        p_prev = self._stance_feet[-1]
        cmd = np.zeros(2) if self._stop_requested else self._cmd
        target = self._clamp_target(cmd, side, c_prev, v_prev, p_prev)
        v1 = target + np.array([0.0, self._osc(side)])
        sgn = 1.0 if side == LEFT else -1.0
        T = self.n_step * self.dt
        p_nom = p_prev + np.array([v1[0] * T, sgn * self.width + target[1] * T])
        res = self._foothold(c_prev, v_prev, v1, p_nom)
        self._commit_run(a, side, res, v1, target)

    def _foothold(self, c_prev, v_prev, v1, p_nom):
        """Algorithm 1 in coordinates centred on ``c_prev`` (keeps the solve's rounding at the scale
        of one step, not of the distance run), shifted back."""
        res = target_foothold(self._run_h, np.zeros(2), v_prev, v1, np.asarray(p_nom) - c_prev)
        return type(res)(res.foothold + c_prev, res.com + c_prev, res.iterations, res.residual)

    def _commit_run(self, a: int, side: int, res, v1: np.ndarray, target: np.ndarray, replace: bool = False) -> None:
        w = self._run_w[1:]
        phase = np.where(w > 0, SS, FLIGHT).astype(np.int8)
        zmp = np.where((w > 0)[:, None], res.foothold[None, :], np.nan)
        z3 = tuple(v[1:] for v in self._run_z)
        self._write(a + 1, res.com[1:], z3, zmp, phase, self._contact(phase, side))
        touchdown = a + self.n_fly
        end = a + self.n_step
        p3 = np.array([res.foothold[0], res.foothold[1], 0.0])
        if replace:
            self._footholds[-1] = (res.foothold.copy(), side)
            self._stance_feet[-1] = res.foothold.copy()
            self.takeoffs[-1] = Takeoff(end, end * self.dt, v1, res.foothold.copy(), res.iterations, "run")
            i0, _, start, _, _ = self._swings[side][-1]
            if self._i > i0:   # re-anchor the swing at the current foot position
                start = self._foot_positions(side, np.array([self._i]))[0]
                i0 = self._i
            self._swings[side][-1] = self._swing(i0, touchdown, start, p3)
            self._last_cmd_target, self._last_target = target, v1
        else:
            self._stance_sides.append(side)
            self._stance_feet.append(res.foothold.copy())
            self._footholds.append((res.foothold.copy(), side))
            lift_idx, lift_pos = self._lift[side]
            self._swings[side].append(self._swing(lift_idx, touchdown, lift_pos, p3))
            self._lift[side] = (end, p3)
            self.takeoffs.append(Takeoff(end, end * self.dt, v1, res.foothold.copy(), res.iterations, "run"))
            self._last_cmd_target, self._last_target = target, v1

    def _plan_stop(self) -> None:
        side, a, c_prev, v_prev = self._planning_state()
        sgn = 1.0 if side == LEFT else -1.0           # A on the left: B is to the right (-y)
        offset = np.array([0.0, -sgn * self.width])
        lo = np.array([-self._half[0], min(0.0, offset[1]) - self._half[1]])
        hi = np.array([self._half[0], max(0.0, offset[1]) + self._half[1]])
        sol, com_rel, zmp_rel = solve_stop(self._stop_w, self.n_stop, self.dt, v_prev, offset, lo, hi,
                                           solver=self._stop_solver)
        delta = c_prev - com_rel[0]
        A, B = delta, delta + offset
        M = len(self._stop_w) - 1
        j = np.arange(M + 1)
        n_ss_end = self.n_fly + self.n_sup
        phase = np.where(j >= n_ss_end, DS, np.where(self._stop_w > 0, SS, FLIGHT)).astype(np.int8)
        zmp = np.where((phase == SS)[:, None], A[None, :], np.nan)
        zmp[n_ss_end:] = zmp_rel + delta
        self._write(a + 1, (com_rel + delta)[1:], tuple(v[1:] for v in self._stop_z), zmp[1:], phase[1:],
                    self._contact(phase, side)[1:])
        self._stance_sides.append(side)
        self._stance_feet.append(A.copy())
        self._footholds += [(A.copy(), side), (B.copy(), 1 - side)]
        A3, B3 = np.append(A, 0.0), np.append(B, 0.0)
        lift_idx, lift_pos = self._lift[side]
        self._swings[side].append(self._swing(lift_idx, a + self.n_fly, lift_pos, A3))
        lift_idx, lift_pos = self._lift[1 - side]
        self._swings[1 - side].append(self._swing(lift_idx, a + n_ss_end, lift_pos, B3))
        self.stop_solution = sol
        self._end = a + M
        self._mid = 0.5 * (A + B)
        self._state = "stopping"
        self._next_plan = None

    def _plan_next(self) -> None:
        """At a take-off: plan the step after the next (running or the stop)."""
        end_prev = self._buf.n - 1
        if (self._stop_requested and np.all(np.abs(self._last_cmd_target) < 1e-12)):
            self._plan_stop()
            return
        self._plan_run()
        self._next_plan = end_prev
        if self._state == "starting" and self._i > self.takeoffs[0].index:
            self._state = "running"

    # ----------------------------------------------------------------- re-planning
    def replan(self, com_pos: np.ndarray, com_vel: np.ndarray) -> None:
        """Re-plan from a measured CoM state at the time of the next sample (:attr:`t`).

        The committed footholds up to the next take-off are kept: the CoM is propagated from the
        measured (x, y) position and velocity with eq. (9') to that take-off, then the step after it
        is planned again by Algorithm 1 (new foothold, same take-off speed target unless the stride
        limits need a different one: then clamped within max_accel_per_step and reported). A swing
        foot already in the air is redirected from where it is. Only while running.

        Raises:
            InputError: non-finite measurement. InfeasibleError: not running.
        """
        pos = np.asarray(com_pos, float).ravel()[:2]
        vel = np.asarray(com_vel, float).ravel()[:2]
        if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(vel))):
            raise InputError("measured CoM state", [*pos, *vel], "finite numbers")
        if self.state != "running" or self._next_plan is None or self._i > self._next_plan:
            raise InfeasibleError(f"replan: only while running between the first take-off and the stop "
                                  f"(state {self.state})")
        i, np_ = self._i, self._next_plan
        buf, dt = self._buf, self.dt
        old_c, old_p = buf.c[i].copy(), self._footholds[-1][0].copy()
        c = np.empty((np_ - i + 1, 2))
        c[0] = pos
        if len(c) > 1:
            c[1] = pos + vel * dt
        p = buf.zmp[i:np_ + 1]
        w = row_weights(buf.z[i:np_ + 1], buf.zdd[i:np_ + 1], self.g, dt)
        p = np.nan_to_num(p)
        cx, cy = c[:, 0].tolist(), c[:, 1].tolist()
        for j in range(1, len(c) - 1):
            cx[j + 1] = (2 + w[j]) * cx[j] - cx[j - 1] - w[j] * p[j, 0]
            cy[j + 1] = (2 + w[j]) * cy[j] - cy[j - 1] - w[j] * p[j, 1]
        c = np.column_stack([cx, cy])
        buf.c[i:np_ + 1] = c
        v_to = (c[-1] - c[-2]) / dt if len(c) > 1 else vel
        side = self._stance_sides[-1]
        tk = self.takeoffs[-1]
        p_prev = self._stance_feet[-2]
        sgn = 1.0 if side == LEFT else -1.0
        osc = np.array([0.0, self._osc(side)])
        # same take-off target unless the new foothold would break the stride limits
        target = self._clamp_target(tk.target - osc, side, c[-1], v_to, p_prev)
        v1 = target + osc
        p_nom = p_prev + np.array([v1[0] * self.n_step * dt, sgn * self.width])
        res = self._foothold(c[-1], v_to, v1, p_nom)
        self._commit_run(np_, side, res, v1, target, replace=True)
        self._event("replan", "com", float(np.hypot(*(pos - old_c))), float(np.hypot(*(res.foothold - old_p))),
                    "requested = measured CoM offset from the plan, applied = foothold shift (m)")

    # ----------------------------------------------------------------- emission
    def _swing(self, i0: int, i1: int, start: np.ndarray, end: np.ndarray) -> tuple:
        """A swing from sample i0 (lift-off) to i1 (touchdown), its path sampled once: the path of
        :func:`gaitshift.swing.swing_path` (minimum-jerk horizontal, sextic height through the apex),
        which is linear in (start, end, apex), so its basis is computed once per swing length."""
        n = i1 - i0
        basis = self._swing_basis.get(n)
        if basis is None:
            u = np.arange(n) / max(n, 1)
            eye = np.eye(3)
            s_blend = min_jerk(u)                                                  # horizontal blend
            coef = sextic_height_coefficients(eye[:, 0], eye[:, 1], eye[:, 2])    # (z0, z1, apex) -> (3, 7)
            zb = (u[:, None] ** np.arange(7)) @ coef.T                              # (n, 3)
            basis = self._swing_basis[n] = (s_blend, zb)
        s_blend, zb = basis
        path = start + (end - start) * s_blend[:, None]
        apex = max(start[2], end[2]) + float(self.sc.swing_apex)
        path[:, 2] = zb @ np.array([start[2], end[2], apex])
        return (i0, i1, start, end, path)

    def _foot_positions(self, foot: int, idx: np.ndarray) -> np.ndarray:
        pos = np.empty((len(idx), 3))
        pos[:] = self._home[foot]
        a, b = int(idx[0]), int(idx[-1]) + 1
        for i0, i1, _, end, path in self._swings[foot]:
            if i1 < b:                      # touched down: stays at the foothold
                pos[max(i1 - a, 0):] = end
            lo, hi = max(i0, a), min(i1, b)
            if lo < hi:
                pos[lo - a:hi - a] = path[lo - i0:hi - i0]
        return pos

    def _prune_swings(self) -> None:
        """Forget swings that ended before the next sample (their end becomes the foot's rest)."""
        for foot, swings in self._swings.items():
            while swings and swings[0][1] < self._i:
                self._home[foot] = swings.pop(0)[3]

    def _ensure_rest(self, upto: int) -> None:
        """After the stop, extend the plan with standing samples up to index ``upto``."""
        buf = self._buf
        if self._end is None or buf.n > upto:
            return
        m = upto - buf.n + 1
        last = buf.n - 1
        self._buf.write(buf.n, c=np.repeat(buf.c[last][None], m, 0), z=np.full(m, buf.z[last]),
                        zd=np.zeros(m), zdd=np.zeros(m), zmp=np.repeat(self._mid[None], m, 0),
                        phase=np.full(m, DS, np.int8), contact=np.ones((m, 2), bool))

    def _emit(self, m: int) -> Samples:
        i, dt, g, buf = self._i, self.dt, self.g, self._buf
        self._ensure_rest(i + m)
        sl = slice(i, i + m)
        cc = buf.c[i - 1:i + m + 1] if i > 0 else np.concatenate([buf.c[0:1], buf.c[0:m + 1]])
        pos, vel, acc = np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3))
        pos[:, :2] = cc[1:-1]
        np.subtract(cc[2:], cc[:-2], out=vel[:, :2])
        vel[:, :2] *= 0.5 / dt
        acc[:, :2] = (cc[2:] - 2.0 * cc[1:-1] + cc[:-2]) * (1.0 / (dt * dt))
        z, zdd = buf.z[sl], buf.zdd[sl]
        pos[:, 2], vel[:, 2], acc[:, 2] = z, buf.zd[sl], zdd
        phase = buf.phase[sl].copy()
        flight = phase == FLIGHT
        # force-free samples: the row of eq. (14) says 0; the positions meet it to rounding
        acc[zdd + g <= FORCE_EPS * g, :2] = 0.0
        zmp = np.zeros((m, 3))
        zmp[:, :2] = buf.zmp[sl]
        zmp[flight] = np.nan
        with np.errstate(invalid="ignore", divide="ignore"):
            stiff = np.sqrt(z / (zdd + g))
        stiff[flight] = np.nan
        idx = np.arange(i, i + m)
        feet = np.empty((m, 2, 3))
        feet[:, LEFT] = self._foot_positions(LEFT, idx)
        feet[:, RIGHT] = self._foot_positions(RIGHT, idx)
        out = Samples(t=idx * dt, com_pos=pos, com_vel=vel, com_acc=acc, zmp=zmp, phase=phase,
                      contact=buf.contact[sl].copy(), foot_pos=feet,
                      command=np.broadcast_to(self._cmd, (m, 2)).copy(), stiffness=stiff)
        self._i += m
        buf.release(self._i - 1)
        self._last_vel = out.com_vel[-1].copy()
        if self.keep_history:
            self._blocks.append(out)
        self._prune_swings()
        return out

    def advance(self, n: int) -> Samples:
        """Advance ``n`` control ticks; returns their samples (planning happens on the way)."""
        if n < 1:
            raise InputError("ticks", n, "an integer >= 1")
        blocks = []
        while n > 0:
            if self._state == "standing":
                self._plan_start()
            if self._next_plan is not None and self._i == self._next_plan:
                self._plan_next()
            limit = n
            if self._next_plan is not None and self._next_plan > self._i:
                limit = min(n, self._next_plan - self._i)
            blocks.append(self._emit(limit))
            n -= limit
        return blocks[0] if len(blocks) == 1 else Samples.concat(blocks)

    def tick(self) -> Samples:
        """Advance one control period (dt); returns that one sample."""
        return self.advance(1)

    def step(self) -> Samples:
        """Advance to the next planning instant (one running step; the whole stop once stopping)."""
        if self._state == "standing":
            self._plan_start()
        if self._next_plan is not None and self._i == self._next_plan:
            self._plan_next()
        if self._next_plan is not None:
            return self.advance(self._next_plan - self._i)
        assert self._end is not None
        return self.advance(max(1, self._end + 1 - self._i))

    # ----------------------------------------------------------------- output
    def trajectory(self) -> Trajectory:
        """Everything emitted so far as the standard :class:`~gaitshift.Trajectory` contract."""
        if not self.keep_history:
            raise InputError("keep_history", False, "True to collect the trajectory")
        if not self._blocks:
            raise InputError("trajectory", "empty", "at least one emitted sample")
        s = Samples.concat(self._blocks)
        fs = np.array([[p[0], p[1], 0.0, 0.0] for p, _ in self._footholds])
        side = np.array([sd for _, sd in self._footholds], dtype=np.int8)
        emitted = [tk for tk in self.takeoffs if tk.index < self._i]
        meta = {
            "planner": "vhip", "gravity": self.g, "foot_size": list(self.sc.foot.size),
            "scenario": self.sc.name, "dt": self.dt,
            "step_period": self.n_step * self.dt, "stance": self.n_sup * self.dt,
            "lateral_oscillation": self.u_left, "step_width": self.width,
            "events": [e.as_dict() for e in self.events],
            "velocity_convention": "central difference; acceleration: second difference (eqs. 7-9)",
        }
        extras = {
            "takeoff_index": np.array([tk.index for tk in emitted], dtype=np.int64),
            "takeoff_target": np.array([tk.target for tk in emitted]).reshape(-1, 2),
            "foothold_iterations": np.array([tk.iterations for tk in emitted], dtype=np.int64).reshape(-1, 2),
        }
        return Trajectory(t=s.t, com_pos=s.com_pos, com_vel=s.com_vel, com_acc=s.com_acc, zmp=s.zmp,
                          phase=s.phase, contact=s.contact, foot_pos=s.foot_pos, stiffness=s.stiffness,
                          footsteps=fs, footstep_side=side, command_vel=s.command, meta=meta, extras=extras)


def run_commands(gen: OnlineGenerator, commands: list[tuple[float, float, float]], stop_at: float,
                 max_time: float = 3600.0) -> OnlineGenerator:
    """Drive ``gen`` with a scripted profile of (t, vx, vy) commands, request the stop at ``stop_at``
    and run until the generator is at rest. A command is applied at the first tick with t >= its time
    (commands already due are applied before the next tick)."""
    dt = gen.dt
    events = sorted(commands, key=lambda c: c[0])
    ci = 0
    stopped = False
    while True:
        while ci < len(events) and events[ci][0] <= gen.t + 1e-12:
            gen.command(events[ci][1], events[ci][2])
            ci += 1
        if not stopped and stop_at <= gen.t + 1e-12:
            gen.stop()
            stopped = True
        if gen.finished:
            return gen
        if gen.t > max_time:
            raise InfeasibleError(f"the scripted run did not stop within {max_time} s")
        if stopped:
            gen.step()
            continue
        nxt = min(events[ci][0], stop_at) if ci < len(events) else stop_at
        gen.advance(max(1, math.ceil(nxt / dt - 1e-9) - gen.tick_index))


def plan_scenario(sc: Any) -> Trajectory:
    """Run the scenario's scripted command profile through the online generator; the whole run
    (start, running, stop at rest) as the standard trajectory contract (meta.planner = "vhip")."""
    gen = OnlineGenerator(sc)
    cmds = [(c.t, c.vx, c.vy) for c in sc.commands]
    stop_at = sc.stop_at if sc.stop_at is not None else max(c[0] for c in cmds) + 2.0
    run_commands(gen, cmds, stop_at)
    return gen.trajectory()
