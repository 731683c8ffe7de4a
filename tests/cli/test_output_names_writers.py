"""Output names of every command that writes a file or a folder are checked before any work (issue 28):
for each writer of benchmarks/contract_flags.py's ``WRITERS`` (plan, plan --rerun, teleop, scale, plot,
wholebody, animate, simulate --out/--video/--figures/--rerun, export, compare-slip, campaign, bench
--json, demo, robot tune --out/--report, dds robot --summary) a name longer than the file system's
NAME_MAX, a folder name beyond it, a path beyond PATH_MAX, a path under a file, and a folder where a
file goes (or a file where a folder goes) are one line naming the flag, exit 2, nothing written, before
any simulation, IK or campaign began (the ``no_work`` fixture makes those raise). The cheap writers also
write exactly the file an upper-case suffix names. The limits come from the file system (``os.pathconf``)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import contract_cases as cc
import contract_flags as cf
import contract_mutate as cm
from gaitshift.common.atomic import TEMP_ROOM, fs_limits

HOSTILE = ("long_name", "long_folder", "long_path", "under_file", "misplaced")


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> cc.Base:
    return cc.Base.make(tmp_path_factory.mktemp("writers-base"))


def _argv(writer: tuple, out: Path, folder: Path, base: cc.Base) -> list[str]:
    head, flag, _, _ = writer
    fill = {
        "{tvlip}": str(base.folder / "tvlip.yaml"),
        "{vhip}": str(base.folder / "vhip.yaml"),
        "{plan}": str(base.folder / "tvlip.npz"),
        "{spec}": str(cc.ROOT / "docs" / "campaigns" / "g1-500-subset.yaml"),
        "{robot}": str(cc.ROBOTS / "op3.yaml"),
        "{folder}": str(folder),
    }
    return [*(cc.fill_placeholders(a, fill) for a in head), flag, str(out)]


@pytest.mark.parametrize("kind", HOSTILE)
@pytest.mark.parametrize("writer", cf.WRITERS, ids=lambda w: f"{w[0][0]}{w[1]}")
def test_a_hostile_output_name_is_one_line_before_any_work(writer, kind, base, cli, tmp_path, no_work):
    folder = tmp_path / "case"
    folder.mkdir()
    (folder / "file.npz").write_bytes(b"x")
    (folder / "dir.npz").mkdir()
    suffix = writer[2]
    if kind == "misplaced":  # a folder where a file goes, a file where a folder goes
        out = folder / ("dir.npz" if suffix else "file.npz")
    else:
        out = cm.NAME_KINDS[kind](folder, suffix)
    before = sorted(os.listdir(folder))
    code, _, err = cli(_argv(writer, out, folder, base))
    assert code == 2 and err.count("\n") == 1 and err.startswith(f"gaitshift: error: {writer[1]} = "), err
    assert sorted(os.listdir(folder)) == before  # and no_work: no simulation, IK or campaign began


@pytest.mark.parametrize("writer", [w for w in cf.WRITERS if w[3]], ids=lambda w: f"{w[0][0]}{w[1]}")
def test_an_upper_case_suffix_writes_exactly_the_named_file(writer, base, cli, tmp_path):
    out = tmp_path / f"out{writer[2].upper()}"
    code, _, err = cli(_argv(writer, out, tmp_path, base))
    assert code == 0, err
    assert sorted(os.listdir(tmp_path)) == [out.name] and out.stat().st_size > 0


def test_the_name_limits_are_the_file_systems(tmp_path, cli):
    """A name of NAME_MAX - TEMP_ROOM bytes is written; one byte more is refused, naming the limit."""
    name_max, _ = fs_limits(tmp_path)
    fits = tmp_path / ("a" * (name_max - TEMP_ROOM - 4) + ".npz")
    assert cli(["plan", str(cc.ROOT / "src/gaitshift/scenario/builtin/g1-walk.yaml"), "--out", str(fits)])[0] == 0
    over = tmp_path / ("b" * (name_max - TEMP_ROOM - 3) + ".npz")
    code, _, err = cli(["plan", "g1-walk", "--out", str(over)])
    assert code == 2 and f"at most {name_max - TEMP_ROOM} bytes" in err and not over.exists()
