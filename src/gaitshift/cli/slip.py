"""``gaitshift compare-slip``: Fig. 9 of paper 001, the TV-LIPM against a periodic 3D-SLIP."""

from __future__ import annotations

import json
import math
from pathlib import Path

import typer

from gaitshift.cli.app import app, flags_named, out_folder
from gaitshift.errors import InputError


@app.command("compare-slip")
def compare_slip_cmd(
    out: Path = typer.Option(..., "--out", help="Output folder for fig9_slip.png and slip_compare.json."),
    speed: float = typer.Option(3.5, "--speed", help="Forward CoM speed at top of flight, m/s."),
    flight: float = typer.Option(0.2, "--flight", help="SLIP flight time per step, s."),
    step_width: float = typer.Option(0.1, "--step-width", help="Foot distance from the running mid-line, m."),
    repeats: int = typer.Option(3, "--repeats", help="Timing repetitions of the SLIP optimisation (median)."),
) -> None:
    """Optimise a periodic 3D-SLIP half cycle, run the TV-LIPM on its timings, plot and time both."""
    from gaitshift.analysis.slip_compare import compare
    from gaitshift.common.atomic import atomic_path
    from gaitshift.plots import slip as slip_plot

    out_folder(out, "--out")
    if not 1 <= repeats <= 100:
        raise InputError("--repeats", repeats, "an integer in [1, 100]")
    with flags_named({"speed": "--speed", "flight": "--flight", "step_width": "--step-width"}):
        cmp = compare(speed, flight=flight, step_width=step_width, slip_repeats=repeats)
    data = cmp.as_dict()
    data["samples"] = {"t": cmp.t.tolist(), "slip_pos": cmp.slip_pos.tolist(), "tvlip_pos": cmp.tvlip_pos.tolist()}
    text = json.dumps(data, indent=2, allow_nan=False)
    out.mkdir(parents=True, exist_ok=True)
    fig_path = slip_plot.save(cmp, out / "fig9_slip.png")
    json_path = out / "slip_compare.json"
    with atomic_path(json_path) as tmp:
        tmp.write_text(text)
    s, tm = data["slip"], data["timing"]
    dev = data["max_deviation_m"]
    typer.echo(
        f"SLIP  k={s['stiffness_N_per_m']:.0f} N/m m={s['mass_kg']:.0f} kg l0={s['leg_length_m']} m: "
        f"tau_SS={s['stance_s']:.4f} s tau_F={s['flight_s']:.4f} s h={s['touchdown_height_m']:.4f} m "
        f"periodicity error {s['periodicity_error']:.1e}"
    )
    typer.echo(f"TV-LIPM T_r={cmp.T_r:.5f} s v_r={cmp.v_r:.4f} m/s")
    typer.echo(
        "max deviation: "
        + ", ".join(f"{a} {v * 1e3:.2f} mm" for a, v in dev.items())
        + f" (x displacement {cmp.displacement[0]:.3f} m)"
    )
    ratio = tm["ratio"]
    typer.echo(
        f"time: SLIP {tm['slip_optimise_and_integrate_s'] * 1e3:.1f} ms, T_r {tm['tvlip_T_r_solve_s'] * 1e3:.3f} ms,"
        f" ratio {ratio:.0f}x"
        + ("" if math.isfinite(ratio) else " (n/a)")
        + f"  [paper: 24.9 s / 8 ms = {tm['paper_ratio']:.0f}x]"
    )
    typer.echo(f"wrote {fig_path} and {json_path}")
