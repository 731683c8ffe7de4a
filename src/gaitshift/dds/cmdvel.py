"""Live velocity commands over DDS: ``rt/gaitshift/cmd_vel`` (:class:`~gaitshift.dds.own_messages.VelocityCommand_`)
read by the brain and passed to the controller's public ``command(vx, vy, yaw_rate)`` / ``stop()``.

The brain's command input (:class:`CommandInput`) takes the commands of every source it was given, each
with the same checks: the topic (:class:`TopicSource`, ``--cmd-topic``) and the commands other threads put
in a :class:`CommandQueue` (the browser page's controls, ``--web``; the keyboard, ``--teleop``).
Each tick the brain polls its sources (:meth:`CommandInput.poll`): every command is checked
(:func:`check_command`): a component not finite or beyond the plan's limits (the locomotion generator's
``max_speed`` forward / backward / sideways, m/s, and ``max_yaw_rate``, rad/s), or a ``stop`` other than 0
or 1, is dropped and counted, with one line naming its source and the field (the first :data:`MAX_LINES`; the rest only
counted); bad input never stops the run. The newest valid command is kept and handed to the controller at
the next locomotion tick (:meth:`CommandInput.apply`; before locomotion it waits). A ``stop`` is final:
the plan ramps down, stands, ends, and the brain exits 0; later commands are dropped.

:func:`publish` is the other side (``gaitshift dds cmd``): a command written a few times on its own
participant, so another program (or a shell) steers the robot; :class:`KeySteer` turns key presses
(``gaitshift dds cmd --teleop``, the keys of ``gaitshift teleop``) into commands.
"""

import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from gaitshift.dds.own_messages import CMD_VEL_TOPIC, VelocityCommand_
from gaitshift.dds.transport import Endpoint, Participant, topic_reader, topic_writer
from gaitshift.errors import InputError
from gaitshift.scenario.commands import KEYS, LOCOMOTION_STEP, key_change

__all__ = [
    "MAX_LINES",
    "CommandInput",
    "CommandLimits",
    "CommandQueue",
    "CommandSource",
    "KeySteer",
    "TopicSource",
    "check_command",
    "command_text",
    "live_limits",
    "publish",
]

#: dropped commands reported each with a line; later drops are only counted
MAX_LINES = 5


@dataclass(frozen=True)
class CommandLimits:
    """The live plan's command limits: ``forward``, ``backward``, ``sideways`` m/s (largest |vx| ahead,
    |vx| back, |vy|), ``yaw_rate`` rad/s."""

    forward: float
    backward: float
    sideways: float
    yaw_rate: float

    def bounds(self) -> dict[str, tuple[float, float, str]]:
        """field -> (low, high, unit)."""
        return {
            "vx": (-self.backward, self.forward, "m/s"),
            "vy": (-self.sideways, self.sideways, "m/s"),
            "yaw_rate": (-self.yaw_rate, self.yaw_rate, "rad/s"),
        }


def live_limits(ctrl: Any, scenario: str = "") -> CommandLimits:
    """The command limits of ``ctrl``'s live plan; :class:`InputError` ``--cmd-topic`` when its plan takes no
    live commands (not a ``planner: locomotion`` scenario)."""
    drv = getattr(ctrl, "driver", None)
    local = getattr(drv, "local", drv)  # a background re-plan: the host's copy of the driver
    gen = getattr(local, "gen", None)
    if gen is None or not hasattr(local, "command") or not hasattr(gen, "p"):
        raise InputError("--cmd-topic", scenario, "a live-command scenario (planner: locomotion)")
    lim = gen.p.limits
    fwd, back, side = (float(v) for v in lim.max_speed)
    return CommandLimits(fwd, back, side, float(lim.max_yaw_rate))


