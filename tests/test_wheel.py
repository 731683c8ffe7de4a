"""The wheel: ``python -m build`` makes a wheel that holds every built-in scenario and robot config
(compared with the files under src/), and that wheel, installed into a fresh venv outside the repo,
runs the demo's planning step and one short ``simulate`` from a folder outside the repo, importing
gaitshift from the venv (not from src/ nor the editable install).

The fresh venv gets the wheel with ``pip install --no-deps``; the dependencies (numpy, mujoco, ...)
come from the test's own environment through a ``.pth`` line that appends its site-packages after
the venv's own (the wheel's gaitshift is found first; the editable install's own ``.pth`` hooks are
not processed from an appended path). The build uses ``--no-isolation`` (setuptools and wheel of
the test extra), so no network is needed.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_DATA = ("scenario/builtin", "robots/configs")

#: two walking steps of the G1 (g1-walk with fewer steps): a short closed-loop run
SHORT = """planner: tvlip
robot: g1
description: "Unitree G1: 2 walking steps (wheel test)"
height: 0.62
timing: {single_support: 0.40, double_support: 0.15, flight: 0.12, start: 0.5, stop: 0.5}
foot: {size: [0.17, 0.05], zmp_margin: 0.01}
gait:
  - {gait: walk, steps: 2}
profile: {max_stride: 0.15, accelerate_steps: 1, decelerate_steps: 1, step_width: 0.237}
swing_height: 0.06
"""


def _run(argv, cwd, env, timeout=300):
    proc = subprocess.run(
        [str(a) for a in argv], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout, check=False
    )
    assert proc.returncode == 0, (argv, proc.stdout[-2000:], proc.stderr[-2000:])
    return proc.stdout


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel built from a copy of the project (the worktree stays clean)."""
    base = tmp_path_factory.mktemp("wheel")
    copy = base / "project"
    copy.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, copy / name)
    shutil.copytree(ROOT / "src", copy / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    _run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", base / "dist", copy], base, env)
    (found,) = (base / "dist").glob("gaitshift-*.whl")
    return found


def test_the_wheel_holds_every_builtin_scenario_and_robot_config(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for folder in PACKAGE_DATA:
        files = sorted((ROOT / "src" / "gaitshift" / folder).glob("*.yaml"))
        assert len(files) >= 5
        assert {f"gaitshift/{folder}/{f.name}" for f in files} <= names
    assert "gaitshift/py.typed" in names
    assert not any(n.startswith(("tests/", "docs/")) for n in names)


def test_the_wheel_plans_and_simulates_from_a_fresh_venv_outside_the_repo(wheel, tmp_path):
    venv, work = tmp_path / "venv", tmp_path / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MUJOCO_GL"] = "egl"
    _run([sys.executable, "-m", "venv", venv], work, env)
    py = venv / "bin" / "python"
    _run([py, "-m", "pip", "install", "--no-deps", "--no-index", "--quiet", wheel], work, env)
    own = Path(_run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], work, env).strip())
    (own / "zz_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    where = _run([py, "-c", "import gaitshift; print(gaitshift.__file__)"], work, env).strip()
    assert Path(where).is_relative_to(venv), where
    gaitshift = venv / "bin" / "gaitshift"
    out = _run([gaitshift, "plan", "paper001-table2-walk-run-walk", "--out", "plan.npz"], work, env)
    assert "wrote plan.npz" in out and (work / "plan.npz").is_file()
    (work / "short.yaml").write_text(SHORT)
    out = _run([gaitshift, "simulate", "short.yaml", "--out", "sim.npz"], work, env)
    assert "fell                           no" in out and (work / "sim.npz").is_file()
    listed = _run([gaitshift, "scenarios"], work, env)
    assert all(p.stem in listed for p in (ROOT / "src/gaitshift/scenario/builtin").glob("*.yaml"))
