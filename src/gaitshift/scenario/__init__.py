"""Scenarios: the validated input of every planner (YAML files or built-in names).

Modules: :mod:`~gaitshift.scenario.fields` (shared types, strict base model, foot, error conversion),
:mod:`~gaitshift.scenario.tvlip` and :mod:`~gaitshift.scenario.vhip` (the two schemas),
:mod:`~gaitshift.scenario.loader` (loading and the schema registry) and
:mod:`~gaitshift.scenario.commands` (the teleop command-script format).
"""

from gaitshift.scenario.loader import builtin_names, load_scenario

__all__ = ["builtin_names", "load_scenario"]
