"""The core commands (stiffness, scenarios, plan, plot, check): results, and one-line errors with exit
code 2 and no output file, including the damaged trajectory files of issue 10."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

GAITSHIFT = str(Path(sys.executable).with_name("gaitshift"))


def _stiffness(height: str, *extra: str) -> subprocess.CompletedProcess[str]:
    """The console script ``gaitshift stiffness`` with the other three durations of the paper's example."""
    args = ["--height", height, "--single-support", "0.4", "--double-support", "0.15", "--flight", "0.15", *extra]
    return subprocess.run([GAITSHIFT, "stiffness", *args], capture_output=True, text=True, check=False)


def test_stiffness_json_has_exactly_the_five_keys():
    res = _stiffness("0.95", "--json")
    assert res.returncode == 0, res.stderr
    d = json.loads(res.stdout)
    assert set(d) == {"T_w", "T_r", "v_r", "T_t0", "T_t1"}
    assert d["T_w"] == pytest.approx((0.95 / 9.81) ** 0.5)


def test_bad_height_is_one_line_exit_2_from_the_console_script():
    res = _stiffness("-0.5")
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "--height = -0.5" in res.stderr and "[0.05, 5]" in res.stderr
    assert "Traceback" not in res.stderr


YAML_CASES = {
    "zero_duration": ("timing: {single_support: 0.0}\n", "timing.single_support"),
    "nan_duration": ("timing: {flight: .nan}\n", "timing.flight"),
    "negative_height": ("height: -1\n", "height"),
    "unknown_key": ("heigth: 0.9\n", "heigth"),
    "unknown_nested_key": ("timing: {singel_support: 0.4}\n", "timing.singel_support"),
    "stride_beyond_reach": ("profile: {max_stride: 1.4}\nlimits: {max_stride: 1.0}\n", "profile.max_stride"),
    "unsolvable_stiffness": ("gait: [{gait: run, steps: 4}]\ntiming: {double_support: 0.05}\n", "double_support"),
    "bad_gait": ("gait: [{gait: hop, steps: 4}]\n", "gait.0.gait"),
    "zmp_infeasible": (
        "gait: [{gait: walk, steps: 1}]\ntiming: {start: 0.05, stop: 0.05}\n"
        "profile: {max_stride: 0.9, accelerate_steps: 0, decelerate_steps: 0}\n",
        "footsteps",
    ),
}


@pytest.mark.parametrize("case", sorted(YAML_CASES))
def test_bad_scenario_exits_2_with_one_line_and_no_file(case, tmp_path, cli):
    text, field = YAML_CASES[case]
    yml = tmp_path / "bad.yaml"
    yml.write_text(text)
    out = tmp_path / "plan.npz"
    code, _, err = cli(["plan", str(yml), "--out", str(out)])
    assert code == 2
    assert err.count("\n") == 1 and field in err, err
    assert not out.exists() and [p.name for p in tmp_path.iterdir()] == ["bad.yaml"]


def test_unknown_scenario_name_lists_the_built_ins(tmp_path, cli):
    code, _, err = cli(["plan", "no-such-scenario", "--out", str(tmp_path / "x.npz")])
    assert code == 2 and "paper001-table2-walk-run-walk" in err


def test_bad_output_suffix_is_rejected_before_planning(tmp_path, cli):
    code, _, err = cli(["plan", "paper001-table2-running", "--out", str(tmp_path / "x.txt")])
    assert code == 2 and "--out" in err and ".npz" in err
    assert list(tmp_path.iterdir()) == []


def test_plan_and_plot_write_the_file_and_figures(tmp_path, cli):
    yml = tmp_path / "short.yaml"
    yml.write_text("gait: [{gait: walk, steps: 2}, {gait: run, steps: 3}, {gait: walk, steps: 2}]\ndt: 0.005\n")
    out = tmp_path / "plan.json"
    code, stdout, _ = cli(["plan", str(yml), "--out", str(out)])
    assert code == 0 and out.exists() and "wrote" in stdout
    code, stdout, _ = cli(["plot", str(out), "--out", str(tmp_path / "figs")])
    assert code == 0
    pngs = sorted(p.name for p in (tmp_path / "figs").glob("*.png"))
    assert {
        "top_view.png",
        "com_height_force.png",
        "fig5_running_half_cycle.png",
        "fig6_transition.png",
        "fig7_Tr_surface.png",
        "capture_point.png",
    } <= set(pngs)
    assert all((tmp_path / "figs" / p).stat().st_size > 10_000 for p in pngs)


def test_scenarios_lists_the_paper_built_ins(cli):
    code, stdout, _ = cli(["scenarios"])
    assert code == 0
    for name in ("paper001-table1-running", "paper001-table2-running", "paper001-table2-walk-run-walk"):
        assert name in stdout


def test_bench_quick_writes_median_p99_and_baseline_ratios(tmp_path, cli):
    out = tmp_path / "bench.json"
    code, stdout, _ = cli(["bench", "--quick", "--only", "stiffness", "--only", "tvlip", "--json", str(out)])
    assert code == 0 and "median" in stdout and "p99" in stdout
    data = json.loads(out.read_text())
    assert data["quick"] is True and data["machine"]["cores"] >= 1
    ops = {r["operation"]: r for r in data["results"]}
    tr = next(r for name, r in ops.items() if name.startswith("T_r solve"))
    assert tr["median_s"] > 0 and tr["p99_s"] >= tr["median_s"] and tr["ratio"] > 0
    sizes = [r["size"] for r in data["results"] if r["operation"].startswith("TV-LIPM boundary")]
    assert any(s.startswith("2000 steps") for s in sizes)


