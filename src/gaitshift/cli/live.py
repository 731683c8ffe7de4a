"""``gaitshift teleop --sim``: the simulated robot driven live by keys (:mod:`gaitshift.sim.teleop`) or,
with ``--web``, by the sliders of a browser page (:mod:`gaitshift.sim.web`)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import typer

from gaitshift.cli.app import out_file
from gaitshift.cli.web import web_view
from gaitshift.errors import InputError


def teleop_sim(
    robot: str,
    actions: list[tuple[str, float]] | None,
    out: Path,
    max_time: float,
    viewer: bool | None,
    realtime: bool,
    web: tuple[bool, int] = (False, 8080),
) -> None:
    """Run a live session on ``robot`` (keyboard, the key script ``actions``, and/or the browser page
    when ``web`` = (enabled, port)), write the sim log."""
    out_file(out, "--out", (".npz",))
    display = bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if viewer is None:
        viewer = display
    if viewer and not display:
        raise InputError("--viewer", "no display", "a graphical display (DISPLAY or WAYLAND_DISPLAY set)")
    if viewer:
        os.environ["MUJOCO_GL"] = "glfw"  # the passive viewer opens a window (before mujoco loads)
    from gaitshift.control.locomotion_driver import LocomotionDriver
    from gaitshift.robots import load_robot
    from gaitshift.scenario import load_scenario
    from gaitshift.sim.metrics import format_metrics
    from gaitshift.sim.teleop import Session, run_session
    from gaitshift.sim.web import CommandRange

    cfg = load_robot(robot)
    sc = load_scenario({"planner": "locomotion", "name": f"teleop-{cfg.name}", "robot": cfg.source or cfg.name})
    driver = LocomotionDriver.live(sc, cfg.facts(), 0.002, max_time)
    session = Session(
        driver, script=list(actions) if actions is not None else None, realtime=realtime, status=typer.echo
    )
    keyboard = actions is None and (not web[0] or sys.stdin.isatty())
    typer.echo(
        f"teleop --sim on {cfg.name}: {'MuJoCo viewer' if viewer else 'status line'}"
        + ("; keys: arrows/wasd speed, z/x turn, space stop, q quit" if keyboard else "")
    )
    if keyboard and not sys.stdin.isatty():
        raise InputError("stdin", "not a terminal", "a terminal, key tokens with --script, or --web")
    lim = driver.gen.p.limits
    controls = CommandRange(*lim.max_speed, lim.max_yaw_rate)
    with web_view(
        *web, lambda: driver.trajectory, controls=controls, on_command=session.set_command, on_quit=session.quit
    ) as views:
        if keyboard:  # pragma: no cover - needs a TTY
            from gaitshift.cli.keys import KeyReader

            with KeyReader() as keys:
                session.poll = keys.poll
                result = run_session(driver, session, viewer, cfg, views)
        else:
            result = run_session(driver, session, viewer, cfg, views)
    result.save(out)
    typer.echo(format_metrics(result.metrics))
    typer.echo(f"wrote {out}")
    if result.fell:
        raise typer.Exit(1)
