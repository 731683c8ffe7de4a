"""Every shipped robot on its estimator (issue 26, docs/robots.md "On the estimate"): the G1's walk,
run, walk-run-walk and live-command tour scaled to each robot (``gaitshift scale``; the G1 runs the
built-ins), simulated closed loop on the estimated state with ``typical`` noise, with sole force
sensors and without them (contact from the motors' torques), over seeds. The runs are a campaign
(Dask, :mod:`gaitshift.campaign`), so an interrupted sweep resumes where it stopped; the table gives
per robot, scenario and contact sensing the falls over the seeds and the worst contact accuracy,
base velocity RMSE (m/s) and tilt RMSE (rad) over them.

    PYTHONPATH=src .venv/bin/python benchmarks/robots_estimate.py OUT [--robots g1 t1 ...]
        [--scenarios walk run ...] [--seeds 0 1 2] [--contact force torque] [--workers 2]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import yaml

from gaitshift.campaign.run import run_campaign
from gaitshift.campaign.spec import load_spec
from gaitshift.campaign.store import Store
from gaitshift.scenario import load_scenario
from gaitshift.wholebody.scaling import scaled_yaml, scenario_yaml

ROBOTS = ("g1", "t1", "h1", "berkeley", "op3")
SCENARIOS = ("walk", "run", "walk-run-walk", "tour")


def scenarios(folder: Path, robots: list[str], which: list[str]) -> list[str]:
    """The scaled scenario files (written once), named ``<robot>-<scenario>.yaml``."""
    folder.mkdir(parents=True, exist_ok=True)
    names = []
    for robot in robots:
        for name in which:
            path = folder / f"{robot}-{name}.yaml"
            if not path.exists():
                g1 = f"g1-{name}"  # the G1 runs the built-in as it is
                text = (
                    scenario_yaml(load_scenario(g1), g1, folder) if robot == "g1" else scaled_yaml(g1, robot, folder)[0]
                )
                path.write_text(text)
            names.append(f"scenarios/{path.name}")
    return names


def table(rows: list[dict]) -> str:
    """Markdown: one line per robot, scenario and contact sensing (module docstring)."""
    groups: dict[tuple[str, str, str], list[dict]] = {}
    for r in rows:
        robot, name = Path(r["scenario"]).stem.split("-", 1)
        groups.setdefault((robot, name, r["contact"]), []).append(r)
    lines = [
        "| robot | scenario | contact | seeds | falls | contact accuracy (min) | base vel RMSE m/s (max) "
        "| tilt RMSE rad (max) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    order = {n: i for i, n in enumerate(ROBOTS)} | {n: i for i, n in enumerate(SCENARIOS)}
    for (robot, name, contact), rs in sorted(
        groups.items(), key=lambda kv: (order[kv[0][0]], order[kv[0][1]], kv[0][2])
    ):
        falls = [f"{r['seed']}@{r['t_fall']:.2f}s" for r in rs if r["fell"]]
        worst = {
            "contact_accuracy": min(r["contact_accuracy"] or 0.0 for r in rs),
            "base_vel_rmse": max(r["base_vel_rmse"] or 0.0 for r in rs),
            "tilt_rmse": max(r["tilt_rmse"] or 0.0 for r in rs),
        }
        lines.append(
            f"| {robot} | {name} | {contact} | {len(rs)} | {len(falls)} {' '.join(falls)} | "
            f"{100 * worst['contact_accuracy']:.1f} % | {worst['base_vel_rmse']:.4f} | {worst['tilt_rmse']:.4f} |"
        )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=ROBOTS)
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS), choices=SCENARIOS)
    ap.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    ap.add_argument("--contact", nargs="+", default=["force", "torque"], choices=["force", "torque"])
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    names = scenarios(args.out / "scenarios", args.robots, args.scenarios)
    spec_data = {
        "name": "robots-estimate",
        "task": "simulate",
        "axes": {"scenario": names, "contact": args.contact, "seed": args.seeds, "state": ["estimated"]},
    }
    spec_text = yaml.safe_dump(spec_data, sort_keys=False)
    (args.out / "spec.yaml").write_text(spec_text)
    spec = load_spec(args.out / "spec.yaml")
    summary = run_campaign(spec, spec_text, args.out / "runs", workers=args.workers)
    print(f"{summary.cases} cases, {summary.ran} run now in {summary.wall_time:.0f} s, {summary.lost} lost")
    print(table(Store(args.out / "runs").table().to_pylist()))


if __name__ == "__main__":
    main()
