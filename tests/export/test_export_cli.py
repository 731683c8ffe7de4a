"""``gaitshift export``'s error contract: a bad format, rate, output suffix or input (not an .npz, an
.npz that is neither a plan nor a simulation log, a missing or corrupt file, a log given another
robot) ends with one line naming the flag, exit code 2, and no file at all in the output folder;
docs/export.md holds the joint and body order tables generated from the G1 and T1 models."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gaitshift.cli import main
from gaitshift.export.kinematics import order_table
from gaitshift.robots import load_robot

DOCS = Path(__file__).resolve().parents[2] / "docs" / "export.md"


def _run(argv, capsys):
    capsys.readouterr()
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    return int(exc.value.code or 0), capsys.readouterr().err


def _cases(plan: Path, log: Path, tmp: Path):
    """(argv tail, out file name, the flag the message must name)."""
    (tmp / "plan.csv").write_text("t,x\n0,1\n")
    np.savez(tmp / "other.npz", a=np.zeros(3))
    (tmp / "corrupt.npz").write_text("not a zip")
    return [
        ([plan, "--format", "bvh"], "m.npz", "--format"),
        ([plan, "--format", "mjlab-npz", "--fps", 0], "m.npz", "--fps"),
        ([plan, "--format", "mjlab-npz", "--fps", 5000], "m.npz", "--fps"),
        ([plan, "--format", "mjlab-npz", "--fps", "fast"], "m.npz", "--fps"),
        ([plan, "--format", "mjlab-npz", "--fps", 30], "m.npz", "--fps"),  # mjlab plays every frame at 50 Hz
        ([plan, "--format", "mjlab-npz"], "m.csv", "--out"),
        ([plan, "--format", "unitree-csv"], "m.npz", "--out"),
        ([tmp / "plan.csv", "--format", "unitree-csv"], "m.csv", "SOURCE"),
        ([tmp / "other.npz", "--format", "unitree-csv"], "m.csv", "SOURCE"),
        ([tmp / "corrupt.npz", "--format", "unitree-csv"], "m.csv", "SOURCE"),
        ([tmp / "missing.npz", "--format", "unitree-csv"], "m.csv", "SOURCE"),
        ([log, "--format", "unitree-csv", "--robot", "t1"], "m.csv", "--robot"),
        ([plan, "--format", "unitree-csv", "--robot", "nao"], "m.csv", "--robot"),
    ]


def test_every_bad_request_is_one_line_exit_2_and_writes_nothing(motions, tmp_path, capsys):
    cases = _cases(motions["g1-plan"], motions["g1-sim"], tmp_path)
    for i, (args, name, flag) in enumerate(cases):
        folder = tmp_path / f"out{i}"
        folder.mkdir()
        code, err = _run(["export", *args, "--out", folder / name], capsys)
        assert code == 2, (args, err)
        assert err.count("\n") == 1 and err.startswith("gaitshift: error: ") and flag in err, (args, err)
        assert list(folder.iterdir()) == [], args


def test_a_good_request_writes_exactly_its_file(motions, tmp_path, capsys):
    code, err = _run(
        ["export", motions["g1-sim"], "--format", "unitree-csv", "--fps", 25, "--out", tmp_path / "m.csv"], capsys
    )
    assert code == 0, err
    assert [p.name for p in tmp_path.iterdir()] == ["m.csv"]
    rows = np.loadtxt(tmp_path / "m.csv", delimiter=",")
    t = np.load(motions["g1-sim"])["t"]
    assert len(rows) == int((t[-1] - t[0]) * 25 + 1e-9) + 1


@pytest.mark.parametrize("robot", ["g1", "t1"])
def test_docs_hold_the_order_tables_generated_from_the_models(robot):
    assert order_table(load_robot(robot)) in DOCS.read_text()
