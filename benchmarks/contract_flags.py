"""Command-line flag and output-name cases of the contract sample (benchmarks/contract_sample.py):
every writer's output flag with hostile names (``WRITERS``), ``simulate``'s flags (``SIM_FLAGS``) and
other commands' flags (``FLAG_CASES``) with values that must be refused before any work.
"""

from __future__ import annotations

import random
from pathlib import Path

from contract_cases import ROBOTS, ROOT, Base, Case, fill_placeholders, with_fixtures
from contract_mutate import NAME_KINDS, VALID_NAMES, hostile_name

#: writers: (argv before the flag, the flag, suffix, cheap on valid names); {plan} = a valid plan file
WRITERS: list[tuple[list[str], str, str, bool]] = [
    (["plan", "{tvlip}"], "--out", ".npz", True),
    (["plan", "{tvlip}", "--out", "{folder}/p.npz"], "--rerun", ".rrd", False),
    (["teleop", "{vhip}", "--script", "up wait=0.3", "--max-time", "1"], "--out", ".json", True),
    (["scale", "paper001-table2-walk-run-walk", "--robot", "g1"], "--out", ".yaml", True),
    (["plot", "{plan}"], "--out", "", False),
    (["wholebody", "{plan}"], "--out", ".npz", False),
    (["animate", "{plan}"], "--out", ".mp4", False),
    (["simulate", "g1-walk"], "--out", ".npz", False),
    (["simulate", "g1-walk", "--out", "{folder}/s.npz"], "--video", ".mp4", False),
    (["simulate", "g1-walk", "--out", "{folder}/s.npz"], "--figures", "", False),
    (["simulate", "g1-walk", "--out", "{folder}/s.npz"], "--rerun", ".rrd", False),
    (["export", "{plan}", "--format", "unitree-csv"], "--out", ".csv", False),
    (["compare-slip"], "--out", "", False),
    (["campaign", "{spec}"], "--out", "", False),
    (["bench", "--quick"], "--json", ".json", False),
    (["demo"], "--out", "", False),
    (["robot", "tune", "{robot}", "--out", "{folder}/t.yaml"], "--report", ".md", False),
    (["robot", "tune", "{robot}"], "--out", ".yaml", False),
    (["dds", "robot"], "--summary", ".json", False),
    (["dds", "robot"], "--record", ".npz", False),
    (["dds", "control", "g1-walk"], "--record", ".npz", False),
]


def out_name_case(rng: random.Random, folder: Path, base: Base) -> Case:
    head, flag, suffix, cheap = rng.choice(WRITERS)
    with_fixtures(folder)
    kinds = list(NAME_KINDS) if cheap else [k for k in NAME_KINDS if k not in VALID_NAMES]
    if not suffix:  # a folder flag: a file is the hostile one; any folder name of <= 255 bytes is fine
        kinds = [k for k in kinds if k not in ("folder", "no_suffix", "bad_suffix", "dot", "long_245")] + ["file"]
    kind = rng.choice(kinds)
    out = folder / "file.npz" if kind == "file" else hostile_name(rng, folder, suffix, kind)[0]
    fill = {
        "{tvlip}": str(base.folder / "tvlip.yaml"),
        "{vhip}": str(base.folder / "vhip.yaml"),
        "{plan}": str(base.folder / "tvlip.npz"),
        "{spec}": str(ROOT / "docs" / "campaigns" / "g1-500-subset.yaml"),
        "{robot}": str(ROBOTS / "op3.yaml"),
        "{folder}": str(folder),
    }
    argv = [fill_placeholders(a, fill) for a in head] + [flag, str(out)]
    valid = kind in VALID_NAMES
    outputs = (out.parent,) if kind == "nested" else (out,)
    return Case("out_names", {flag}, argv=argv, outputs=outputs, codes=(0, 2) if valid else (2,), note=kind)


#: simulate's flags: (invalid values, valid values); a case gives 1-3 invalid ones, so nothing runs
SIM_FLAGS: dict[str, tuple[list[str], list[str]]] = {
    "--control-period": (["0", "-1", "nan", "abc", "1", "0.5", "1e-9", "inf"], ["0.002", "0.001"]),
    "--push": (["abc", "-1", "nan", "inf", "1,2,3,4,5,6,7,8", "x=1"], ["10"]),
    "--bump": (["abc", "1", "nan,0.01", "1,-5", "1,1e9", ","], ["1.0,0.02"]),
    "--mass-scale": (["0", "-1", "nan", "1e9", "abc"], ["1.0", "0.9"]),
    "--joint-vel-noise": (["-1", "nan", "1e9", "inf"], ["0.01"]),
    "--state": (["truth", "", "x" * 300], ["oracle", "estimated"]),
    "--noise": (["loud", "", "None"], ["none", "typical", "rl-peer"]),
    "--noise-scale": (["-1", "nan", "1e9", "abc"], ["1.0"]),
    "--latency": (["-1", "1e9", "abc", "1.5", "99999999999999999999999"], ["0", "2"]),
    "--friction": (["0", "-1", "nan", "1e9", "inf"], ["0.8"]),
    "--contact": (["feet", ""], ["force"]),
    "--seed": (["-1", "abc", "1.5"], ["0", "7"]),
    "--video-size": (["0x0", "abcxdef", "1281x720", "99999x99999", "1280", "x"], ["640x360"]),
    "--video-fps": (["0", "-1", "abc", "100000"], ["30"]),
    "--robot": (["nope", "/nonexistent/robot.yaml", "op3"], ["g1"]),
}


