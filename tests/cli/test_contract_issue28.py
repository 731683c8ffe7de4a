"""The failing cases of issue 28's "Why" and those the 10 000-case contract sample found, each as it
ends now: a result, or one line naming the field with exit 2, before any work and without a file.

* a running plan saved as CSV passes ``gaitshift check`` (the CSV has no ``boundary_t``: the check
  finds the stiffness steps of the transition phases in the per-sample ``stiffness`` column);
* ``Replanner.replan`` refuses a time in the closing stand or beyond (a singular KKT system), a
  measured state too large for eq. (1) (NaN references); ``reference`` refuses non-finite times;
* ``LocomotionGenerator.command/goto/advance`` and ``SensorFrame.checked`` refuse wrong types and
  huge values (TypeError/ValueError from numpy before); ``simulate``/``Controller.from_scenario`` and
  ``Trajectory.load`` refuse an argument of the wrong kind (AttributeError/TypeError before);
* ``simulate --control-period 0`` names the flag; ``animate`` names ``--joints``, ``--fps`` and the
  size before any IK; ``robot tune --work FILE`` is one line (NotADirectoryError after a campaign
  started); ``dds robot`` names an unknown ``--iface`` or ``--noise`` before it starts;
* ``campaign report`` ignores a stray non-Parquet file in ``parts/``, names a damaged part file, and
  refuses a ``report`` that is a file before drawing.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

import gaitshift
from gaitshift.api import robot_facts

ROOT = Path(__file__).resolve().parents[2]


def _one_line(result: tuple[int, str, str], flag: str) -> str:
    code, _, err = result
    assert code == 2 and err.count("\n") == 1 and err.startswith(f"gaitshift: error: {flag} = "), err
    return err


@pytest.mark.parametrize("name", ["g1-run", "paper001-table2-running"])
def test_a_running_plan_saved_as_csv_passes_check(name, cli, tmp_path):
    path = gaitshift.plan(name).save(tmp_path / "p.csv")
    code, out, err = cli(["check", str(path)])
    assert code == 0, out + err


def test_check_on_a_csv_still_finds_a_wrong_acceleration(cli, tmp_path):
    traj = gaitshift.plan("g1-run")
    arrays = traj.arrays()
    i = len(traj) // 3 + 7  # one sample inside a phase
    arrays["com_acc"][i, 0] += 1.0
    bad = gaitshift.Trajectory.from_arrays(arrays, dict(traj.meta))
    code, out, _ = cli(["check", str(bad.save(tmp_path / "bad.csv"))])
    assert code == 1 and "fd_acceleration" in out


def test_replan_refuses_times_outside_what_it_can_replan():
    r = gaitshift.Replanner.from_scenario(gaitshift.load_scenario("paper001-table2-walk-run-walk"))
    stand = float(r.seq.boundary_times[-2])
    for t in (-1.0, stand, r.duration, 1e300):
        with pytest.raises(gaitshift.InputError) as info:
            r.replan(t, [0.0, 0.0], [0.0, 0.0])
        assert info.value.field == "t"
    with pytest.raises(gaitshift.InputError) as info:
        r.replan(2.0, [1e300, 0.0], [0.0, 0.0])
    assert info.value.field == "p_xy"
    with pytest.raises(gaitshift.InputError) as info:
        r.reference([2.0, math.nan])
    assert info.value.field == "t"


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda g: g.command("fast"), "command.vx"),
        (lambda g: g.command(0.3, [1]), "command.vy"),
        (lambda g: g.command(0.3, 0.0, 1e300), "command.yaw_rate"),
        (lambda g: g.goto(None, 1.0), "goto.x"),
        (lambda g: g.goto(1.0, {"a": 1}), "goto.y"),
        (lambda g: g.advance("3"), "ticks"),
        (lambda g: g.advance(10**9), "ticks"),
        (lambda g: g.advance(True), "ticks"),
    ],
)
def test_the_locomotion_generator_refuses_wrong_types(call, field):
    sc = gaitshift.load_scenario("g1-tour")
    gen = gaitshift.LocomotionGenerator.from_scenario(sc, robot_facts(sc))
    with pytest.raises(gaitshift.InputError) as info:
        call(gen)
    assert info.value.field == field and "\n" not in str(info.value)


def test_an_advance_of_numpy_integers_is_taken():
    sc = gaitshift.load_scenario("g1-tour")
    gen = gaitshift.LocomotionGenerator.from_scenario(sc, robot_facts(sc))
    assert len(gen.advance(np.int64(5)).com_pos) == 5


@pytest.mark.parametrize("what", [None, 3, [1], b"g1-walk"])
def test_simulate_and_controller_refuse_a_scenario_of_the_wrong_kind(what):
    for fn in (gaitshift.simulate, gaitshift.Controller.from_scenario):
        with pytest.raises(gaitshift.ScenarioError) as info:
            fn(what)
        assert info.value.field == "scenario"


def test_load_scenario_takes_a_loaded_scenario_and_trajectory_load_refuses_a_number():
    sc = gaitshift.load_scenario("g1-walk")
    assert gaitshift.load_scenario(sc) is sc
    with pytest.raises(gaitshift.InputError) as info:
        gaitshift.Trajectory.load(3)
    assert info.value.field == "file"


def test_a_sensor_frame_takes_a_huge_integer_time_and_refuses_nan():
    imu = {"imu_quat": [1, 0, 0, 0], "imu_gyro": [0] * 3, "imu_acc": [0] * 3, "q": [0], "dq": [0], "tau_est": [0]}
    assert gaitshift.SensorFrame.checked(1, t=10**30, **imu).t == 1e30  # np.isfinite(10**30): TypeError before
    with pytest.raises(gaitshift.InputError) as info:
        gaitshift.SensorFrame.checked(1, t=math.nan, **imu)
    assert info.value.field == "SensorFrame.t"


def test_simulate_and_animate_name_their_flags_before_any_work(cli, tmp_path, no_work):
    sim = ["simulate", "g1-walk", "--out", str(tmp_path / "s.npz")]
    _one_line(cli([*sim, "--control-period", "0"]), "--control-period")
    (tmp_path / "F").write_text("x")
    _one_line(cli([*sim, "--figures", str(tmp_path / "F")]), "--figures")
    plan = gaitshift.plan("g1-walk").save(tmp_path / "p.npz")
    (tmp_path / "j.npz").write_bytes(plan.read_bytes()[:300])
    out = str(tmp_path / "m.mp4")
    _one_line(cli(["animate", str(plan), "--joints", str(tmp_path / "j.npz"), "--out", out]), "--joints")
    _one_line(cli(["animate", str(plan), "--fps", "0", "--out", out]), "--fps")
    _one_line(cli(["animate", str(plan), "--width", "641", "--out", out]), "--width/--height")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["F", "j.npz", "p.npz"]


def test_robot_tune_refuses_a_work_folder_that_is_a_file(cli, tmp_path):
    (tmp_path / "w").write_text("x")
    argv = ["robot", "tune", str(ROOT / "src/gaitshift/robots/configs/op3.yaml"), "--out", str(tmp_path / "t.yaml")]
    _one_line(cli([*argv, "--work", str(tmp_path / "w")]), "--work")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w"]


@pytest.mark.parametrize(("flag", "value"), [("--iface", "nope0"), ("--noise", "loud")])
def test_dds_robot_names_a_bad_interface_or_noise_before_it_starts(flag, value, cli):
    _one_line(cli(["dds", "robot", "--duration", "0.1", flag, value]), flag)


@pytest.fixture
def campaign(tmp_path) -> Path:
    table = pq.read_table(ROOT / "docs" / "campaigns" / "g1-500-results.parquet")
    (tmp_path / "c" / "parts").mkdir(parents=True)
    for i in (0, 100, 200):
        pq.write_table(table.slice(i, 1), tmp_path / "c" / "parts" / f"{table['case_hash'][i]}.parquet")
    shutil.copy(ROOT / "docs" / "campaigns" / "g1-500-subset.yaml", tmp_path / "c" / "spec.yaml")
    return tmp_path / "c"


def test_campaign_report_ignores_stray_files_and_names_a_damaged_part(campaign, cli):
    (campaign / "parts" / "notes.txt").write_text("my notes")
    code, _, err = cli(["campaign", "report", str(campaign)])
    assert code == 0 and (campaign / "report" / "summary.md").exists(), err
    shutil.rmtree(campaign / "report")
    (campaign / "parts" / "zz.parquet").write_bytes(b"PAR1 damaged")
    err = _one_line(cli(["campaign", "report", str(campaign)]), "parts/zz.parquet")
    assert not (campaign / "report").exists() and "part files" in err


def test_campaign_report_refuses_a_report_that_is_a_file(campaign, cli):
    (campaign / "report").write_text("x")
    _one_line(cli(["campaign", "report", str(campaign)]), "DIR")
    assert (campaign / "report").read_text() == "x"


@pytest.mark.parametrize("header", [b"{'descr': '<f8', 'fortran_order': False, 'shape': (3,", b"{'descr': <f8 ??"])
def test_check_names_a_member_whose_npy_header_numpy_cannot_parse(header, cli, tmp_path):
    """A .npy header cut inside a bracket makes numpy's header parser raise ``tokenize.TokenError``, a
    garbled one ``SyntaxError`` (found by benchmarks/contract_sample.py, seed 0, case 5295): one line,
    exit 2, naming the member."""
    import struct
    import zipfile

    header = header + b" " * (64 - 10 - len(header) - 1) + b"\n"
    path = tmp_path / "traj.npz"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("t.npy", b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header + bytes(24))
    code, out, err = cli(["check", str(path), "--json"])
    assert code == 2 and out == "" and err.count("\n") == 1 and "t = " in err and "unreadable member" in err
