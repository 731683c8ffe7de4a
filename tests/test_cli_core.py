"""The CLI: stiffness JSON, plan/plot outputs, and one-line errors with exit code 2 and no output file."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from gaitshift.cli import main

GAITSHIFT = str(Path(sys.executable).with_name("gaitshift"))


def run(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    out = capsys.readouterr()
    return exc.value.code, out.out, out.err


def test_stiffness_json_has_exactly_the_five_keys():
    res = subprocess.run([GAITSHIFT, "stiffness", "--height", "0.95", "--single-support", "0.4",
                          "--double-support", "0.15", "--flight", "0.15", "--json"],
                         capture_output=True, text=True, check=True)
    d = json.loads(res.stdout)
    assert set(d) == {"T_w", "T_r", "v_r", "T_t0", "T_t1"}
    assert d["T_w"] == pytest.approx((0.95 / 9.81) ** 0.5)


def test_bad_height_is_one_line_exit_2_from_the_console_script():
    res = subprocess.run([GAITSHIFT, "stiffness", "--height", "-0.5", "--single-support", "0.4",
                          "--double-support", "0.15", "--flight", "0.15"], capture_output=True, text=True)
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "height" in res.stderr and "-0.5" in res.stderr and "> 0" in res.stderr
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
    "zmp_infeasible": ("gait: [{gait: walk, steps: 1}]\ntiming: {start: 0.05, stop: 0.05}\n"
                       "profile: {max_stride: 0.9, accelerate_steps: 0, decelerate_steps: 0}\n", "footsteps"),
}


@pytest.mark.parametrize("case", sorted(YAML_CASES))
def test_bad_scenario_exits_2_with_one_line_and_no_file(case, tmp_path, capsys):
    text, field = YAML_CASES[case]
    yml = tmp_path / "bad.yaml"
    yml.write_text(text)
    out = tmp_path / "plan.npz"
    code, _, err = run(["plan", str(yml), "--out", str(out)], capsys)
    assert code == 2
    assert err.count("\n") == 1 and field in err, err
    assert not out.exists() and [p.name for p in tmp_path.iterdir()] == ["bad.yaml"]


def test_unknown_scenario_name_lists_the_built_ins(tmp_path, capsys):
    code, _, err = run(["plan", "no-such-scenario", "--out", str(tmp_path / "x.npz")], capsys)
    assert code == 2 and "paper001-table2-walk-run-walk" in err


def test_bad_output_suffix_is_rejected_before_planning(tmp_path, capsys):
    code, _, err = run(["plan", "paper001-table2-running", "--out", str(tmp_path / "x.txt")], capsys)
    assert code == 2 and "--out" in err and ".npz" in err
    assert list(tmp_path.iterdir()) == []


def test_plan_and_plot_write_the_file_and_figures(tmp_path, capsys):
    yml = tmp_path / "short.yaml"
    yml.write_text("gait: [{gait: walk, steps: 2}, {gait: run, steps: 3}, {gait: walk, steps: 2}]\ndt: 0.005\n")
    out = tmp_path / "plan.json"
    code, stdout, _ = run(["plan", str(yml), "--out", str(out)], capsys)
    assert code == 0 and out.exists() and "wrote" in stdout
    code, stdout, _ = run(["plot", str(out), "--out", str(tmp_path / "figs")], capsys)
    assert code == 0
    pngs = sorted(p.name for p in (tmp_path / "figs").glob("*.png"))
    assert {"top_view.png", "com_height_force.png", "fig5_running_half_cycle.png", "fig6_transition.png",
            "fig7_Tr_surface.png", "capture_point.png"} <= set(pngs)
    assert all((tmp_path / "figs" / p).stat().st_size > 10_000 for p in pngs)


def test_scenarios_lists_the_paper_built_ins(capsys):
    code, stdout, _ = run(["scenarios"], capsys)
    assert code == 0
    for name in ("paper001-table1-running", "paper001-table2-running", "paper001-table2-walk-run-walk"):
        assert name in stdout


def test_bench_quick_writes_median_p99_and_baseline_ratios(tmp_path, capsys):
    out = tmp_path / "bench.json"
    code, stdout, _ = run(["bench", "--quick", "--only", "stiffness", "--only", "tvlip", "--json", str(out)], capsys)
    assert code == 0 and "median" in stdout and "p99" in stdout
    data = json.loads(out.read_text())
    assert data["quick"] is True and data["machine"]["cores"] >= 1
    ops = {r["operation"]: r for r in data["results"]}
    tr = next(r for name, r in ops.items() if name.startswith("T_r solve"))
    assert tr["median_s"] > 0 and tr["p99_s"] >= tr["median_s"] and tr["ratio"] > 0
    sizes = [r["size"] for r in data["results"] if r["operation"].startswith("TV-LIPM boundary")]
    assert any(s.startswith("2000 steps") for s in sizes)


def test_check_passes_a_plan_and_fails_a_corrupted_one(tmp_path, capsys):
    import gaitshift
    from gaitshift.trajectory import Trajectory

    sc = gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2},
                                           {"gait": "walk", "steps": 2}]})
    traj = gaitshift.plan(sc)
    good = traj.save(tmp_path / "good.npz")
    code, stdout, _ = run(["check", str(good)], capsys)
    assert code == 0 and "FAIL" not in stdout
    arrays = traj.arrays()
    arrays["com_pos"] = arrays["com_pos"].copy()
    arrays["com_pos"][len(traj) // 2:, 0] += 0.01  # a 1 cm jump in the middle
    bad = Trajectory.from_arrays(arrays, traj.meta).save(tmp_path / "bad.npz")
    code, stdout, _ = run(["check", str(bad), "--json"], capsys)
    rep = json.loads(stdout)
    assert code == 1 and not rep["pass"]["position_jump"] and not rep["pass"]["zmp_identity"]


def test_full_quick_bench_runs_every_topic(tmp_path):
    """`gaitshift bench --quick` (the CI smoke run) runs every registered benchmark to completion."""
    out = tmp_path / "quick.json"
    res = subprocess.run([GAITSHIFT, "bench", "--quick", "--json", str(out)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr[-2000:]
    ops = " ".join(f"{r['operation']} {r['baseline']}" for r in json.loads(out.read_text())["results"])
    for needle in ("T_r solve", "TV-LIPM boundary solve", "eq. (13) solve", "foothold", "start NLP",
                   "one online step", "whole-body IK", "G1 control tick", "SLIP optimise", "IPOPT"):
        assert needle in ops, needle
