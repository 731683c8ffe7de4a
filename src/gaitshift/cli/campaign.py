"""``gaitshift campaign``: run a campaign spec on Dask, or report on a campaign's dataset.

* ``gaitshift campaign SPEC.yaml --out DIR [--scheduler ADDRESS] [--workers N]``: run the cases of the
  spec that DIR does not hold yet (:mod:`gaitshift.campaign.run`); exit 0 when the dataset is complete,
  1 when cases were lost (run the command again to finish them), 2 on a bad spec or scheduler.
* ``gaitshift campaign report DIR``: survival heatmaps, fall-time histogram, per-robot table
  (:mod:`gaitshift.campaign.report`).
"""

from __future__ import annotations

from pathlib import Path

import typer

from gaitshift.cli.app import app, out_folder
from gaitshift.errors import InputError


@app.command("campaign")
def campaign_cmd(
    target: str = typer.Argument(..., help="Campaign spec YAML, or the word `report`."),
    folder: Path | None = typer.Argument(None, help="With `report`: the campaign folder."),
    out: Path | None = typer.Option(None, "--out", help="Dataset folder (created; resumed when it exists)."),
    scheduler: str | None = typer.Option(None, "--scheduler", help="Address of a running Dask scheduler."),
    workers: int | None = typer.Option(None, "--workers", help="Local worker processes (default: every core)."),
) -> None:
    """Run the cases of a campaign spec on Dask (resumable), or `campaign report DIR`."""
    if target == "report":
        _report(folder)
        return
    if folder is not None:
        raise InputError("FOLDER", str(folder), "no second argument when running a spec (use --out DIR)")
    if out is None:
        raise InputError("--out", None, "a dataset folder")
    from gaitshift.campaign.run import run_campaign
    from gaitshift.campaign.spec import load_spec

    spec = load_spec(target)
    out_folder(out, "--out")
    summary = run_campaign(spec, Path(target).read_text(), out, scheduler=scheduler, workers=workers)
    typer.echo(
        f"{summary.cases} cases: {summary.skipped} already done, {summary.ran} ran, {summary.lost} lost, "
        f"{summary.wall_time:.1f} s; dataset {'complete' if summary.complete else 'INCOMPLETE (run again)'}: {out}"
    )
    if not summary.complete:
        raise typer.Exit(1)


def _report(folder: Path | None) -> None:
    from gaitshift.campaign.report import write_report

    if folder is None or not (folder / "parts").is_dir():
        raise InputError("DIR", str(folder), "a campaign folder (with parts/)")
    for path in write_report(folder):
        typer.echo(f"wrote {path}")