def test_check_passes_a_plan_and_fails_a_corrupted_one(tmp_path, cli):
    import gaitshift
    from gaitshift.trajectory.contract import Trajectory

    sc = gaitshift.load_scenario(
        {"gait": [{"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2}, {"gait": "walk", "steps": 2}]}
    )
    traj = gaitshift.plan(sc)
    good = traj.save(tmp_path / "good.npz")
    code, stdout, _ = cli(["check", str(good)])
    assert code == 0 and "FAIL" not in stdout
    arrays = traj.arrays()
    arrays["com_pos"] = arrays["com_pos"].copy()
    arrays["com_pos"][len(traj) // 2 :, 0] += 0.01  # a 1 cm jump in the middle
    bad = Trajectory.from_arrays(arrays, traj.meta).save(tmp_path / "bad.npz")
    code, stdout, _ = cli(["check", str(bad), "--json"])
    rep = json.loads(stdout)
    assert code == 1 and not rep["pass"]["position_jump"] and not rep["pass"]["zmp_identity"]


def test_full_quick_bench_runs_every_topic(tmp_path):
    """`gaitshift bench --quick` (the CI smoke run) runs every registered benchmark to completion."""
    out = tmp_path / "quick.json"
    res = subprocess.run(
        [GAITSHIFT, "bench", "--quick", "--json", str(out)], capture_output=True, text=True, check=False
    )
    assert res.returncode == 0, res.stderr[-2000:]
    ops = " ".join(f"{r['operation']} {r['baseline']}" for r in json.loads(out.read_text())["results"])
    for needle in (
        "T_r solve",
        "TV-LIPM boundary solve",
        "eq. (13) solve",
        "foothold",
        "start NLP",
        "one online step",
        "whole-body IK",
        "G1 control tick",
        "G1 estimator tick",
        "SO(3) exp",
        "SLIP optimise",
        "IPOPT",
    ):
        assert needle in ops, needle


def test_check_on_damaged_files_is_one_line_exit_2(tmp_path, cli):
    """The breaks of issue 10: a malformed .npz raised ValueError, a .csv without columns KeyError."""
    import gaitshift

    traj = gaitshift.plan(gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 1}], "dt": 0.02}))
    npz = traj.save(tmp_path / "p.npz")
    npz.write_bytes(npz.read_bytes()[:500])
    lines = traj.save(tmp_path / "p.csv").read_text().splitlines()
    keep = [i for i, c in enumerate(lines[4].split(",")) if not c.startswith("zmp")]
    csv = tmp_path / "p.csv"
    csv.write_text("\n".join(lines[:4] + [",".join(r.split(",")[i] for i in keep) for r in lines[4:]]) + "\n")
    for path, key in ((npz, "file"), (csv, "column line 5")):
        code, out, err = cli(["check", str(path), "--json"])
        assert code == 2 and out == "" and err.count("\n") == 1
        assert err.startswith(f"gaitshift: error: {path}: {key} = ")


def test_check_json_writes_null_where_no_sample_is_in_support(tmp_path, cli):
    import numpy as np

    import gaitshift
    from gaitshift.trajectory.contract import FLIGHT, Trajectory

    traj = gaitshift.plan(gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 1}], "dt": 0.02}))
    arrays = traj.arrays()
    n = len(traj)
    arrays.update(phase=np.full(n, FLIGHT), contact=np.zeros((n, 2), bool), zmp=np.full((n, 3), np.nan))
    arrays.update(stiffness=np.full(n, np.nan))
    path = Trajectory.from_arrays(arrays, traj.meta).save(tmp_path / "x.json")
    code, out, _ = cli(["check", str(path), "--json"])
    rep = json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in JSON"))
    assert rep["report"]["min_vertical_force"] is None and rep["pass"]["min_vertical_force"] is True
    assert code == 1 and rep["pass"]["flight_acc"] is False  # the walk's CoM does not fall freely


def test_plot_out_must_be_a_folder(tmp_path, cli):
    src = tmp_path / "p.npz"
    src.write_bytes(b"")
    code, _, err = cli(["plot", str(src), "--out", str(src)])
    assert code == 2 and "--out" in err and "this is a file" in err


@pytest.mark.parametrize("flag", ["--height", "--single-support", "--double-support", "--flight", "--gravity"])
@pytest.mark.parametrize("value", ["nan", "-1", "1e-300", "1e300"])
def test_stiffness_flags_out_of_their_physical_range_exit_2(flag, value, cli):
    argv = {"--height": "0.95", "--single-support": "0.4", "--double-support": "0.15", "--flight": "0.15"}
    argv[flag] = value
    code, out, err = cli(["stiffness", *[x for kv in argv.items() for x in kv]])
    assert code == 2 and out == "" and err.startswith(f"gaitshift: error: {flag} = ")


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda m: m.pop("height"), "meta.height"),
        (lambda m: m["scenario"]["timing"].update(flight=-1.0), "meta.scenario.timing.flight"),
        (lambda m: m.pop("scenario"), "meta.scenario"),
        (lambda m: m.update(planner="slip"), "meta.planner"),
    ],
)
def test_plot_checks_the_meta_its_figures_need_before_drawing(tmp_path, cli, edit, field):
    import gaitshift
    from gaitshift.trajectory.contract import Trajectory

    traj = gaitshift.plan(gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 1}], "dt": 0.02}))
    meta = json.loads(json.dumps(traj.meta))
    edit(meta)
    src = Trajectory.from_arrays(traj.arrays(), meta).save(tmp_path / "p.npz")
    code, _, err = cli(["plot", str(src), "--out", str(tmp_path / "figs")])
    assert code == 2 and err.startswith(f"gaitshift: error: {src}: {field}") and err.count("\n") == 1
    assert not (tmp_path / "figs").exists()
