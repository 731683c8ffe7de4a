"""What the DDS tests share: the tiny walking scenario, the brain's short safety phases, and
``gaitshift`` commands run as real processes."""

from __future__ import annotations

import os
import subprocess
import sys

#: a 0.5 s walk at 0.2 m/s (the brain's and the replanner's test scenario)
TINY = """planner: locomotion
name: tiny-walk
robot: g1
gait: walk
timing: {start: 0.3, stop: 0.3}
commands:
  - {t: 0.0, vx: 0.2}
stop_at: 0.5
"""


def live_scenario(name: str) -> str:
    """A standing start steered by live commands (zero speed until one comes), for 30 s of plan time."""
    return f"""planner: locomotion
name: {name}
robot: g1
gait: walk
timing: {{start: 0.3, stop: 0.3}}
commands:
  - {{t: 0.0, vx: 0.0}}
stop_at: 30.0
"""


#: short safety phases for a test (a 0.2 s hold); the stale limit leaves room for a loaded machine in lockstep
BRAIN_FLAGS = ["--lockstep", "--damping-time", "0.02", "--standup-time", "0.3", "--stale-limit", "0.3", "--hold", "0.2"]


def gaitshift(tmp_path, name, *argv):
    """``gaitshift argv`` as a process; stdout to ``name``.out, stderr to ``name``.err. Returns the
    process and the two open files."""
    code = "from gaitshift.cli import main; main()"
    out, err = open(tmp_path / f"{name}.out", "w"), open(tmp_path / f"{name}.err", "w")  # noqa: SIM115
    env = {**os.environ, "MUJOCO_GL": "egl"}
    return subprocess.Popen([sys.executable, "-c", code, *argv], stdout=out, stderr=err, env=env), (out, err)


def finish(proc, files, timeout=120.0):
    """Wait up to ``timeout`` s for ``proc`` (killed if it is still running), then close ``files``."""
    try:
        proc.wait(timeout=timeout)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for f in files:
            f.close()


class FakeController:
    """A controller that records the live commands it is given (``command``, ``stop``) in ``calls``."""

    def __init__(self):
        self.calls = []

    def command(self, vx, vy, yaw_rate):
        self.calls.append(("command", vx, vy, yaw_rate))

    def stop(self):
        self.calls.append(("stop",))
