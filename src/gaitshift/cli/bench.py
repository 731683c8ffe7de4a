"""``gaitshift bench``: measure every performance claim."""

from __future__ import annotations

from pathlib import Path

import typer

from gaitshift import bench as _bench
from gaitshift.cli.app import app, out_file
from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError


@app.command("bench")
def bench_cmd(
    quick: bool = typer.Option(False, "--quick", help="Smoke run: every benchmark, few repeats."),
    json_out: Path | None = typer.Option(None, "--json", help="Write the numbers to this JSON file."),
    only: list[str] | None = typer.Option(None, "--only", help="Run benchmarks whose name contains this."),
) -> None:
    """Print median and p99 of every benchmark with its baseline ratio and the paper's figure."""
    known = _bench.names()
    for part in only or ():
        if not any(part in name for name in known):
            raise InputError("--only", part, "part of a benchmark name: " + ", ".join(known))
    if json_out is not None:
        out_file(json_out, "--json", (".json",))
    typer.echo(_bench.machine_line())
    results = _bench.run(quick=quick, only=only, progress=lambda n: typer.echo(f"  running {n} ...", err=True))
    typer.echo(_bench.format_table(results))
    if json_out is not None:
        with atomic_path(json_out, "--json") as tmp:
            tmp.write_text(_bench.to_json(results, quick))
        typer.echo(f"wrote {json_out}")
