"""Every flag of the core, slip and bench commands (and the video, Rerun and export flags) keeps the
error contract: a bad value (negative,
NaN, inf, text for a number, an unknown name, a missing file, a folder or a device given as an output
file, a file given as an output folder, an unwritable location) ends in exactly one line on stderr
that names the flag, the value and what is allowed, exit code 2, no traceback and no file written.
Every case fails before any planning or measuring, so the module runs in about a second."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

STIFF = ["stiffness", "--height", "0.95", "--single-support", "0.4", "--double-support", "0.15", "--flight", "0.15"]


def _with(argv: list[str], flag: str, value: str) -> list[str]:
    """``argv`` with ``flag`` set to ``value`` (replaced when present, else appended)."""
    out = list(argv)
    if flag in out:
        out[out.index(flag) + 1] = value
    else:
        out += [flag, value]
    return out


@pytest.fixture
def place(tmp_path: Path) -> Path:
    """A folder with a file, a sub-folder and a FIFO to misuse as outputs."""
    (tmp_path / "file.npz").write_bytes(b"not an archive")
    (tmp_path / "dir.npz").mkdir()
    (tmp_path / "dir.json").mkdir()
    os.mkfifo(tmp_path / "fifo.json")
    return tmp_path


#: (argv with {tmp} for the test folder, flag the message must name, value it must show)
CASES = [
    (_with(STIFF, "--height", "nan"), "--height", "nan"),
    (_with(STIFF, "--height", "abc"), "--height", "'abc'"),
    (_with(STIFF, "--single-support", "-1"), "--single-support", "-1.0"),
    (_with(STIFF, "--double-support", "inf"), "--double-support", "inf"),
    (_with(STIFF, "--flight", "-inf"), "--flight", "-inf"),
    (_with(STIFF, "--gravity", "0"), "--gravity", "0.0"),
    (_with(STIFF, "--gravity", "1e400"), "--gravity", "inf"),
    (["plan", "no-such-scenario", "--out", "{tmp}/p.npz"], "scenario", "'no-such-scenario'"),
    (["plan", "{tmp}/missing.yaml", "--out", "{tmp}/p.npz"], "scenario", "missing.yaml"),
    (["plan", "paper001-table1-running", "--out", "{tmp}/dir.npz"], "--out", "dir.npz"),
    (["plan", "paper001-table1-running", "--out", "{tmp}/p.txt"], "--out", "p.txt"),
    (["plan", "paper001-table1-running", "--out", "{tmp}/file.npz/p.npz"], "--out", "file.npz/p.npz"),
    (["plan", "paper001-table1-running", "--out", "/dev/null"], "--out", "/dev/null"),
    (["plan", "paper001-table1-running", "--out", "/proc/gaitshift/p.npz"], "--out", "/proc/gaitshift/p.npz"),
    (["plot", "{tmp}/missing.npz", "--out", "{tmp}/figs"], "file", "no such file"),
    (["plot", "{tmp}/dir.npz", "--out", "{tmp}/figs"], "file", "dir.npz"),
    (["plot", "{tmp}/file.npz", "--out", "{tmp}/file.npz"], "--out", "file.npz"),
    (["plot", "{tmp}/file.npz", "--out", "/proc/gaitshift/figs"], "--out", "/proc/gaitshift/figs"),
    (["check", "{tmp}/missing.npz"], "file", "no such file"),
    (["check", "{tmp}/dir.npz"], "file", "dir.npz"),
    (["check", "{tmp}/file.npz"], "file", "unreadable"),
    (["compare-slip", "--out", "{tmp}/o", "--speed", "nan"], "--speed", "nan"),
    (["compare-slip", "--out", "{tmp}/o", "--speed", "-3"], "--speed", "-3.0"),
    (["compare-slip", "--out", "{tmp}/o", "--flight", "inf"], "--flight", "inf"),
    (["compare-slip", "--out", "{tmp}/o", "--step-width", "-0.1"], "--step-width", "-0.1"),
    (["compare-slip", "--out", "{tmp}/o", "--step-width", "2"], "--step-width", "2.0"),
    (["compare-slip", "--out", "{tmp}/o", "--repeats", "0"], "--repeats", "0"),
    (["compare-slip", "--out", "{tmp}/o", "--repeats", "1.5"], "--repeats", "'1.5'"),
    (["compare-slip", "--out", "{tmp}/file.npz"], "--out", "file.npz"),
    (["compare-slip", "--out", "/proc/gaitshift/o"], "--out", "/proc/gaitshift/o"),
    (["bench", "--quick", "--only", "no-such-benchmark"], "--only", "'no-such-benchmark'"),
    (["bench", "--quick", "--only", "stiffness", "--json", "{tmp}/dir.json"], "--json", "dir.json"),
    (["bench", "--quick", "--only", "stiffness", "--json", "{tmp}/fifo.json"], "--json", "fifo.json"),
    (["bench", "--quick", "--only", "stiffness", "--json", "{tmp}/b.txt"], "--json", "b.txt"),
    (
        ["bench", "--quick", "--only", "stiffness", "--json", "/proc/gaitshift/b.json"],
        "--json",
        "/proc/gaitshift/b.json",
    ),
    (["demo", "--no-video", "--out", "{tmp}/file.npz"], "--out", "file.npz"),
    (["demo", "--no-video", "--out", "/proc/gaitshift/demo"], "--out", "/proc/gaitshift/demo"),
    (
        ["simulate", "g1-walk", "--out", "{tmp}/s.npz", "--video", "{tmp}/v.mp4", "--video-size", "13x7"],
        "--video-size",
        "13x7",
    ),
    (
        ["simulate", "g1-walk", "--out", "{tmp}/s.npz", "--video", "{tmp}/v.mp4", "--video-size", "hd"],
        "--video-size",
        "hd",
    ),
    (["simulate", "g1-walk", "--out", "{tmp}/s.npz", "--video", "{tmp}/v.mp4", "--video-fps", "0"], "--video-fps", "0"),
    (["simulate", "g1-walk", "--out", "{tmp}/s.npz", "--rerun", "{tmp}/r.txt"], "--rerun", "r.txt"),
    (["simulate", "g1-walk", "--out", "{tmp}/s.npz", "--rerun", "{tmp}/dir.npz"], "--rerun", "dir.npz"),
    (["plan", "g1-walk", "--out", "{tmp}/p.npz", "--rerun", "/proc/gaitshift/p.rrd"], "--rerun", "/proc/gaitshift"),
    (["export", "{tmp}/file.npz", "--format", "mjlab-npz", "--out", "{tmp}/m.npz", "--fps", "-5"], "--fps", "-5"),
]


@pytest.mark.parametrize(("argv", "flag", "value"), CASES, ids=lambda x: " ".join(x) if isinstance(x, list) else None)
def test_bad_flag_value_is_one_line_naming_flag_value_and_what_is_allowed(argv, flag, value, place, cli):
    before = sorted(p.name for p in place.iterdir())
    code, out, err = cli([a.replace("{tmp}", str(place)) for a in argv])
    assert code == 2, (out, err)
    assert err.count("\n") == 1 and err.startswith("gaitshift: error: "), err
    assert flag in err and value in err and "allowed" in err, err
    assert "Traceback" not in err
    assert sorted(p.name for p in place.iterdir()) == before  # nothing written, not even a folder
    assert not Path("/proc/gaitshift").exists()
