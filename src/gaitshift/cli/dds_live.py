"""The live command inputs of ``gaitshift dds control``: ``--cmd-topic`` (``rt/gaitshift/cmd_vel``), ``--web``
(the browser page: the robot as the brain estimates it and the sliders of ``teleop --sim --web``) and
``--teleop`` (the keys of ``gaitshift teleop``). The page's and the keyboard's commands go into a
:class:`~gaitshift.dds.cmdvel.CommandQueue` each, which the brain's command input takes every tick beside
the topic, with the same checks (:class:`~gaitshift.dds.cmdvel.CommandInput`). The keys are read in a
thread of their own (:func:`gaitshift.cli.keys.key_loop`), the page is drawn in another
(:mod:`gaitshift.dds.brain_web`): the tick only takes the queues and hands its record over."""

from __future__ import annotations

import contextlib
import sys
import threading
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import typer

from gaitshift.cli.app import number
from gaitshift.cli.keys import require_terminal
from gaitshift.errors import InputError

if TYPE_CHECKING:
    from gaitshift.control.controller import Controller
    from gaitshift.dds.brain_web import BrainFeed
    from gaitshift.dds.cmdvel import CommandLimits, CommandQueue

__all__ = ["check_live_flags", "live_inputs", "live_scenario"]

#: the keys, as ``gaitshift dds cmd --teleop`` and ``gaitshift teleop`` print them
KEYS_HELP = "keys: arrows/wasd speed, z/x turn, space stand, q stop the run"


def live_scenario(scenario: str, flag: str) -> None:
    """:class:`InputError` naming ``flag`` unless ``scenario`` plans with ``planner: locomotion`` (live commands)."""
    from gaitshift.scenario import load_scenario

    if load_scenario(scenario).planner != "locomotion":
        raise InputError(flag, scenario, "a live-command scenario (planner: locomotion)")


def check_live_flags(scenario: str, cmd_topic: bool, web_port: int, teleop: bool) -> None:
    """The live flags refused before anything is built (one line, exit 2): ``--web-port`` outside 0-65535;
    ``--teleop`` without a terminal on stdin or on a scenario that takes no live command; ``--cmd-topic``
    on such a scenario. (``--web`` on one is a view without controls.)"""
    number(web_port, "--web-port", 0, 65535)
    if teleop:
        require_terminal("--teleop")
    for flag, on in (("--cmd-topic", cmd_topic), ("--teleop", teleop)):
        if on:
            live_scenario(scenario, flag)


def plan_limits(ctrl: Controller) -> CommandLimits | None:
    """The live plan's command limits, or None when ``ctrl``'s plan takes no live command."""
    from gaitshift.dds.cmdvel import live_limits

    try:
        return live_limits(ctrl)
    except InputError:
        return None


@contextlib.contextmanager
def live_inputs(
    ctrl: Controller, cmd_topic: bool, web: tuple[bool, int], teleop: bool, say: Callable[[str], None]
) -> Iterator[tuple[list[CommandQueue], BrainFeed | None]]:
    """The brain's command queues (the page's, the keyboard's) and the page's hand-off (None without
    ``--web``) for the block; the threads and the server stop, and the terminal is restored, when it ends."""
    from gaitshift.dds.cmdvel import CommandQueue

    limits = plan_limits(ctrl)
    queues: list[CommandQueue] = []
    page = None
    with contextlib.ExitStack() as stack:
        if web[0]:
            page_queue = CommandQueue("the web page") if limits is not None else None
            page = stack.enter_context(_page(ctrl, web[1], limits, page_queue))
            queues += [page_queue] if page_queue is not None else []
        if teleop:
            queues.append(CommandQueue("the keyboard"))
            stack.enter_context(_keyboard(queues[-1], say))
        if limits is not None and (cmd_topic or queues):
            names = [*(["rt/gaitshift/cmd_vel"] if cmd_topic else []), *(q.name for q in queues)]
            say(
                f"live commands from {', '.join(names)}: vx [{-limits.backward:.3g}, {limits.forward:.3g}] m/s, "
                f"|vy| <= {limits.sideways:.3g} m/s, |yaw_rate| <= {limits.yaw_rate:.3g} rad/s"
            )
        yield queues, page


@contextlib.contextmanager
def _page(ctrl: Controller, port: int, limits: CommandLimits | None, queue: CommandQueue | None) -> Iterator[BrainFeed]:
    """The browser page on ``port`` (its URL on stderr), drawn from a :class:`BrainFeed`; with ``queue`` its
    sliders (ranged to ``limits``), *Stop* and *End run* feed it."""
    from gaitshift.cli.web import web_view
    from gaitshift.dds.brain_web import BrainFeed
    from gaitshift.sim.web import CommandRange

    kw: dict[str, Any] = {}
    if limits is not None and queue is not None:
        kw = {
            "controls": CommandRange(limits.forward, limits.backward, limits.sideways, limits.yaw_rate),
            "on_command": lambda vx, vy, w, _t: queue.command(vx, vy, w),
            "on_quit": lambda _t: queue.stop(),
        }
    feed = BrainFeed(ctrl.robot.model)
    with web_view(True, port, feed.plan, err=True, **kw) as views:
        feed.start(views[0])
        try:
            yield feed
        finally:
            feed.close()


@contextlib.contextmanager
def _keyboard(queue: CommandQueue, say: Callable[[str], None]) -> Iterator[None]:
    """The keys of stdin (a terminal, in cbreak mode for the block) to ``queue``, one line each on ``say``."""
    from gaitshift.cli.keys import KeyReader, key_loop
    from gaitshift.dds.cmdvel import KeySteer, command_text

    def put(msg: Any) -> None:
        queue.put(msg)
        say(f"keys: {'stop' if msg.stop else command_text(msg)}")

    done = threading.Event()
    typer.echo(KEYS_HELP, err=True)
    with KeyReader(out=sys.stderr) as keys:
        thread = threading.Thread(target=key_loop, args=(keys, KeySteer(), put, done), name="gaitshift-keys")
        thread.daemon = True
        thread.start()
        try:
            yield
        finally:
            done.set()
            thread.join()
