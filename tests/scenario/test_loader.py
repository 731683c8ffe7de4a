"""Loading scenarios: every built-in loads, the schema registry covers the planners, every way a
file or name can be wrong ends in one ScenarioError that says which, and a relative robot YAML path in
a scenario file is relative to that file's folder, not to the working directory."""

import pytest

from gaitshift.errors import ScenarioError
from gaitshift.planners.registry import PLANNERS
from gaitshift.scenario import builtin_names, load_scenario
from gaitshift.scenario.loader import SCHEMAS


def _error(arg) -> ScenarioError:
    with pytest.raises(ScenarioError) as exc:
        load_scenario(arg)
    assert "\n" not in str(exc.value)
    return exc.value


def test_every_builtin_loads_and_is_named_after_its_file():
    names = builtin_names()
    assert "paper001-table2-walk-run-walk" in names and "paper003-variable-speed" in names
    for name in names:
        sc = load_scenario(name)
        assert sc.name == name and sc.planner in SCHEMAS


def test_the_schema_registry_has_one_schema_per_planner():
    assert set(SCHEMAS) == set(PLANNERS)
    for name, schema in SCHEMAS.items():
        assert schema.model_fields["planner"].default == name


def test_a_dict_defaults_to_tvlip_and_keeps_its_name():
    sc = load_scenario({"gait": [{"gait": "walk", "steps": 1}]})
    assert sc.planner == "tvlip" and sc.name == "custom"


def test_missing_file_folder_and_unknown_name_are_told_apart(tmp_path):
    assert "no such file" in _error(tmp_path / "none.yaml").allowed
    (tmp_path / "d.yaml").mkdir()
    assert "folder" in _error(tmp_path / "d.yaml").allowed
    err = _error("no-such-scenario")
    assert err.field == "scenario" and "paper003-variable-speed" in err.allowed


@pytest.mark.parametrize(
    "raw, fragment",
    [
        (b"height: \xff\n", "UTF-8"),
        (b"a: [\n", "valid YAML"),
        (b"when: 2001-13-45\n", "valid YAML"),
        (b"n: " + b"9" * 5000 + b"\n", "valid YAML"),
        (b"- 1\n- 2\n", "a YAML mapping"),
        (b"", "a YAML mapping"),
        (b"!!python/object:os.system {}\n", "valid YAML"),
    ],
)
def test_unreadable_files_name_the_scenario(tmp_path, raw, fragment):
    path = tmp_path / "s.yaml"
    path.write_bytes(raw)
    err = _error(path)
    assert err.field == "scenario" and fragment in err.allowed


def test_keys_and_planner_must_be_names(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("1: 2\n")
    assert "field names (strings)" in _error(path).allowed
    for planner in ("[1]", "{a: 1}", "hop"):
        path.write_text(f"planner: {planner}\n")
        err = _error(path)
        assert err.field == "planner" and err.allowed == "one of: tvlip, vhip, locomotion"


def test_a_relative_robot_path_is_relative_to_the_scenario_file(tmp_path, monkeypatch):
    (tmp_path / "robots").mkdir()
    (tmp_path / "scenarios").mkdir()
    (tmp_path / "elsewhere").mkdir()
    robot = tmp_path / "robots" / "mine.yaml"
    robot.write_text("name: mine\n")
    path = tmp_path / "scenarios" / "walk.yaml"
    path.write_text("planner: locomotion\nrobot: ../robots/mine.yaml\n")
    monkeypatch.chdir(tmp_path / "elsewhere")
    assert load_scenario(str(path)).robot == str(robot.resolve())
    path.write_text("planner: locomotion\nrobot: g1\n")  # a built-in name stays a name
    assert load_scenario(str(path)).robot == "g1"
