"""``export_motion``: a plan or a simulation log -> frames at the format's rate -> a motion file.

The flags are checked before any work (format, rate, output suffix), the source is read (the plan
through the whole-body IK), resampled (:mod:`gaitshift.export.resample`) and written atomically by the
format's writer (:data:`gaitshift.export.formats.FORMATS`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gaitshift.common.atomic import atomic_path, check_suffix
from gaitshift.errors import InputError, check_choice
from gaitshift.export.formats import FORMATS, ExportFormat, Frames
from gaitshift.export.resample import resample
from gaitshift.export.source import load_source

#: highest frame rate, Hz
MAX_FPS = 1000


def check_request(fmt: str, fps: int | None, out: str | Path) -> tuple[ExportFormat, int]:
    """The format and frame rate of a request, checked.

    Raises:
        InputError: unknown format (``format``), a rate outside [1, MAX_FPS] (``fps``), or an output
            file without the format's suffix (``out``).
    """
    check_choice("format", fmt, FORMATS)
    spec = FORMATS[fmt]
    rate = spec.default_fps if fps is None else fps
    if isinstance(rate, bool) or not isinstance(rate, int) or not 1 <= rate <= MAX_FPS:
        raise InputError("fps", fps, f"an integer frame rate in [1, {MAX_FPS}] Hz")
    if spec.fixed_fps is not None and rate != spec.fixed_fps:
        allowed = f"{spec.fixed_fps} Hz for {fmt} (the consumer plays one frame per {spec.fixed_fps} Hz step)"
        raise InputError("fps", fps, allowed)
    check_suffix(out, "out", (spec.suffix,), f" for {fmt}")
    return spec, rate


def export_motion(
    source: str | Path, out: str | Path, fmt: str, fps: int | None = None, robot: str | None = None
) -> dict[str, Any]:
    """Write the motion of ``source`` (plan or simulation log .npz) as ``fmt`` to ``out``.

    Returns:
        a report: format, fps, frames, duration_s, robot, source kind and the source's metadata.

    Raises:
        InputError: bad format, rate, output name or input file (nothing is written).
        InfeasibleError: the robot cannot follow the plan.
    """
    spec, rate = check_request(fmt, fps, out)
    motion = load_source(source, robot, rate)
    t, qpos, qvel = resample(motion.t, motion.qpos, rate)
    frames = Frames(rate, qpos, qvel, motion.robot.model())
    with atomic_path(out) as tmp:
        spec.write(frames, tmp)
    return {
        "format": spec.name,
        "fps": rate,
        "frames": len(t),
        "duration_s": float(t[-1] - t[0]),
        "robot": motion.robot.name,
        "source": motion.kind,
        **{k: v for k, v in motion.meta.items() if k != "robot"},
    }
