"""Motion files of the export tests, made once per session through the CLI: G1 and T1 plans (the
T1's is g1-walk scaled to the T1), a G1 simulation log, the Rerun recordings of the G1 plan and run,
and their exports in both formats."""

from __future__ import annotations

from pathlib import Path

import pytest

from gaitshift.cli import main


def run(argv: list[str]) -> int:
    """``gaitshift argv`` in-process; its exit code."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    return int(exc.value.code or 0)


@pytest.fixture(scope="session")
def motions(tmp_path_factory) -> dict[str, Path]:
    """Source files: ``g1-plan``, ``t1-plan`` (plans, .npz), ``g1-sim`` (simulation log), and the
    recordings ``g1-plan-rrd`` and ``g1-sim-rrd`` (.rrd) made by the same commands."""
    d = tmp_path_factory.mktemp("motions")
    assert run(["scale", "g1-walk", "--robot", "t1", "--out", d / "t1-walk.yaml"]) == 0
    files = {"g1-plan": d / "g1-plan.npz", "t1-plan": d / "t1-plan.npz", "g1-sim": d / "g1-sim.npz"}
    files |= {"g1-plan-rrd": d / "g1-plan.rrd", "g1-sim-rrd": d / "g1-sim.rrd"}
    assert run(["plan", "g1-walk", "--out", files["g1-plan"], "--rerun", files["g1-plan-rrd"]]) == 0
    assert run(["plan", d / "t1-walk.yaml", "--out", files["t1-plan"]]) == 0
    assert run(["simulate", "g1-walk", "--out", files["g1-sim"], "--rerun", files["g1-sim-rrd"]]) == 0
    return files


@pytest.fixture(scope="session")
def exported(motions, tmp_path_factory):
    """``exported(source, format, fps=None) -> Path``: the export of a source file, made once."""
    d = tmp_path_factory.mktemp("exported")
    cache: dict[tuple[str, str, int | None], Path] = {}

    def get(source: str, fmt: str, fps: int | None = None) -> Path:
        key = (source, fmt, fps)
        if key not in cache:
            out = d / f"{source}-{fmt}-{fps}.{'csv' if fmt == 'unitree-csv' else 'npz'}"
            argv = ["export", motions[source], "--format", fmt, "--out", out]
            assert run([*argv, "--fps", fps] if fps else argv) == 0
            cache[key] = out
        return cache[key]

    return get
