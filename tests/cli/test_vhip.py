"""`gaitshift teleop` without a keyboard, `gaitshift plan` of the vhip scenario, bad input, figures."""

from __future__ import annotations

import io
import sys

import numpy as np
import pytest

import gaitshift
from gaitshift.trajectory.contract import FLIGHT, SS


def _takeoff_vx(tr):
    ph = tr.phase
    to = np.flatnonzero((ph[1:] == FLIGHT) & (ph[:-1] == SS)) + 1
    return tr.com_vel[to, 0]


def test_teleop_script_runs_and_writes_a_run_that_ends_at_rest(tmp_path, cli):
    out = tmp_path / "teleop.npz"
    code, text, err = cli(["teleop", "--script", "up wait=2 up wait=2 down wait=2", "--out", str(out)])
    assert code == 0, err
    assert "steps=" in text and "planned=" in text and f"wrote {out}" in text
    tr = gaitshift.Trajectory.load(out)
    assert tr.meta["planner"] == "vhip"
    # the arrows moved the command by 0.3 m/s; the take-offs reached 0.3 and 0.6
    assert {0.3, 0.6} <= {round(float(c), 9) for c in tr.command_vel[:, 0]}
    assert {0.3, 0.6} <= {round(float(v), 6) for v in _takeoff_vx(tr)}
    assert np.all(np.abs(tr.com_vel[-1]) < 1e-9) and tr.phase[-1] == 0


def test_teleop_reads_keys_from_stdin_when_not_a_tty(tmp_path, cli, monkeypatch):
    monkeypatch.setattr(sys, "stdin", io.StringIO("up\nwait=1.5\nleft\nwait=1\nquit\n"))
    out = tmp_path / "stdin.json"
    code, _, err = cli(["teleop", "--out", str(out)])
    assert code == 0, err
    tr = gaitshift.Trajectory.load(out)
    assert np.max(tr.command_vel[:, 0]) == pytest.approx(0.3)
    assert np.max(tr.command_vel[:, 1]) > 0  # left arrow: lateral command, clamped to the limit


def test_teleop_bad_token_exits_2_without_output(tmp_path, cli):
    out = tmp_path / "bad.npz"
    code, _, err = cli(["teleop", "--script", "up fly", "--out", str(out)])
    assert code == 2 and not out.exists()
    assert err.count("\n") == 1 and "--script" in err


def test_teleop_stdin_that_is_not_utf8_exits_2_naming_stdin(tmp_path, cli, monkeypatch):
    raw = io.TextIOWrapper(io.BytesIO(b"up \xff wait=1"), encoding="utf-8")
    monkeypatch.setattr(sys, "stdin", raw)
    out = tmp_path / "x.npz"
    code, _, err = cli(["teleop", "--out", str(out)])
    assert code == 2 and err.startswith("gaitshift: error: stdin = ") and "UTF-8" in err and not out.exists()


@pytest.mark.parametrize("max_time", ["nan", "-1", "0", "601"])
def test_teleop_max_time_must_be_in_0_600(tmp_path, cli, max_time):
    out = tmp_path / "x.npz"
    code, _, err = cli(["teleop", "--script", "up", "--max-time", max_time, "--out", str(out)])
    assert code == 2 and "--max-time" in err and "(0, 600]" in err and list(tmp_path.iterdir()) == []


def test_teleop_checks_flags_and_script_before_loading_the_scenario(tmp_path, cli):
    out = tmp_path / "x.npz"
    code, _, err = cli(["teleop", "no-such-scenario", "--script", "fly", "--out", str(out)])
    assert code == 2 and "--script = 'fly'" in err


@pytest.mark.parametrize(
    "yaml_text, field",
    [
        ("planner: vhip\nstance_ratio: 1.3\n", "stance_ratio"),
        ("planner: vhip\nheights: {takeoff: 0.8, z_low: 0.9}\n", "heights.z_low"),
        ("planner: vhip\nheights: {z_low: 0.55}\n", "heights.z_low"),
        ("planner: vhip\nstep_period: 0.4003\n", "step_period"),
        ("planner: vhip\ncommands: [{t: 0, vx: .nan}]\n", "commands.0.vx"),
    ],
)
def test_bad_vhip_scenarios_exit_2_naming_the_field_without_output(tmp_path, cli, yaml_text, field):
    sc = tmp_path / "bad.yaml"
    sc.write_text(yaml_text)
    for cmd in (
        ["plan", str(sc), "--out", str(tmp_path / "x.npz")],
        ["teleop", str(sc), "--script", "up", "--out", str(tmp_path / "y.npz")],
    ):
        code, _, err = cli(cmd)
        assert code == 2
        assert err.count("\n") == 1 and field in err, err
    assert not (tmp_path / "x.npz").exists() and not (tmp_path / "y.npz").exists()


def test_plan_cli_writes_the_vhip_contract(tmp_path, cli):
    out = tmp_path / "run.npz"
    code, _, err = cli(["plan", "paper003-variable-speed", "--out", str(out)])
    assert code == 0, err
    tr = gaitshift.Trajectory.load(out)
    assert tr.meta["planner"] == "vhip" and np.all(np.isfinite(tr.command_vel))
    assert {0.3, 0.6, 0.9} <= {round(float(v), 6) for v in _takeoff_vx(tr)}


def test_figures_3_4_7_are_written(tmp_path):
    from gaitshift.plots.vhip import write_figures

    tr = gaitshift.plan("paper003-variable-speed")
    paths = write_figures(tr, tmp_path)
    assert [p.name for p in paths] == ["fig3_start.png", "fig4_run.png", "fig7_speed.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)


def test_teleop_keyboard_in_a_terminal(tmp_path):
    """The interactive path: a pseudo-terminal sends an up arrow, then q (stop to rest, write)."""
    import os
    import pty
    import select
    import time
    from pathlib import Path

    exe = Path(sys.executable).parent / "gaitshift"
    out = tmp_path / "kb.npz"
    pid, fd = pty.fork()
    if pid == 0:  # pragma: no cover - child
        os.execv(str(exe), [str(exe), "teleop", "--out", str(out)])
    text = b""

    def pump(until: bytes | None, seconds: float) -> None:
        """Read the child's output until ``until`` appears (or it exits, or time runs out)."""
        nonlocal text
        end = time.time() + seconds
        while time.time() < end and (until is None or until not in text):
            if select.select([fd], [], [], 0.05)[0]:
                try:
                    text += os.read(fd, 4096)
                except OSError:
                    return

    pump(b"steps=", 30.0)  # the live status line is running
    os.write(fd, b"\x1b[A")  # up arrow
    pump(b"command=(+0.30", 30.0)
    pump(None, 0.3)
    os.write(fd, b"q")
    pump(b"wrote", 60.0)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, text.decode(errors="ignore")[-500:]
    tr = gaitshift.Trajectory.load(out)
    assert np.max(tr.command_vel[:, 0]) == pytest.approx(0.3)
    assert b"steps=" in text and np.all(np.abs(tr.com_vel[-1]) < 1e-9)