def simulate_case(rng: random.Random, folder: Path, base: Base) -> Case:
    with_fixtures(folder)
    bad = set(rng.sample(sorted(SIM_FLAGS), rng.choice([1, 1, 2, 3])))
    argv = ["simulate", rng.choice(["g1-walk", "g1-run"]), "--out", str(folder / "s.npz")]
    for flag in sorted(set(rng.sample(sorted(SIM_FLAGS), rng.randrange(4))) | bad):
        argv += [flag, rng.choice(SIM_FLAGS[flag][0 if flag in bad else 1])]
    if "--video-size" in argv or "--video-fps" in argv:
        argv += ["--video", str(folder / "v.mp4")]
    return Case("simulate", set(SIM_FLAGS) | {"--video"}, argv=argv, codes=(2,), note=",".join(sorted(bad)))


#: other commands' flags with values that must be refused before any work: (argv, flag, bad values)
FLAG_CASES: list[tuple[list[str], str, list[str]]] = [
    (["wholebody", "{plan}", "--out", "{folder}/j.npz"], "--rate", ["0", "-1", "nan", "1e9", "abc"]),
    (["animate", "{plan}", "--out", "{folder}/m.mp4", "--rate", "100"], "--fps", ["0", "-1", "nan", "1e9"]),
    (["animate", "{plan}", "--out", "{folder}/m.mp4", "--rate", "100"], "--width", ["0", "-2", "641", "100000"]),
    (["animate", "{plan}", "--out", "{folder}/m.mp4"], "--rate", ["0", "-1", "nan", "inf"]),
    (["animate", "{plan}", "--out", "{folder}/m.mp4", "--rate", "100"], "--robot", ["nope", "/nonexistent/r.yaml"]),
    (["wholebody", "{plan}", "--out", "{folder}/j.npz"], "--robot", ["nope", "op3"]),
    (["scale", "paper001-table2-walk-run-walk", "--out", "{folder}/s.yaml"], "--robot", ["nope", ""]),
    (["scale", "paper001-table2-walk-run-walk", "--out", "{folder}/s.yaml"], "--time-scale", ["fast", ""]),
    (["plan", "{tvlip}", "--out", "{folder}/p.npz"], "--robot", ["nope", "/nonexistent/r.yaml"]),
    (["compare-slip", "--out", "{folder}/slip"], "--speed", ["0", "-1", "nan", "1e9"]),
    (["compare-slip", "--out", "{folder}/slip"], "--flight", ["0", "-1", "nan", "1e9"]),
    (["compare-slip", "--out", "{folder}/slip"], "--repeats", ["0", "-1", "1e9", "abc"]),
    (["robot", "tune", "{robot}", "--out", "{folder}/t.yaml"], "--seed", ["-1", "abc"]),
    (["robot", "tune", "{robot}", "--out", "{folder}/t.yaml"], "--workers", ["0", "-1", "abc"]),
    (["robot", "tune", "{robot}", "--out", "{folder}/t.yaml"], "--work", ["{folder}/file.npz"]),
    (["dds", "robot", "--duration", "1"], "--domain", ["-1", "300", "abc"]),
    (["dds", "robot", "--duration", "1"], "--iface", ["nope0", ""]),
    (["dds", "robot"], "--duration", ["-1", "nan", "inf"]),
    (["dds", "robot", "--duration", "1"], "--noise", ["loud"]),
    (["dds", "control", "g1-walk"], "--domain", ["-1", "300", "0"]),
    (["dds", "control", "g1-walk"], "--state-timeout", ["0", "-1", "nan"]),
    (["teleop", "--sim", "--script", "quit"], "--robot", ["nope"]),
    (["bench"], "--only", ["no-such-benchmark"]),
    (["campaign", "{spec}", "--out", "{folder}/c"], "--workers", ["0", "-1", "abc"]),
    (["campaign", "{spec}", "--out", "{folder}/c"], "--scheduler", ["nope:1", "tcp://256.0.0.1:1", ""]),
    (["robot", "check", "g1"], "SCENARIO", ["nope", "{folder}/file.npz"]),
    (["robots"], "ROBOTS", ["nope", "{folder}/file.npz"]),
]


def flags_case(rng: random.Random, folder: Path, base: Base) -> Case:
    head, flag, bad = rng.choice(FLAG_CASES)
    with_fixtures(folder)
    fill = {
        "{tvlip}": str(base.folder / "tvlip.yaml"),
        "{plan}": str(base.folder / "tvlip.npz"),
        "{spec}": str(ROOT / "docs" / "campaigns" / "g1-500-subset.yaml"),
        "{robot}": str(ROBOTS / "op3.yaml"),
        "{folder}": str(folder),
    }
    value = fill_placeholders(rng.choice(bad), fill)
    argv = [fill_placeholders(a, fill) for a in head] + ([value] if flag.isupper() else [flag, value])
    names = {flag, flag.lstrip("-").replace("-", "_"), "robot", "scenario", "file", "SCENARIO"}
    return Case("flags", names, argv=argv, codes=(2,), note=f"{argv[0]} {flag} {value[:30]}")