def check_command(msg: Any, limits: CommandLimits) -> str:
    """Why the command ``msg`` is refused (one line naming its field), or "" when it is valid."""
    if msg.stop not in (0, 1):
        return f"VelocityCommand_.stop = {msg.stop!r} is invalid: allowed 0 or 1"
    if msg.stop:
        return ""
    for name, (lo, hi, unit) in limits.bounds().items():
        v = float(getattr(msg, name))
        if not (math.isfinite(v) and lo <= v <= hi):
            return f"VelocityCommand_.{name} = {v!r} is invalid: allowed a number in [{lo:.3g}, {hi:.3g}] {unit}"
    return ""


def command_text(msg: Any) -> str:
    """A velocity command in one line: ``vx +0.30 m/s, vy +0.00 m/s, yaw_rate +0.00 rad/s``."""
    return f"vx {msg.vx:+.2f} m/s, vy {msg.vy:+.2f} m/s, yaw_rate {msg.yaw_rate:+.2f} rad/s"


class CommandSource(Protocol):
    """Where live commands come from: ``name`` (in a dropped command's line) and ``take()``, the
    :class:`VelocityCommand_` samples that came since the last call, oldest first."""

    name: str

    def take(self) -> list[Any]:
        """The commands since the last call, oldest first."""
        ...


class TopicSource:
    """``rt/gaitshift/cmd_vel`` read on the brain's ``endpoint`` (its participant)."""

    name = CMD_VEL_TOPIC

    def __init__(self, endpoint: Endpoint) -> None:
        self.reader = topic_reader(endpoint, CMD_VEL_TOPIC, VelocityCommand_)

    def take(self) -> list[Any]:
        """The samples received since the last call (at most 64), oldest first."""
        return [m for m in self.reader.take(N=64) if isinstance(m, VelocityCommand_)]


class CommandQueue:
    """Commands put by other threads (the browser page's callbacks, the key loop), taken by the brain's
    tick: a list swapped under a lock, so that the tick's cost is one lock and no waiting on the page.

    Args:
        name: the source in a dropped command's line (``the web page``, ``the keyboard``).
    """

    def __init__(self, name: str) -> None:
        self.name = name
        self.lock = threading.Lock()
        self.items: list[Any] = []
        self.seq = 0

    def put(self, msg: Any) -> None:
        """Queue one :class:`VelocityCommand_` (any thread)."""
        with self.lock:
            self.items.append(msg)

    def command(self, vx: float, vy: float, yaw_rate: float) -> None:
        """Queue the velocity command (vx, vy m/s in the heading frame, yaw_rate rad/s)."""
        self.numbered(VelocityCommand_(stamp=time.time(), vx=vx, vy=vy, yaw_rate=yaw_rate))

    def stop(self) -> None:
        """Queue the stop command (ramp down, stand, end the run)."""
        self.numbered(VelocityCommand_(stamp=time.time(), stop=1))

    def numbered(self, msg: Any) -> None:
        """Queue ``msg`` with the queue's next ``seq`` (1, 2, ...)."""
        with self.lock:
            self.seq += 1
            msg.seq = self.seq
            self.items.append(msg)

    def take(self) -> list[Any]:
        """The commands queued since the last call, oldest first."""
        with self.lock:
            out, self.items = self.items, []
        return out


