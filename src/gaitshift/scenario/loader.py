"""Loading scenarios: built-in names, YAML files or dicts, validated by the schema their ``planner``
names (:data:`SCHEMAS`, the one registry of scenario schemas).

Built-in scenarios are the YAML files of ``gaitshift/scenario/builtin``. Every failure becomes one
:class:`~gaitshift.errors.ScenarioError` that names the dotted field, the value and what is allowed.

A relative robot YAML path in a scenario file (``robot: ../robots/mine.yaml``) is relative to the
scenario file's folder, as ``mjcf:`` is in a robot YAML (not to the working directory); the loaded
scenario holds it as an absolute path.
"""

from __future__ import annotations

from importlib import resources
from os import PathLike
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ValidationError

from gaitshift.errors import InputError, ScenarioError, one_of
from gaitshift.scenario.fields import input_error, one_line, short_repr
from gaitshift.scenario.locomotion import LocomotionScenario
from gaitshift.scenario.tvlip import TvlipScenario
from gaitshift.scenario.vhip import VhipScenario

#: planner name -> its scenario schema (the ``planner`` key of a scenario; default ``tvlip``)
SCHEMAS: dict[str, type[BaseModel]] = {"tvlip": TvlipScenario, "vhip": VhipScenario, "locomotion": LocomotionScenario}
DEFAULT_PLANNER = "tvlip"
YAML_SUFFIXES = (".yaml", ".yml")


def builtin_names() -> list[str]:
    """Names of the built-in scenarios, sorted."""
    folder = resources.files("gaitshift.scenario") / "builtin"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def builtin_text(name: str) -> str:
    """The YAML text of a built-in scenario."""
    return (resources.files("gaitshift.scenario") / "builtin" / f"{name}.yaml").read_text()


def load_scenario(name_or_path: str | Path | dict[str, Any]) -> Any:
    """Load a scenario from a built-in name, a YAML path, or a dict; validate it. A scenario already
    loaded (a model of :data:`SCHEMAS`) is returned as is.

    Returns the scenario model of its planner (:data:`SCHEMAS`).

    Raises:
        ScenarioError: not one of those kinds, unknown name, missing or unreadable file, invalid YAML,
            unknown key, or a value out of range.
    """
    if isinstance(name_or_path, tuple(SCHEMAS.values())):
        return name_or_path
    if not isinstance(name_or_path, str | PathLike | dict) or isinstance(name_or_path, bytes):
        kinds = "a built-in name, a YAML path, a dict or a loaded scenario"
        raise ScenarioError("scenario", short_repr(name_or_path), kinds)
    if isinstance(name_or_path, dict):
        data, origin = dict(name_or_path), None
    else:
        origin = str(name_or_path)
        data = yaml_mapping(_read(origin), "scenario", origin, "scenario field names")
    planner = data.setdefault("planner", DEFAULT_PLANNER)
    if not isinstance(planner, str) or planner not in SCHEMAS:
        raise ScenarioError("planner", short_repr(planner), one_of(SCHEMAS))
    if "name" not in data and origin is not None:
        data["name"] = Path(origin).stem
    if origin is not None and origin not in builtin_names():
        data["robot"] = robot_path_from(data.get("robot"), Path(origin).parent)
    schema = SCHEMAS[planner]
    try:
        return schema.model_validate(data)
    except ValidationError as exc:
        raise input_error(exc, schema, ScenarioError) from None


def robot_path_from(robot: Any, folder: Path) -> Any:
    """``robot`` made absolute from ``folder`` when it is a relative robot YAML path (a name, an
    absolute path or anything else is returned as is)."""
    if not isinstance(robot, str) or Path(robot).suffix.lower() not in YAML_SUFFIXES or Path(robot).is_absolute():
        return robot
    return str((folder / robot).resolve())


def _read(key: str) -> str:
    """The YAML text of a built-in name or a file path."""
    if key in builtin_names():
        return builtin_text(key)
    return yaml_text(Path(key), "scenario", one_of(builtin_names()), ScenarioError)


def yaml_text(path: Path, field: str, choices: str, error: type[InputError] = ScenarioError) -> str:
    """The UTF-8 text of the YAML file ``path`` given for ``field`` (``choices``: the built-ins).

    Raises:
        error: not a .yaml/.yml name, no such file, a folder, unreadable, or not UTF-8.
    """
    key = str(path)
    if path.suffix.lower() not in YAML_SUFFIXES:
        raise error(field, key, f"a YAML file (.yaml, .yml), or {choices}")
    if not path.exists():
        raise error(field, key, f"an existing YAML file (no such file), or {choices}")
    if not path.is_file():
        raise error(field, key, "a YAML file (this is a folder)")
    try:
        return path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(field, key, f"UTF-8 text (byte {exc.start} is not)") from None
    except OSError as exc:
        raise error(field, key, f"a readable file ({exc.strerror})") from None


def yaml_mapping(
    text: str, field: str, origin: str, what: str, error: type[InputError] = ScenarioError
) -> dict[str, Any]:
    """The top-level YAML mapping of ``text`` (read from ``origin``), its keys strings.

    Raises:
        error: invalid YAML, a value YAML cannot build, a document that is not a mapping of ``what``.
    """
    try:
        data = yaml.safe_load(text)
    except (yaml.YAMLError, ValueError) as exc:  # ValueError: a bad date, an integer of > 4300 digits
        raise error(field, origin, f"valid YAML ({one_line(exc)})") from None
    except RecursionError:  # absurdly deep nesting
        raise error(field, origin, "valid YAML nested less than ~500 levels") from None
    if not isinstance(data, dict):
        raise error(field, origin, f"a YAML mapping of {what}")
    bad = next((k for k in data if not isinstance(k, str)), None)
    if bad is not None:
        raise error(short_repr(bad), short_repr(data[bad]), f"keys that are {what} (strings)")
    return data
