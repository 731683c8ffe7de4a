"""``gaitshift export``: whole-body reference motions (Unitree CSV, mjlab npz) from a plan or a simulation log."""

from __future__ import annotations

from pathlib import Path

import typer

from gaitshift.cli.app import app, out_file


@app.command("export")
def export_cmd(
    source: Path = typer.Argument(
        ..., help="A plan .npz (gaitshift plan) or a simulation log .npz (gaitshift simulate)."
    ),
    fmt: str = typer.Option(..., "--format", help="unitree-csv (.csv, 30 fps) or mjlab-npz (.npz, 50 fps)."),
    out: Path = typer.Option(..., "--out", help="Motion file (.csv for unitree-csv, .npz for mjlab-npz)."),
    fps: int | None = typer.Option(None, "--fps", help="Frame rate, Hz (default: the format's)."),
    robot: str | None = typer.Option(None, "--robot", help="Robot (name or YAML; default: the one the file names)."),
) -> None:
    """Export the whole-body motion of a plan (through the IK) or of a simulation log, resampled to
    the format's frame rate (docs/export.md: formats, joint and body order)."""
    from gaitshift.cli.app import flags_named
    from gaitshift.export.motion import check_request, export_motion

    flags = {"format": "--format", "fps": "--fps", "out": "--out", "input": "SOURCE", "robot": "--robot"}
    with flags_named(flags):
        spec, _ = check_request(fmt, fps, out)
        out_file(out, "--out", (spec.suffix,))
        report = export_motion(source, out, fmt, fps, robot)
    typer.echo(
        f"exported {report['source']} motion of {report['robot']}: {report['frames']} frames at "
        f"{report['fps']} Hz ({report['duration_s']:.2f} s) as {report['format']}"
    )
    typer.echo(f"wrote {out}")