class CommandInput:
    """The brain's live command input (module docstring).

    Args:
        sources: where the commands come from (:class:`TopicSource`, :class:`CommandQueue`).
        limits: the live plan's limits. say: where a dropped command's line goes.

    Attributes:
        received, accepted, dropped: commands taken, valid, refused. applied: handed to the controller.
        stopped: a stop was handed to the controller. last_error: the last refusal's line.
    """

    def __init__(self, sources: Sequence[CommandSource], limits: CommandLimits, say: Callable[[str], None]) -> None:
        self.sources = list(sources)
        self.limits, self.say = limits, say
        self.received = self.accepted = self.dropped = self.applied = 0
        self.pending: Any = None
        self.stopped = False
        self.last_error = ""

    def poll(self) -> None:
        """Take every command of every source; keep the newest valid one (a stop is kept over later commands,
        which are dropped; a repeated stop is accepted and changes nothing)."""
        for source in self.sources:
            for msg in source.take():
                self.check(msg, source.name)

    def check(self, msg: Any, source: str = CMD_VEL_TOPIC) -> None:
        """Count ``msg`` from ``source``; keep it when valid, else drop it with its line."""
        if not isinstance(msg, VelocityCommand_):
            return
        self.received += 1
        why = check_command(msg, self.limits)
        stopping = self.stopped or (self.pending is not None and self.pending.stop)
        if not why and stopping and not msg.stop:
            why = "VelocityCommand_ after a stop: ignored (the run is ending)"
        if why:
            self.drop(why, source)
            return
        self.accepted += 1
        if not stopping:  # a repeated stop changes nothing
            self.pending = msg

    def drop(self, why: str, source: str = CMD_VEL_TOPIC) -> None:
        """Count a refused command; its line (naming ``source``) for the first :data:`MAX_LINES`."""
        self.dropped += 1
        self.last_error = why
        if self.dropped <= MAX_LINES:
            more = "" if self.dropped < MAX_LINES else " (further drops only counted)"
            self.say(f"gaitshift: dropped {source}: {why}{more}")

    def apply(self, ctrl: Any) -> None:
        """Hand the pending command to ``ctrl`` (``command`` or ``stop``); call at a locomotion tick."""
        msg, self.pending = self.pending, None
        if msg is None:
            return
        if msg.stop:
            ctrl.stop()
            self.stopped = True
        else:
            ctrl.command(float(msg.vx), float(msg.vy), float(msg.yaw_rate))
        self.applied += 1


def publish(
    endpoint: Endpoint | Participant, msg: Any, repeat: int = 5, interval: float = 0.05, wait: float = 2.0
) -> bool:
    """Write ``msg`` on ``rt/gaitshift/cmd_vel`` ``repeat`` times, ``interval`` s apart, once a reader is
    matched (waiting up to ``wait`` s for one); True when a reader was matched. The brain takes the newest,
    so the repeats only cover a reader that joins late."""
    writer = topic_writer(endpoint, CMD_VEL_TOPIC, VelocityCommand_)
    end = time.monotonic() + wait
    while not _matched(writer) and time.monotonic() < end:
        time.sleep(0.02)
    matched = _matched(writer)
    for i in range(repeat):
        writer.write(msg)
        if i + 1 < repeat:
            time.sleep(interval)
    return matched


def _matched(writer: Any) -> bool:
    """The writer has a matched reader."""
    return bool(writer.get_matched_subscriptions())


class KeySteer:
    """Key actions (:data:`gaitshift.cli.keys.KEY_ACTIONS`) as commands: ``up``/``down``, ``left``/``right``,
    ``turn-left``/``turn-right`` change (vx, vy, yaw_rate) by :data:`~gaitshift.scenario.commands.LOCOMOTION_STEP`
    (0.1 m/s, 0.05 m/s, 0.2 rad/s) a press; ``stop`` (space) sets them to zero (the robot stands, the run goes on);
    ``quit`` (q) is the stop command (the run ends)."""

    def __init__(self) -> None:
        self.v = [0.0, 0.0, 0.0]
        self.seq = 0

    def press(self, action: str) -> Any:
        """The :class:`VelocityCommand_` of one key action (None for an unknown action)."""
        if action in KEYS:
            self.v = [a + b for a, b in zip(self.v, key_change(action, LOCOMOTION_STEP), strict=True)]
        elif action == "stop":
            self.v = [0.0, 0.0, 0.0]
        elif action != "quit":
            return None
        self.seq += 1
        vx, vy, w = (round(c, 9) for c in self.v)
        return VelocityCommand_(seq=self.seq, stamp=time.time(), vx=vx, vy=vy, yaw_rate=w, stop=int(action == "quit"))
