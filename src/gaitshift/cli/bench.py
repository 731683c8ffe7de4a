"""``gaitshift bench``: measure every performance claim."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from .. import bench as _bench
from ..io import atomic_path
from .app import app


@app.command("bench")
def bench_cmd(
    quick: bool = typer.Option(False, "--quick", help="Smoke run: every benchmark, few repeats."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the numbers to this JSON file."),
    only: Optional[list[str]] = typer.Option(None, "--only", help="Run benchmarks whose name contains this."),
) -> None:
    """Print median and p99 of every benchmark with its baseline ratio and the paper's figure."""
    typer.echo(_bench.machine_line())
    results = _bench.run(quick=quick, only=only, progress=lambda n: typer.echo(f"  running {n} ...", err=True))
    typer.echo(_bench.format_table(results))
    if json_out is not None:
        with atomic_path(json_out) as tmp:
            tmp.write_text(_bench.to_json(results, quick))
        typer.echo(f"wrote {json_out}")
